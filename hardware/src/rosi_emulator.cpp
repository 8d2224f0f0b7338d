#include "clearway/hardware/rosi_emulator.h"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>

#include "clearway/hardware/lms200_protocol.h"
#include "clearway/hardware/turntable_protocol.h"
#include "clearway/sim/ray_caster.h"
#include "clearway/sim/rosi_simulator.h"
#include "link_speeds.h"

namespace clearway::hardware {
namespace {

using Clock = std::chrono::steady_clock;

// The master side of a new pseudo-terminal, raw; `path` is the side a driver opens.
int openPseudoTerminal(std::string& path) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0)
    throw std::runtime_error("cannot open a pseudo-terminal");
  path = ::ptsname(master);
  termios settings{};
  ::tcgetattr(master, &settings);
  ::cfmakeraw(&settings);
  ::tcsetattr(master, TCSANOW, &settings);
  ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
  return master;
}

// True when every byte went out.
bool writeAll(int fd, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  while (size > 0) {
    const ssize_t written = ::write(fd, bytes, size);
    if (written <= 0) return false;  // nobody reads (the driver closed the port): drop the rest
    bytes += written;
    size -= std::size_t(written);
  }
  return true;
}

// The simulator's placement that puts the scanner at `world_from_scanner`.
sim::ScannerPlacement placementFor(const Eigen::Isometry3d& world_from_scanner) {
  sim::ScannerPlacement placement;
  placement.position = world_from_scanner.translation();
  placement.axis = world_from_scanner.linear().col(2);
  placement.axis_roll_deg = 0.0;
  // The placement's own beta = 0 direction, then the roll about the axis that turns it into ours.
  const Eigen::Vector3d x0 = placement.worldFromScanner().linear().col(0);
  const Eigen::Vector3d x = world_from_scanner.linear().col(0);
  placement.axis_roll_deg = std::atan2(placement.axis.normalized().dot(x0.cross(x)), x0.dot(x)) *
                            180.0 / std::numbers::pi;
  return placement;
}

}  // namespace

struct RosiEmulator::Impl {
  sim::Scene scene;
  EmulatorOptions options;
  sim::RayCaster caster;
  sim::SensorModel sensor;
  sim::ScannerPlacement placement;
  std::string lms_path, turntable_path, arm_path;
  int lms_fd = -1, turntable_fd = -1, arm_fd = -1;
  std::atomic<bool> running{true}, stalled{false}, corrupt_next{false}, corrupt_all{false},
      hung_up{false}, laser_stalled{false}, table_stalled{false}, angles_muted{false};
  std::atomic<int> corrupt_every{0};
  std::atomic<std::uint64_t> lines_sent{0};
  // Where the arm holds the tool, and so the scanner: read by the serving thread for every line,
  // changed by MOVE (that thread) or moveArm() (any thread).
  mutable std::mutex pose_mutex;
  Eigen::Isometry3d robot_from_tool = Eigen::Isometry3d::Identity();
  line_protocol::LineSplitter arm_lines;
  // The laser's output queue (serving thread only): bytes not yet taken by the terminal, and
  // where in the stream each queued line ends.
  static constexpr std::size_t kMaxQueuedBytes = 4 << 20;  // ~5,700 lines: minutes of a stall
  std::string lms_out;
  std::uint64_t lms_out_written = 0;
  std::deque<std::uint64_t> line_ends;
  // The laser's link speed (a termios speed_t): 9600 baud at power-up, changed by its operating
  // mode telegrams after their reply, kept until power-off. Its queued output is sent at the
  // speed it had when queued: where in the stream each speed's bytes end.
  speed_t laser_speed = B9600;
  std::atomic<int> laser_baud{9600};
  std::deque<std::pair<std::uint64_t, speed_t>> speed_ends;
  std::thread thread;

