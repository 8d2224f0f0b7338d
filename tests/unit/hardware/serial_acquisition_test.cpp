// The acquisition driver against the emulator over real pseudo-terminals: a full revolution, the
// same scene the simulator sees, a device that stops answering, and no device at all.

#include <gtest/gtest.h>

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "clearway/hardware/lms200_protocol.h"
#include "clearway/hardware/rosi_emulator.h"
#include "clearway/hardware/serial_acquisition.h"
#include "clearway/hardware/serial_turntable.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/rosi_simulator.h"

namespace clearway::hardware {
namespace {

double meanValidRange(const Scan& scan) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    const Point3f& p = scan.points[i];
    sum += std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    ++count;
  }
  return count ? sum / double(count) : 0.0;
}

TEST(SerialAcquisition, OneRevolutionFromTheEmulatorLooksLikeTheSimulatorsScan) {
  const sim::Scene scene = *sim::builtinScene("garage");
  // 5x real time (a turn in 1.6 s, a line each 5 ms): at 20x a line came every 1.3 ms and a
  // machine busy with parallel builds stamped some late enough to shift the count.
  RosiEmulator emulator(scene, {5.0, 3});
  const Acquisition acquisition = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort());
  ASSERT_TRUE(acquisition.complete) << acquisition.error;
  const Scan& scan = acquisition.scan;
  EXPECT_TRUE(scan.isOrganised());
  EXPECT_EQ(scan.pointsPerLine(), 180u);
  // 37.5 lines/s at 45 deg/s is 300 lines a turn, whatever the speed-up.
  EXPECT_GT(scan.lines.size(), 285u);
  EXPECT_LT(scan.lines.size(), 315u);
  EXPECT_NEAR(scan.lines.back().beta, 2 * M_PI, 0.2);
  checkScanInvariants(scan);

  sim::SensorModel sensor;
  sensor.lines = int(scan.lines.size());
  const Scan simulated = sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene)).scan;
  const double valid_share = double(scan.validCount()) / double(scan.size());
  const double simulated_share = double(simulated.validCount()) / double(simulated.size());
  EXPECT_NEAR(valid_share, simulated_share, 0.05);
  EXPECT_NEAR(meanValidRange(scan), meanValidRange(simulated), 0.1 * meanValidRange(simulated));
}

TEST(SerialAcquisition, ADeviceThatStopsAnsweringLeavesAPartialScanAndAReason) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {2.0, 3});  // slow: a turn takes 4 s
  AcquisitionOptions options;
  options.answer_timeout_ms = 400;
  // The device hangs once a twentieth of the turn has arrived.
  const Acquisition acquisition =
      acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options, [&](double fraction) {
        if (fraction > 0.05) emulator.stall(true);
        return true;
      });
  EXPECT_FALSE(acquisition.complete);
  // Both devices hang at once: both are named (whichever's silence the watchdog saw first was
  // blamed alone; on a loaded machine the turntable).
  EXPECT_NE(acquisition.error.find("neither the laser scanner nor the turntable sends anything"),
            std::string::npos)
      << acquisition.error;
  EXPECT_GT(acquisition.scan.lines.size(), 0u);
  EXPECT_LT(acquisition.scan.lines.size(), 300u);
}

TEST(SerialAcquisition, ALinkTooNoisyForAnyTelegramIsReported) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  emulator.corruptEveryTelegram(true);  // setup replies are not measured values: they pass
  const Acquisition acquisition = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort());
  EXPECT_FALSE(acquisition.complete);
  EXPECT_NE(acquisition.error.find("too noisy"), std::string::npos) << acquisition.error;
}

TEST(SerialAcquisition, APulledCableKeepsWhatArrived) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {2.0, 3});
  AcquisitionOptions options;
  options.answer_timeout_ms = 400;
  const Acquisition acquisition =
      acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options, [&](double fraction) {
        if (fraction > 0.05) emulator.hangUp();
        return true;
      });
  EXPECT_FALSE(acquisition.complete);
  EXPECT_GT(acquisition.scan.lines.size(), 0u);
  // The laser is named, not the turntable whose watchdog ran out first.
  EXPECT_NE(acquisition.error.find("laser scanner's line hung up"), std::string::npos)
      << acquisition.error;
}

TEST(SerialAcquisition, RunsAt500kBaudAndRefusesSpeedsTheLms200DoesNotHave) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  AcquisitionOptions options;
  options.baud = 500000;
  options.lines = 40;
  const Acquisition fast = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options);
  EXPECT_TRUE(fast.complete) << fast.error;
  EXPECT_EQ(fast.scan.lines.size(), 40u);
  options.baud = 115200;
  const Acquisition wrong = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options);
  EXPECT_NE(wrong.error.find("cannot run at 115200"), std::string::npos) << wrong.error;
}

