#pragma once

// Turns the two streams of an acquisition -- measured-value lines stamped with their arrival time
// and turntable angle samples stamped the same way -- into an organised RoSi scan: each line gets
// the angle interpolated at its arrival. The live acquisition and the journal's recovery feed the
// same events through this class, so a recovered scan is the scan the acquisition would have
// saved. Internal to hardware/.

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "clearway/hardware/turntable_protocol.h"
#include "clearway/scan.h"

namespace clearway::hardware::detail {

// The RoSi uses values 180 .. 359 of the LMS200's 361: alpha 0 .. 89.5 deg.
constexpr int kRosiPoints = 180;
using LineRanges = std::vector<std::optional<double>>;  // kRosiPoints ranges [m], none = no echo
// The RoSi's half of a 361-value LMS200 line.
LineRanges rosiHalf(const std::vector<std::optional<double>>& lms_ranges);

class ScanAssembler {
 public:
  // Lines waiting for an angle beyond this are the oldest dropped (counted untagged): memory
  // stays bounded however long a turntable stays silent. 4096 lines are 110 s at 37.5 lines/s.
  static constexpr std::size_t kMaxPendingLines = 4096;
  // When the scan ends early, lines up to this long after the last angle sample (or before the
  // first) get an angle extrapolated from the table's speed; later ones cannot be trusted.
  static constexpr std::int64_t kMaxExtrapolationUs = 1'000'000;

  // `target_lines` > 0: complete after that many lines; 0: after one revolution.
  explicit ScanAssembler(int target_lines);

  void addAngle(const turntable::AngleSample& sample);
  void addLine(std::int64_t time_us, LineRanges ranges);
  // Places the waiting lines whose time lies within the sampled angles (needs two samples).
  // Returns how many were placed. Lines after completion are ignored.
  std::size_t place();
  // The scan ends incomplete: lines close to the sampled span get an extrapolated angle.
  void finishIncomplete();

  bool complete() const { return complete_; }
  double turnedDeg() const { return turned_deg_; }
  std::size_t untagged() const { return untagged_; }
  std::size_t pending() const { return pending_.size(); }
  std::size_t angleSamples() const { return angles_.size(); }
  Scan& scan() { return scan_; }

 private:
  struct Pending {
    std::int64_t time_us;
    LineRanges ranges;
  };
  std::optional<double> angleAt(std::int64_t time_us, bool extrapolate) const;
  void append(double angle_deg, const LineRanges& ranges);

  int target_lines_;
  Scan scan_;
  turntable::AngleTrack angles_;
  std::deque<Pending> pending_;
  // The first two and last two samples (unwrapped), for extrapolation.
  std::int64_t first_time_[2] = {0, 0}, last_time_[2] = {0, 0};
  double first_angle_[2] = {0.0, 0.0}, last_angle_[2] = {0.0, 0.0};
  std::optional<double> start_angle_;
  double turned_deg_ = 0.0;
  bool complete_ = false;
  std::size_t untagged_ = 0;
};

}  // namespace clearway::hardware::detail
