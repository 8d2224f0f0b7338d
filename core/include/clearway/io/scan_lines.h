#pragma once

// Recovering the scan-line structure of files that store points in acquisition order without it
// (octomap scan.dat, PCL room scans, hannover .3d, KITTI). The sensor sits at the origin.

#include <cstddef>
#include <string>
#include <vector>

#include "clearway/scan.h"

namespace clearway {

// Splits scan.points into lines where the angle that sweeps along a line (elevation for vertical
// fans, azimuth for horizontal ones; whichever moves more between neighbours) jumps back by more
// than `break_angle_rad`, and horizontal lines also where the azimuth has swept a full turn
// (multi-beam rings stored one after another, as KITTI does). Invalid points stay in the line they
// were recorded in. Replaces scan.lines; a cloud with no sweeping angle becomes a single line.
void reconstructScanLines(Scan& scan, double break_angle_rad);

// Multi-beam frames with a ring index per point (a PCD `ring` field): one line per ring, rings in
// increasing index, each in the order the file keeps it. Points are reordered; lines replaced.
void groupIntoRings(Scan& scan, const std::vector<int>& ring_of);

// Multi-beam frames with a known number of rings but no usable order: each ring is a cluster of
// elevation angles (cut at the `rings` - 1 widest gaps between sorted elevations), its points in
// azimuth order. Points are reordered (lowest ring first); lines replaced. Returns why not (the
// scan unchanged) when the elevations do not fall into that many rings; empty on success.
std::string recoverRings(Scan& scan, std::size_t rings);

// Scanners that report "no echo" as their maximum range leave a crowd of points at exactly that
// range. If at least `min_fraction` of the valid points lie within 0.1 % of the largest range,
// marks them kMaxRange and returns how many; otherwise marks nothing and returns 0.
std::size_t markSaturatedRange(Scan& scan, double min_fraction = 0.005);

}  // namespace clearway
