#include <iostream>

#include "arguments.h"
#include "clearway/eval/evaluation.h"
#include "clearway/io/result_manifest.h"
#include "clearway/sim/ground_truth_io.h"
#include "commands.h"

namespace clearway::cli {

int runEval(const std::vector<std::string>& words) {
  const Arguments arguments(words, {"json"}, {"tolerance"});
  arguments.expectPositional(2, "clearway-cli eval [--json] SCAN.truth.json RESULT_DIR");
  eval::EvaluationOptions options;
  options.footprint_tolerance_m =
      arguments.number("tolerance", options.footprint_tolerance_m, 0.0, 1.0);
  const sim::GroundTruth truth = sim::loadGroundTruth(arguments.positional()[0]);
  // A folder mixing files of two runs (a re-run that failed half-way) is refused, not scored.
  verifyResultFolder(arguments.positional()[1]);
  const eval::SegmentationResult result = eval::loadSegmentationResult(arguments.positional()[1]);
  // A truth scored against another scan's result (both of 7,200 points) gave numbers without a
  // word: the names each file gives are compared, and a difference said (files may be renamed).
  if (!truth.scan.empty() && !result.scan.empty() && truth.scan != result.scan)
    std::cerr << "clearway-cli eval: caution: the truth is for '" << truth.scan
              << "', the result for '" << result.scan << "'\n";
  const eval::Evaluation evaluation = eval::evaluate(truth, result, options);
  std::cout << (arguments.flag("json") ? eval::toJson(evaluation) + "\n"
                                       : eval::toText(evaluation));
  return 0;
}

}  // namespace clearway::cli
