#include "clearway/hardware/serial_acquisition.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "clearway/hardware/lms200_protocol.h"
#include "clearway/hardware/scan_journal.h"
#include "clearway/hardware/serial_turntable.h"
#include "clearway/hardware/turntable_protocol.h"
#include "link_speeds.h"
#include "scan_assembler.h"
#include "serial_port.h"

namespace clearway::hardware {
namespace {

using Clock = std::chrono::steady_clock;
using detail::kLinkSpeeds;
using detail::kPowerUpSpeed;
using detail::LinkSpeed;
using detail::nowMicros;
using detail::SerialPort;
using detail::stopRequested;
using detail::waitReadable;

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

// Sends a request and waits for the scanner's ACK and its reply telegram with `reply_command`,
// or until `stop_fd` asks to stop (a silent laser with a long --timeout ignored Ctrl-C for 40 s).
std::optional<lms200::Telegram> request(SerialPort& lms, lms200::Parser& parser,
                                        const lms200::Bytes& telegram, std::uint8_t reply_command,
                                        int timeout_ms, std::string& error,
                                        std::vector<lms200::ParseEvent>* after_reply = nullptr,
                                        int stop_fd = -1) {
  if (!lms.send(telegram)) {
    error = "cannot write to " + lms.path();
    return std::nullopt;
  }
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  std::string unrecognised;  // what came back while no telegram did: tells a wrong device apart
  bool any_telegram = false;
  while (Clock::now() < deadline) {
    if (stopRequested(stop_fd)) {
      error = "stopped by a signal";
      return std::nullopt;
    }
    if (!waitReadable(lms.fd(), 20)) continue;
    const std::string bytes = lms.readAvailable();
    if (unrecognised.size() < 256) unrecognised += bytes;
    std::vector<lms200::ParseEvent> events =
        parser.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    for (std::size_t i = 0; i < events.size(); ++i) {
      const lms200::ParseEvent& event = events[i];
      any_telegram = any_telegram || event.kind != lms200::ParseEvent::Kind::kSkipped;
      if (event.kind == lms200::ParseEvent::Kind::kRefused) {
        error = "the laser scanner refused a command (NAK)";
        return std::nullopt;
      }
      if (event.kind == lms200::ParseEvent::Kind::kTelegram &&
          event.telegram.command == reply_command) {
        // What came in the same read after the reply (the first measured values, when the
        // reply starts the continuous output) belongs to the caller.
        if (after_reply) after_reply->assign(events.begin() + std::ptrdiff_t(i) + 1, events.end());
        return event.telegram;
      }
    }
  }
  error = any_telegram || unrecognised.empty() ? "the laser scanner does not answer on " +
                                                     lms.path() + " (is it connected and powered?)"
                                               : wrongDeviceReason(lms.path(), unrecognised);
  return std::nullopt;
}

// A laser left streaming (the process that started it killed mid-scan, the laser still powered)
// fills the line with measured values, and the bytes of a telegram joined halfway read as ACK or
// NAK: the first command was "refused". If anything arrives unasked, the laser is told to stop
// its output (values on request) and the line is drained until it has been quiet a while. False
// when it never went quiet: the laser did not understand (it sends at another speed).
bool quietTheLaser(SerialPort& lms, int timeout_ms, int stop_fd) {
  constexpr int kQuietMs = 60;  // silence that says nothing more is coming
  if (!waitReadable(lms.fd(), kQuietMs)) return true;
  lms.send(lms200::changeOperatingMode(lms200::kModeValuesOnRequest));
  const auto deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  while (Clock::now() < deadline && !stopRequested(stop_fd)) {
    if (!waitReadable(lms.fd(), kQuietMs)) return true;
    lms.readAvailable();
  }
  return false;
}

// Finds the speed the laser listens at and enters its installation mode there. The LMS200 keeps
// the speed it was switched to until it is powered off, so it starts at 9600 baud only after
// power-up: an acquisition killed before it switched the laser back (or another program) leaves
// it at another. Tried in turn: 9600, the speed this acquisition wants (what a killed one of ours
// left), the others. Returns the speed it answered at.
std::optional<LinkSpeed> findTheLaser(SerialPort& lms, lms200::Parser& parser,
                                      const LinkSpeed& wanted, int timeout_ms, int stop_fd,
                                      std::string& error) {
  std::vector<LinkSpeed> order = {kPowerUpSpeed, wanted};
  for (const LinkSpeed& speed : kLinkSpeeds)
    order.push_back(speed);
  std::string first_error, tried;
  std::vector<int> tried_bauds;
  for (const LinkSpeed& speed : order) {
    if (stopRequested(stop_fd)) break;
    if (std::find(tried_bauds.begin(), tried_bauds.end(), speed.baud) != tried_bauds.end())
      continue;
    if (!lms.setSpeed(speed.speed)) continue;  // a port that cannot run at this speed
    tried_bauds.push_back(speed.baud);
    tried += (tried.empty() ? "" : ", ") + std::to_string(speed.baud);
    parser = lms200::Parser{};  // nothing heard at another speed carries over
    std::string attempt_error;
    if (!quietTheLaser(lms, timeout_ms, stop_fd))
      attempt_error = "the laser scanner's line on " + lms.path() + " never went quiet at " +
                      std::to_string(speed.baud) + " baud (a laser sending at another speed?)";
    else if (request(lms, parser, lms200::enterInstallationMode(), 0xA0, timeout_ms, attempt_error,
                     nullptr, stop_fd))
      return speed;
    if (first_error.empty()) first_error = attempt_error;
  }
  error = first_error + " (tried at " + tried + " baud)";
  return std::nullopt;
}

// The laser's side of one acquisition. However it ends, the laser's output is stopped and, unless
// it stopped answering, it is switched back to 9600 baud: the next acquisition, or another
// program, finds it at the speed it has after power-up.
class LaserSession {
 public:
  // `parser`: the acquisition's, in step with the stream (a new one would read the tail of a
  // measured-values telegram, cut anywhere, as ACK or NAK).
  LaserSession(SerialPort& lms, lms200::Parser& parser, int timeout_ms)
      : lms_(lms), parser_(parser), timeout_ms_(timeout_ms) {}
  ~LaserSession() { release(); }
  LaserSession(const LaserSession&) = delete;
  LaserSession& operator=(const LaserSession&) = delete;

