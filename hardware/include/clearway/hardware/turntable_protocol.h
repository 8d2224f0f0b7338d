#pragma once

// Clearway's turntable protocol (docs/TURNTABLE.md): the RoSi's platform controller is not
// documented publicly, so any controller that speaks these ASCII lines can be plugged in.
//
//   host -> table: HOME | SPEED <deg/s> | START | STOP | STATUS            (one per line, '\n')
//   table -> host: OK <command> | ERR <reason> | ANGLE <time_us> <millideg>
//                  | STATUS <idle|homing|turning> <millideg> <deg/s>
//
// ANGLE samples stream while turning; the angle grows from 0 and wraps at 360000 millidegrees.
// Every scan line is tagged with the angle interpolated at the line's timestamp (AngleTrack).

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "clearway/hardware/line_protocol.h"

namespace clearway::hardware::turntable {

std::string homeCommand();
std::string speedCommand(double degrees_per_second);
std::string startCommand();
std::string stopCommand();
std::string statusCommand();

using line_protocol::Error;
using line_protocol::LineSplitter;
using line_protocol::Ok;
struct AngleSample {
  std::int64_t time_us = 0;
  double angle_deg = 0.0;  // [0, 360)
};
struct Status {
  std::string state;
  double angle_deg = 0.0;
  double speed_deg_s = 0.0;
};
using Reply = std::variant<Ok, Error, AngleSample, Status>;

// Parses one line (without its '\n'); nullopt for a line that is not a reply (noise, a cut line).
std::optional<Reply> parseReply(const std::string& line);

// Angle samples over time, unwrapped across full turns; the angle at any time between two samples
// is interpolated linearly.
class AngleTrack {
 public:
  // The table turns one way: a sample up to this far behind the previous one is a reading's
  // jitter; one farther behind has wrapped past 360 deg, however far it moved on [deg].
  static constexpr double kLargestStepBackDeg = 10.0;
  // Samples must come in time order; older or equal times are ignored.
  void add(const AngleSample& sample);
  // Unwrapped angle [deg] at `time_us`, or nullopt outside the sampled span.
  std::optional<double> angleAt(std::int64_t time_us) const;
  std::size_t size() const { return times_.size(); }
  // True when `time_us` precedes every sample: no sample can ever give its angle.
  bool before(std::int64_t time_us) const { return !times_.empty() && time_us < times_.front(); }

 private:
  std::vector<std::int64_t> times_;
  std::vector<double> unwrapped_;
};

// The table stamps its samples with its own clock; the host maps them onto its own:
// host = table + offset. The offset is the smallest host-minus-table difference seen, the sample
// least delayed on its way (a sample can arrive late, never early); a table whose clock restarts
// is re-synchronised.
class TableClock {
 public:
  // `samples`, stamped by the table, were read together at the host's `read_us`: the same samples
  // stamped with the host's clock, each with the offset known once the newest was read.
  std::vector<AngleSample> toHost(std::vector<AngleSample> samples, std::int64_t read_us);

 private:
  std::optional<std::int64_t> offset_us_;
  std::int64_t last_table_us_ = 0;
};

}  // namespace clearway::hardware::turntable
