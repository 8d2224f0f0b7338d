#include "clearway/eval/evaluation.h"

#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <numbers>
#include <queue>
#include <sstream>

#include "clearway/eval/robot_fit.h"
#include "clearway/sim/scene.h"

namespace clearway::eval {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr std::size_t kListedFalseCells = 20;
// The map lies on the reference ground plane, the true ground under a cell may be another level:
// it is looked for downwards from this high above the map's plane, above any level a scene
// holds that the robot could reach (a platform, a stair's landing) [m].
constexpr double kLevelSearchHeight = 1.5;
// A place (a room's middle, a yard) belongs to the traversable component found within this
// distance of it: a place's own cell may be on a table's rim or a door jamb's shadow [m].
constexpr double kPlaceSearchRadius = 0.3;

std::array<ClassScore, kPointClassCount> scoreClasses(const sim::GroundTruth& truth,
                                                      const std::vector<PointClass>& predicted) {
  std::array<ClassScore, kPointClassCount> scores{};
  for (int c = 0; c < kPointClassCount; ++c)
    scores[std::size_t(c)].point_class = PointClass(c);
  for (std::size_t i = 0; i < truth.classes.size(); ++i) {
    if (truth.classes[i] == PointClass::kNone) continue;  // no return: nothing to classify
    const auto t = std::size_t(truth.classes[i]), p = std::size_t(predicted[i]);
    ++scores[t].truth;
    ++scores[p].predicted;
    if (t == p) ++scores[t].both;
  }
  for (ClassScore& s : scores) {
    s.precision = s.predicted ? double(s.both) / double(s.predicted) : 0.0;
    s.recall = s.truth ? double(s.both) / double(s.truth) : 0.0;
    const std::size_t either = s.truth + s.predicted - s.both;
    s.iou = either ? double(s.both) / double(either) : 0.0;
  }
  return scores;
}

}  // namespace

bool planesMatch(const sim::SurfaceTruth& surface, const ResultPlane& plane,
                 const EvaluationOptions& options, double& normal_error, double& offset_error) {
  // A plane and its flipped twin are the same plane.
  const double sign = surface.normal.dot(plane.normal) < 0 ? -1.0 : 1.0;
  const double cosine = std::clamp(sign * surface.normal.dot(plane.normal), -1.0, 1.0);
  normal_error = std::acos(cosine) * kRadToDeg;
  offset_error = std::abs(sign * plane.offset - surface.offset);
  return normal_error <= options.max_normal_error_deg && offset_error <= options.max_offset_error_m;
}

PlaneScore scorePlanes(const sim::GroundTruth& truth, const std::vector<ResultPlane>& planes,
                       const EvaluationOptions& options) {
  PlaneScore score;
  score.result_planes = planes.size();
  std::vector<bool> result_matched(planes.size(), false);
  double normal_sum = 0.0, offset_sum = 0.0;
  for (const sim::SurfaceTruth& surface : truth.seen_surfaces) {
    if (!surface.planar || surface.points < options.min_surface_points) continue;
    ++score.truth_planes;
    double best_normal = 0.0, best_offset = 0.0, best_cost = std::numeric_limits<double>::max();
    for (std::size_t k = 0; k < planes.size(); ++k) {
      double normal_error = 0.0, offset_error = 0.0;
      if (!planesMatch(surface, planes[k], options, normal_error, offset_error)) continue;
      result_matched[k] = true;
      const double cost =
          normal_error / options.max_normal_error_deg + offset_error / options.max_offset_error_m;
      if (cost < best_cost) {
        best_cost = cost;
        best_normal = normal_error;
        best_offset = offset_error;
      }
    }
    if (best_cost == std::numeric_limits<double>::max()) continue;
    ++score.matched;
    normal_sum += best_normal;
    offset_sum += best_offset;
  }
  score.result_matched =
      std::size_t(std::count(result_matched.begin(), result_matched.end(), true));
  score.recall = score.truth_planes ? double(score.matched) / double(score.truth_planes) : 0.0;
  score.precision =
      score.result_planes ? double(score.result_matched) / double(score.result_planes) : 0.0;
  if (score.matched) {
    score.mean_normal_error_deg = normal_sum / double(score.matched);
    score.mean_offset_error_m = offset_sum / double(score.matched);
  }
  return score;
}

namespace {

bool isTraversable(std::uint8_t label) {
  return label == 1 || label == 2;
}

}  // namespace

