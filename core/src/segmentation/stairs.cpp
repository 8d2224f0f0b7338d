// Stair detection (docs/ALGORITHM.md, 4b). Scanner-agnostic: it looks at the scan's points
// in the map frame, not at how the scan lines cross the flight, so it works for the RoSi's vertical
// fans and for a nodding scanner's near-horizontal ones alike.
//
// 1. A height grid of every valid point: per cell the lowest point, the highest point within a
//    riser's height of it, and whether something taller stands there (a wall, a post).
// 2. Riser cells: a vertical extent between half the lowest riser and the highest riser, nothing
//    taller. Seen from below, the top of a riser (the nosing) is always visible, its foot often
//    not (hidden by the step in front), so the top is what a riser is known by.
// 3. Risers: 8-connected riser cells with the same top height, pieces of one riser (split by a
//    handrail post) joined, fitted as lines through the riser faces' points; short ones dropped.
// 4. Flights: from each riser the nearest parallel, overlapping riser ahead must be one tread on
//    and one rise up, and what is seen of the strip between them must be near-horizontal (a
//    tread); chains of at least min_steps risers are staircases. On a ramp the nearest "riser"
//    ahead is a cell or two away and the surface between climbs, so a ramp is no staircase.
// 5. Rise and tread are the slopes of the risers' tops and offsets against their index.

#include "clearway/segmentation/stairs.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <queue>

namespace clearway {
namespace {

// Cells of one riser agree on its top within this (range noise, a leaning nosing) [m].
constexpr double kHeightTolerance = 0.04;
// Seen from below, at least this share of the lowest riser shows above the step in front of it.
constexpr double kMinVisibleRiseShare = 0.5;
// Something more than a riser and less than this above a cell's lowest point is a wall or a post,
// not a step; higher things (a handrail, a ceiling) do not matter [m].
constexpr double kTallHeight = 0.5;
// Risers are parallel within this angle [deg].
constexpr double kMaxRiserAngleDeg = 15.0;
// Pieces of one riser may be this far apart along it (a handrail post between them) [m].
constexpr double kMaxRiserGap = 0.5;
// Neighbouring risers overlap along their length by at least this share of the shorter one.
constexpr double kMinOverlapShare = 0.5;
// Risers closer than this along their normal are the same line, not a step apart [m].
constexpr double kSameOffset = 0.03;
// The tread between two risers is looked at this far from both of them and from their ends [m].
constexpr double kStripInset = 0.05;
// A tread shows at least this many points, spread at least this much along the flight [m], or it
// is taken as unseen.
constexpr double kMinTreadPoints = 8;
constexpr double kMinTreadSpread = 0.02;
// Treads are near-horizontal: steeper than this between two risers is a ramp [deg].
constexpr double kMaxTreadSlopeDeg = 10.0;
// The height grid never grows beyond this many cells (the search area shrinks around the scanner).
constexpr std::size_t kMaxGridCells = 8'000'000;
// A riser's face is the middle of its cell's vertical extent: this share at the foot may be the
// tread in front, the same share at the top the nosing's rounded edge.
constexpr float kFaceEndShare = 0.25F;
// A cell needs two points to have a vertical extent at all.
constexpr std::uint32_t kMinRiserCellPoints = 2;
// A riser line is fitted through at least two cells' faces: one gives no direction.
constexpr std::size_t kMinRiserCells = 2;

struct HeightCell {
  float lowest = std::numeric_limits<float>::infinity();
  float top = -std::numeric_limits<float>::infinity();  // highest point within a riser of lowest
  std::uint32_t count = 0;
  bool tall = false;
  // Points on the riser face (the middle of the cell's vertical extent), for the face's position.
  float face_x = 0.0F, face_y = 0.0F;
  std::uint32_t face_count = 0;
};

struct Riser {
  std::vector<std::uint32_t> cells;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d along = Eigen::Vector2d::UnitX();  // unit, along the riser
  Eigen::Vector2d normal = Eigen::Vector2d::UnitY();
  double from = 0.0, to = 0.0;  // extent along `along`, relative to centre [m]
  double top = 0.0;             // median top of its cells [m]
  double thickness = 0.0;       // RMS distance of the face points from the fitted line [m]

