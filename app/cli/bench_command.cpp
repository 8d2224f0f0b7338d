// clearway-cli bench: the whole pipeline, timed on scans already in memory (no file I/O in the
// figures), after a warm-up run; medians and 95th percentiles per stage, throughput and the extra
// memory a run needs beyond the loaded scan.

#include <malloc.h>
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "arguments.h"
#include "bench_peers.h"
#include "bench_timing.h"
#include "clearway/io/result_manifest.h"
#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "clearway/sim/ground_truth_io.h"
#include "clearway/sim/scene_io.h"
#include "commands.h"
#include "pose_options.h"
#include "robot_options.h"

namespace clearway::cli {
namespace {

// A /proc/self/status field in kB, or -1 where /proc is not there.
long statusKilobytes(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  return -1;
}

// Returns freed memory to the system and resets the peak resident size to the current one, so the
// peak after the runs is theirs alone and not the loader's. Returns false where the kernel does not
// allow it.
bool resetPeakMemory() {
  // Freed heap pages of earlier scans would otherwise stay resident and hide this scan's needs.
  malloc_trim(0);
  std::ofstream clear_refs("/proc/self/clear_refs");
  clear_refs << "5";
  return bool(clear_refs.flush());
}

struct BenchFigures {
  std::string scan;
  std::size_t points = 0;
  int repeat = 0;
  int threads = 0;
  std::vector<std::string> stage_order;
  std::map<std::string, std::vector<double>> stage_ms;
  std::vector<double> total_ms;
  std::vector<double> goal_ms;  // one "Can it get there?" query per run
  long extra_kilobytes = -1;
  bool trusted = false;
  std::size_t planes = 0;               // validated planes
  std::optional<OwnAccuracy> accuracy;  // when the simulator's truth is beside the scan
  std::vector<PeerFigures> peers;

