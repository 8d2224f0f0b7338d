#include <iostream>

#include "arguments.h"
#include "clearway/hardware/serial_acquisition.h"
#include "clearway/io/scan_io.h"
#include "commands.h"

namespace clearway::cli {

int runAcquire(const std::vector<std::string>& words) {
  for (const std::string& word : words)
    if (word == "--remote" || word.starts_with("--remote=")) return runRemoteAcquire(words);
  const Arguments arguments(
      words, {}, {"lms", "turntable", "lines", "speed", "timeout", "baud", "o", "output"});
  arguments.expectPositional(
      0, "clearway-cli acquire --lms PORT --turntable PORT [--lines N] -o SCAN.pcd");
  const auto lms = arguments.option("lms"), table = arguments.option("turntable");
  const auto output = arguments.option("o") ? arguments.option("o") : arguments.option("output");
  if (!lms || !table || !output)
    throw UsageError("--lms PORT, --turntable PORT and -o SCAN.pcd are required");
  hardware::AcquisitionOptions options;
  options.lines = int(arguments.integer("lines", 0, 0, 100000));
  options.turntable_speed_deg_s =
      arguments.number("speed", options.turntable_speed_deg_s, 0.1, 360.0);
  options.answer_timeout_ms =
      int(arguments.integer("timeout", options.answer_timeout_ms, 50, 60000));

  const hardware::Acquisition acquisition = hardware::acquireRosiScan(*lms, *table, options);
  if (acquisition.complete) {
    saveRosiPcd(acquisition.scan, *output);
    std::cout << "acquired " << acquisition.scan.lines.size() << " lines x 180 points: " << *output
              << "\n";
    return 0;
  }
  std::cerr << "clearway-cli acquire: " << acquisition.error << "\n";
  if (!acquisition.scan.empty()) {
    // Nothing the operator acquired is lost: the lines that arrived are kept, marked partial.
    std::filesystem::path partial = *output;
    partial.replace_extension(".partial.pcd");
    saveRosiPcd(acquisition.scan, partial);
    std::cerr << "clearway-cli acquire: the " << acquisition.scan.lines.size()
              << " lines that arrived are in " << partial.string() << "\n";
  }
  return 1;
}

}  // namespace clearway::cli