  double length() const { return to - from; }
};

class HeightGrid {
 public:
  HeightGrid(const Scan& scan, const Eigen::Isometry3d& map_from_scanner, const StairParams& params)
      : cell_(params.cell_size) {
    // The points within reach of the scanner, and the box they span.
    const Eigen::Matrix3f rotation = map_from_scanner.linear().cast<float>();
    const Eigen::Vector3f translation = map_from_scanner.translation().cast<float>();
    const Eigen::Vector2f scanner = translation.head<2>();
    double reach = params.max_distance;
    // Shrink the search area when the grid could grow too large.
    if (std::pow(2 * reach / cell_, 2) > double(kMaxGridCells))
      reach = std::sqrt(double(kMaxGridCells)) * cell_ / 2;
    points_.reserve(scan.validCount());
    Eigen::AlignedBox2f box;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!scan.isValid(i)) continue;
      const Point3f& p = scan.points[i];
      // Floats: within the search distance they keep better than 0.1 mm.
      const Eigen::Vector3f m = rotation * Eigen::Vector3f(p.x, p.y, p.z) + translation;
      if ((m.head<2>() - scanner).cwiseAbs().maxCoeff() > float(reach)) continue;
      box.extend(m.head<2>());
      points_.push_back({0, m.x(), m.y(), m.z()});
    }
    if (box.isEmpty()) return;
    origin_ = box.min().cast<double>();
    width_ = int(std::floor((double(box.max().x()) - origin_.x()) / cell_)) + 1;
    height_ = int(std::floor((double(box.max().y()) - origin_.y()) / cell_)) + 1;
    cells_.resize(std::size_t(width_) * std::size_t(height_));
    for (MapPoint& p : points_) {
      const int column = std::min(int((p.x - origin_.x()) / cell_), width_ - 1);
      const int row = std::min(int((p.y - origin_.y()) / cell_), height_ - 1);
      p.cell = std::uint32_t(row * width_ + column);
      HeightCell& c = cells_[p.cell];
      c.lowest = std::min(c.lowest, p.z);
      ++c.count;
    }
    const float riser_reach = float(params.max_rise + kHeightTolerance);
    for (const MapPoint& p : points_) {
      HeightCell& c = cells_[p.cell];
      const float above = p.z - c.lowest;
      if (above <= riser_reach)
        c.top = std::max(c.top, p.z);
      else if (above <= float(kTallHeight))
        c.tall = true;
    }
    for (const MapPoint& p : points_) {
      HeightCell& c = cells_[p.cell];
      const float span = c.top - c.lowest;
      if (p.z > c.lowest + kFaceEndShare * span && p.z < c.top - kFaceEndShare * span) {
        c.face_x += p.x;
        c.face_y += p.y;
        ++c.face_count;
      }
    }
  }

  // Sorts the points by cell (CSR), for looking at the surface between two risers (forPointsIn):
  // only where there are two risers to look between.
  void sortPointsByCell() {
    cell_start_.assign(cells_.size() + 1, 0);
    for (std::size_t cell = 0; cell < cells_.size(); ++cell)
      cell_start_[cell + 1] = cell_start_[cell] + cells_[cell].count;
    std::vector<MapPoint> sorted(points_.size());
    std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (const MapPoint& p : points_)
      sorted[fill[p.cell]++] = p;
    points_ = std::move(sorted);
  }

