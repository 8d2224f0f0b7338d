#include "clearway/hardware/serial_turntable.h"

#include <algorithm>
#include <chrono>

#include "serial_port.h"

namespace clearway::hardware {

struct SerialTurntable::Impl {
  explicit Impl(const std::string& port) : serial(port) {}
  detail::SerialPort serial;
  turntable::LineSplitter lines;
  std::vector<std::string> backlog;  // lines read while waiting for an answer
  turntable::TableClock clock;
};

SerialTurntable::SerialTurntable(const std::string& port) : impl_(std::make_unique<Impl>(port)) {}
SerialTurntable::~SerialTurntable() = default;

std::string SerialTurntable::openError() const {
  return impl_->serial.error();
}
int SerialTurntable::descriptor() const {
  return impl_->serial.fd();
}

std::string SerialTurntable::command(const std::string& line, int timeout_ms) {
  if (!impl_->serial.send(line)) return "cannot write to " + impl_->serial.path();
  const std::string expected = "OK " + line.substr(0, line.find_first_of(" \n"));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    // A stop asked while a silent table is awaited (a --timeout of 20 s ignored Ctrl-C for 20 s).
    if (detail::stopRequested(stop_fd_)) return "stopped by a signal";
    if (!detail::waitReadable(impl_->serial.fd(), 20)) continue;
    for (const std::string& reply : impl_->lines.feed(impl_->serial.readAvailable())) {
      if (reply == expected) return {};
      if (reply.rfind("ERR", 0) == 0)
        return "the turntable refused '" + line.substr(0, line.size() - 1) +
               "': " + reply.substr(4);
      impl_->backlog.push_back(reply);
    }
  }
  return "the turntable does not answer on " + impl_->serial.path();
}

std::string SerialTurntable::home(int timeout_ms) {
  return command(turntable::homeCommand(), timeout_ms);
}
std::string SerialTurntable::setSpeed(double degrees_per_second, int timeout_ms) {
  return command(turntable::speedCommand(degrees_per_second), timeout_ms);
}
std::string SerialTurntable::start(int timeout_ms) {
  std::string error = command(turntable::startCommand(), timeout_ms);
  // Angles read while waiting for the answers were sent before the table started: stale.
  impl_->backlog.clear();
  return error;
}
void SerialTurntable::stop() {
  impl_->serial.send(turntable::stopCommand());
}

std::vector<turntable::AngleSample> SerialTurntable::readSamples(std::int64_t now_us) {
  std::vector<std::string> lines = std::move(impl_->backlog);
  impl_->backlog.clear();
  for (std::string& line : impl_->lines.feed(impl_->serial.readAvailable()))
    lines.push_back(std::move(line));
  // The host's time after the read: a sample can arrive between `now_us` and the read, and the
  // clock mapping below relies on no sample looking earlier than it arrived.
  now_us = std::max(now_us, detail::nowMicros());
  // Each sample is stamped with the table's own time, mapped onto the host's clock: stamping
  // with the time of the read would add the host's scheduling delay (milliseconds on a busy
  // machine, degrees of angle at speed) to every line's angle.
  std::vector<turntable::AngleSample> samples;
  for (const std::string& line : lines) {
    const auto reply = turntable::parseReply(line);
    if (reply && std::holds_alternative<turntable::AngleSample>(*reply))
      samples.push_back(std::get<turntable::AngleSample>(*reply));
  }
  return impl_->clock.toHost(std::move(samples), now_us);
}

}  // namespace clearway::hardware
