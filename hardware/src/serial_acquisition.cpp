#include "clearway/hardware/serial_acquisition.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <numbers>
#include <optional>

#include "clearway/hardware/lms200_protocol.h"
#include "clearway/hardware/serial_turntable.h"
#include "clearway/hardware/turntable_protocol.h"
#include "serial_port.h"

namespace clearway::hardware {
namespace {

using Clock = std::chrono::steady_clock;
using detail::nowMicros;
using detail::SerialPort;
using detail::waitReadable;
constexpr int kRosiPoints = 180;  // the half line alpha 0 .. 89.5 deg: LMS values 180 .. 359
constexpr double kDeg = std::numbers::pi / 180.0;

// Something answers on the laser's port, but never with an LMS200 telegram. Quote the first line
// when it is text: the turntable's "ERR ..." there means the two cables are swapped.
std::string wrongDeviceReason(const std::string& path, const std::string& bytes) {
  std::string line;
  for (const char c : bytes) {
    if (c == '\n' && !line.empty()) break;
    if (c >= 0x20 && c < 0x7f) line += c;
  }
  std::string reason = "the device on " + path + " answers, but not as an LMS200";
  if (line.size() >= 3) reason += " (it says \"" + line.substr(0, 60) + "\")";
  return reason + ": are the laser and turntable ports swapped?";
}

// Sends a request and waits for the scanner's ACK and its reply telegram with `reply_command`.
std::optional<lms200::Telegram> request(SerialPort& lms, lms200::Parser& parser,
                                        const lms200::Bytes& telegram, std::uint8_t reply_command,
                                        int timeout_ms, std::string& error) {
  if (!lms.send(telegram)) {
    error = "cannot write to " + lms.path();
    return std::nullopt;
  }
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  std::string unrecognised;  // what came back while no telegram did: tells a wrong device apart
  bool any_telegram = false;
  while (Clock::now() < deadline) {
    if (!waitReadable(lms.fd(), 20)) continue;
    const std::string bytes = lms.readAvailable();
    if (unrecognised.size() < 256) unrecognised += bytes;
    for (const auto& event :
         parser.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) {
      any_telegram = any_telegram || event.kind != lms200::ParseEvent::Kind::kSkipped;
      if (event.kind == lms200::ParseEvent::Kind::kRefused) {
        error = "the laser scanner refused a command (NAK)";
        return std::nullopt;
      }
      if (event.kind == lms200::ParseEvent::Kind::kTelegram &&
          event.telegram.command == reply_command)
        return event.telegram;
    }
  }
  error = any_telegram || unrecognised.empty() ? "the laser scanner does not answer on " +
                                                     lms.path() + " (is it connected and powered?)"
                                               : wrongDeviceReason(lms.path(), unrecognised);
  return std::nullopt;
}

struct LinkSpeed {
  std::uint8_t mode;  // the operating-mode telegram that switches the LMS200
  speed_t speed;      // the port's setting to follow it
};

std::optional<LinkSpeed> linkSpeed(int baud) {
  switch (baud) {
    case 9600:
      return LinkSpeed{lms200::kModeBaud9600, B9600};
    case 19200:
      return LinkSpeed{lms200::kModeBaud19200, B19200};
    case 38400:
      return LinkSpeed{lms200::kModeBaud38400, B38400};
    case 500000:
      return LinkSpeed{lms200::kModeBaud500k, B500000};
    default:
      return std::nullopt;
  }
}

struct PendingLine {
  std::int64_t time_us;
  std::vector<std::optional<double>> ranges;
};

void appendLine(Scan& scan, double beta, const std::vector<std::optional<double>>& ranges) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  scan.lines.push_back({scan.size(), kRosiPoints, beta});
  for (int k = 0; k < kRosiPoints; ++k) {
    const double alpha = k * 0.5 * kDeg;
    const auto& range = ranges[std::size_t(180 + k)];
    scan.alpha.push_back(float(alpha));
    scan.intensity.push_back(0.0F);
    if (!range) {
      scan.points.push_back({nan, nan, nan});
      scan.status.push_back(PointStatus::kNoReturn);
      continue;
    }
    const double d = *range;
    scan.points.push_back({float(std::cos(beta) * std::cos(alpha) * d),
                           float(std::sin(beta) * std::cos(alpha) * d),
                           float(std::sin(alpha) * d)});
    scan.status.push_back(PointStatus::kValid);
  }
}

}  // namespace

Acquisition acquireRosiScan(const std::string& lms_port, const std::string& turntable_port,
                            const AcquisitionOptions& options, const ProgressCallback& progress) {
  SerialTurntable table(turntable_port);
  return acquireRosiScan(lms_port, table, options, progress);
}

