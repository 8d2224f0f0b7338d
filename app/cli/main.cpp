// clearway-cli: the headless face of Clearway. main() only dispatches and maps failures to exit
// codes: 0 success, 1 the work failed, 2 the command line was wrong.

#include <exception>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "arguments.h"
#include "clearway/io/scan_error.h"
#include "clearway/memory_tuning.h"
#include "clearway/progress.h"
#include "clearway/sim/scene_io.h"
#include "commands.h"

namespace {

constexpr const char* kUsage =
    "usage: clearway-cli COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  info [--json] [--self-hit-radius M] [--rings N] FILE\n"
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
    "          [--threads N] [--rings N] [--pose P] [--up U] [--goal X,Y]\n"
    "                                            planes, ground, traversability map, 3D scene\n"
    "  emulate [--scene SCENE] [--ports FILE] [--speed X] [--seconds S] [--arm-tilt DEG]\n"
    "          [--arm-roll DEG] [--mount POSE] [--stall-after S] [--laser-silent-after S]\n"
    "          [--table-silent-after S] [--hang-up-after S] [--mute-angles] [--corrupt-every N]\n"
    "                                            an LMS200, turntable and arm on pseudo-terminals\n"
    "  acquire --lms PORT --turntable PORT [--arm PORT] [--mount TX,TY,TZ,QW,QX,QY,QZ]\n"
    "          [--lines N] [--speed DEG_S] [--timeout MS] [--baud B] -o SCAN.pcd\n"
    "                                            one RoSi scan from the devices (or the emulator)\n"
    "  acquire --recover SCAN.journal -o SCAN.pcd  the lines a crashed acquisition journaled\n"
    "  acquire --remote HOST:PORT --credentials DIR [--lines N] [--watch] -o SCAN.pcd\n"
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

}  // namespace

int main(int argc, char** argv) {
  clearway::keepFreedMemoryForReuse();
  using Command = std::function<int(const std::vector<std::string>&)>;
  const std::map<std::string, Command> commands = {
      {"info", clearway::cli::runInfo},       {"simulate", clearway::cli::runSimulate},
      {"scene", clearway::cli::runScene},     {"eval", clearway::cli::runEval},
      {"segment", clearway::cli::runSegment}, {"emulate", clearway::cli::runEmulate},
      {"acquire", clearway::cli::runAcquire}, {"bench", clearway::cli::runBench},
      {"serve", clearway::cli::runServe},
  };
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    std::cout << kUsage;
    return argc < 2 ? 2 : 0;
  }
  const auto command = commands.find(argv[1]);
  if (command == commands.end()) {
    std::cerr << "clearway-cli: unknown command '" << argv[1] << "'\n" << kUsage;
    return 2;
  }
  try {
    return command->second(std::vector<std::string>(argv + 2, argv + argc));
  } catch (const clearway::cli::UsageError& error) {
    std::cerr << "clearway-cli " << argv[1] << ": " << error.what() << '\n';
    return 2;
  } catch (const clearway::ScanError& error) {
    std::cerr << "clearway-cli: " << error.what() << '\n';
    return 1;
  } catch (const clearway::sim::SceneError& error) {
    std::cerr << "clearway-cli: " << error.what() << '\n';
    return 1;
  } catch (const clearway::OperationCancelled&) {
    std::cerr << "clearway-cli: cancelled\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "clearway-cli: out of memory\n";
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "clearway-cli: " << error.what() << '\n';
    return 1;
  }
}
