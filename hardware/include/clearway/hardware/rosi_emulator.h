#pragma once

// An emulated RoSi on two pseudo-terminals: an LMS200 (real telegrams, CRC, ACK/NAK, operating
// modes, the 180 deg / 0.5 deg variant, continuous measured values at 37.5 lines/s x speed-up) and
// the turntable (docs/TURNTABLE.md), both observing a simulated scene. Drivers under test open the
// two ports as they would open the real devices.
//
// The LMS200 reports 361 values over 180 deg; the RoSi uses the half from 90 to 180 deg, which is
// alpha 0 .. 90 deg of the simulator. The other half looks at the mount and reports no echo.

#include <memory>
#include <string>

#include "clearway/sim/scene.h"

namespace clearway::hardware {

struct EmulatorOptions {
  double speedup = 1.0;  // how much faster than real time lines and angles arrive
  std::uint32_t seed = 1;
};

class RosiEmulator {
 public:
  // Opens the two pseudo-terminals and starts serving them on a thread of its own.
  // Throws std::runtime_error when the system has no pseudo-terminals to give.
  RosiEmulator(sim::Scene scene, EmulatorOptions options = {});
  ~RosiEmulator();  // stops the thread, closes the terminals
  RosiEmulator(const RosiEmulator&) = delete;
  RosiEmulator& operator=(const RosiEmulator&) = delete;

  // The device paths a driver opens, e.g. /dev/pts/3.
  const std::string& lmsPort() const;
  const std::string& turntablePort() const;
  // {"lms": "...", "turntable": "..."}
  std::string portsJson() const;

  // Fault injection for driver tests.
  void stall(bool stalled);                 // stop answering and sending, as a hung device
  void corruptNextTelegram();               // flip a bit in the next measured-values telegram
  void corruptEveryTelegram(bool corrupt);  // a link so noisy no measured values survive
  void hangUp();                            // the laser's cable is pulled: its terminal closes

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clearway::hardware
