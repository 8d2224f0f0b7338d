#include "plane_borders.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "ground_triangles.h"

namespace clearway::detail {
namespace {

// Calls visit(here, there, a, b, between) for every two side-by-side ground cells of different
// planes a and b (`between`: the middle of their shared side).
template <typename Visit>
void forEachPlaneBorder(const MapInputs& inputs, Visit&& visit) {
  const MapGrid& grid = inputs.grid;
  for (int row = 0; row < grid.height; ++row) {
    for (int column = 0; column < grid.width; ++column) {
      const std::size_t here = grid.index(column, row);
      const int a = inputs.ground_plane[here];
      if (a < 0) continue;
      for (const auto& [dc, dr] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (!grid.inside(column + dc, row + dr)) continue;
        const std::size_t there = grid.index(column + dc, row + dr);
        const int b = inputs.ground_plane[there];
        if (b < 0 || b == a) continue;
        visit(here, there, a, b,
              Eigen::Vector2d((grid.centre(column, row) + grid.centre(column + dc, row + dr)) / 2));
      }
    }
  }
}

// Calls visit(here, there, a, b, between) for every two ground cells of different planes a and b
// with one unobserved cell between them along a row, a column or a diagonal (`between`: its
// centre). The traversability stage lets the robot's box stand over such a cell (a beam that fell
// between two cells), so the ground either side must be as close as side-by-side cells' is.
template <typename Visit>
void forEachPlaneBorderAcrossAGap(const MapInputs& inputs, Visit&& visit) {
  const MapGrid& grid = inputs.grid;
  const int width = grid.width, height = grid.height;
  const auto* plane = inputs.ground_plane.data();
  // Along a row, a column and both diagonals: each pair of cells is met once.
  struct Direction {
    int dc, dr;
  };
  constexpr Direction kDirections[] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  // A pass over every cell of a multi-beam frame's map (hundreds of thousands): indices by hand,
  // and a cell whose four middle cells are all ground (most) left at once.
  const auto w = std::ptrdiff_t(width);
  for (int row = 0; row < height; ++row)
    for (int column = 0; column < width; ++column) {
      const std::size_t here = std::size_t(row) * std::size_t(width) + std::size_t(column);
      const int a = plane[here];
      if (a < 0) continue;
      if (row > 0 && row + 1 < height && column + 1 < width) {
        const auto* at = plane + here;
        if (at[1] >= 0 && at[w] >= 0 && at[w + 1] >= 0 && at[1 - w] >= 0) continue;
      }
      for (const Direction d : kDirections) {
        const int far_column = column + 2 * d.dc, far_row = row + 2 * d.dr;
        if (far_column >= width || far_row < 0 || far_row >= height) continue;
        const std::ptrdiff_t step = d.dc + d.dr * w;
        if (plane[std::size_t(std::ptrdiff_t(here) + step)] >= 0) continue;
        const std::size_t there = std::size_t(std::ptrdiff_t(here) + 2 * step);
        const int b = plane[there];
        if (b < 0 || b == a) continue;
        visit(here, there, a, b, grid.centre(column + d.dc, row + d.dr));
      }
    }
}

}  // namespace

// Where cells of two ground planes meet with more than kTouchingStep between them, the step is at
// least the planes' difference there: an upper level's support band takes in the top of its own
// edge's face (returns up to 5 cm below it), so the cell at the edge stands lower than its level,
// and a 0.15 m drop measured cell to cell splits into two steps a 0.1 m robot takes (the outdoor
// scene's kerb seen from beyond it). Both cells keep that step (seam_step), as a join's do.
void markPlaneEdges(MapInputs& inputs, const std::vector<Eigen::Vector3d>& plane_heights,
                    const std::vector<Plane>& planes) {
  auto planeZ = [&](int plane, const Eigen::Vector2d& p) {
    return heightOnPlane(plane_heights[std::size_t(plane)], p.x(), p.y());
  };
  auto markEdge = [&](std::size_t here, std::size_t there, int a, int b,
                      const Eigen::Vector2d& between) {
    const double cells_step =
        std::abs(double(inputs.ground_height[here]) - double(inputs.ground_height[there]));
    if (cells_step <= EdgeLimit::kTouchingStep) return;
    const double planes_step = std::abs(planeZ(a, between) - planeZ(b, between));
    // Measured as a join's step is (EdgeLimit::joinedStep), plus what either side is measured to:
    // each plane's height is good to about its rms residual (a plane fitted over slabs tilted
    // against each other passes centimetres off the slab at its edge), and the cells either side
    // hold the face's returns. Without the allowance the outdoor scene's slab joint, 0.14-0.17 m
    // where the robot's box stood, was measured 0.12-0.15 m and crossed with a 0.14 m step (140
    // false cells, docs/ALGORITHM.md).
    const double uncertainty = std::max(EdgeLimit::kJoinedStepUncertainty,
                                        planes[std::size_t(a)].rms + planes[std::size_t(b)].rms);
    const float step =
        float(std::max(cells_step, std::isfinite(planes_step) ? planes_step : 0.0) + uncertainty);
    inputs.seam_step[here] = std::max(inputs.seam_step[here], step);
    inputs.seam_step[there] = std::max(inputs.seam_step[there], step);
  };
  forEachPlaneBorder(inputs, markEdge);
  forEachPlaneBorderAcrossAGap(inputs, markEdge);
}

// Where cells of two ground planes touch, and the smallest step between them.
std::vector<GroundContact> groundContacts(const MapInputs& inputs) {
  std::map<std::pair<int, int>, float> steps;
  forEachPlaneBorder(inputs, [&](std::size_t here, std::size_t there, int a, int b,
                                 const Eigen::Vector2d&) {
    // Cells a triangle joining two planes fills lie on a ramp between them: the step they stand
    // for is the one the triangle spans.
    const float step = std::max({std::abs(inputs.ground_height[here] - inputs.ground_height[there]),
                                 inputs.seam_step[here], inputs.seam_step[there]});
    const auto key = std::minmax(a, b);
    const auto it = steps.find(key);
    if (it == steps.end() || step < it->second) steps[key] = step;
  });
  std::vector<GroundContact> contacts;
  for (const auto& [key, step] : steps)
    contacts.push_back({key.first, key.second, step});
  return contacts;
}

}  // namespace clearway::detail