  // Device state (the emulator's thread only).
  lms200::Parser lms_parser;
  turntable::LineSplitter turntable_lines;
  bool continuous = false;
  bool was_streaming = false;
  bool turning = false;
  double speed_deg_s = 45.0;
  double angle_deg = 0.0;
  std::uint32_t line_counter = 0;
  Clock::time_point start = Clock::now(), last_step = Clock::now(), next_line = Clock::now(),
                    next_angle = Clock::now();

  Impl(sim::Scene s, EmulatorOptions o) : scene(std::move(s)), options(o), caster(scene) {
    sensor.range_noise_sigma = 0.01;
    placement = sim::defaultPlacement(scene);
    if (options.arm_tilt_deg || options.arm_roll_deg) {
      moveArm(options.arm_tilt_deg.value_or(0.0), options.arm_roll_deg.value_or(0.0));
    } else {
      // The scene's own placement; the arm reports the pose that puts the scanner there.
      robot_from_tool =
          placement.worldFromScanner() * options.tool_from_scanner.isometry().inverse();
    }
    lms_fd = openPseudoTerminal(lms_path);
    turntable_fd = openPseudoTerminal(turntable_path);
    arm_fd = openPseudoTerminal(arm_path);
  }

  void moveArm(double tilt_deg, double roll_deg) {
    Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
    tool.linear() = armRotation(tilt_deg, roll_deg).toRotationMatrix();
    tool.translation() = scene.scanner_position;
    const std::lock_guard lock(pose_mutex);
    robot_from_tool = tool;
    placement = placementFor(tool * options.tool_from_scanner.isometry());
  }

  Eigen::Isometry3d worldFromScanner() const {
    const std::lock_guard lock(pose_mutex);
    return robot_from_tool * options.tool_from_scanner.isometry();
  }

