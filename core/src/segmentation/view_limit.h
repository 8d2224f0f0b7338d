#pragma once

// How high the scanner looked about itself (MapInputs::view, docs/ALGORITHM.md, "Above the
// scanner's view").

#include <Eigen/Geometry>

#include "clearway/scan.h"
#include "clearway/segmentation/scan_analysis.h"
#include "clearway/sensor_geometry.h"

namespace clearway::detail {

// Every beam's direction in the map frame and how far it went: a return as far as itself, a beam
// that brought nothing back (no echo, out of range) on beyond the last reach class. A turntable
// turns one fan, so every line of a rotating 2D scanner spans the same angles from the axis, from
// the least to the greatest of all the scan's returns': the angles of a line where it has no
// return are its lost beams (an unorganised file keeps only the returns). A multi-beam head turns
// every ring all the way round: its view is its top ring's in every sector. Sectors between fans
// (a sparse scan's) take the lower of their two sides' views across gaps of a few turntable
// steps; wider gaps (a partial turn) stay out of view. Fans tilted about a horizontal axis and
// files of no known sensor give no view (ViewLimit::known() false): it is not judged.
ViewLimit viewLimitOf(const Scan& scan, const SensorGeometry& sensor,
                      const Eigen::Isometry3d& map_from_scanner, int threads);

}  // namespace clearway::detail