  // Calls visit(x, y, z) for every point in the cells the box touches (once sortPointsByCell()).
  template <typename Visit>
  void forPointsIn(const Eigen::AlignedBox2d& box, Visit visit) const {
    if (cells_.empty() || cell_start_.empty()) return;
    const int c0 = std::max(0, int(std::floor((box.min().x() - origin_.x()) / cell_)));
    const int r0 = std::max(0, int(std::floor((box.min().y() - origin_.y()) / cell_)));
    const int c1 = std::min(width_ - 1, int(std::floor((box.max().x() - origin_.x()) / cell_)));
    const int r1 = std::min(height_ - 1, int(std::floor((box.max().y() - origin_.y()) / cell_)));
    for (int row = r0; row <= r1; ++row)
      for (int column = c0; column <= c1; ++column) {
        const auto cell = std::size_t(row * width_ + column);
        for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k)
          visit(points_[k].x, points_[k].y, points_[k].z);
      }
  }

  bool isRiserCell(std::uint32_t cell, const StairParams& params) const {
    const HeightCell& c = cells_[cell];
    if (c.count < kMinRiserCellPoints || c.tall || c.face_count == 0) return false;
    const double span = c.top - c.lowest;
    return span >= kMinVisibleRiseShare * params.min_rise &&
           span <= params.max_rise + kHeightTolerance;
  }

  // Riser cells grouped 8-connected with the same top.
  std::vector<std::vector<std::uint32_t>> riserComponents(const StairParams& params) const {
    std::vector<std::uint8_t> riser(cells_.size(), 0);
    for (std::uint32_t cell = 0; cell < cells_.size(); ++cell)
      riser[cell] = isRiserCell(cell, params) ? 1 : 0;
    std::vector<std::vector<std::uint32_t>> components;
    std::queue<std::uint32_t> frontier;
    for (std::uint32_t seed = 0; seed < cells_.size(); ++seed) {
      if (!riser[seed]) continue;
      riser[seed] = 0;
      components.emplace_back();
      frontier.push(seed);
      while (!frontier.empty()) {
        const std::uint32_t cell = frontier.front();
        frontier.pop();
        components.back().push_back(cell);
        const int column = int(cell % std::uint32_t(width_)),
                  row = int(cell / std::uint32_t(width_));
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int c = column + dc, r = row + dr;
            if (c < 0 || r < 0 || c >= width_ || r >= height_) continue;
            const auto next = std::uint32_t(r * width_ + c);
            if (!riser[next] || std::abs(cells_[next].top - cells_[cell].top) > kHeightTolerance)
              continue;
            riser[next] = 0;
            frontier.push(next);
          }
      }
    }
    return components;
  }

  Eigen::Vector2d face(std::uint32_t cell) const {
    const HeightCell& c = cells_[cell];
    return {c.face_x / c.face_count, c.face_y / c.face_count};
  }
  double top(std::uint32_t cell) const { return cells_[cell].top; }
  double cellSize() const { return cell_; }

 private:
  struct MapPoint {
    std::uint32_t cell;
    float x, y, z;
  };
  double cell_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int width_ = 0, height_ = 0;
  std::vector<HeightCell> cells_;
  std::vector<MapPoint> points_;  // sorted by cell once sortPointsByCell() ran
  std::vector<std::uint32_t> cell_start_;
};