  void handleArm(const std::string& line) {
    std::string answer;
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "POSE?") {
      const std::lock_guard lock(pose_mutex);
      answer = arm::poseReply(RigidPose::fromIsometry(robot_from_tool));
    } else if (keyword == "MOVE") {
      double tilt = 0.0, roll = 0.0;
      if (words >> tilt >> roll && std::abs(tilt) <= 180.0 && std::abs(roll) <= 180.0) {
        moveArm(tilt, roll);
        answer = "OK MOVE\n";
      } else {
        answer = "ERR MOVE needs a tilt and a roll in degrees\n";
      }
    } else {
      answer = "ERR unknown command\n";
    }
    writeAll(arm_fd, answer.data(), answer.size());
  }

  void reply(std::uint8_t command, lms200::Bytes data) {
    data.push_back(0x10);  // status: all fine
    const lms200::Bytes telegram = lms200::encode(command, data, lms200::kFromScanner);
    queueLms(telegram.data(), telegram.size(), false);
  }

  // The laser's output goes through a queue, as through a serial line: a reader that falls
  // behind (the pseudo-terminal's buffer is full) gets the bytes later, never a telegram cut in
  // half. A line counts as sent once its last byte is in the terminal.
  void queueLms(const void* data, std::size_t size, bool is_line) {
    if (lms_out.size() + size > kMaxQueuedBytes) return;  // nobody reads any more: dropped whole
    lms_out.append(static_cast<const char*>(data), size);
    const std::uint64_t end = lms_out_written + lms_out.size();
    if (is_line) line_ends.push_back(end);
    if (!speed_ends.empty() && speed_ends.back().second == laser_speed)
      speed_ends.back().first = end;
    else
      speed_ends.emplace_back(end, laser_speed);
    flushLms();
  }

  // The speed the driver set on its side of the terminal (the master reads the slave's settings).
  speed_t driverSpeed() const {
    termios settings{};
    if (lms_fd < 0 || ::tcgetattr(lms_fd, &settings) != 0) return B0;
    return ::cfgetospeed(&settings);
  }

  // What a UART set to another speed makes of a byte: another byte. A bijection under which no
  // telegram survives (its checksum fails) and lone bytes may still read as ACK or NAK, as on a
  // real line at the wrong speed.
  static char garbled(char byte) {
    const auto value = std::uint8_t(byte);
    return char(std::uint8_t((value << 3) | (value >> 5)) ^ 0x5A);
  }

  void flushLms() {
    while (lms_fd >= 0 && !lms_out.empty() && !speed_ends.empty()) {
      const auto [run_end, run_speed] = speed_ends.front();
      // At most what a terminal takes at once: a reader that fell behind leaves megabytes queued.
      constexpr std::uint64_t kLargestWrite = 1 << 16;
      const auto run = std::size_t(
          std::min({run_end - lms_out_written, std::uint64_t(lms_out.size()), kLargestWrite}));
      std::string bytes = lms_out.substr(0, run);
      if (driverSpeed() != run_speed)
        std::transform(bytes.begin(), bytes.end(), bytes.begin(), garbled);
      const ssize_t n = ::write(lms_fd, bytes.data(), bytes.size());
      if (n <= 0) break;
      lms_out.erase(0, std::size_t(n));
      lms_out_written += std::uint64_t(n);
      if (lms_out_written >= run_end) speed_ends.pop_front();
    }
    while (!line_ends.empty() && line_ends.front() <= lms_out_written) {
      line_ends.pop_front();
      ++lines_sent;
    }
  }

  void handleLms(const lms200::Telegram& request) {
    const std::uint8_t ack = lms200::kAck;
    const std::uint8_t nak = lms200::kNak;
    switch (request.command) {
      case lms200::kChangeOperatingMode: {
        if (request.data.empty()) break;
        const std::uint8_t mode = request.data[0];
        if (mode == lms200::kModeInstallation &&
            std::string(request.data.begin() + 1, request.data.end()) != "SICK_LMS") {
          queueLms(&ack, 1, false);
          reply(0xA0, {0x01});  // wrong password
          return;
        }
        if (mode == lms200::kModeContinuousOutput) continuous = true;
        if (mode == lms200::kModeValuesOnRequest) continuous = false;
        // A new link speed takes effect after the reply, which still goes at the old one. It is
        // told (laserBaud) before the reply can be read: whoever waited for it sees the new one.
        const auto baud = detail::linkSpeedOfMode(mode);
        if (baud) laser_baud = baud->baud;
        queueLms(&ack, 1, false);
        reply(0xA0, {0x00});
        if (baud) laser_speed = baud->speed;
        return;
      }
      case lms200::kSwitchVariant:
        queueLms(&ack, 1, false);
        reply(0xBB, {0x01, 180, 0, 50, 0});
        return;
      case lms200::kRequestStatus:
        queueLms(&ack, 1, false);
        reply(0xB1, {'L', 'M', 'S', '2', '0', '0', ' ', 'e', 'm', 'u'});
        return;
      default:
        break;
    }
    queueLms(&nak, 1, false);
  }

  void handleTurntable(const std::string& line) {
    std::string answer;
    if (line == "HOME") {
      angle_deg = 0.0;
      answer = "OK HOME\n";
    } else if (line.rfind("SPEED ", 0) == 0) {
      const double speed = std::atof(line.c_str() + 6);
      if (speed > 0.0 && speed <= 360.0) {
        speed_deg_s = speed;
        answer = "OK SPEED\n";
      } else {
        answer = "ERR speed out of range\n";
      }
    } else if (line == "START") {
      turning = true;
      answer = "OK START\n";
    } else if (line == "STOP") {
      turning = false;
      answer = "OK STOP\n";
    } else if (line == "STATUS") {
      answer = "STATUS " + std::string(turning ? "turning" : "idle") + " " +
               std::to_string(std::lround(angle_deg * 1000) % 360000) + " " +
               std::to_string(speed_deg_s) + "\n";
    } else {
      answer = "ERR unknown command\n";
    }
    writeAll(turntable_fd, answer.data(), answer.size());
  }

  // One LMS200 line of 361 values in centimetres at the current angle.
  // One line measured at `line_angle_deg`.
  void sendLine(double line_angle_deg) {
    const double beta = line_angle_deg * std::numbers::pi / 180.0;
    sim::ScannerPlacement where;
    {
      const std::lock_guard lock(pose_mutex);
      where = placement;
    }
    const std::vector<double> ranges =
        sim::simulateLineRanges(scene, caster, sensor, where, beta, options.seed + line_counter++);
    lms200::Bytes data;
    constexpr std::uint16_t kValues = 361;
    data.push_back(std::uint8_t(kValues & 0xFF));
    data.push_back(std::uint8_t(kValues >> 8));  // unit bits 00: centimetres
    for (std::uint16_t k = 0; k < kValues; ++k) {
      std::uint16_t value = 0x1FFF;  // no echo
      if (k >= 180 && std::size_t(k - 180) < ranges.size() && std::isfinite(ranges[k - 180u]))
        value = std::uint16_t(std::clamp(std::lround(ranges[k - 180u] * 100.0), 0L, 0x1FF6L));
      data.push_back(std::uint8_t(value & 0xFF));
      data.push_back(std::uint8_t(value >> 8));
    }
    data.push_back(0x10);
    lms200::Bytes telegram =
        lms200::encode(lms200::kMeasuredValuesReply, data, lms200::kFromScanner);
    const int every = corrupt_every;
    if (corrupt_next.exchange(false) || corrupt_all || (every > 0 && line_counter % every == 0))
      telegram[10] ^= 0x04;
    queueLms(telegram.data(), telegram.size(), true);
  }

  void serve() {
    const auto line_period =
        std::chrono::duration<double>(1.0 / (sim::SensorModel::kLineRateHz * options.speedup));
    const auto angle_period = std::chrono::duration<double>(0.02 / options.speedup);
    std::uint8_t buffer[4096];
    while (running) {
      pollfd fds[3] = {{lms_fd, POLLIN, 0}, {turntable_fd, POLLIN, 0}, {arm_fd, POLLIN, 0}};
      ::poll(fds, 3, 2);
      const auto now = Clock::now();
      if (hung_up && lms_fd >= 0) {
        ::close(lms_fd);  // the driver's side sees the line hang up
        lms_fd = -1;
      }
      if (fds[2].revents & POLLIN) {
        const ssize_t n = ::read(arm_fd, buffer, sizeof buffer);
        if (n > 0)
          for (const std::string& line :
               arm_lines.feed(std::string(reinterpret_cast<char*>(buffer), std::size_t(n))))
            handleArm(line);
      }
      flushLms();
      if (stalled || lms_fd < 0) {
        // A hung device: it reads nothing, answers nothing; time still passes for the table.
        last_step = now;
        was_streaming = false;
        continue;
      }
      if ((fds[0].revents & POLLIN) && !laser_stalled) {
        const ssize_t n = ::read(lms_fd, buffer, sizeof buffer);
        // Sent at another speed than the laser's, the bytes are framing errors: it hears nothing.
        if (n > 0 && driverSpeed() == laser_speed)
          for (const auto& event : lms_parser.feed(buffer, std::size_t(n)))
            if (event.kind == lms200::ParseEvent::Kind::kTelegram) handleLms(event.telegram);
      }
      if ((fds[1].revents & POLLIN) && !table_stalled) {
        const ssize_t n = ::read(turntable_fd, buffer, sizeof buffer);
        if (n > 0)
          for (const std::string& line :
               turntable_lines.feed(std::string(reinterpret_cast<char*>(buffer), std::size_t(n))))
            handleTurntable(line);
      }
      // The table turns in emulated time.
      const double elapsed =
          std::chrono::duration<double>(now - last_step).count() * options.speedup;
      last_step = now;
      if (turning) angle_deg = std::fmod(angle_deg + speed_deg_s * elapsed, 360.0);
      if (turning && now >= next_angle && !table_stalled && !angles_muted) {
        const auto micros =
            std::chrono::duration_cast<std::chrono::microseconds>(now - start).count();
        const std::string sample = "ANGLE " + std::to_string(micros) + " " +
                                   std::to_string(std::lround(angle_deg * 1000) % 360000) + "\n";
        writeAll(turntable_fd, sample.data(), sample.size());
        next_angle = now + std::chrono::duration_cast<Clock::duration>(angle_period);
      }
      // Lines keep the device's rate even when this loop wakes late (poll's granularity is
      // coarser than a line at high speed-ups): the lines that are due are sent together, as a
      // serial buffer would deliver them. After a long gap (a stall) the schedule starts afresh.
      const auto line_step = std::chrono::duration_cast<Clock::duration>(line_period);
      // The laser measures at its fixed rate from the moment it streams; a hung laser measures
      // nothing, so its schedule starts afresh when it streams again. A late loop (a busy
      // machine) sends every line that fell due, each measured where the table was then.
      const bool streaming = continuous && !laser_stalled && !stalled;
      if (streaming && !was_streaming) next_line = now;
      was_streaming = streaming;
      while (streaming && now >= next_line) {
        // A line due earlier than now was measured where the table was then, as the real
        // device measures at its fixed rate whenever the bytes get out.
        const double late_s =
            std::chrono::duration<double>(now - next_line).count() * options.speedup;
        const double line_angle = turning ? angle_deg - speed_deg_s * late_s : angle_deg;
        sendLine(std::fmod(line_angle + 360.0, 360.0));
        next_line += line_step;
      }
    }
  }
};

