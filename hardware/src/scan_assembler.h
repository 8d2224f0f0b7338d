#pragma once

// Turns the two streams of an acquisition -- measured-value lines stamped with their arrival time
// and turntable angle samples stamped the same way -- into an organised RoSi scan: each line gets
// the angle interpolated at its arrival. The live acquisition and the journal's recovery feed the
// same events through this class, so a recovered scan is the scan the acquisition would have
// saved. Internal to hardware/.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "clearway/hardware/turntable_protocol.h"
#include "clearway/scan.h"

namespace clearway::hardware::detail {

// The RoSi uses values 180 .. 359 of the LMS200's 361: alpha 0 .. 89.5 deg.
constexpr int kRosiPoints = 180;
using LineRanges = std::vector<std::optional<double>>;  // kRosiPoints ranges [m], none = no echo
// The RoSi's half of a 361-value LMS200 line.
LineRanges rosiHalf(const std::vector<std::optional<double>>& lms_ranges);

// When each LMS200 line was measured. The scanner sends at a fixed rate; a telegram reaches the
// host late (serial buffering, a busy machine), never early, and several often come in one read.
// The stamps are therefore a regular grid fitted under the arrivals: the period is the slope
// between the least-delayed telegrams near the start and near the end, and each telegram's grid
// point is anchored on the least-delayed telegram among its neighbours (kWindow around it, so a
// stamp is best once kWindow / 2 later telegrams are known). Stamping with the time of the read
// instead would make every line late by the host's delay: at 45 deg/s, 10 ms is 0.45 deg.
class LineClock {
 public:
  static constexpr std::size_t kWindow = 64;  // telegrams; ~1.7 s at 37.5 lines/s
  static constexpr std::size_t kWarmUp = 8;   // with fewer arrivals, a stamp is the arrival

  // A telegram (a corrupt one too: it took its slot) was read at `arrival_us`; its index.
  std::size_t arrive(std::int64_t arrival_us);
  std::size_t count() const { return arrivals_.size(); }
  // When telegram `index` was measured, from the arrivals so far. Call in increasing order.
  std::int64_t stampOf(std::size_t index);
  // The same from the grid fitted under every arrival (the laser's clock is steady over a scan):
  // once the scan has ended, the best estimate.
  std::int64_t finalStampOf(std::size_t index) const;
  double periodUs() const { return period_us_; }

 private:
  std::size_t leastDelayed(std::size_t from, std::size_t to, double period) const;
  std::vector<std::int64_t> arrivals_;
  double period_us_ = 0.0;
  std::int64_t last_stamp_ = 0;
};

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

  // Lines wait this many later telegrams before they are stamped (LineClock).
  static constexpr std::size_t kStampLag = LineClock::kWindow / 2;

  void addAngle(const turntable::AngleSample& sample);
  // A line read at `arrival_us`.
  void addLine(std::int64_t arrival_us, LineRanges ranges);
  // A telegram lost to corruption, read at `arrival_us`: it held a line's place in time.
  void addLostTelegram(std::int64_t arrival_us);
  // Places the waiting lines whose time lies within the sampled angles (needs two samples).
  // Returns how many were placed. Lines after completion are ignored.
  std::size_t place();
  // The scan ends before it was seen complete: the lines still waiting for their stamp are placed,
  // and true when they complete it by the sampled angles (the lines of a full turn had arrived;
  // the last kStampLag of them wait for later telegrams, and a device that fell silent just after
  // the turn left a complete scan called partial). Otherwise lines close to the sampled span get
  // an extrapolated angle, and false.
  bool finishIncomplete();
  // Once the scan has ended: every line's beta again from its final stamp (LineClock); the
  // stamps given while it ran could only use the telegrams that had arrived.
  void refine();

  // Why the placed lines are no sweep of the table (empty when they are): the table turns one way
  // at a steady speed, so each line's angle lies about one step beyond the line's before it. A
  // line more than kLargestLineStepFactor usual steps back (anywhere) or beyond (from kStampLag
  // lines on: the first read's angle stamps are the least sure) was placed by angles or times that
  // cannot be trusted (a host held up for seconds, its backlog read in one
  // burst: 157 lines with a 113 deg jump back were saved as a complete turn). A turn found
  // complete while it ran must still cover 360 deg (less kLargestLineStepFactor usual steps).
  std::string sweepProblem() const;
  static constexpr double kLargestLineStepFactor = 3.0;

  bool complete() const { return complete_; }
  double turnedDeg() const { return turned_deg_; }
  std::size_t untagged() const { return untagged_; }
  std::size_t pending() const { return pending_.size() + unstamped_.size(); }
  std::size_t angleSamples() const { return angles_.size(); }
  Scan& scan() { return scan_; }

 private:
  struct Pending {
    std::int64_t time_us;
    LineRanges ranges;
    std::size_t telegram;
  };
  struct Unstamped {
    std::size_t telegram;
    LineRanges ranges;
  };
  // Moves the lines whose stamp is settled (all: the scan ends) to those waiting for an angle.
  void stampLines(bool all);
  std::optional<double> angleAt(std::int64_t time_us, bool extrapolate) const;
  void append(double angle_deg, const LineRanges& ranges, std::size_t telegram);

  int target_lines_;
  Scan scan_;
  turntable::AngleTrack angles_;
  LineClock clock_;
  std::deque<Unstamped> unstamped_;
  std::deque<Pending> pending_;
  std::vector<std::size_t> line_telegrams_;  // per placed line
  // The first two and last two samples (unwrapped), for extrapolation.
  std::int64_t first_time_[2] = {0, 0}, last_time_[2] = {0, 0};
  double first_angle_[2] = {0.0, 0.0}, last_angle_[2] = {0.0, 0.0};
  std::optional<double> start_angle_;
  double turned_deg_ = 0.0;
  bool complete_ = false;
  std::size_t untagged_ = 0;
};

}  // namespace clearway::hardware::detail
