#include <iostream>

#include "arguments.h"
#include "clearway/io/scan_io.h"
#include "clearway/scan_summary.h"
#include "commands.h"

namespace clearway::cli {

int runInfo(const std::vector<std::string>& words) {
  const Arguments arguments(words, {"json"}, {"self-hit-radius", "rings"});
  arguments.expectPositional(1, "one scan file: clearway-cli info [--json] [--rings N] FILE");
  LoadOptions options;
  options.self_hit_radius =
      arguments.number("self-hit-radius", options.self_hit_radius, 0.0, 100.0);
  options.rings = std::size_t(arguments.integer("rings", 0, 0, kMaxRings));
  const Scan scan = loadScan(arguments.positional()[0], options);
  const ScanSummary summary = summarise(scan);
  std::cout << (arguments.flag("json") ? toJson(summary) + "\n" : toText(summary));
  return 0;
}

}  // namespace clearway::cli
