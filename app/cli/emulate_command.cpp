#include <atomic>
#include <chrono>
#include <csignal>
#include <functional>
#include <iostream>
#include <thread>

#include "arguments.h"
#include "clearway/hardware/rosi_emulator.h"
#include "clearway/io/file_util.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/scene_io.h"
#include "commands.h"

namespace clearway::cli {
namespace {

std::atomic<bool> stop_requested{false};
void requestStop(int) {
  stop_requested = true;
}

// A fault switched on once the emulator has run this long (seconds of wall time).
struct TimedFault {
  double after_s;
  std::function<void()> start;
  bool started = false;
};

}  // namespace

int runEmulate(const std::vector<std::string>& words) {
  const Arguments arguments(
      words, {"mute-angles"},
      {"scene", "ports", "speed", "seconds", "seed", "arm-tilt", "arm-roll", "mount", "stall-after",
       "laser-silent-after", "table-silent-after", "hang-up-after", "corrupt-every"});
  arguments.expectPositional(
      0, "no positional arguments: clearway-cli emulate --scene SCENE [--ports FILE]");
  const std::string scene_name = arguments.option("scene").value_or("garage");
  std::optional<sim::Scene> scene = sim::builtinScene(scene_name);
  if (!scene) {
    if (!scene_name.ends_with(".json")) throw UsageError("unknown scene '" + scene_name + "'");
    scene = sim::loadScene(scene_name);
  }
  hardware::EmulatorOptions options;
  options.speedup = arguments.number("speed", 1.0, 0.01, 1000.0);
  options.seed = std::uint32_t(arguments.integer("seed", 1, 0, 4'294'967'295L));
  if (arguments.option("arm-tilt")) options.arm_tilt_deg = arguments.number("arm-tilt", 0, -90, 90);
  if (arguments.option("arm-roll"))
    options.arm_roll_deg = arguments.number("arm-roll", 0, -180, 180);
  if (const auto mount = arguments.option("mount")) {
    std::string error;
    const auto pose = hardware::parsePose(*mount, error);
    if (!pose) throw UsageError("--mount: " + error);
    options.tool_from_scanner = *pose;
  }
  const double seconds = arguments.number("seconds", 0.0, 0.0, 1e7);  // 0 = until interrupted
  const int corrupt_every = int(arguments.integer("corrupt-every", 0, 0, 1'000'000));

  hardware::RosiEmulator emulator(*scene, options);
  // The fault switches, for trying a driver against a misbehaving RoSi from the shell.
  std::vector<TimedFault> faults;
  const auto timed = [&](const std::string& name, std::function<void()> start) {
    if (arguments.option(name))
      faults.push_back({arguments.number(name, 0.0, 0.0, 1e7), std::move(start)});
  };
  timed("stall-after", [&] { emulator.stall(true); });
  timed("laser-silent-after", [&] { emulator.stallLaser(true); });
  timed("table-silent-after", [&] { emulator.stallTurntable(true); });
  timed("hang-up-after", [&] { emulator.hangUp(); });
  if (arguments.flag("mute-angles")) emulator.muteAngles(true);
  emulator.corruptEvery(corrupt_every);

  if (const auto ports = arguments.option("ports"))
    writeTextFileAtomically(*ports, emulator.portsJson() + "\n");
  std::cout << "emulating a RoSi observing '" << scene->name << "' (speed x" << options.speedup
            << ")\n"
            << emulator.portsJson() << std::endl;
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  const auto begin = std::chrono::steady_clock::now();
  const auto until = begin + std::chrono::duration<double>(seconds);
  while (!stop_requested && (seconds == 0.0 || std::chrono::steady_clock::now() < until)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    for (TimedFault& fault : faults)
      if (!fault.started && elapsed >= fault.after_s) {
        fault.start();
        fault.started = true;
        std::cout << "fault switched on after " << fault.after_s << " s" << std::endl;
      }
  }
  std::cout << "measured-values lines sent: " << emulator.linesSent() << std::endl;
  return 0;
}

}  // namespace clearway::cli
