#pragma once

// Which scan lines (or fans within them) lie side by side, and how their points pair up: the
// pairs along which the ground is followed across lines (continueGround) and triangulated
// (groundTriangles). For ragged rings, also each ring's azimuth gaps (its lost returns).

#include <cstdint>
#include <vector>

#include "clearway/scan.h"
#include "clearway/sensor_geometry.h"

namespace clearway::detail {

// Which lines lie side by side and how their points pair up: the scan's lines, or the fans
// within lines a file ran together, in the order of their angle (file order when the sensor's
// geometry is unknown; a full turn closes on itself); points paired by the angle along the line,
// or by index in an organised scan. Made once per scan: the ground is followed across the lines
// (continueGround) and triangulated (groundTriangles) over the same pairs.
class LinePairing {
 public:
  // `ground_of`: per point, its ground plane or -1 (where a turntable's two passes cover the same
  // angles, the one with more ground there is paired); the scanner `scanner_height` above the
  // map's ground.
  LinePairing(const Scan& scan, const std::vector<std::int32_t>& ground_of,
              const SensorGeometry& sensor, double scanner_height, int threads);

  std::size_t pairs() const { return pairs_; }
  // The two lines of pair `pair`, side by side.
  const ScanLine& before(std::size_t pair) const { return lines_[order_[pair]]; }
  const ScanLine& after(std::size_t pair) const {
    return lines_[order_[(pair + 1) % order_.size()]];
  }
  // For each point of `from` (one line of a pair), its partner on `to` (the other), in `out`.
  void partners(const ScanLine& from, const ScanLine& to, std::vector<std::size_t>& out) const;
  // Rings, a fraction of a degree between returns along them and metres between them.
  bool multiBeam() const { return multi_beam_; }
  // Rings of a file that keeps only the returns (KITTI's .bin, an unorganised ring PCD): a lost
  // return shows only as a gap in its ring's azimuths.
  bool raggedRings() const { return !azimuth_.empty(); }
  // Ragged rings: the azimuth of `point` as measured (unwrapped along its ring) [rad].
  double azimuth(std::size_t point) const { return double(azimuth_[point]); }
  // Ragged rings: the widest azimuth gap [rad] between returns of `line` that lie next to each
  // other in azimuth, over the gaps that reach into [low, high] (a return stored out of azimuth
  // order fills the gap it left); once one is wider than `enough`, that one.
  double widestGap(const ScanLine& line, double low, double high, double enough) const;

 private:
  bool multi_beam_ = false;
  std::vector<double> along_;  // per point, the angle along its line; empty: by index
  // Ragged rings only: per point its azimuth as measured (along_ holds dips level), and per ring
  // the same values sorted.
  std::vector<float> azimuth_, sorted_azimuth_;
  std::vector<ScanLine> lines_;     // what is paired: the lines, or the fans within them
  std::vector<std::size_t> order_;  // lines_ side by side
  std::size_t pairs_ = 0;
};

}  // namespace clearway::detail
