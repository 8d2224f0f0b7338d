#include "scan_assembler.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace clearway::hardware::detail {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kLmsValues = 361;

}  // namespace

LineRanges rosiHalf(const std::vector<std::optional<double>>& lms_ranges) {
  if (lms_ranges.size() != std::size_t(kLmsValues)) return {};
  return LineRanges(lms_ranges.begin() + (kLmsValues - 1) / 2, lms_ranges.end() - 1);
}

ScanAssembler::ScanAssembler(int target_lines) : target_lines_(target_lines) {
  scan_.metadata.format = "rosi acquisition";
  scan_.metadata.frame = "RoSi scanner frame: metres, z = turntable axis";
}

void ScanAssembler::addAngle(const turntable::AngleSample& sample) {
  const std::size_t before = angles_.size();
  angles_.add(sample);
  if (angles_.size() == before) return;  // out of order: ignored, as AngleTrack does
  const double unwrapped = *angles_.angleAt(sample.time_us);
  if (before < 2) {
    first_time_[before] = sample.time_us;
    first_angle_[before] = unwrapped;
  }
  last_time_[0] = last_time_[1];
  last_angle_[0] = last_angle_[1];
  last_time_[1] = sample.time_us;
  last_angle_[1] = unwrapped;
}

void ScanAssembler::addLine(std::int64_t time_us, LineRanges ranges) {
  if (complete_ || ranges.size() != std::size_t(kRosiPoints)) return;
  if (pending_.size() >= kMaxPendingLines) {
    pending_.pop_front();
    ++untagged_;
  }
  pending_.push_back({time_us, std::move(ranges)});
}

std::optional<double> ScanAssembler::angleAt(std::int64_t time_us, bool extrapolate) const {
  if (angles_.size() < 2) return std::nullopt;
  if (const auto angle = angles_.angleAt(time_us)) return angle;
  // Before the first sample: the line is older than every angle; it can be given one from the
  // first two samples' speed (also live: no later sample will ever cover it).
  if (time_us < first_time_[0]) {
    if (first_time_[0] - time_us > kMaxExtrapolationUs || first_time_[1] == first_time_[0])
      return std::nullopt;
    const double speed =
        (first_angle_[1] - first_angle_[0]) / double(first_time_[1] - first_time_[0]);
    return first_angle_[0] - speed * double(first_time_[0] - time_us);
  }
  if (!extrapolate || time_us - last_time_[1] > kMaxExtrapolationUs ||
      last_time_[1] == last_time_[0])
    return std::nullopt;
  const double speed = (last_angle_[1] - last_angle_[0]) / double(last_time_[1] - last_time_[0]);
  return last_angle_[1] + speed * double(time_us - last_time_[1]);
}

void ScanAssembler::append(double angle_deg, const LineRanges& ranges) {
  if (!start_angle_) start_angle_ = angle_deg;
  turned_deg_ = angle_deg - *start_angle_;
  // beta is the table's own angle from its home mark, not from the first line: the scanner
  // frame (and so the scan's pose) has beta = 0 at the home mark.
  const double beta = angle_deg * kDeg;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  scan_.lines.push_back({scan_.size(), std::size_t(kRosiPoints), beta});
  for (int k = 0; k < kRosiPoints; ++k) {
    const double alpha = k * 0.5 * kDeg;
    scan_.alpha.push_back(float(alpha));
    scan_.intensity.push_back(0.0F);
    const auto& range = ranges[std::size_t(k)];
    if (!range) {
      scan_.points.push_back({nan, nan, nan});
      scan_.status.push_back(PointStatus::kNoReturn);
      continue;
    }
    const double d = *range;
    scan_.points.push_back({float(std::cos(beta) * std::cos(alpha) * d),
                            float(std::sin(beta) * std::cos(alpha) * d),
                            float(std::sin(alpha) * d)});
    scan_.status.push_back(PointStatus::kValid);
  }
  const bool enough_lines = target_lines_ > 0 && int(scan_.lines.size()) >= target_lines_;
  complete_ = enough_lines || (target_lines_ == 0 && turned_deg_ >= 360.0);
}

std::size_t ScanAssembler::place() {
  std::size_t placed = 0;
  while (!complete_ && !pending_.empty()) {
    const auto angle = angleAt(pending_.front().time_us, false);
    if (!angle) {
      // Too long before the first sample: it can never get an angle.
      if (angles_.size() >= 2 && pending_.front().time_us < first_time_[0]) {
        pending_.pop_front();
        ++untagged_;
        continue;
      }
      break;  // after the last sample: waits for the next one
    }
    append(*angle, pending_.front().ranges);
    pending_.pop_front();
    ++placed;
  }
  if (complete_) pending_.clear();  // beyond the revolution: not part of this scan
  return placed;
}

void ScanAssembler::finishIncomplete() {
  place();
  while (!complete_ && !pending_.empty()) {
    if (const auto angle = angleAt(pending_.front().time_us, true))
      append(*angle, pending_.front().ranges);
    else
      ++untagged_;
    pending_.pop_front();
  }
  pending_.clear();
}

}  // namespace clearway::hardware::detail
