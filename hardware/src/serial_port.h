#pragma once

// A serial port opened raw with termios, shared by the LMS200 acquisition and the serial
// turntable. Internal to hardware/.

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace clearway::hardware::detail {

inline std::int64_t nowMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

inline bool waitReadable(int fd, int timeout_ms) {
  pollfd descriptor{fd, POLLIN, 0};
  return ::poll(&descriptor, 1, timeout_ms) > 0;
}

// Whether the stop descriptor (a signal's self-pipe; -1: none) asks to stop.
inline bool stopRequested(int stop_fd) {
  return stop_fd >= 0 && waitReadable(stop_fd, 0);
}

class SerialPort {
 public:
  explicit SerialPort(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (fd_ < 0) {
      error_ = "cannot open " + path + ": " + std::strerror(errno);
      return;
    }
    // One program per device: a second acquisition on the same port would steal half the
    // telegrams of the first. flock is released by the kernel when the process dies, even by
    // kill -9, so a crash never leaves the port locked.
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      error_ = path + " is in use by another program (another clearway-cli acquire, or the " +
               "console's scanner?): close it first";
      ::close(fd_);
      fd_ = -1;
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
    // Whatever a previous, killed run left unread (a half line cut by a full buffer, a stream
    // of measured values) would garble the first answers.
    ::tcflush(fd_, TCIFLUSH);
  }
  ~SerialPort() {
    if (fd_ >= 0) ::close(fd_);
  }
  SerialPort(const SerialPort&) = delete;  // one owner closes the descriptor
  SerialPort& operator=(const SerialPort&) = delete;
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
  bool send(const std::vector<std::uint8_t>& bytes) {
    return send(std::string(bytes.begin(), bytes.end()));
  }
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

}  // namespace clearway::hardware::detail
