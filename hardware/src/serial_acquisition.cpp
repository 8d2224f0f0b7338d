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
#include "clearway/hardware/turntable_protocol.h"

namespace clearway::hardware {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kRosiPoints = 180;  // the half line alpha 0 .. 89.5 deg: LMS values 180 .. 359
constexpr double kDeg = std::numbers::pi / 180.0;

std::int64_t nowMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch())
      .count();
}

class SerialPort {
 public:
  explicit SerialPort(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (fd_ < 0) {
      error_ = "cannot open " + path + ": " + std::strerror(errno);
      return;
    }
    termios settings{};
    if (::tcgetattr(fd_, &settings) != 0) {
      error_ = path + " is not a serial port";
      return;
    }
    ::cfmakeraw(&settings);
    ::cfsetspeed(&settings, B9600);  // the LMS200's speed after power-up; a pty ignores it
    ::tcsetattr(fd_, TCSANOW, &settings);
  }
  ~SerialPort() {
    if (fd_ >= 0) ::close(fd_);
  }
  const std::string& error() const { return error_; }
  // The LMS200 changes its speed after acknowledging the mode telegram; the port follows.
  bool setSpeed(speed_t speed) {
    termios settings{};
    if (::tcgetattr(fd_, &settings) != 0) return false;
    ::cfsetspeed(&settings, speed);
    return ::tcsetattr(fd_, TCSADRAIN, &settings) == 0;
  }
  const std::string& path() const { return path_; }
  int fd() const { return fd_; }
  bool send(const std::string& bytes) {
    return ::write(fd_, bytes.data(), bytes.size()) == ssize_t(bytes.size());
  }
  bool send(const lms200::Bytes& bytes) { return send(std::string(bytes.begin(), bytes.end())); }
  std::string readAvailable() {
    std::string bytes;
    char buffer[4096];
    ssize_t n;
    while ((n = ::read(fd_, buffer, sizeof buffer)) > 0)
      bytes.append(buffer, std::size_t(n));
    return bytes;
  }

 private:
  std::string path_;
  std::string error_;
  int fd_ = -1;
};

bool waitReadable(int fd, int timeout_ms) {
  pollfd descriptor{fd, POLLIN, 0};
  return ::poll(&descriptor, 1, timeout_ms) > 0;
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
  while (Clock::now() < deadline) {
    if (!waitReadable(lms.fd(), 20)) continue;
    const std::string bytes = lms.readAvailable();
    for (const auto& event :
         parser.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) {
      if (event.kind == lms200::ParseEvent::Kind::kRefused) {
        error = "the laser scanner refused a command (NAK)";
        return std::nullopt;
      }
      if (event.kind == lms200::ParseEvent::Kind::kTelegram &&
          event.telegram.command == reply_command)
        return event.telegram;
    }
  }
  error = "the laser scanner does not answer on " + lms.path() + " (is it connected and powered?)";
  return std::nullopt;
}

bool turntableCommand(SerialPort& table, turntable::LineSplitter& lines, const std::string& command,
                      int timeout_ms, std::string& error) {
  if (!table.send(command)) {
    error = "cannot write to " + table.path();
    return false;
  }
  const std::string expected = "OK " + command.substr(0, command.find_first_of(" \n"));
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  while (Clock::now() < deadline) {
    if (!waitReadable(table.fd(), 20)) continue;
    for (const std::string& line : lines.feed(table.readAvailable())) {
      if (line == expected) return true;
      if (line.rfind("ERR", 0) == 0) {
        error = "the turntable refused '" + command.substr(0, command.size() - 1) +
                "': " + line.substr(4);
        return false;
      }
    }
  }
  error = "the turntable does not answer on " + table.path();
  return false;
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
  Acquisition result;
  result.scan.metadata.format = "rosi acquisition";
  result.scan.metadata.frame = "RoSi scanner frame: metres, z = turntable axis";
  SerialPort lms(lms_port), table(turntable_port);
  if (!lms.error().empty() || !table.error().empty()) {
    result.error = !lms.error().empty() ? lms.error() : table.error();
    return result;
  }
  lms200::Parser parser;
  turntable::LineSplitter table_lines;
  const int timeout = options.answer_timeout_ms;
  const std::optional<LinkSpeed> link = linkSpeed(options.baud);
  if (!link) {
    result.error = "the LMS200 cannot run at " + std::to_string(options.baud) +
                   " baud (9600, 19200, 38400 or 500000)";
    return result;
  }
  std::string& error = result.error;
  if (!request(lms, parser, lms200::enterInstallationMode(), 0xA0, timeout, error) ||
      !request(lms, parser, lms200::changeOperatingMode(link->mode), 0xA0, timeout, error) ||
      !lms.setSpeed(link->speed) ||
      !request(lms, parser, lms200::switchVariant(180, 50), 0xBB, timeout, error) ||
      !turntableCommand(table, table_lines, turntable::homeCommand(), timeout, error) ||
      !turntableCommand(table, table_lines, turntable::speedCommand(options.turntable_speed_deg_s),
                        timeout, error) ||
      !turntableCommand(table, table_lines, turntable::startCommand(), timeout, error) ||
      !request(lms, parser, lms200::changeOperatingMode(lms200::kModeContinuousOutput), 0xA0,
               timeout, error))
    return result;

  turntable::AngleTrack angles;
  std::deque<PendingLine> pending;
  std::optional<double> first_angle;
  int bad_in_a_row = 0;
  auto last_heard = Clock::now();
  bool done = false;
  while (!done) {
    pollfd fds[2] = {{lms.fd(), POLLIN, 0}, {table.fd(), POLLIN, 0}};
    ::poll(fds, 2, 20);
    const std::int64_t now = nowMicros();
    if (fds[1].revents & POLLIN)
      for (const std::string& line : table_lines.feed(table.readAvailable()))
        if (const auto reply = turntable::parseReply(line);
            reply && std::holds_alternative<turntable::AngleSample>(*reply))
          angles.add(
              {now, std::get<turntable::AngleSample>(*reply).angle_deg});  // the host's clock
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
        if (angles.size() > 0 && pending.front().time_us < nowMicros() - 2'000'000)
          pending.pop_front();
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
  table.send(turntable::stopCommand());
  return result;
}

}  // namespace clearway::hardware