// Fits a riser line through the face points of its cells.
Riser fitRiser(const HeightGrid& grid, std::vector<std::uint32_t> cells) {
  Riser riser;
  riser.cells = std::move(cells);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (std::uint32_t cell : riser.cells)
    sum += grid.face(cell);
  riser.centre = sum / double(riser.cells.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (std::uint32_t cell : riser.cells) {
    const Eigen::Vector2d d = grid.face(cell) - riser.centre;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  riser.along = solver.eigenvectors().col(1).normalized();
  riser.normal = Eigen::Vector2d(-riser.along.y(), riser.along.x());
  riser.from = std::numeric_limits<double>::max();
  riser.to = std::numeric_limits<double>::lowest();
  double across = 0.0;
  std::vector<double> tops;
  for (std::uint32_t cell : riser.cells) {
    const Eigen::Vector2d d = grid.face(cell) - riser.centre;
    riser.from = std::min(riser.from, d.dot(riser.along));
    riser.to = std::max(riser.to, d.dot(riser.along));
    across += std::pow(d.dot(riser.normal), 2);
    tops.push_back(grid.top(cell));
  }
  // Each cell stands for its whole width along the riser.
  riser.from -= grid.cellSize() / 2;
  riser.to += grid.cellSize() / 2;
  riser.thickness = std::sqrt(across / double(riser.cells.size()));
  std::nth_element(tops.begin(), tops.begin() + std::ptrdiff_t(tops.size() / 2), tops.end());
  riser.top = tops[tops.size() / 2];
  return riser;
}

bool parallel(const Riser& a, const Riser& b) {
  return std::abs(a.normal.dot(b.normal)) >= std::cos(kMaxRiserAngleDeg * std::numbers::pi / 180);
}

// Extent of b along a's direction, relative to a's centre.
std::pair<double, double> extentAlong(const Riser& a, const Riser& b) {
  const double centre = (b.centre - a.centre).dot(a.along);
  const double half = b.length() / 2 * std::abs(b.along.dot(a.along));
  const double middle = centre + (b.from + b.to) / 2 * b.along.dot(a.along);
  return {middle - half, middle + half};
}

double overlap(const Riser& a, const Riser& b) {
  const auto [from, to] = extentAlong(a, b);
  return std::min(a.to, to) - std::max(a.from, from);
}

int findRoot(std::vector<int>& parent, int i) {
  while (parent[std::size_t(i)] != i)
    i = parent[std::size_t(i)] = parent[std::size_t(parent[std::size_t(i)])];
  return i;
}

// Joins the pieces of one riser: parallel, in line, at the same height, close along it.
std::vector<Riser> joinPieces(const HeightGrid& grid, const std::vector<Riser>& pieces) {
  std::vector<int> parent(pieces.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t i = 0; i < pieces.size(); ++i)
    for (std::size_t j = i + 1; j < pieces.size(); ++j) {
      const Riser &a = pieces[i], &b = pieces[j];
      if (!parallel(a, b) || std::abs(a.top - b.top) > kHeightTolerance) continue;
      if (std::abs((b.centre - a.centre).dot(a.normal)) > grid.cellSize()) continue;
      if (overlap(a, b) < -kMaxRiserGap) continue;
      parent[std::size_t(findRoot(parent, int(i)))] = findRoot(parent, int(j));
    }
  std::vector<std::vector<std::uint32_t>> groups(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    auto& group = groups[std::size_t(findRoot(parent, int(i)))];
    group.insert(group.end(), pieces[i].cells.begin(), pieces[i].cells.end());
  }
  std::vector<Riser> risers;
  for (auto& group : groups)
    if (!group.empty()) risers.push_back(fitRiser(grid, std::move(group)));
  return risers;
}

// Whether the strip between riser a and a riser `distance` ahead of it (along side * a.normal)
// is a tread: what it shows of itself (nothing, seen from below) is near-horizontal. Between a
// ramp's rows of riser-like cells the surface climbs instead.
bool treadBetween(const HeightGrid& grid, const Riser& a, const Riser& b, double side,
                  double distance) {
  const Eigen::Vector2d normal = side * a.normal;
  const auto [b_from, b_to] = extentAlong(a, b);
  const double v0 = std::max(a.from, b_from) + kStripInset, v1 = std::min(a.to, b_to) - kStripInset;
  const double u0 = kStripInset, u1 = distance - kStripInset;
  if (v1 <= v0 || u1 <= u0) return true;
  Eigen::AlignedBox2d box;
  for (double u : {u0, u1})
    for (double v : {v0, v1})
      box.extend(a.centre + u * normal + v * a.along);
  double n = 0, su = 0, sz = 0, suu = 0, suz = 0;
  grid.forPointsIn(box, [&](float x, float y, float z) {
    const Eigen::Vector2d d = Eigen::Vector2d(x, y) - a.centre;
    const double u = d.dot(normal), v = d.dot(a.along);
    if (u < u0 || u > u1 || v < v0 || v > v1) return;
    n += 1;
    su += u;
    sz += z;
    suu += u * u;
    suz += u * z;
  });
  if (n < kMinTreadPoints) return true;  // not seen: no evidence either way
  const double variance = suu / n - std::pow(su / n, 2);
  if (variance < std::pow(kMinTreadSpread, 2)) return true;
  const double slope = (suz / n - su / n * sz / n) / variance;
  return std::abs(slope) <= std::tan(kMaxTreadSlopeDeg * std::numbers::pi / 180);
}

// Least-squares slope of values against their index.
double slopeOverIndex(const std::vector<double>& values) {
  const double n = double(values.size());
  const double mean_index = (n - 1) / 2;
  const double mean_value = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double covariance = 0.0, variance = 0.0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    covariance += (double(k) - mean_index) * (values[k] - mean_value);
    variance += std::pow(double(k) - mean_index, 2);
  }
  return variance > 0 ? covariance / variance : 0.0;
}

// The staircase of a chain of risers, bottom first, or nothing when it is not regular.
std::optional<Staircase> fitStaircase(const std::vector<const Riser*>& chain,
                                      const StairParams& params, double cell) {
  Staircase stairs;
  Eigen::Vector2d up = Eigen::Vector2d::Zero();
  const Eigen::Vector2d climb = chain.back()->centre - chain.front()->centre;
  for (const Riser* riser : chain)
    up += riser->normal.dot(climb) >= 0 ? riser->normal : -riser->normal;
  stairs.up = up.normalized();
  stairs.across = Eigen::Vector2d(-stairs.up.y(), stairs.up.x());
  // The flight's sides: the median of its risers' ends (one riser run on into something else
  // in line with it, at the same height, does not widen the flight).
  std::vector<double> lows, highs;
  for (const Riser* riser : chain) {
    stairs.riser_offsets.push_back(stairs.up.dot(riser->centre));
    stairs.riser_tops.push_back(riser->top);
    const double a = stairs.across.dot(riser->centre + riser->from * riser->along),
                 b = stairs.across.dot(riser->centre + riser->to * riser->along);
    lows.push_back(std::min(a, b));
    highs.push_back(std::max(a, b));
  }
  auto median = [](std::vector<double>& values) {
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2),
                     values.end());
    return values[values.size() / 2];
  };
  stairs.across_min = median(lows);
  stairs.across_max = median(highs);
  stairs.rise = slopeOverIndex(stairs.riser_tops);
  stairs.tread = slopeOverIndex(stairs.riser_offsets);
  // The fitted step must itself be a stair's (a cell of slack for the tread's quantisation).
  if (stairs.rise < params.min_rise - kHeightTolerance / 2 ||
      stairs.rise > params.max_rise + kHeightTolerance / 2 ||
      stairs.tread < params.min_tread - cell / 2 || stairs.tread > params.max_tread + cell / 2 ||
      stairs.width() < params.min_width)
    return std::nullopt;
  return stairs;
}

}  // namespace

