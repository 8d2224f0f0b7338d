#pragma once

// Ground triangles between neighbouring scan lines whose three corners are ground of the same
// plane (or of planes meeting without a step) and close together: they cover sampling gaps but
// cannot bridge a shadow, because inside a shadow the neighbouring beam hit the obstacle, not the
// ground (docs/ALGORITHM.md, section 5).

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "clearway/scan.h"
#include "clearway/sensor_geometry.h"
#include "line_pairing.h"

namespace clearway::detail {

// The longest triangle edge allowed near a point: the fixed limit, or where the scan is sparser
// (far ground), a few times the spacing the sensor's angular steps give at that range. Whether an
// obstacle could hide in such a triangle is the density check's question (cell_classes.cpp).
struct EdgeLimit {
  const std::vector<Eigen::Vector3f>& mapped;
  const SensorGeometry& sensor;
  double fixed = 1.0;
  double scanner_height = 1.0;
  // Triangles whose corners lie on different ground planes join them only where the step between
  // them (joinedStep) is at most this much [m]: the robot's step. The outdoor ground is several
  // planes that touch (a paving's slight bends), or meet at a low kerb whose face the beams passed
  // over; a stair's treads are too high to join. The map keeps the step each joining triangle
  // spans (MapInputs::seam_step), so a robot with a smaller step is still stopped there.
  double largest_seam_step = 0.05;
  // Per plane (index into the validated planes): its map height coefficients (heightOnPlane());
  // NaN for planes that are not ground. Empty: corners' heights only.
  std::vector<Eigen::Vector3d> plane_heights = {};
  // Per point, true where it is ground no plane took in (continueGround): it may lie up to a step
  // off its plane, so a triangle with such a corner joins as two planes do. Empty: none.
  std::vector<bool> continued = {};

