// Ground triangles between neighbouring scan lines (docs/ALGORITHM.md, section 5): the step a
// triangle joins or spans, and which triangles join ground over the lines LinePairing pairs.

#include "ground_triangles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "clearway/segmentation/scan_analysis.h"
#include "parallel.h"
#include "release_memory.h"

namespace clearway::detail {

double EdgeLimit::joinedStep(const std::vector<std::int32_t>& ground_of, std::size_t a,
                             std::size_t b, std::size_t c) const {
  const std::int32_t g = ground_of[a];
  const bool one_plane = ground_of[b] == g && ground_of[c] == g;
  const bool off_plane = !continued.empty() && (continued[a] || continued[b] || continued[c]);
  if (one_plane && !off_plane) return 0.0;
  const float za = mapped[a].z(), zb = mapped[b].z(), zc = mapped[c].z();
  const double step = std::max({za, zb, zc}) - std::min({za, zb, zc});
  if (step <= kTouchingStep || plane_heights.empty() || one_plane)
    return step + kJoinedStepUncertainty;
  const Eigen::Vector2d centre =
      ((mapped[a] + mapped[b] + mapped[c]) / 3.0F).head<2>().cast<double>();
  double lowest = std::numeric_limits<double>::max(),
         highest = std::numeric_limits<double>::lowest();
  for (const std::int32_t plane : {ground_of[a], ground_of[b], ground_of[c]}) {
    const double z = heightOnPlane(plane_heights[std::size_t(plane)], centre.x(), centre.y());
    if (!std::isfinite(z)) return std::numeric_limits<double>::infinity();
    lowest = std::min(lowest, z);
    highest = std::max(highest, z);
  }
  return std::max(step, highest - lowest) + kJoinedStepUncertainty;
}

double EdgeLimit::spannedStep(const std::vector<std::int32_t>& ground_of, std::size_t a,
                              std::size_t b, std::size_t c) const {
  const std::int32_t g = ground_of[a];
  if (plane_heights.empty() || ground_of[b] != g || ground_of[c] != g) return 0.0;
  if (!continued.empty() && (continued[a] || continued[b] || continued[c])) return 0.0;
  const std::array<const Eigen::Vector3f*, 3> corners = {&mapped[a], &mapped[b], &mapped[c]};
  const double longest_squared = std::max({(*corners[0] - *corners[1]).head<2>().squaredNorm(),
                                           (*corners[1] - *corners[2]).head<2>().squaredNorm(),
                                           (*corners[0] - *corners[2]).head<2>().squaredNorm()});
  if (longest_squared <= kStepRunLength * kStepRunLength) return 0.0;
  // However far apart the samples lie: no beam saw the ground between two neighbouring returns
  // either, and a drop deeper than the robot's step between them may be a step anywhere in
  // between. (Triangles no longer than two samples' spacing once spanned nothing: where two
  // paving slabs' joint fell 5-7 cm away from the scanner over one spacing, a robot taking 5 cm
  // steps was shown green across it, 34 cells in one randomised run.)
  std::array<double, 3> range_squared;  // from the scanner (the map's origin), horizontally
  for (std::size_t i = 0; i < 3; ++i)
    range_squared[i] = corners[i]->head<2>().squaredNorm();
  // How far a corner farther from the scanner lies below a nearer one, about the plane: a drop
  // away from the scanner hides in its own shadow, while a rise towards it is seen (its face's
  // returns) and a rise away from it is seen on its slope.
  const Eigen::Vector3d& plane = plane_heights[std::size_t(g)];
  std::array<double, 3> off_plane;
  for (std::size_t i = 0; i < 3; ++i)
    off_plane[i] = double(corners[i]->z()) - heightOnPlane(plane, corners[i]->x(), corners[i]->y());
  double drop = 0.0;
  for (std::size_t near = 0; near < 3; ++near)
    for (std::size_t far = 0; far < 3; ++far)
      if (range_squared[far] > range_squared[near])
        drop = std::max(drop, off_plane[near] - off_plane[far]);
  return std::isfinite(drop) ? drop : 0.0;
}

// Ragged rings (a file that keeps only the returns): two neighbouring returns of a ring and the
// nearest return of the next ring span up to about one and a half of the sensor's steps in
// azimuth (its returns jitter a fraction of a step); a triangle spanning more than
// kNeighbourRingSpan steps has its rings' gaps looked up (it may bridge lost returns, or pair a
// return stored out of azimuth order, whose ring's other returns fill the span: a frame corrected
// for the vehicle's motion has hundreds, up to 6 deg back). A gap wider than kWidestRingGap steps
// lost more than kLostReturnsBridged returns in a row, as an obstacle that returns nothing does.
constexpr double kNeighbourRingSpan = 1.75;
constexpr double kWidestRingGap = double(kLostReturnsBridged) + 1.5;

std::vector<std::array<std::uint32_t, 3>> groundTriangles(
    const Scan& scan, const LinePairing& pairing, const std::vector<std::int32_t>& ground_of,
    const EdgeLimit& limit, int threads, SweepPartners* sweep_partners,
    std::vector<BridgedTriangle>* bridged) {
  std::vector<std::array<std::uint32_t, 3>> triangles;
  auto squaredDistance = [&](std::size_t a, std::size_t b) {
    const Point3f& p = scan.points[a];
    const Point3f& q = scan.points[b];
    const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
    return dx * dx + dy * dy + dz * dz;
  };
  const double fixed_edge_squared = limit.fixed * limit.fixed;
  // A triangle joins two lines. A rotating scanner's fans are paired from the one before (its
  // corner sets the limit, as it always has); two rings are paired in whatever order the file
  // keeps them (KITTI's top down, a ROS driver's bottom up), so the limit is the farthest
  // corner's, the ring whose spacing the edges between the two rings span: the same triangles
  // either way (KITTI 000002 with its rings bottom up showed 81,330 traversable cells against
  // 86,289 as stored).
  const bool rings = pairing.multiBeam();
  auto edgeLimitSquared = [&](std::size_t a, std::size_t b, std::size_t c) {
    if (!rings) return limit.maxEdgeSquared(a);
    return std::max({limit.maxEdgeSquared(a), limit.maxEdgeSquared(b), limit.maxEdgeSquared(c)});
  };
  // Always inlined: called from two loops, the compiler kept it out of line, and every quad of a
  // line without lost returns paid two calls (groundTriangles +13 % instructions on the garage).
  auto add = [&](std::vector<std::array<std::uint32_t, 3>> & out, std::size_t a, std::size_t b,
                 std::size_t c) __attribute__((always_inline)) {
    const std::int32_t g = ground_of[a];
    if (g < 0 || ground_of[b] < 0 || ground_of[c] < 0) return false;
    // Ground of two planes joins only where the two meet with no more than the robot's step.
    if (limit.joinedStep(ground_of, a, b, c) > limit.largest_seam_step) return false;
    // The limit is never below the fixed one: only a longer edge needs the range's.
    const double longest =
        std::max({squaredDistance(a, b), squaredDistance(b, c), squaredDistance(a, c)});
    if (longest > fixed_edge_squared && longest > edgeLimitSquared(a, b, c)) return false;
    out.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
    return true;
  };
  // A lost return stands in the triangles as the nearer of the two returns around it on its line
  // (its stand-in), where at most kLostReturnsBridged were lost in a row; `lost`: how many. A
  // triangle with two corners on one stand-in is no triangle; its neighbours cover the gap. Not a
  // self-hit: the robot's own body hid the ground there.
  struct Corner {
    std::size_t point;
    std::size_t lost;
  };
  auto lostReturn = [&](std::size_t i) {
    const PointStatus status = scan.status[i];
    return status == PointStatus::kNoReturn || status == PointStatus::kMaxRange;
  };
  // Whether a line holds a lost return at all: most lines of most scans do not, and their pairs
  // are triangulated without stand-ins (one pass over the statuses, not four looks per quad).
  auto anyLost = [&](const ScanLine& line) {
    bool lost = false;
    for (std::size_t i = line.first; i < line.first + line.count; ++i)
      lost |= lostReturn(i);
    return lost;
  };
  auto standIn = [&](const ScanLine& line, std::size_t i) -> Corner {
    if (!lostReturn(i)) return {i, 0};
    std::size_t first = i, last = i;  // the run of lost returns around i
    while (first > line.first && lostReturn(first - 1) && i - first < kLostReturnsBridged)
      --first;
    while (last + 1 < line.first + line.count && lostReturn(last + 1) &&
           last - i < kLostReturnsBridged)
      ++last;
    if (first == line.first || last + 1 == line.first + line.count) return {i, 0};
    const std::size_t before = first - 1, after = last + 1;
    if (!scan.isValid(before) || !scan.isValid(after) || last - first + 1 > kLostReturnsBridged)
      return {i, 0};
    return {i - before <= after - i ? before : after, last - first + 1};
  };
  const std::size_t pairs = pairing.pairs();
  // The ground is uneven along the turn (a wall close by on one side, open floor on the other):
  // several parts per thread keep both threads busy to the end.
  constexpr std::size_t kPartsPerThread = 4;
  detail::PerPart<std::vector<std::array<std::uint32_t, 3>>> parts(
      detail::chunkCount(pairs, threads, kPartsPerThread));
  // The bridging triangles per part, as `parts`.
  detail::PerPart<std::vector<BridgedTriangle>> bridged_parts(bridged ? parts.size() : 0);
  // Along ragged rings, how many of the sensor's steps apart the samples under a triangle of
  // `line` and `other` lie (1 to kLostReturnsBridged + 1), or 0 where it would bridge more lost
  // returns in a row: the widest gap between azimuth neighbours of either ring across the
  // corners' azimuths.
  const double ring_step = limit.sensor.along_line_step;
  const bool ragged_rings = pairing.raggedRings() && ring_step > 0.0;
  auto ringStepsApart = [&](const ScanLine& line, const ScanLine& other, std::size_t a,
                            std::size_t b, std::size_t c) -> std::size_t {
    const double azimuths[] = {pairing.azimuth(a), pairing.azimuth(b), pairing.azimuth(c)};
    const auto [low, high] = std::minmax_element(std::begin(azimuths), std::end(azimuths));
    if (*high - *low <= kNeighbourRingSpan * ring_step) return 1;
    const double widest_allowed = kWidestRingGap * ring_step;
    const double widest = std::max(pairing.widestGap(line, *low, *high, widest_allowed),
                                   pairing.widestGap(other, *low, *high, widest_allowed));
    if (widest > widest_allowed) return 0;
    return std::clamp<std::size_t>(std::size_t(std::lround(widest / ring_step)), 1,
                                   kLostReturnsBridged + 1);
  };
  // Adds the triangle with `steps_apart` (at least that many along its lines), where it may be
  // made: along ragged rings, only where it bridges no more than kLostReturnsBridged in a row.
  auto addApart = [&](std::size_t chunk, const ScanLine& line, const ScanLine& other, std::size_t a,
                      std::size_t b, std::size_t c, std::size_t steps_apart) {
    if (ragged_rings) {
      if (ground_of[a] < 0 || ground_of[b] < 0 || ground_of[c] < 0) return;
      const std::size_t along_rings = ringStepsApart(line, other, a, b, c);
      if (along_rings == 0) return;
      steps_apart = std::max(steps_apart, along_rings);
    }
    if (!add(parts[chunk], a, b, c)) return;
    if (steps_apart > 1 && bridged)
      bridged_parts[chunk].push_back({parts[chunk].back(), std::uint8_t(steps_apart)});
  };
  // Out of line, so that `add` stays inlined in the loop over lines that lost nothing.
  auto addCorners = [&](std::size_t chunk, const ScanLine& line, const ScanLine& other,
                        const Corner& a, const Corner& b, const Corner& c)
      __attribute__((noinline)) {
    if (a.point == b.point || b.point == c.point || a.point == c.point) return;
    addApart(chunk, line, other, a.point, b.point, c.point, std::max({a.lost, b.lost, c.lost}) + 1);
  };
  // A multi-beam frame sweeps along its rings, a fraction of a degree between returns: no partners.
  const bool across_lines = sweep_partners && !rings;
  if (across_lines)
    sweep_partners->partners.assign(sweep_partners->points().size(), {kNoPartner, kNoPartner});
  // Each chosen point of a line with its entry, walking `points` beside the line.
  auto forChosen = [&](const ScanLine& line, auto&& visit) {
    const std::vector<std::uint32_t>& chosen = sweep_partners->points();
    auto it = std::lower_bound(chosen.begin(), chosen.end(), line.first);
    for (; it != chosen.end() && *it < line.first + line.count; ++it)
      visit(std::size_t(*it - line.first), std::size_t(it - chosen.begin()));
  };
  detail::parallelChunks(
      pairs, threads,
      [&](std::size_t begin, std::size_t end, std::size_t chunk) {
        // Room for the most a part can make, two triangles per quad of its lines: a dense scan's
        // parts grown by doubling held up to twice their triangles at the run's memory peak. The
        // room never filled is never touched, so it costs address space, not memory.
        std::size_t most = 0;
        for (std::size_t l = begin; l < end; ++l)
          most += 2 * pairing.before(l).count;
        parts[chunk].reserve(most);
        std::vector<std::size_t> partners;
        for (std::size_t l = begin; l < end; ++l) {
          const ScanLine& a = pairing.before(l);
          const ScanLine& b = pairing.after(l);
          if (a.count == 0 || b.count == 0) continue;
          pairing.partners(a, b, partners);
          if (anyLost(a) || anyLost(b)) {
            for (std::size_t k = 0; k + 1 < a.count; ++k) {
              const Corner a0 = standIn(a, a.first + k), a1 = standIn(a, a.first + k + 1);
              const Corner b0 = standIn(b, partners[k]), b1 = standIn(b, partners[k + 1]);
              addCorners(chunk, a, b, a0, a1, b0);
              addCorners(chunk, a, b, a1, b1, b0);
            }
          } else if (ragged_rings) {
            for (std::size_t k = 0; k + 1 < a.count; ++k) {
              const std::size_t a0 = a.first + k, a1 = a0 + 1;
              const std::size_t b0 = partners[k], b1 = partners[k + 1];
              addApart(chunk, a, b, a0, a1, b0, 1);
              if (b1 != b0) addApart(chunk, a, b, a1, b1, b0, 1);
            }
          } else {
            for (std::size_t k = 0; k + 1 < a.count; ++k) {
              const std::size_t a0 = a.first + k, a1 = a0 + 1;
              const std::size_t b0 = partners[k], b1 = partners[k + 1];
              add(parts[chunk], a0, a1, b0);
              if (b1 != b0) add(parts[chunk], a1, b1, b0);
            }
          }
          if (!across_lines) continue;
          // Each pair of lines writes the after-partners of a's points and the
          // before-partners of b's: no element is written twice.
          forChosen(a, [&](std::size_t k, std::size_t entry) {
            sweep_partners->partners[entry][1] = std::uint32_t(partners[k]);
          });
          pairing.partners(b, a, partners);
          forChosen(b, [&](std::size_t k, std::size_t entry) {
            sweep_partners->partners[entry][0] = std::uint32_t(partners[k]);
          });
        }
      },
      kPartsPerThread);
  if (bridged)
    for (const auto& part : bridged_parts)
      bridged->insert(bridged->end(), part.begin(), part.end());
  if (parts.size() == 1) return std::move(parts.front());
  std::size_t total = 0;
  for (const auto& part : parts)
    total += part.size();
  triangles.reserve(total);
  for (auto& part : parts) {
    triangles.insert(triangles.end(), part.begin(), part.end());
    releaseMemory(part);  // as it is copied: the mesh is the largest thing a dense scan's map keeps
  }
  return triangles;
}

}  // namespace clearway::detail