  double median() const { return quantile(total_ms, 0.5); }
  // The median over runs of the summed time of `stages`.
  double stagesMedian(std::initializer_list<const char*> stages) const {
    std::vector<double> sums(total_ms.size(), 0.0);
    for (const char* stage : stages) {
      const auto times = stage_ms.find(stage);
      if (times == stage_ms.end()) continue;
      for (std::size_t run = 0; run < sums.size() && run < times->second.size(); ++run)
        sums[run] += times->second[run];
    }
    return sums.empty() ? 0.0 : quantile(sums, 0.5);
  }
  OwnTimes ownTimes() const {
    return {median(), stagesMedian({"sensor", "lines", "clustering", "validation", "ground"}),
            stagesMedian({"traversability"})};
  }
  double p95() const { return quantile(total_ms, 0.95); }
  double pointsPerSecond() const { return double(points) / (median() / 1000.0); }
  double extraMegabytes() const { return double(extra_kilobytes) / 1024.0; }
  double extraBytesPerPoint() const {
    return double(extra_kilobytes) * 1024.0 / double(std::max<std::size_t>(1, points));
  }
};

// The simulator's truth for `file`, when it is beside it. Throws SceneError when it is not this
// scan's truth.
std::optional<sim::GroundTruth> truthFor(const std::filesystem::path& file, const Scan& scan) {
  const std::filesystem::path truth_file = sim::truthPathFor(file);
  if (!std::filesystem::exists(truth_file)) return std::nullopt;
  sim::GroundTruth truth = sim::loadGroundTruth(truth_file);
  if (truth.surfaces.size() != scan.size())
    throw sim::SceneError(truth_file.string() + " describes " +
                          std::to_string(truth.surfaces.size()) + " points, " + file.string() +
                          " has " + std::to_string(scan.size()) + ": not this scan's truth");
  return truth;
}

// The reachable cell farthest from the robot: the hardest goal query a map offers.
std::optional<Eigen::Vector2d> farthestReachable(const TraversabilityMap& map) {
  std::optional<Eigen::Vector2d> farthest;
  double best = -1.0;
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      if (map.reach.empty() || !map.reach[map.grid.index(column, row)]) continue;
      const Eigen::Vector2d centre = map.grid.centre(column, row);
      const double distance =
          std::hypot(centre.x() - map.robot_pose.x, centre.y() - map.robot_pose.y);
      if (distance > best) {
        best = distance;
        farthest = centre;
      }
    }
  return farthest;
}

BenchFigures benchScan(const std::filesystem::path& file, const Arguments& arguments,
                       SegmentationParams params, int repeat, int threads, bool with_peers) {
  BenchFigures figures;
  figures.scan = file.string();
  figures.repeat = repeat;
  figures.threads = threads;
  const Scan scan = loadScanWithPose(file, arguments, params).scan;
  figures.points = scan.size();
  const PipelineResult warm_up = runPipeline(scan, params, threads);  // caches, pool
  figures.trusted = warm_up.trusted();
  figures.planes = warm_up.analysis->planes.planes.size();
  const std::optional<sim::GroundTruth> truth = truthFor(file, scan);
  if (truth) figures.accuracy = scoreOwnResult(*truth, warm_up);
  const bool peak_reset = resetPeakMemory();
  const long resident_before = statusKilobytes("VmRSS");
  for (int run = 0; run < repeat; ++run) {
    // The total is the call's wall time, not the sum of its stages: whatever runs between the
    // stages' clocks counts too.
    const auto call_start = std::chrono::steady_clock::now();
    const PipelineResult result = runPipeline(scan, params, threads);
    figures.total_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - call_start)
            .count());
    // "Can it get there?" to the farthest reachable cell: timed apart, not part of the total.
    if (const auto goal = farthestReachable(result.map)) {
      const auto start = std::chrono::steady_clock::now();
      const GoalResult answer = planPath(result.map, goal->x(), goal->y());
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      if (answer.reachable) figures.goal_ms.push_back(ms);
    }
    for (const StageTiming& stage : result.timings) {
      if (!figures.stage_ms.count(stage.stage)) figures.stage_order.push_back(stage.stage);
      figures.stage_ms[stage.stage].push_back(stage.milliseconds);
    }
  }
  const long peak = statusKilobytes("VmHWM");
  if (peak_reset && peak >= 0 && resident_before >= 0)
    figures.extra_kilobytes = std::max(0L, peak - resident_before);
  if (with_peers)
    figures.peers = benchPeers(scan, warm_up, params, truth ? &*truth : nullptr, repeat, threads);
  return figures;
}

nlohmann::json toJson(const BenchFigures& figures) {
  nlohmann::json stages = nlohmann::json::object();
  for (const std::string& name : figures.stage_order) {
    const std::vector<double>& times = figures.stage_ms.at(name);
    stages[name] = {{"median_ms", quantile(times, 0.5)}, {"p95_ms", quantile(times, 0.95)}};
  }
  nlohmann::json json = {{"scan", utf8FileName(figures.scan)},
                         {"points", figures.points},
                         {"repeat", figures.repeat},
                         {"threads", figures.threads},
                         {"ground_found", figures.trusted},
                         {"planes", figures.planes},
                         {"median_ms", figures.median()},
                         {"p95_ms", figures.p95()},
                         {"points_per_s", figures.pointsPerSecond()},
                         {"stages", stages}};
  // Stages 5-6 are what a robot change re-runs (reachability included in "traversability").
  json["robot_rerun_median_ms"] = figures.stagesMedian({"traversability", "scene"});
  if (!figures.goal_ms.empty())
    json["goal_query"] = {{"median_ms", quantile(figures.goal_ms, 0.5)},
                          {"p95_ms", quantile(figures.goal_ms, 0.95)}};
  if (figures.extra_kilobytes >= 0) {
    json["extra_memory_mb"] = figures.extraMegabytes();
    json["extra_bytes_per_point"] = figures.extraBytesPerPoint();
  }
  if (figures.accuracy) {
    json["accuracy"] = accuracyJson(figures.accuracy->planes);
    json["map_accuracy"] = mapScoreJson(figures.accuracy->map);
  }
  if (!figures.peers.empty()) {
    json["peers"] = nlohmann::json::object();
    const OwnTimes own = figures.ownTimes();
    for (const PeerFigures& peer : figures.peers)
      json["peers"][peer.name] = peerJson(peer, own);
  }
  return json;
}