  void atSpeed(const LinkSpeed& speed) { speed_ = speed; }
  void lost() { answering_ = false; }
  void release() {
    if (released_) return;
    released_ = true;
    if (!answering_) {
      lms_.send(lms200::changeOperatingMode(lms200::kModeValuesOnRequest));
      return;
    }
    std::string ignored;
    if (!request(lms_, parser_, lms200::changeOperatingMode(lms200::kModeValuesOnRequest), 0xA0,
                 timeout_ms_, ignored) ||
        speed_.baud == kPowerUpSpeed.baud)
      return;
    if (request(lms_, parser_, lms200::changeOperatingMode(kPowerUpSpeed.mode), 0xA0, timeout_ms_,
                ignored))
      lms_.setSpeed(kPowerUpSpeed.speed);
  }

 private:
  SerialPort& lms_;
  lms200::Parser& parser_;
  int timeout_ms_;
  LinkSpeed speed_ = kPowerUpSpeed;
  bool answering_ = true;
  bool released_ = false;
};

}  // namespace

Acquisition acquireRosiScan(const std::string& lms_port, const std::string& turntable_port,
                            const AcquisitionOptions& options, const ProgressCallback& progress) {
  SerialTurntable table(turntable_port);
  return acquireRosiScan(lms_port, table, options, progress);
}

Acquisition acquireRosiScan(const std::string& lms_port, Turntable& table,
                            const AcquisitionOptions& options, const ProgressCallback& progress) {
  Acquisition result;
  result.pose = options.pose;
  result.scan.metadata.format = "rosi acquisition";
  result.scan.metadata.frame = "RoSi scanner frame: metres, z = turntable axis";
  const std::optional<LinkSpeed> link = detail::linkSpeedOfBaud(options.baud);
  if (!link) {
    result.error = "the LMS200 cannot run at " + std::to_string(options.baud) +
                   " baud (9600, 19200, 38400 or 500000)";
    return result;
  }
  SerialPort lms(lms_port);
  if (!lms.error().empty() || !table.openError().empty()) {
    result.error = !lms.error().empty() ? lms.error() : table.openError();
    return result;
  }
  const int timeout = options.answer_timeout_ms;
  lms200::Parser parser;
  std::string& error = result.error;
  const auto interrupted = [&] {
    if (!stopRequested(options.stop_fd)) return false;
    result.stopped = true;
    error = "stopped by a signal after " + std::to_string(result.lines_received) + " lines";
    return true;
  };
  // The laser: found at its speed in installation mode, switched to the link speed and the
  // 180 deg / 0.5 deg variant.
  const std::optional<LinkSpeed> found =
      findTheLaser(lms, parser, *link, timeout, options.stop_fd, error);
  if (!found) {
    interrupted();  // says so, where a stop ended the search
    return result;
  }
  LaserSession laser(lms, parser, timeout);
  laser.atSpeed(*found);
  if (!request(lms, parser, lms200::changeOperatingMode(link->mode), 0xA0, timeout, error, nullptr,
               options.stop_fd)) {
    interrupted();
    return result;
  }
  laser.atSpeed(*link);
  if (!lms.setSpeed(link->speed)) {
    // The laser now talks at a speed this port cannot follow (an adapter without 500,000 baud):
    // nothing more can be said to it until it is powered off or found at its speed again.
    error = "cannot set " + lms.path() + " to " + std::to_string(link->baud) +
            " baud (does the serial adapter support it?); the laser stays at that speed until it "
            "is powered off: choose another --baud";
    laser.lost();
    return result;
  }
  if (!request(lms, parser, lms200::switchVariant(180, 50), 0xBB, timeout, error, nullptr,
               options.stop_fd) ||
      interrupted())
    return result;
  // The table: home, speed, turn.
  table.watchStop(options.stop_fd);
  error = table.home(timeout);
  if (error.empty()) error = table.setSpeed(options.turntable_speed_deg_s, timeout);
  if (error.empty()) error = table.start(timeout);
  if (interrupted()) {  // says so, also where a stop ended the wait for the table's answer
    table.stop();
    return result;
  }
  if (!error.empty()) return result;

  std::optional<ScanJournal> journal;
  if (!options.journal.empty()) {
    journal.emplace(options.journal, options.lines);
    if (!journal->error().empty()) {
      // Refused before the laser streams: nothing is lost yet, and nothing unrecovered is
      // overwritten.
      error = journal->error();
      table.stop();
      return result;
    }
    if (options.pose) journal->pose(*options.pose);
  }
  // And the laser's continuous output.
  std::vector<lms200::ParseEvent> events;  // the first lines may come with the reply
  if (!request(lms, parser, lms200::changeOperatingMode(lms200::kModeContinuousOutput), 0xA0,
               timeout, error, &events)) {
    table.stop();
    if (journal) journal->end(false, error);
    return result;
  }

  detail::ScanAssembler assembler(options.lines);
  int bad_in_a_row = 0;
  // The watchdog's clocks: the last line, the last angle sample, the last change of angle.
  auto last_line = Clock::now(), last_angle = Clock::now(), last_turn = Clock::now();
  std::optional<double> previous_angle;
  bool journal_failure_told = false;
  bool done = false;
  while (!done) {
    pollfd fds[3] = {
        {lms.fd(), POLLIN, 0}, {table.descriptor(), POLLIN, 0}, {options.stop_fd, POLLIN, 0}};
    ::poll(fds, 3, 20);
    const std::int64_t now = nowMicros();
    for (const turntable::AngleSample& sample : table.readSamples(now)) {
      if (journal) journal->angle(sample);
      assembler.addAngle(sample);
      last_angle = Clock::now();
      if (!previous_angle || sample.angle_deg != *previous_angle) last_turn = last_angle;
      previous_angle = sample.angle_deg;
    }
    std::int64_t arrival = now;  // no later than the telegrams' true arrival
    if (fds[0].revents & POLLIN) {
      const std::string bytes = lms.readAvailable();
      // Taken after the read: a telegram may arrive between `now` and the read, but never after
      // the read, and the line clock relies on stamps never being early.
      arrival = nowMicros();
      auto more = parser.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      events.insert(events.end(), std::make_move_iterator(more.begin()),
                    std::make_move_iterator(more.end()));
    }
    {
      for (const auto& event : events) {
        if (event.kind == lms200::ParseEvent::Kind::kBadCrc) {
          // A corrupt telegram while streaming is a lost line: counted, reported, never silent.
          assembler.addLostTelegram(arrival);
          ++result.dropped_lines;
          if (journal) journal->dropped(arrival, "bad checksum");
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
        last_line = Clock::now();
        try {
          detail::LineRanges ranges =
              detail::rosiHalf(lms200::decodeMeasuredValues(event.telegram).ranges);
          if (ranges.empty()) throw std::invalid_argument("not 361 values");
          ++result.lines_received;
          if (journal) journal->line(arrival, ranges);
          assembler.addLine(arrival, std::move(ranges));
        } catch (const std::invalid_argument&) {
          ++result.dropped_lines;
          assembler.addLostTelegram(arrival);
          if (journal) journal->dropped(arrival, "malformed measured values");
        }
      }
      events.clear();
    }
    // A journal that stopped (its disk full) is told at once, while the operator can still make
    // space or stop the scan; the lines go on into memory. It was told only when the scan ended.
    if (journal && !journal_failure_told && !journal->error().empty()) {
      journal_failure_told = true;
      if (options.journal_failed) options.journal_failed(journal->error(), journal->lines());
    }
    const std::size_t every = std::size_t(std::max(1, options.lines_arrived_every));
    const std::size_t before = assembler.scan().lines.size();
    assembler.place();
    const std::size_t placed = assembler.scan().lines.size();
    if (options.lines_arrived && placed / every != before / every)
      options.lines_arrived(assembler.scan());
    if (assembler.complete()) {
      result.complete = true;
      break;
    }
    const auto silent = [&](Clock::time_point since) {
      return Clock::now() - since > std::chrono::milliseconds(timeout);
    };
    const std::string so_far = " after " + std::to_string(result.lines_received) + " lines";
    if (done) break;
    if (interrupted()) break;
    // A line that hung up (cable pulled, device gone) is said at once, after what it sent was
    // read: the watchdog saw only silence after `timeout`, and blamed the device whose clock ran
    // out first (the turntable, when the laser's cable was pulled).
    if (fds[0].revents & (POLLHUP | POLLERR)) {
      error = "the laser scanner's line hung up (cable pulled, or the device gone)" + so_far;
      laser.lost();
      break;
    }
    // Both silent for most of the timeout: the whole RoSi hung (its power, its shared cable), not
    // the one whose clock ran out first (a stall was blamed on the turntable alone).
    const auto quiet_a_while = [&](Clock::time_point since) {
      return Clock::now() - since > std::chrono::milliseconds(timeout / 2);
    };
    if ((silent(last_line) || silent(last_angle)) && quiet_a_while(last_line) &&
        quiet_a_while(last_angle)) {
      error =
          "neither the laser scanner nor the turntable sends anything (the whole RoSi hung, or "
          "its power or cable)" +
          so_far;
      laser.lost();
      break;
    }
    if (silent(last_line)) {
      error = "the laser scanner stopped answering" + so_far;
      laser.lost();
      break;
    }
    if (silent(last_angle)) {
      error = assembler.angleSamples() == 0
                  ? "the turntable sends no angles (it answered, but never reported turning)"
                  : "the turntable stopped sending angles" + so_far;
      break;
    }
    if (silent(last_turn)) {
      error = "the turntable does not turn (its angle stays at " +
              std::to_string(previous_angle.value_or(0.0)) + " deg)" + so_far;
      break;
    }
    if (progress) {
      const double fraction =
          options.lines > 0 ? double(placed) / options.lines : assembler.turnedDeg() / 360.0;
      if (!progress(fraction)) {
        error = "cancelled by the operator" + so_far;
        break;
      }
    }
  }
  // Stop the devices whatever happened; they may not answer any more.
  laser.release();
  table.stop();
  // A full turn whose last lines had arrived is complete, whatever ended the loop after them.
  if (!result.complete && assembler.finishIncomplete()) {
    result.complete = true;
    error.clear();
  }
  assembler.refine();
  const std::string sweep_problem = assembler.sweepProblem();
  result.untagged_lines = assembler.untagged();
  const ScanMetadata metadata = result.scan.metadata;
  result.scan = std::move(assembler.scan());
  result.scan.metadata = metadata;
  if (options.pose) result.scan.sensor_pose = sensorPoseOf(options.pose->world_from_scanner);
  if (result.complete && result.dropped_lines > 0) {
    result.complete = false;
    error = std::to_string(result.dropped_lines) +
            " lines were dropped (corrupt telegrams): the scan has gaps";
  }
  // Lines dropped say why the scan has gaps; with none, lines out of their sweep say it.
  if (result.complete && !sweep_problem.empty()) {
    result.complete = false;
    error = sweep_problem;
  }
  if (journal) {
    result.journal_error = journal->error();
    result.lines_journaled = journal->lines();
    journal->end(result.complete, error);
    if (result.lines_received == 0) journal->remove();  // nothing arrived: nothing to keep
  }
  return result;
}

}  // namespace clearway::hardware
