#include "clearway/hardware/serial_turntable.h"

#include <chrono>

#include "serial_port.h"

namespace clearway::hardware {

struct SerialTurntable::Impl {
  explicit Impl(const std::string& port) : serial(port) {}
  detail::SerialPort serial;
  turntable::LineSplitter lines;
  std::vector<std::string> backlog;  // lines read while waiting for an answer
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
  // Only the newest angle describes the table at `now_us` (the host's clock); older ones in the
  // same read would be stamped too late.
  std::optional<double> newest;
  for (const std::string& line : lines)
    if (const auto reply = turntable::parseReply(line);
        reply && std::holds_alternative<turntable::AngleSample>(*reply))
      newest = std::get<turntable::AngleSample>(*reply).angle_deg;
  if (!newest) return {};
  return {{now_us, *newest}};
}

}  // namespace clearway::hardware
