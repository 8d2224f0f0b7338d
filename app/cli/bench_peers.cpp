#include "bench_peers.h"

#include <algorithm>
#include <iomanip>
#include <iostream>

#include "bench_timing.h"
#include "clearway/peers/plane_peers.h"
#include "clearway/peers/traversability_peer.h"

namespace clearway::cli {
namespace {

constexpr int kMaxPeerRuns = 5;
constexpr const char* kPlanes = "planes";
constexpr const char* kTraversability = "traversability";

eval::SegmentationResult mapResult(const MapGrid& grid, const std::vector<std::uint8_t>& labels,
                                   const ScanAnalysis& analysis, const RobotParams& robot) {
  eval::SegmentationResult result;
  result.robot = {robot.width, robot.length, robot.height, robot.max_step};
  result.map = eval::resultMapOf(grid, labels, analysis.map_from_scanner);
  result.has_map = true;
  result.ground_found = analysis.ground_found;
  return result;
}

std::size_t traversableCells(const std::vector<std::uint8_t>& labels) {
  return std::size_t(std::count_if(labels.begin(), labels.end(), [](std::uint8_t label) {
    return label == std::uint8_t(CellLabel::kTraversable) ||
           label == std::uint8_t(CellLabel::kCareful);
  }));
}

PeerFigures benchPlanePeer(const peers::PlanePeer& peer, const Scan& scan,
                           const sim::GroundTruth* truth, int runs, int threads) {
  PeerFigures figures;
  figures.name = peer.name;
  figures.replaces = kPlanes;
  figures.skipped = peer.unsuitable(scan);
  if (!figures.skipped.empty()) return figures;
  eval::PointPlanes result;
  figures.milliseconds = timeRuns(runs, [&] { result = peer.run(scan, threads, {}); });
  figures.planes = result.planes.size();
  if (truth) figures.accuracy = eval::scoreSegmentation(*truth, result);
  return figures;
}

PeerFigures benchDilatePeer(const PipelineResult& ours, const SegmentationParams& params,
                            const sim::GroundTruth* truth, int runs, int threads) {
  PeerFigures figures;
  figures.name = "opencv_dilate_footprints";
  figures.replaces = kTraversability;
  if (!ours.analysis->ground_found) {
    figures.skipped = "no ground found: there is no map to compute";
    return figures;
  }
  std::vector<std::uint8_t> labels;
  figures.milliseconds = timeRuns(runs, [&] {
    labels =
        peers::dilateTraversability(*ours.analysis, ours.robot, params.map, ours.map.yaws, threads);
  });
  figures.traversable_cells = traversableCells(labels);
  if (truth)
    figures.map_score = eval::scoreMap(
        *truth, mapResult(ours.analysis->inputs.grid, labels, *ours.analysis, ours.robot));
  return figures;
}

double ratio(double peer_ms, double own_ms) {
  return own_ms > 0 ? peer_ms / own_ms : 0.0;
}

}  // namespace

OwnAccuracy scoreOwnResult(const sim::GroundTruth& truth, const PipelineResult& result) {
  return {eval::scoreSegmentation(truth, eval::pointPlanesOf(*result.analysis)),
          eval::scoreMap(truth, mapResult(result.map.grid, result.map.labels, *result.analysis,
                                          result.robot))};
}

std::vector<PeerFigures> benchPeers(const Scan& scan, const PipelineResult& ours,
                                    const SegmentationParams& params, const sim::GroundTruth* truth,
                                    int repeat, int threads) {
  const int runs = std::min(repeat, kMaxPeerRuns);
  std::vector<PeerFigures> figures;
  for (const peers::PlanePeer& peer : peers::planePeers())
    figures.push_back(benchPlanePeer(peer, scan, truth, runs, threads));
  figures.push_back(benchDilatePeer(ours, params, truth, runs, threads));
  return figures;
}

nlohmann::json accuracyJson(const eval::SegmentationAccuracy& accuracy) {
  return {{"plane_recall", accuracy.planes.recall},
          {"plane_precision", accuracy.planes.precision},
          {"truth_planes", accuracy.planes.truth_planes},
          {"mean_normal_error_deg", accuracy.planes.mean_normal_error_deg},
          {"point_purity", accuracy.point_purity},
          {"coverage", accuracy.coverage}};
}

std::size_t wrongPlacePairs(const eval::MapScore& score) {
  return std::size_t(
      std::count_if(score.places.begin(), score.places.end(),
                    [](const eval::PlaceCheck& p) { return p.expected != p.found; }));
}

nlohmann::json mapScoreJson(const eval::MapScore& score) {
  const std::size_t places_wrong = wrongPlacePairs(score);
  return {{"traversable_cells", score.traversable_cells},
          {"false_traversable_cells", score.false_traversable_cells},
          {"false_traversable_rate", score.false_traversable_rate},
          {"place_pairs", score.places.size()},
          {"place_pairs_wrong", places_wrong}};
}

nlohmann::json peerJson(const PeerFigures& peer, const OwnTimes& own) {
  nlohmann::json json = {{"replaces", peer.replaces}};
  if (!peer.skipped.empty()) {
    json["skipped"] = peer.skipped;
    return json;
  }
  const double median = quantile(peer.milliseconds, 0.5);
  json["median_ms"] = median;
  json["p95_ms"] = quantile(peer.milliseconds, 0.95);
  json["runs"] = peer.milliseconds.size();
  if (peer.replaces == kPlanes) {
    json["planes"] = peer.planes;
    json["times_our_planes"] = ratio(median, own.planes);
    json["times_our_total"] = ratio(median, own.total);
  } else {
    json["traversable_cells"] = peer.traversable_cells;
    json["times_our_traversability"] = ratio(median, own.traversability);
  }
  if (peer.accuracy) json["accuracy"] = accuracyJson(*peer.accuracy);
  if (peer.map_score) json["map_accuracy"] = mapScoreJson(*peer.map_score);
  return json;
}

void printPeers(const std::vector<PeerFigures>& peers, const OwnTimes& own) {
  std::cout << "  peers (same scan, same threads; \"x ours\" = their median over ours for the same"
               " work: stages 1-4 for planes, stage 5 for maps)\n";
  std::cout << "  " << std::left << std::setw(26) << "peer" << std::right << std::setw(11)
            << "median ms" << std::setw(9) << "x ours"
            << "  accuracy\n";
  for (const PeerFigures& peer : peers) {
    std::cout << "  " << std::left << std::setw(26) << peer.name << std::right;
    if (!peer.skipped.empty()) {
      std::cout << "  skipped: " << peer.skipped << "\n";
      continue;
    }
    const double median = quantile(peer.milliseconds, 0.5);
    const double reference = peer.replaces == kPlanes ? own.planes : own.traversability;
    std::cout << std::fixed << std::setprecision(1) << std::setw(11) << median << std::setw(9)
              << ratio(median, reference) << "  ";
    if (peer.replaces == kPlanes) std::cout << peer.planes << " planes";
    if (peer.replaces == kTraversability) std::cout << peer.traversable_cells << " cells fit";
    if (peer.accuracy)
      std::cout << std::setprecision(2) << ", recall " << peer.accuracy->planes.recall
                << ", precision " << peer.accuracy->planes.precision << ", purity "
                << peer.accuracy->point_purity << ", coverage " << peer.accuracy->coverage
                << ", normal error " << peer.accuracy->planes.mean_normal_error_deg << " deg";
    if (peer.map_score)
      std::cout << ", " << peer.map_score->false_traversable_cells << " false traversable, "
                << wrongPlacePairs(*peer.map_score) << " of " << peer.map_score->places.size()
                << " place pairs wrong";
    std::cout << "\n";
  }
}

}  // namespace clearway::cli