std::vector<Staircase> detectStairs(const Scan& scan, const Eigen::Isometry3d& map_from_scanner,
                                    const StairParams& params) {
  HeightGrid grid(scan, map_from_scanner, params);
  const double cell = grid.cellSize();
  std::vector<Riser> pieces;
  for (auto& component : grid.riserComponents(params))
    if (component.size() >= kMinRiserCells) pieces.push_back(fitRiser(grid, std::move(component)));
  std::vector<Riser> risers;
  for (Riser& riser : joinPieces(grid, pieces))
    if (riser.length() >= params.min_width && riser.thickness <= cell) risers.push_back(riser);
  // A staircase is a riser with a successor: one riser alone is none.
  if (risers.size() < 2) return {};
  grid.sortPointsByCell();

  // Each riser's successor: the nearest parallel, overlapping riser ahead (either way), if it is
  // a tread away and a rise higher.
  constexpr int kNone = -1;
  std::vector<int> next(risers.size(), kNone), previous(risers.size(), kNone);
  for (std::size_t i = 0; i < risers.size(); ++i) {
    const Riser& a = risers[i];
    for (const double side : {1.0, -1.0}) {
      int nearest = kNone;
      double nearest_distance = std::numeric_limits<double>::max();
      for (std::size_t j = 0; j < risers.size(); ++j) {
        const Riser& b = risers[j];
        if (j == i || !parallel(a, b)) continue;
        if (overlap(a, b) < kMinOverlapShare * std::min(a.length(), b.length())) continue;
        const double ahead = side * (b.centre - a.centre).dot(a.normal);
        if (ahead > kSameOffset && ahead < nearest_distance) {
          nearest = int(j);
          nearest_distance = ahead;
        }
      }
      if (nearest == kNone) continue;
      const double rise = risers[std::size_t(nearest)].top - a.top;
      if (nearest_distance < params.min_tread - cell / 2 ||
          nearest_distance > params.max_tread + cell / 2 ||
          rise < params.min_rise - kHeightTolerance || rise > params.max_rise + kHeightTolerance)
        continue;
      if (previous[std::size_t(nearest)] != kNone) continue;  // claimed by a nearer riser
      if (!treadBetween(grid, a, risers[std::size_t(nearest)], side, nearest_distance)) continue;
      next[i] = nearest;
      previous[std::size_t(nearest)] = int(i);
      break;
    }
  }

  std::vector<Staircase> staircases;
  for (std::size_t i = 0; i < risers.size(); ++i) {
    if (previous[i] != kNone || next[i] == kNone) continue;
    std::vector<const Riser*> chain;
    for (int k = int(i); k != kNone; k = next[std::size_t(k)])
      chain.push_back(&risers[std::size_t(k)]);
    if (int(chain.size()) < params.min_steps) continue;
    if (auto stairs = fitStaircase(chain, params, cell)) staircases.push_back(std::move(*stairs));
  }
  return staircases;
}

}  // namespace clearway