MapScore scoreMap(const sim::GroundTruth& truth, const SegmentationResult& result,
                  const EvaluationOptions& options) {
  const ResultMap& map = result.map;
  const Eigen::Isometry3d world_from_map =
      truth.placement.worldFromScanner() * map.map_from_scanner.inverse();
  const RobotFit fit(truth.scene);
  sim::RobotBox robot = result.robot;
  robot.width = std::max(0.01, robot.width - 2 * options.footprint_tolerance_m);
  robot.length = std::max(0.01, robot.length - 2 * options.footprint_tolerance_m);

  MapScore score;
  for (int row = 0; row < map.height; ++row) {
    for (int column = 0; column < map.width; ++column) {
      if (!isTraversable(map.at(column, row))) continue;
      ++score.traversable_cells;
      const Eigen::Vector3d cell(map.origin.x() + (column + 0.5) * map.resolution,
                                 map.origin.y() + (row + 0.5) * map.resolution, 0.0);
      Eigen::Vector3d world = world_from_map * cell;
      // The map lies on the reference ground plane; the true ground may be another level.
      world.z() += kLevelSearchHeight;
      if (const auto ground = fit.groundHeight(world.x(), world.y(), world.z()))
        world.z() = *ground;
      if (!fit.fitsAnyOrientation(robot, world, options.orientations)) {
        ++score.false_traversable_cells;
        if (score.false_cells.size() < kListedFalseCells) score.false_cells.push_back(world);
      }
    }
  }
  score.false_traversable_rate = score.traversable_cells ? double(score.false_traversable_cells) /
                                                               double(score.traversable_cells)
                                                         : 0.0;

  // Components of traversable cells (8-connected) and where each place falls.
  std::vector<int> component(map.labels.size(), -1);
  auto index = [&](int column, int row) {
    return std::size_t(row) * std::size_t(map.width) + std::size_t(column);
  };
  int components = 0;
  for (int row = 0; row < map.height; ++row) {
    for (int column = 0; column < map.width; ++column) {
      if (!isTraversable(map.at(column, row)) || component[index(column, row)] >= 0) continue;
      std::queue<std::pair<int, int>> frontier;
      frontier.push({column, row});
      component[index(column, row)] = components;
      while (!frontier.empty()) {
        const auto [c, r] = frontier.front();
        frontier.pop();
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int nc = c + dc, nr = r + dr;
            if (nc < 0 || nr < 0 || nc >= map.width || nr >= map.height) continue;
            if (!isTraversable(map.at(nc, nr)) || component[index(nc, nr)] >= 0) continue;
            component[index(nc, nr)] = components;
            frontier.push({nc, nr});
          }
      }
      ++components;
    }
  }
  const Eigen::Isometry3d map_from_world = world_from_map.inverse();
  auto componentOf = [&](const sim::Place& place) {
    const Eigen::Vector3d m = map_from_world * place.position;
    const int column = int(std::floor((m.x() - map.origin.x()) / map.resolution));
    const int row = int(std::floor((m.y() - map.origin.y()) / map.resolution));
    const int search = int(std::ceil(kPlaceSearchRadius / map.resolution));
    for (int radius = 0; radius <= search; ++radius)
      for (int dr = -radius; dr <= radius; ++dr)
        for (int dc = -radius; dc <= radius; ++dc) {
          const int c = column + dc, r = row + dr;
          if (c < 0 || r < 0 || c >= map.width || r >= map.height) continue;
          if (component[index(c, r)] >= 0) return component[index(c, r)];
        }
    return -1;
  };
  const auto reachable = sim::reachablePlaces(truth.scene, result.robot);
  const auto& places = truth.scene.places;
  for (std::size_t i = 0; i < places.size(); ++i)
    for (std::size_t j = i + 1; j < places.size(); ++j) {
      PlaceCheck check{places[i].name, places[j].name};
      check.expected = std::find(reachable.begin(), reachable.end(),
                                 std::make_pair(places[i].name, places[j].name)) != reachable.end();
      const int a = componentOf(places[i]), b = componentOf(places[j]);
      check.found = a >= 0 && a == b;
      score.places.push_back(check);
    }
  return score;
}