Acquisition acquireRosiScan(const std::string& lms_port, Turntable& table,
                            const AcquisitionOptions& options, const ProgressCallback& progress) {
  Acquisition result;
  result.scan.metadata.format = "rosi acquisition";
  result.scan.metadata.frame = "RoSi scanner frame: metres, z = turntable axis";
  SerialPort lms(lms_port);
  if (!lms.error().empty() || !table.openError().empty()) {
    result.error = !lms.error().empty() ? lms.error() : table.openError();
    return result;
  }
  lms200::Parser parser;
  const int timeout = options.answer_timeout_ms;
  const std::optional<LinkSpeed> link = linkSpeed(options.baud);
  if (!link) {
    result.error = "the LMS200 cannot run at " + std::to_string(options.baud) +
                   " baud (9600, 19200, 38400 or 500000)";
    return result;
  }
  std::string& error = result.error;
  // The laser: installation mode, its link speed, the 180 deg / 0.5 deg variant.
  if (!request(lms, parser, lms200::enterInstallationMode(), 0xA0, timeout, error) ||
      !request(lms, parser, lms200::changeOperatingMode(link->mode), 0xA0, timeout, error) ||
      !lms.setSpeed(link->speed) ||
      !request(lms, parser, lms200::switchVariant(180, 50), 0xBB, timeout, error))
    return result;
  // The table: home, speed, turn.
  error = table.home(timeout);
  if (error.empty()) error = table.setSpeed(options.turntable_speed_deg_s, timeout);
  if (error.empty()) error = table.start(timeout);
  if (!error.empty()) return result;
  // And the laser's continuous output.
  if (!request(lms, parser, lms200::changeOperatingMode(lms200::kModeContinuousOutput), 0xA0,
               timeout, error)) {
    table.stop();
    return result;
  }

  turntable::AngleTrack angles;
  std::deque<PendingLine> pending;
  std::optional<double> first_angle;
  int bad_in_a_row = 0;
  auto last_heard = Clock::now();
  bool done = false;
  while (!done) {
    pollfd fds[2] = {{lms.fd(), POLLIN, 0}, {table.descriptor(), POLLIN, 0}};
    ::poll(fds, 2, 20);
    const std::int64_t now = nowMicros();
    for (const turntable::AngleSample& sample : table.readSamples(now))
      angles.add(sample);
    if (fds[0].revents & POLLIN) {
      const std::string bytes = lms.readAvailable();
      for (const auto& event :
           parser.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) {
        if (event.kind == lms200::ParseEvent::Kind::kBadCrc) {
          if (++bad_in_a_row >= options.max_bad_telegrams) {
            error = "the link to the laser scanner is too noisy (" + std::to_string(bad_in_a_row) +
                    " corrupt telegrams in a row)";
            done = true;
          }
          continue;
        }
        if (event.kind != lms200::ParseEvent::Kind::kTelegram ||
            event.telegram.command != lms200::kMeasuredValuesReply)
          continue;
        bad_in_a_row = 0;
        last_heard = Clock::now();
        try {
          auto values = lms200::decodeMeasuredValues(event.telegram);
          if (values.ranges.size() == 361) pending.push_back({now, std::move(values.ranges)});
        } catch (const std::invalid_argument&) {
          // a malformed line is dropped; the next one follows
        }
      }
    }
    // Lines whose arrival lies within the sampled angles get their angle.
    while (!pending.empty()) {
      const auto angle = angles.angleAt(pending.front().time_us);
      if (!angle) {
        // A line from before the table's first sample can never be tagged: drop it now rather
        // than let it hold up the lines behind it. One after the last sample waits for the next.
        if (angles.before(pending.front().time_us) ||
            (angles.size() > 0 && pending.front().time_us < nowMicros() - 2'000'000)) {
          pending.pop_front();
          continue;
        }
        break;
      }
      if (!first_angle) first_angle = *angle;
      appendLine(result.scan, (*angle - *first_angle) * kDeg, pending.front().ranges);
      pending.pop_front();
      if (options.lines_arrived &&
          result.scan.lines.size() % std::size_t(std::max(1, options.lines_arrived_every)) == 0)
        options.lines_arrived(result.scan);
      const double turned = *angle - *first_angle;
      const bool enough_lines = options.lines > 0 && int(result.scan.lines.size()) >= options.lines;
      if (enough_lines || (options.lines == 0 && turned >= 360.0)) {
        result.complete = true;
        done = true;
        break;
      }
    }
    if (!done && Clock::now() - last_heard > std::chrono::milliseconds(timeout)) {
      error = "the laser scanner stopped answering after " +
              std::to_string(result.scan.lines.size()) + " lines";
      done = true;
    }
    if (!done && progress) {
      const double fraction = options.lines > 0
                                  ? double(result.scan.lines.size()) / options.lines
                                  : (result.scan.lines.empty()
                                         ? 0.0
                                         : result.scan.lines.back().beta / (2 * std::numbers::pi));
      if (!progress(fraction)) {
        error = "cancelled by the operator after " + std::to_string(result.scan.lines.size()) +
                " lines";
        done = true;
      }
    }
  }
  // Stop the devices whatever happened; they may not answer any more.
  lms.send(lms200::changeOperatingMode(lms200::kModeValuesOnRequest));
  table.stop();
  return result;
}

}  // namespace clearway::hardware
