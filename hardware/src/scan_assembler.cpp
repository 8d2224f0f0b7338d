#include "scan_assembler.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

std::size_t LineClock::arrive(std::int64_t arrival_us) {
  arrivals_.push_back(arrival_us);
  const std::size_t n = arrivals_.size();
  if (n > kWarmUp) {
    // A first guess of the period, then its slope between the least-delayed telegrams of the
    // first and the last window (relative to that guess).
    const double rough = double(arrival_us - arrivals_.front()) / double(n - 1);
    const std::size_t window = std::min(kWindow, n / 2);
    const std::size_t early = leastDelayed(0, window, rough);
    const std::size_t late = leastDelayed(n - window, n, rough);
    period_us_ =
        late > early ? double(arrivals_[late] - arrivals_[early]) / double(late - early) : rough;
  }
  return n - 1;
}

std::size_t LineClock::leastDelayed(std::size_t from, std::size_t to, double period) const {
  std::size_t best = from;
  for (std::size_t j = from; j < to; ++j)
    if (double(arrivals_[j]) - double(j) * period < double(arrivals_[best]) - double(best) * period)
      best = j;
  return best;
}

std::int64_t LineClock::stampOf(std::size_t index) {
  const std::size_t n = arrivals_.size();
  std::int64_t stamp = arrivals_[index];
  if (n > kWarmUp) {
    const std::size_t from = index > kWindow / 2 ? index - kWindow / 2 : 0;
    const std::size_t to = std::min(n, index + kWindow / 2 + 1);
    const std::size_t anchor = leastDelayed(from, to, period_us_);
    stamp = arrivals_[anchor] + std::int64_t((double(index) - double(anchor)) * period_us_);
    stamp = std::min(stamp, arrivals_[index]);  // never after it arrived
  }
  stamp = std::max(stamp, last_stamp_ + 1);  // in order
  last_stamp_ = stamp;
  return stamp;
}

std::int64_t LineClock::finalStampOf(std::size_t index) const {
  const std::size_t n = arrivals_.size();
  if (n <= kWarmUp) return arrivals_[index];
  // The grid under all arrivals: shifted to the least-delayed telegram of the whole scan.
  const std::size_t anchor = leastDelayed(0, n, period_us_);
  const std::int64_t stamp =
      arrivals_[anchor] + std::int64_t((double(index) - double(anchor)) * period_us_);
  return std::min(stamp, arrivals_[index]);
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

void ScanAssembler::addLine(std::int64_t arrival_us, LineRanges ranges) {
  const std::size_t telegram = clock_.arrive(arrival_us);
  if (complete_ || ranges.size() != std::size_t(kRosiPoints)) return;
  unstamped_.push_back({telegram, std::move(ranges)});
  stampLines(false);
}

void ScanAssembler::addLostTelegram(std::int64_t arrival_us) {
  clock_.arrive(arrival_us);
  stampLines(false);
}

void ScanAssembler::stampLines(bool all) {
  while (!unstamped_.empty() && (all || unstamped_.front().telegram + kStampLag < clock_.count())) {
    if (pending_.size() >= kMaxPendingLines) {
      pending_.pop_front();
      ++untagged_;
    }
    Unstamped& line = unstamped_.front();
    pending_.push_back({clock_.stampOf(line.telegram), std::move(line.ranges), line.telegram});
    unstamped_.pop_front();
  }
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

void ScanAssembler::append(double angle_deg, const LineRanges& ranges, std::size_t telegram) {
  line_telegrams_.push_back(telegram);
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
    append(*angle, pending_.front().ranges, pending_.front().telegram);
    pending_.pop_front();
    ++placed;
  }
  if (complete_) {  // beyond the revolution: not part of this scan
    pending_.clear();
    unstamped_.clear();
  }
  return placed;
}

bool ScanAssembler::finishIncomplete() {
  stampLines(true);
  place();
  if (complete_) return true;
  while (!complete_ && !pending_.empty()) {
    if (const auto angle = angleAt(pending_.front().time_us, true))
      append(*angle, pending_.front().ranges, pending_.front().telegram);
    else
      ++untagged_;
    pending_.pop_front();
  }
  pending_.clear();
  return false;
}

}  // namespace clearway::hardware::detail

namespace clearway::hardware::detail {

void ScanAssembler::refine() {
  for (std::size_t l = 0; l < scan_.lines.size(); ++l) {
    const auto angle = angleAt(clock_.finalStampOf(line_telegrams_[l]), true);
    if (!angle) continue;  // keeps the angle it had
    ScanLine& line = scan_.lines[l];
    const double turn = *angle * kDeg - line.beta;
    // x = cos(beta) cos(alpha) d, y = sin(beta) cos(alpha) d: a new beta turns (x, y) about z.
    const double c = std::cos(turn), s = std::sin(turn);
    for (std::size_t i = line.first; i < line.first + line.count; ++i) {
      if (!scan_.isValid(i)) continue;
      Point3f& p = scan_.points[i];
      const double x = p.x, y = p.y;
      p.x = float(c * x - s * y);
      p.y = float(s * x + c * y);
    }
    line.beta = *angle * kDeg;
  }
}

std::string ScanAssembler::sweepProblem() const {
  const std::vector<ScanLine>& lines = scan_.lines;
  if (lines.size() < 3) return {};
  std::vector<double> steps;
  for (std::size_t l = 1; l < lines.size(); ++l)
    steps.push_back((lines[l].beta - lines[l - 1].beta) / kDeg);
  std::vector<double> sorted = steps;
  const auto middle = sorted.begin() + std::ptrdiff_t(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double usual = *middle;
  auto shown = [](double degrees) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", degrees);
    return std::string(text);
  };
  if (!(usual > 0.0)) return "the lines' angles do not move on: the table did not turn one way";
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const std::string where =
        " after line " + std::to_string(k + 1) + " of " + std::to_string(lines.size());
    // A table that has not yet started, or a jittery angle reading, holds lines at one angle or
    // a little back: within the same bound either way.
    if (steps[k] < -kLargestLineStepFactor * usual)
      return "the lines' angles fall back by " + shown(-steps[k]) + " deg" + where +
             ": the acquisition was held up (the computer paused or overloaded) and what it read "
             "afterwards cannot be placed";
    // The first read's angle samples are stamped as late as the newest of them (TableClock): on
    // a loaded machine the emulator's first lines at 20x were still up to 7 deg (6 steps) behind
    // the next. Holes are judged from kStampLag lines on.
    if (k >= kStampLag && steps[k] > kLargestLineStepFactor * usual)
      return "the lines' angles jump " + shown(steps[k]) + " deg" + where + " (usually " +
             shown(usual) +
             "): lines are missing there (the acquisition was held up, or lines were lost)";
  }
  // The turn was found complete by the stamps its lines had while it ran; stamped again at its
  // end they may cover less (a host held up 3 s at the end of the turn, its backlog of lines read
  // in one burst: 299 lines over 319 deg, one step each, were saved as a complete turn).
  const double covered = (lines.back().beta - lines.front().beta) / kDeg;
  if (complete_ && target_lines_ == 0 && covered < 360.0 - kLargestLineStepFactor * usual)
    return "the lines cover " + shown(covered) +
           " deg, not the full turn: the acquisition was held up (the computer paused or "
           "overloaded) and the lines it read afterwards cannot be placed";
  return {};
}

}  // namespace clearway::hardware::detail
