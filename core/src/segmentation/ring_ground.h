#pragma once

// A sparse multi-beam head's far rings lie metres apart on the road (a VLP-16 1.73 m up: 6 m
// from its ring at 14 m to the next, 13 m to the one after), each a thin arc of its own: no plane
// is clustered from one ring's segments, and a quarter of the road's returns were on no plane.
// Ground is followed outward instead, ring by ring along the azimuth, as the ground triangles
// join rings: a return facing a ground return of the next ring down (nearest in azimuth) joins
// that return's plane when it lies within the robot's step of the plane, plus the range's share
// of noise, and the rise to it from that return is no steeper than the robot drives. A car's
// side, a hedge's top or a bonnet stand higher above the road than a step and stay off it.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "clearway/scan.h"
#include "clearway/segmentation/planes.h"

namespace clearway::detail {

struct RingLayout;  // ring_support.h

struct OutwardGroundLimits {
  double off_plane = 0.1;  // [m] the robot's step: at most this far off the plane ...
  double per_metre = 0.0;  // ... plus this much per metre of range (the fit's tilt, the noise)
  double max_slope = 0.0;  // tangent: the steepest rise from the return it follows
  double noise = 0.02;     // [m] range noise on either return, added to that rise
};

// Puts on a ground plane the returns of `point_plane` (per point, its plane or -1) on no plane
// that continue a ground plane outward, walking the rings `rings_by_elevation` (indices into
// scan.lines, lowest first) up, each return's facing one on the next ring given by `layout`.
// `ground`: the ground planes' indices into `planes`. Returns how many points it put on a plane.
std::size_t followGroundOutward(const Scan& scan,
                                const std::vector<std::size_t>& rings_by_elevation,
                                const RingLayout& layout, const std::vector<Plane>& planes,
                                const std::vector<int>& ground, const OutwardGroundLimits& limits,
                                std::vector<std::int32_t>& point_plane);

}  // namespace clearway::detail
