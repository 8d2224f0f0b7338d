#pragma once

// The turntable as the acquisition sees it, so another controller can be plugged in, and the
// implementation that speaks Clearway's line protocol (docs/TURNTABLE.md) on a serial port.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "clearway/hardware/turntable_protocol.h"

namespace clearway::hardware {

class Turntable {
 public:
  virtual ~Turntable() = default;
  // Empty when the controller is usable, else why not (cannot open the port, ...).
  virtual std::string openError() const = 0;
  // A descriptor that becomes readable when the operator asks to stop (a signal's self-pipe): the
  // commands below then give up waiting for an answer. -1 (the default): none. A controller that
  // answers at once may ignore it.
  virtual void watchStop(int /*stop_fd*/) {}
  // Each returns an empty string on success, else an operator-readable reason.
  virtual std::string home(int timeout_ms) = 0;
  virtual std::string setSpeed(double degrees_per_second, int timeout_ms) = 0;
  virtual std::string start(int timeout_ms) = 0;
  virtual void stop() = 0;
  // A descriptor that becomes readable when samples arrive (for poll), or -1.
  virtual int descriptor() const = 0;
  // The angle samples that arrived since the last call, stamped with the host's time `now_us`.
  virtual std::vector<turntable::AngleSample> readSamples(std::int64_t now_us) = 0;
};

class SerialTurntable : public Turntable {
 public:
  explicit SerialTurntable(const std::string& port);
  ~SerialTurntable() override;

  std::string openError() const override;
  void watchStop(int stop_fd) override { stop_fd_ = stop_fd; }
  std::string home(int timeout_ms) override;
  std::string setSpeed(double degrees_per_second, int timeout_ms) override;
  std::string start(int timeout_ms) override;
  void stop() override;
  int descriptor() const override;
  std::vector<turntable::AngleSample> readSamples(std::int64_t now_us) override;

 private:
  std::string command(const std::string& line, int timeout_ms);
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int stop_fd_ = -1;
};

}  // namespace clearway::hardware