RosiEmulator::RosiEmulator(sim::Scene scene, EmulatorOptions options)
    : impl_(std::make_unique<Impl>(std::move(scene), options)) {
  impl_->thread = std::thread([this] { impl_->serve(); });
}

RosiEmulator::~RosiEmulator() {
  impl_->running = false;
  if (impl_->thread.joinable()) impl_->thread.join();
  if (impl_->lms_fd >= 0) ::close(impl_->lms_fd);
  ::close(impl_->turntable_fd);
  ::close(impl_->arm_fd);
}

const std::string& RosiEmulator::lmsPort() const {
  return impl_->lms_path;
}
const std::string& RosiEmulator::turntablePort() const {
  return impl_->turntable_path;
}

const std::string& RosiEmulator::armPort() const {
  return impl_->arm_path;
}

std::string RosiEmulator::portsJson() const {
  return "{\"lms\": \"" + impl_->lms_path + "\", \"turntable\": \"" + impl_->turntable_path +
         "\", \"arm\": \"" + impl_->arm_path + "\"}";
}

void RosiEmulator::moveArm(double tilt_deg, double roll_deg) {
  impl_->moveArm(tilt_deg, roll_deg);
}
RigidPose RosiEmulator::worldFromScanner() const {
  return RigidPose::fromIsometry(impl_->worldFromScanner());
}
std::uint64_t RosiEmulator::linesSent() const {
  return impl_->lines_sent;
}
int RosiEmulator::laserBaud() const {
  return impl_->laser_baud;
}
void RosiEmulator::stallLaser(bool stalled) {
  impl_->laser_stalled = stalled;
}
void RosiEmulator::stallTurntable(bool stalled) {
  impl_->table_stalled = stalled;
}
void RosiEmulator::muteAngles(bool muted) {
  impl_->angles_muted = muted;
}
void RosiEmulator::corruptEvery(int n) {
  impl_->corrupt_every = n;
}

void RosiEmulator::stall(bool stalled) {
  impl_->stalled = stalled;
}
void RosiEmulator::corruptNextTelegram() {
  impl_->corrupt_next = true;
}
void RosiEmulator::corruptEveryTelegram(bool corrupt) {
  impl_->corrupt_all = corrupt;
}
void RosiEmulator::hangUp() {
  impl_->hung_up = true;
}

}  // namespace clearway::hardware
