#pragma once

// An emulated RoSi on two pseudo-terminals: an LMS200 (real telegrams, CRC, ACK/NAK, operating
// modes, link speeds kept until power-off, the 180 deg / 0.5 deg variant, continuous measured
// values at 37.5 lines/s x speed-up) and the turntable (docs/TURNTABLE.md), both observing a
// simulated scene. Drivers under test open the two ports as they would open the real devices.
//
// The LMS200 reports 361 values over 180 deg; the RoSi uses the half from 90 to 180 deg, which is
// alpha 0 .. 90 deg of the simulator. The other half looks at the mount and reports no echo.
//
// A third pseudo-terminal is the robot's arm controller (docs/ARM.md). Without an arm pose the
// scanner sits where the scene places it and the arm reports the pose that puts it there; with
// one (options or MOVE on the arm's port, between scans) the scanner is simulated where the arm
// holds it: world_from_scanner = robot_from_tool(tilt, roll) * tool_from_scanner, the tool at the
// scene's scanner position. Either way the pose the arm reports is the one the scan is taken from.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "clearway/hardware/arm_protocol.h"
#include "clearway/sim/scene.h"

namespace clearway::hardware {

struct EmulatorOptions {
  EmulatorOptions() = default;
  EmulatorOptions(double speedup_factor, std::uint32_t random_seed)
      : speedup(speedup_factor), seed(random_seed) {}

  double speedup = 1.0;  // how much faster than real time lines and angles arrive
  std::uint32_t seed = 1;
  std::optional<double> arm_tilt_deg, arm_roll_deg;  // set either: the arm holds the scanner
  RigidPose tool_from_scanner = defaultToolFromScanner();
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
  const std::string& armPort() const;
  // {"lms": "...", "turntable": "...", "arm": "..."}
  std::string portsJson() const;

  // Moves the arm (as MOVE on its port does): the next lines are taken from there.
  void moveArm(double tilt_deg, double roll_deg);
  // The scanner's true pose now (what the arm reports, composed with the mounting).
  RigidPose worldFromScanner() const;
  // Measured-values lines written whole to the laser's port so far: the emulator's own count
  // that tests hold an acquisition's journal against.
  std::uint64_t linesSent() const;
  // The laser's link speed now: 9600 baud at power-up, then what its last speed telegram set.
  // Bytes the driver sends at another speed go unheard; the laser's reach it garbled.
  int laserBaud() const;

  // Fault injection for driver tests.
  void stall(bool stalled);                 // stop answering and sending, as a hung device
  void stallLaser(bool stalled);            // only the laser hangs; the table keeps turning
  void stallTurntable(bool stalled);        // only the table hangs: no answers, no angles
  void muteAngles(bool muted);              // the table answers but never sends an angle
  void corruptEvery(int n);                 // every n-th measured-values telegram corrupt; 0: none
  void corruptNextTelegram();               // flip a bit in the next measured-values telegram
  void corruptEveryTelegram(bool corrupt);  // a link so noisy no measured values survive
  void hangUp();                            // the laser's cable is pulled: its terminal closes

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clearway::hardware
