#include <atomic>
#include <chrono>
#include <csignal>
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

}  // namespace

int runEmulate(const std::vector<std::string>& words) {
  const Arguments arguments(words, {}, {"scene", "ports", "speed", "seconds", "seed"});
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
  const double seconds = arguments.number("seconds", 0.0, 0.0, 1e7);  // 0 = until interrupted

  hardware::RosiEmulator emulator(*scene, options);
  if (const auto ports = arguments.option("ports"))
    writeTextFileAtomically(*ports, emulator.portsJson() + "\n");
  std::cout << "emulating a RoSi observing '" << scene->name << "' (speed x" << options.speedup
            << ")\n"
            << emulator.portsJson() << std::endl;
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!stop_requested && (seconds == 0.0 || std::chrono::steady_clock::now() < until))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return 0;
}

}  // namespace clearway::cli