void printTable(const BenchFigures& figures) {
  std::cout << figures.scan << ": " << figures.points << " points, " << figures.planes
            << " planes, " << figures.repeat << " runs after a warm-up, " << figures.threads
            << " threads" << (figures.trusted ? "" : " (no ground found: the map is all untrusted)")
            << "\n";
  std::cout << std::fixed << std::setprecision(2);
  std::cout << "  " << std::left << std::setw(18) << "stage" << std::right << std::setw(10)
            << "median ms" << std::setw(10) << "p95 ms"
            << "\n";
  for (const std::string& name : figures.stage_order) {
    const std::vector<double>& times = figures.stage_ms.at(name);
    std::cout << "  " << std::left << std::setw(18) << name << std::right << std::setw(10)
              << quantile(times, 0.5) << std::setw(10) << quantile(times, 0.95) << "\n";
  }
  std::cout << "  " << std::left << std::setw(18) << "total" << std::right << std::setw(10)
            << figures.median() << std::setw(10) << figures.p95() << "\n";
  std::cout << std::setprecision(1) << "  " << figures.pointsPerSecond() / 1e6 << " M points/s";
  if (figures.extra_kilobytes >= 0)
    std::cout << ", extra memory " << figures.extraMegabytes() << " MB ("
              << figures.extraBytesPerPoint() << " B/point)";
  std::cout << "\n";
  if (figures.accuracy) {
    const eval::SegmentationAccuracy& planes = figures.accuracy->planes;
    std::cout << std::setprecision(2) << "  accuracy against the simulator's truth: plane recall "
              << planes.planes.recall << ", precision " << planes.planes.precision << ", purity "
              << planes.point_purity << ", coverage " << planes.coverage << ", normal error "
              << planes.planes.mean_normal_error_deg << " deg; "
              << figures.accuracy->map.false_traversable_cells << " false traversable of "
              << figures.accuracy->map.traversable_cells << " cells, "
              << wrongPlacePairs(figures.accuracy->map) << " of "
              << figures.accuracy->map.places.size() << " place pairs wrong\n";
  }
  std::cout << "  robot re-run (traversability with reachability + scene): "
            << figures.stagesMedian({"traversability", "scene"}) << " ms median";
  if (!figures.goal_ms.empty())
    std::cout << "; goal query to the farthest reachable cell: " << quantile(figures.goal_ms, 0.5)
              << " ms median";
  std::cout << "\n";
  if (!figures.peers.empty()) printPeers(figures.peers, figures.ownTimes());
}

}  // namespace

int runBench(const std::vector<std::string>& words) {
  const Arguments arguments(words, {"json", "peers"},
                            withPoseOptions(withRobotOptions({"repeat", "threads", "params"})));
  if (arguments.positional().empty())
    throw UsageError(
        "one or more scans: clearway-cli bench SCAN... [--repeat N] [--threads T] [--peers] "
        "[--rings N]");
  const int repeat = int(arguments.integer("repeat", 20, 1, 100000));
  const int threads = int(arguments.integer("threads", kDefaultThreads, 1, kMaxThreads));
  const SegmentationParams params = paramsFromArguments(arguments);

  nlohmann::json all = nlohmann::json::array();
  for (const std::string& file : arguments.positional()) {
    const BenchFigures figures =
        benchScan(file, arguments, params, repeat, threads, arguments.flag("peers"));
    if (arguments.flag("json"))
      all.push_back(toJson(figures));
    else
      printTable(figures);
  }
  if (arguments.flag("json")) std::cout << (all.size() == 1 ? all[0] : all).dump(2) << "\n";
  return 0;
}

}  // namespace clearway::cli
