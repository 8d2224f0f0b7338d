#include "clearway/eval/segmentation_accuracy.h"

#include <stdexcept>
#include <string>
#include <unordered_map>

namespace clearway::eval {

PointPlanes pointPlanesOf(const ScanAnalysis& analysis) {
  PointPlanes result;
  for (const Plane& plane : analysis.planes.planes)
    result.planes.push_back({plane.normal, plane.offset, planeKindName(plane.kind)});
  result.point_plane = analysis.planes.point_plane;
  return result;
}

SegmentationAccuracy scoreSegmentation(const sim::GroundTruth& truth, const PointPlanes& result,
                                       const EvaluationOptions& options) {
  if (result.point_plane.size() != truth.surfaces.size())
    throw std::invalid_argument("the segmentation labels " +
                                std::to_string(result.point_plane.size()) +
                                " points, the truth has " + std::to_string(truth.surfaces.size()));
  std::unordered_map<int, const sim::SurfaceTruth*> surface_by_id;
  for (const sim::SurfaceTruth& surface : truth.seen_surfaces)
    surface_by_id[surface.id] = &surface;

  // Whether truth surface s lies on result plane k, decided once per pair seen.
  std::unordered_map<std::uint64_t, bool> on_plane;
  auto lies_on = [&](int surface_id, std::int32_t plane) {
    const std::uint64_t key =
        (std::uint64_t(std::uint32_t(surface_id)) << 32) | std::uint32_t(plane);
    const auto known = on_plane.find(key);
    if (known != on_plane.end()) return known->second;
    const auto surface = surface_by_id.find(surface_id);
    double normal_error = 0.0, offset_error = 0.0;
    const bool yes = surface != surface_by_id.end() && surface->second->planar &&
                     planesMatch(*surface->second, result.planes[std::size_t(plane)], options,
                                 normal_error, offset_error);
    on_plane.emplace(key, yes);
    return yes;
  };

  SegmentationAccuracy accuracy;
  accuracy.planes = scorePlanes(truth, result.planes, options);
  std::size_t pure = 0, planar_points = 0, planar_assigned = 0;
  for (std::size_t i = 0; i < truth.surfaces.size(); ++i) {
    const int surface_id = truth.surfaces[i];
    if (surface_id < 0) continue;  // no return
    const auto surface = surface_by_id.find(surface_id);
    const bool planar = surface != surface_by_id.end() && surface->second->planar;
    planar_points += planar;
    const std::int32_t plane = result.point_plane[i];
    if (plane < 0) continue;
    if (std::size_t(plane) >= result.planes.size())
      throw std::invalid_argument("point " + std::to_string(i) + " names plane " +
                                  std::to_string(plane) + " of " +
                                  std::to_string(result.planes.size()));
    ++accuracy.assigned_points;
    planar_assigned += planar;
    pure += lies_on(surface_id, plane);
  }
  accuracy.point_purity =
      accuracy.assigned_points ? double(pure) / double(accuracy.assigned_points) : 0.0;
  accuracy.coverage = planar_points ? double(planar_assigned) / double(planar_points) : 0.0;
  return accuracy;
}

}  // namespace clearway::eval
