#pragma once

// `clearway-cli bench --peers`: PCL's plane segmentations and an OpenCV traversability baseline,
// timed in the same process on the same scan with the same thread count as our pipeline, and,
// where the scan has the simulator's truth beside it, scored by the same measures.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "clearway/eval/segmentation_accuracy.h"
#include "clearway/pipeline.h"
#include "clearway/sim/rosi_simulator.h"

namespace clearway::cli {

struct PeerFigures {
  std::string name;
  std::string replaces;  // the part of our pipeline it does: "planes" or "traversability"
  std::string skipped;   // why it did not run on this scan; empty when it ran
  std::vector<double> milliseconds;
  std::size_t planes = 0;                              // plane peers
  std::size_t traversable_cells = 0;                   // traversability peers
  std::optional<eval::SegmentationAccuracy> accuracy;  // plane peers, with truth
  std::optional<eval::MapScore> map_score;             // traversability peers, with truth
};

// What our own pipeline's result scores against the truth.
struct OwnAccuracy {
  eval::SegmentationAccuracy planes;
  eval::MapScore map;
};
OwnAccuracy scoreOwnResult(const sim::GroundTruth& truth, const PipelineResult& result);

// Peers run min(repeat, 5) times after a warm-up: the slowest take seconds per run.
std::vector<PeerFigures> benchPeers(const Scan& scan, const PipelineResult& ours,
                                    const SegmentationParams& params, const sim::GroundTruth* truth,
                                    int repeat, int threads);

nlohmann::json accuracyJson(const eval::SegmentationAccuracy& accuracy);
nlohmann::json mapScoreJson(const eval::MapScore& score);
// Place pairs whose reachability the map gets wrong.
std::size_t wrongPlacePairs(const eval::MapScore& score);
// Our medians the peers are compared with [ms].
struct OwnTimes {
  double total = 0.0;           // the whole pipeline
  double planes = 0.0;          // lines, clustering, validation and ground: what plane peers do
  double traversability = 0.0;  // the traversability stage: what the map peer does
};

nlohmann::json peerJson(const PeerFigures& peer, const OwnTimes& own);
// One table row per peer, with how many times slower than the same work in our pipeline it is.
void printPeers(const std::vector<PeerFigures>& peers, const OwnTimes& own);

}  // namespace clearway::cli
