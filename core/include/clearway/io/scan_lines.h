#pragma once

// Recovering the scan-line structure of files that store points in acquisition order without it
// (octomap scan.dat, PCL room scans, hannover .3d, KITTI). The sensor sits at the origin.

#include <cstddef>

#include "clearway/scan.h"

namespace clearway {

// Splits scan.points into lines where the angle that sweeps along a line (elevation for vertical
// fans, azimuth for horizontal ones; whichever moves more between neighbours) jumps back by more
// than `break_angle_rad`. Invalid points stay in the line they were recorded in. Replaces
// scan.lines; a cloud with no sweeping angle becomes a single line.
void reconstructScanLines(Scan& scan, double break_angle_rad);

// Scanners that report "no echo" as their maximum range leave a crowd of points at exactly that
// range. If at least `min_fraction` of the valid points lie within 0.1 % of the largest range,
// marks them kMaxRange and returns how many; otherwise marks nothing and returns 0.
std::size_t markSaturatedRange(Scan& scan, double min_fraction = 0.005);

}  // namespace clearway
