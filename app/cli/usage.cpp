#include "usage.h"

#include <sstream>

namespace clearway::cli {
namespace {

constexpr const char* kUsage =
    "usage: clearway-cli COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  info [--json] [--rings N] [--pose P] [--up U] [--self-hit-radius M] FILE\n"
    "                                            describe a scan file\n"
    "  simulate SCENE -o FILE.pcd [--lines N | --speed DEG_S] [--axis up|down|forward|side|X,Y,Z]\n"
    "           [--tilt DEG] [--axis-roll DEG] [--position X,Y,Z] [--seed S] [--noise M]\n"
    "           [--max-range M] [--mixed-pixels] [--dropout P] [--door-width W] [--door-height H]\n"
    "           [--ramp-slope DEG] [--stair-rise M] [--stair-tread M] [--encoding E]\n"
    "                                            simulated RoSi scan + FILE.truth.json\n"
    "  scene --list | scene NAME [-o FILE.json]  list or export the built-in scenes\n"
    "  segment SCAN -o DIR [--robot-width W] [--robot-length L] [--robot-height H]\n"
    "          [--max-step M] [--max-slope DEG] [--max-stair-rise M] [--max-stair-slope DEG]\n"
    "          [--params FILE] [--method split-and-merge|hough]\n"
    "          [--threads N] [--rings N] [--pose P] [--up U] [--self-hit-radius M] [--goal X,Y]\n"
    "          [--quiet]\n"
    "                                            planes, ground, traversability map, 3D scene\n"
    "  emulate [--scene SCENE] [--ports FILE] [--speed X] [--seconds S] [--seed S] [--arm-tilt "
    "DEG]\n"
    "          [--arm-roll DEG] [--mount POSE] [--stall-after S] [--laser-silent-after S]\n"
    "          [--table-silent-after S] [--hang-up-after S] [--mute-angles] [--corrupt-every N]\n"
    "                                            an LMS200, turntable and arm on pseudo-terminals\n"
    "  acquire --lms PORT --turntable PORT [--arm PORT] [--mount TX,TY,TZ,QW,QX,QY,QZ]\n"
    "          [--lines N] [--speed DEG_S] [--timeout MS] [--baud B] -o SCAN.pcd\n"
    "                                            one RoSi scan from the devices (or the emulator)\n"
    "  acquire --recover SCAN.journal -o SCAN.pcd  the lines a crashed acquisition journaled\n"
    "  acquire --remote HOST:PORT --credentials DIR [--lines N] [--speed DEG_S] [--watch]\n"
    "          -o SCAN.pcd\n"
    "                                            one scan from `serve` on the robot\n"
    "  serve --credentials DIR --listen HOST:PORT (--simulate SCENE [--speed X] |\n"
    "        --lms PORT --turntable PORT [--baud B]) [--storage DIR] [--seconds S]\n"
    "                                            the RoSi on the robot, for remote consoles\n"
    "  serve --init-credentials DIR              write the robot's and the console's keys\n"
    "  bench SCAN... [--repeat N] [--threads T] [--peers] [--json] [--rings N]\n"
    "          [robot, pose and --params options]\n"
    "                                            time the pipeline: per-stage median and p95\n"
    "  eval [--json] [--tolerance M] SCAN.truth.json RESULT_DIR\n"
    "                                            score a segment result against the truth\n"
    "\n"
    "--rings N: a multi-beam LiDAR's number of rings (recovered from the elevation angles).\n"
    "Formats: .pcd .ply .xyz/.txt/.dat/.asc .bin (KITTI) .3d (+ .pose, 3DTK uos).\n"
    "See README.md and docs/FORMATS.md.\n";

// A command's usage starts on a line indented by exactly this much; its continuation lines are
// indented further.
constexpr std::string_view kCommandIndent = "  ";

}  // namespace

std::string_view usageText() {
  return kUsage;
}

std::string commandUsage(std::string_view command) {
  std::istringstream lines{std::string(kUsage)};
  std::string line, usage;
  bool inside = false;
  while (std::getline(lines, line)) {
    const bool starts_command = line.size() > kCommandIndent.size() &&
                                line.starts_with(kCommandIndent) &&
                                line[kCommandIndent.size()] != ' ';
    if (starts_command) {
      const std::string_view head = std::string_view(line).substr(kCommandIndent.size());
      inside = head.starts_with(command) &&
               (head.size() == command.size() || head[command.size()] == ' ');
    } else if (line.empty() || !line.starts_with(kCommandIndent)) {
      inside = false;
    }
    if (inside) usage += line + '\n';
  }
  return usage;
}

}  // namespace clearway::cli
