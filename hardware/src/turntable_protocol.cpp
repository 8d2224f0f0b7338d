#include "clearway/hardware/turntable_protocol.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace clearway::hardware::turntable {
namespace {

constexpr double kMillidegrees = 1000.0;

}  // namespace

std::string homeCommand() {
  return "HOME\n";
}
std::string startCommand() {
  return "START\n";
}
std::string stopCommand() {
  return "STOP\n";
}
std::string statusCommand() {
  return "STATUS\n";
}

std::string speedCommand(double degrees_per_second) {
  std::ostringstream line;
  line.precision(6);
  line << "SPEED " << degrees_per_second << "\n";
  return line.str();
}

std::optional<Reply> parseReply(const std::string& line) {
  std::istringstream words(line);
  std::string keyword;
  if (!(words >> keyword)) return std::nullopt;
  if (const auto acknowledgement = line_protocol::parseAcknowledgement(line))
    return std::visit([](const auto& reply) { return Reply(reply); }, *acknowledgement);
  if (keyword == "ANGLE") {
    AngleSample sample;
    std::int64_t millidegrees = 0;
    if (!(words >> sample.time_us >> millidegrees) || millidegrees < 0 || millidegrees >= 360000)
      return std::nullopt;
    sample.angle_deg = double(millidegrees) / kMillidegrees;
    return sample;
  }
  if (keyword == "STATUS") {
    Status status;
    std::int64_t millidegrees = 0;
    if (!(words >> status.state >> millidegrees >> status.speed_deg_s)) return std::nullopt;
    status.angle_deg = double(millidegrees) / kMillidegrees;
    return status;
  }
  return std::nullopt;
}

void AngleTrack::add(const AngleSample& sample) {
  if (!times_.empty() && sample.time_us <= times_.back()) return;
  double unwrapped = sample.angle_deg;
  if (!unwrapped_.empty()) {
    // The table turns one way: the angle moves on from the previous sample's, by however much
    // (a host held up for 6 s read its next sample 228 deg on, which the nearest turn made 132
    // deg back), and falls back by at most a reading's jitter.
    const double previous = unwrapped_.back();
    const double turns = std::floor(previous / 360.0);
    unwrapped = turns * 360.0 + sample.angle_deg;
    while (unwrapped < previous - kLargestStepBackDeg)
      unwrapped += 360.0;
  }
  times_.push_back(sample.time_us);
  unwrapped_.push_back(unwrapped);
}

std::optional<double> AngleTrack::angleAt(std::int64_t time_us) const {
  if (times_.empty() || time_us < times_.front() || time_us > times_.back()) return std::nullopt;
  const auto after = std::lower_bound(times_.begin(), times_.end(), time_us);
  const std::size_t k = std::size_t(after - times_.begin());
  if (times_[k] == time_us) return unwrapped_[k];
  const double t = double(time_us - times_[k - 1]) / double(times_[k] - times_[k - 1]);
  return unwrapped_[k - 1] + t * (unwrapped_[k] - unwrapped_[k - 1]);
}

std::vector<AngleSample> TableClock::toHost(std::vector<AngleSample> samples,
                                            std::int64_t read_us) {
  // Samples read together are mapped by the newest of them, the least delayed. Each mapped by
  // the samples up to it was stamped with the read's time: the first read of a scan holds every
  // sample since START, and its oldest angle stood at the newest time (the first lines placed up
  // to 176 deg off at 20x, a "full turn" of 2 lines saved).
  std::size_t from = 0;  // the first sample not yet mapped
  const auto map = [&](std::size_t to) {
    for (; from < to; ++from)
      samples[from].time_us += *offset_us_;
  };
  for (std::size_t k = 0; k < samples.size(); ++k) {
    if (samples[k].time_us < last_table_us_) {  // its clock restarted: a new mapping from here
      map(k);
      offset_us_.reset();
    }
    last_table_us_ = samples[k].time_us;
    const std::int64_t offset = read_us - samples[k].time_us;
    if (!offset_us_ || offset < *offset_us_) offset_us_ = offset;
  }
  map(samples.size());
  return samples;
}

}  // namespace clearway::hardware::turntable