ResultMap resultMapOf(const MapGrid& grid, const std::vector<std::uint8_t>& labels_bottom_up,
                      const Eigen::Isometry3d& map_from_scanner) {
  ResultMap map;
  map.resolution = grid.resolution;
  map.origin = grid.origin;
  map.width = grid.width;
  map.height = grid.height;
  map.map_from_scanner = map_from_scanner;
  map.labels.resize(labels_bottom_up.size());
  for (int row = 0; row < grid.height; ++row)
    std::copy_n(labels_bottom_up.begin() + std::ptrdiff_t(grid.index(0, row)), grid.width,
                map.labels.begin() + std::ptrdiff_t(grid.index(0, grid.height - 1 - row)));
  return map;
}

Evaluation evaluate(const sim::GroundTruth& truth, const SegmentationResult& result,
                    const EvaluationOptions& options) {
  Evaluation evaluation;
  if (!result.point_classes.empty()) {
    if (result.point_classes.size() != truth.classes.size())
      throw std::runtime_error("the result has " + std::to_string(result.point_classes.size()) +
                               " point classes, the truth " + std::to_string(truth.classes.size()) +
                               " points: not the same scan?");
    evaluation.classes = scoreClasses(truth, result.point_classes);
    evaluation.has_point_classes = true;
  }
  evaluation.planes = scorePlanes(truth, result.planes, options);
  if (result.has_map) {
    evaluation.map = scoreMap(truth, result, options);
    evaluation.has_map = true;
  }
  return evaluation;
}

std::string toText(const Evaluation& e) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3);
  if (e.has_point_classes) {
    out << "class       truth  predicted  precision  recall    IoU\n";
    for (const ClassScore& s : e.classes) {
      if (s.point_class == PointClass::kNone || (s.truth == 0 && s.predicted == 0)) continue;
      out << std::left << std::setw(10) << className(s.point_class) << std::right << std::setw(7)
          << s.truth << std::setw(11) << s.predicted << std::setw(11) << s.precision << std::setw(8)
          << s.recall << std::setw(7) << s.iou << "\n";
    }
  }
  const PlaneScore& p = e.planes;
  out << "planes: " << p.matched << " of " << p.truth_planes << " truth planes found (recall "
      << p.recall << "), " << p.result_matched << " of " << p.result_planes
      << " result planes real (precision " << p.precision << "), mean normal error "
      << p.mean_normal_error_deg << " deg, mean offset error " << p.mean_offset_error_m << " m\n";
  if (e.has_map) {
    out << "map: " << e.map.traversable_cells << " traversable cells, "
        << e.map.false_traversable_cells
        << " where the robot cannot truly stand (false-traversable rate "
        << e.map.false_traversable_rate << ")\n";
    for (const Eigen::Vector3d& w : e.map.false_cells)
      out << "  false traversable at world (" << w.x() << ", " << w.y() << ", " << w.z() << ")\n";
    for (const PlaceCheck& c : e.map.places)
      out << "  " << c.from << " -> " << c.to << ": expected "
          << (c.expected ? "reachable" : "unreachable") << ", map says "
          << (c.found ? "reachable" : "unreachable")
          << (c.expected == c.found ? "" : (c.found ? "  <-- UNSAFE" : "  <-- missed")) << "\n";
  }
  return out.str();
}

std::string toJson(const Evaluation& e) {
  nlohmann::ordered_json json;
  if (e.has_point_classes) {
    for (const ClassScore& s : e.classes) {
      if (s.point_class == PointClass::kNone) continue;
      json["classes"][std::string(className(s.point_class))] = {{"truth", s.truth},
                                                                {"predicted", s.predicted},
                                                                {"precision", s.precision},
                                                                {"recall", s.recall},
                                                                {"iou", s.iou}};
    }
  }
  const PlaneScore& p = e.planes;
  json["planes"] = {{"truth_planes", p.truth_planes},
                    {"matched", p.matched},
                    {"result_planes", p.result_planes},
                    {"result_matched", p.result_matched},
                    {"recall", p.recall},
                    {"precision", p.precision},
                    {"mean_normal_error_deg", p.mean_normal_error_deg},
                    {"mean_offset_error_m", p.mean_offset_error_m}};
  if (e.has_map) {
    json["map"] = {{"traversable_cells", e.map.traversable_cells},
                   {"false_traversable_cells", e.map.false_traversable_cells},
                   {"false_traversable_rate", e.map.false_traversable_rate}};
    auto places = nlohmann::ordered_json::array();
    for (const PlaceCheck& c : e.map.places)
      places.push_back(
          {{"from", c.from}, {"to", c.to}, {"expected", c.expected}, {"found", c.found}});
    json["map"]["places"] = places;
  }
  return json.dump(2);
}

}  // namespace clearway::eval
