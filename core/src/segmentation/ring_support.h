#pragma once
// A multi-beam sensor samples a surface ring by ring: densely along each ring (a fraction of a
// degree of azimuth), sparsely from one ring to the next (0.4 deg for an HDL-64E, 1.33 deg for an
// HDL-32E, 2 deg for a VLP-16). On a plane's support image (0.2 m cells) the rings are thin arcs
// that the validation's opening (which removes a phantom plane's thin strips) takes away once the
// rings lie more than a cell apart: a VLP-16's road, 0.5 m and more between rings, had no supported
// area at all. Where two neighbouring rings both support the plane at the same azimuth, the
// surface between them is that plane (the same inference as the ground triangles across lines), so
// the cells on the segment between the two returns count as supported. A phantom plane cuts each
// ring at a different azimuth and gets no such segments, or only thin ones along its cut.

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "clearway/scan.h"
#include "clearway/segmentation/planes.h"

namespace clearway::detail {

// For each return, the return of the next ring up that faces it: nearest in azimuth, within
// kFacingSteps azimuth steps, however far away (each use asks its own distance: the support
// between rings, the ground followed outward). Worked out once per frame.
struct RingLayout {
  static constexpr std::uint32_t kNone = 0xffffffffU;
  std::vector<std::uint32_t> facing;  // per point; kNone where no return faces it
  bool empty() const { return facing.empty(); }
};

// The layout of the lines `rings_by_elevation` (indices into scan.lines, lowest first), whose
// returns lie `azimuth_step` apart along each ring.
RingLayout ringLayout(const Scan& scan, const std::vector<std::size_t>& rings_by_elevation,
                      double azimuth_step, int threads);

// Where a plane's support image lies: a point p is at uv = ((p - centre) . u_axis,
// (p - centre) . v_axis), and cells of `cell` metres start at `uv0`.
struct SupportFrame {
  Eigen::Vector3d centre, u_axis, v_axis;
  Eigen::Vector2d uv0;
  double cell = 0.0;
};

// Raises to `min_count` the `counts` (CV_16U, the support image) of the cells on the segment from
// each point of `support` (at `uv`) to the return facing it on the next ring up, when that return
// lies more than `min_gap` and at most `max_gap` away (two returns a support cell apart or less
// leave no cell between their own) and in the plane's support band too:
// |normal . p - offset| <= tolerance + per_metre x range.
void supportBetweenRings(const Scan& scan, const RingLayout& layout, double min_gap, double max_gap,
                         const Plane& plane, double tolerance, double per_metre,
                         const std::vector<std::uint32_t>& support,
                         const std::vector<Eigen::Vector2d>& uv, const SupportFrame& frame,
                         cv::Mat& counts, int min_count);

}  // namespace clearway::detail
