#pragma once

// Recovering the scan-line structure of files that store points in acquisition order without it
// (octomap scan.dat, PCL room scans, hannover .3d, KITTI). The sensor sits at the origin.

#include <array>
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

// The names multi-beam drivers give each point's ring (laser) number: `ring` (Velodyne's, Ouster's
// and Hesai's ROS drivers), `laser_id` (VeloView's exports).
inline constexpr std::array<const char*, 2> kRingFieldNames = {"ring", "laser_id"};

// Multi-beam frames with a ring number per point (a PCD or PLY ring field): one line per ring,
// rings in increasing number when the numbers follow the elevation (a ROS driver's), else in
// order of their median elevation, lowest first (VeloView's laser_id: the firing order), each in
// the order the file keeps it. Points are reordered; lines
// replaced. Returns why not, the scan unchanged, when a value is no ring number (not a whole
// number from 0 to 65535: NaN, negative, fractional).
std::string groupIntoRings(Scan& scan, const std::vector<double>& ring_numbers);

// Multi-beam frames with a known number of rings but no usable order: each ring is a cluster of
// elevation angles (cut at the `rings` - 1 widest gaps between sorted elevations), its points in
// azimuth order. Points are reordered (lowest ring first); lines replaced. Returns why not (the
// scan unchanged) when the elevations do not fall into that many rings; empty on success.
std::string recoverRings(Scan& scan, std::size_t rings);

// Multi-beam frames kept firing after firing (one return of each laser per column of azimuth, as
// drivers send them, the lasers in any order) with no ring field: reconstructScanLines cuts them
// into columns, or none, zig-zagging over the head's few degrees of elevation. When the frame lies
// within 50 deg of elevation, its elevations fall into separate bands (at most 128), and nearly
// every return is followed in the file by one of another band, each band becomes a ring as
// recoverRings makes them. Returns the number of rings, or 0 (the scan unchanged) when the frame
// is not one.
std::size_t recoverFiringOrderRings(Scan& scan);

// Scanners that report "no echo" as their maximum range leave a crowd of points at exactly that
// range. If at least `min_fraction` of the valid points lie within 0.1 % of the largest range,
// marks them kMaxRange and returns how many; otherwise marks nothing and returns 0.
std::size_t markSaturatedRange(Scan& scan, double min_fraction = 0.005);

}  // namespace clearway