// What a program killed mid-scan leaves: the laser switched to 19200 baud and streaming, its port
// closed without a word more.
void leaveTheLaserStreamingAt19200(const std::string& port) {
  const int fd = ::open(port.c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(fd, 0) << port;
  termios settings{};
  ::tcgetattr(fd, &settings);
  ::cfmakeraw(&settings);
  ::cfsetspeed(&settings, B9600);
  ::tcsetattr(fd, TCSANOW, &settings);
  const auto send = [fd](const lms200::Bytes& telegram) {
    ASSERT_EQ(::write(fd, telegram.data(), telegram.size()), ssize_t(telegram.size()));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // its answer, unread
  };
  send(lms200::changeOperatingMode(lms200::kModeBaud19200));
  ::cfsetspeed(&settings, B19200);
  ::tcsetattr(fd, TCSADRAIN, &settings);
  send(lms200::changeOperatingMode(lms200::kModeContinuousOutput));
  ::close(fd);
}

// The LMS200 keeps the speed it was switched to until it is powered off. Each acquisition leaves it
// at 9600 baud, where the next one (or another program) looks first; a laser left at another speed
// by a process killed mid-scan, or by another program, is found there.
TEST(SerialAcquisition, TheLaserIsLeftAt9600BaudAndFoundAtWhateverSpeedItWasLeftAt) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  AcquisitionOptions options;
  options.lines = 30;
  options.answer_timeout_ms = 400;
  for (const int baud : {38400, 500000}) {
    options.baud = baud;
    const Acquisition scan = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options);
    EXPECT_TRUE(scan.complete) << baud << ": " << scan.error;
    EXPECT_EQ(emulator.laserBaud(), 9600) << "after a scan at " << baud;
  }
  // Left at 19200 and streaming by a program that then died: the next scan at 38400 finds it.
  leaveTheLaserStreamingAt19200(emulator.lmsPort());
  EXPECT_EQ(emulator.laserBaud(), 19200);
  options.baud = 38400;
  const Acquisition next = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options);
  EXPECT_TRUE(next.complete) << next.error;
  EXPECT_EQ(next.scan.lines.size(), 30u);
  EXPECT_EQ(emulator.laserBaud(), 9600);
}

// Another controller behind the Turntable interface: it turns at 900 deg/s by the clock.
class ClockTurntable : public Turntable {
 public:
  std::string openError() const override { return {}; }
  std::string home(int) override { return {}; }
  std::string setSpeed(double, int) override { return {}; }
  std::string start(int) override {
    started_ = std::chrono::steady_clock::now();
    return {};
  }
  void stop() override { ++stops; }
  int descriptor() const override { return -1; }
  std::vector<turntable::AngleSample> readSamples(std::int64_t now_us) override {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    return {{now_us, std::fmod(900.0 * seconds, 360.0)}};
  }
  int stops = 0;

 private:
  std::chrono::steady_clock::time_point started_;
};

TEST(SerialAcquisition, AnotherTurntableControllerPlugsIn) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  ClockTurntable table;
  const Acquisition acquisition = acquireRosiScan(emulator.lmsPort(), table);
  ASSERT_TRUE(acquisition.complete) << acquisition.error;
  EXPECT_GT(acquisition.scan.lines.size(), 100u);
  EXPECT_NEAR(acquisition.scan.lines.back().beta, 2 * M_PI, 0.3);
  EXPECT_EQ(table.stops, 1);
}

TEST(SerialAcquisition, SwappedCablesAreNamedAsSuch) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  AcquisitionOptions options;
  options.answer_timeout_ms = 400;
  const Acquisition acquisition =
      acquireRosiScan(emulator.turntablePort(), emulator.lmsPort(), options);
  EXPECT_FALSE(acquisition.complete);
  EXPECT_NE(acquisition.error.find("not as an LMS200"), std::string::npos) << acquisition.error;
  EXPECT_NE(acquisition.error.find("swapped"), std::string::npos) << acquisition.error;
  EXPECT_TRUE(acquisition.scan.empty());
}

TEST(SerialAcquisition, NoDeviceIsAClearErrorNotAHang) {
  const Acquisition acquisition =
      acquireRosiScan("/dev/clearway-no-such-port", "/dev/clearway-no-table");
  EXPECT_FALSE(acquisition.complete);
  EXPECT_NE(acquisition.error.find("cannot open /dev/clearway-no-such-port"), std::string::npos)
      << acquisition.error;
  EXPECT_TRUE(acquisition.scan.empty());
}

}  // namespace
}  // namespace clearway::hardware
