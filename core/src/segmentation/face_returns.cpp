#include "face_returns.h"

#include <cmath>

#include "clearway/segmentation/scan_analysis.h"

namespace clearway::detail {

std::size_t dropFaceReturns(std::vector<std::int32_t>& ground_of, const Scan& scan,
                            const std::vector<Eigen::Vector3f>& mapped,
                            const std::vector<Eigen::Vector3d>& plane_heights,
                            const FaceReturnLimits& limits) {
  auto raisedAbovePlane = [&](std::size_t i) {
    const std::int32_t plane = ground_of[i];
    if (plane < 0 || std::size_t(plane) >= plane_heights.size()) return false;
    const Eigen::Vector3f& p = mapped[i];
    const double z = heightOnPlane(plane_heights[std::size_t(plane)], double(p.x()), double(p.y()));
    return std::isfinite(z) && double(p.z()) - z > double(limits.raised);
  };
  const float reach_squared = limits.reach * limits.reach;
  std::vector<std::uint8_t> face(scan.size(), 0);
  // From `source`, the last return of the line that is not ground, the walk goes on over the
  // ground returns within reach of it; a face's returns in the ground's band stay below it, not
  // each below the one before: they scatter by the range noise as they come down.
  auto walk = [&](std::size_t i, std::size_t& source, bool& on_face) {
    if (!scan.isValid(i)) {
      on_face = false;  // nothing known between the returns either side
      return;
    }
    if (ground_of[i] < 0) {
      source = i;
      on_face = true;
      return;
    }
    const Eigen::Vector3f& p = mapped[i];
    const Eigen::Vector3f& top = mapped[source];
    if (on_face && p.z() < top.z() &&
        (p.head<2>() - top.head<2>()).squaredNorm() <= reach_squared && raisedAbovePlane(i)) {
      face[i] = 1;
      return;
    }
    on_face = false;
  };
  for (const ScanLine& line : scan.lines) {
    const std::size_t end = line.first + line.count;
    std::size_t source = 0;
    bool on_face = false;
    for (std::size_t i = line.first; i < end; ++i)
      walk(i, source, on_face);
    on_face = false;
    for (std::size_t i = end; i-- > line.first;)
      walk(i, source, on_face);
  }
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < face.size(); ++i)
    if (face[i]) {
      ground_of[i] = -1;
      ++dropped;
    }
  return dropped;
}

}  // namespace clearway::detail