  // The step a triangle of ground points `a`, `b`, `c` (planes `ground_of`) spans between two
  // ground planes, 0 when all three lie on one: its corners' height range where that is at most
  // kTouchingStep (the planes touch there), above it also at least the planes' height difference
  // at its centre (two tilted slabs meet with a step that their samples a few centimetres from the
  // joint understate; the planes, fitted to many points, give it at the joint); a triangle with a
  // corner that continues its plane (`continued`) spans its corners' range. Far from where two
  // planes touch their extrapolated heights part, so they are not asked where the samples agree.
  // Either is measured to about 2 cm (1 cm range noise either side; a plane fitted over paving
  // slabs tilted against each other is a centimetre off at their joint), which is added: without
  // it, slabs meeting 0.11 m apart were joined for a 0.1 m step (scripts/variant-sweep, the
  // outdoor scene tilted 35 deg).
  double joinedStep(const std::vector<std::int32_t>& ground_of, std::size_t a, std::size_t b,
                    std::size_t c) const;
  static constexpr double kTouchingStep = 0.05;
  static constexpr double kJoinedStepUncertainty = 0.02;
  // The step a triangle of ground points `a`, `b`, `c` of one plane may hide: how far, about the
  // plane (its own slope is no step), a corner farther from the scanner lies below a nearer one,
  // where its longest edge is longer than kStepRunLength (scan_analysis.h); 0 for a shorter
  // triangle (the cells' step rule compares heights over such runs) and for one joining planes
  // (joinedStep). Behind a drop away from the scanner the ground lies in the drop's shadow: a long
  // triangle bridges it from the edge to the first return beyond, and a drop just deeper than the
  // robot's step became a gentle slope. Ground rising away from the scanner is seen on its slope.
  double spannedStep(const std::vector<std::int32_t>& ground_of, std::size_t a, std::size_t b,
                     std::size_t c) const;
  double maxEdgeSquared(std::size_t point) const {
    const double range = double(mapped[point].head<2>().norm());
    const double spacing = expectedGroundSpacing(sensor, range, scanner_height);
    const double edge = std::max(fixed, kSpacingsPerEdge * std::min(spacing, kLongestEdge));
    return edge * edge;
  }
  // Two samples' worth of slack: a beam lost between neighbours still closes the triangle.
  static constexpr double kSpacingsPerEdge = 2.0;
  // However sparse the scan, no triangle edge is longer than this [m].
  static constexpr double kLongestEdge = 5.0;
};

// A scanner "at ground level" (files whose origin is on the floor) still sees the ground at a
// grazing angle; its spacing is worked out for at least this height [m].
inline constexpr double kLowestScannerHeight = 0.3;

// The partners across the sweep (on the lines either side, before and after: the points the
// ground triangles pair them with) of chosen points, `points` (ascending scan indices). kNoPartner
// where there is no such line (the ends of a partial turn, a fan left out); `partners` stays empty
// for a multi-beam frame.
inline constexpr std::uint32_t kNoPartner = 0xFFFFFFFFU;
class SweepPartners {
 public:
  // `points`: ascending scan indices, all below `scan_size`.
  SweepPartners(std::vector<std::uint32_t> points, std::size_t scan_size)
      : points_(std::move(points)), bits_((scan_size + 63) / 64, 0), rank_(bits_.size(), 0) {
    for (const std::uint32_t point : points_)
      bits_[point / 64] |= std::uint64_t{1} << (point % 64);
    std::uint32_t before = 0;
    for (std::size_t word = 0; word < bits_.size(); ++word) {
      rank_[word] = before;
      before += std::uint32_t(std::popcount(bits_[word]));
    }
  }
  const std::vector<std::uint32_t>& points() const { return points_; }
  // The entry of scan point `point` in points(), or kNoPartner: a bit per scan point and a count
  // per 64 of them (no search, a fiftieth of a per-point index's memory).
  std::uint32_t entryOf(std::size_t point) const {
    const std::uint64_t word = bits_[point / 64], bit = std::uint64_t{1} << (point % 64);
    if (!(word & bit)) return kNoPartner;
    return rank_[point / 64] + std::uint32_t(std::popcount(word & (bit - 1)));
  }
  // Per entry of points(): its partners before and after; empty when none were looked for.
  std::vector<std::array<std::uint32_t, 2>> partners;

 private:
  std::vector<std::uint32_t> points_;
  std::vector<std::uint64_t> bits_;
  std::vector<std::uint32_t> rank_;
};

// Returns the scanner lost (no echo, or a saturated range: dark or wet ground, a puddle, dust) at
// most this many in a row between two returns of their line are bridged: the triangles join the
// returns either side, as if the lost ones were not in the file. A longer run is unobserved (a
// black obstacle would lose that many). Real scans lose returns everywhere: with a fifth of
// Hannover's lost at random, the ground triangles kept about one in two, and 0.3 % and 0.03 % of
// the campus's open floor showed green or orange.
inline constexpr std::size_t kLostReturnsBridged = 2;

// A ground triangle whose corners lie farther apart along their line than the sensor's step,
// because it bridges lost returns: its corners, and how many of the sensor's steps along the line
// its samples are apart there (2 or 3). The density check counts that spacing under it.
struct BridgedTriangle {
  std::array<std::uint32_t, 3> corners;
  std::uint8_t steps_apart;
};

// The triangles (scan point indices) over the ground points (`ground_of`: plane per point, -1 not
// ground) between the lines `pairing` pairs, over up to kLostReturnsBridged lost returns in a row
// (those triangles also in `bridged`, when given). With `partners`, also the partners across the
// sweep of its `points` (a rotating scanner's neighbouring lines).
std::vector<std::array<std::uint32_t, 3>> groundTriangles(
    const Scan& scan, const LinePairing& pairing, const std::vector<std::int32_t>& ground_of,
    const EdgeLimit& limit, int threads, SweepPartners* partners = nullptr,
    std::vector<BridgedTriangle>* bridged = nullptr);

}  // namespace clearway::detail
