// How a scan is put together from the two streams the host reads, each stamped on arrival: a full
// turn is complete even when the device falls silent right after it, and lines placed by angles
// or times that cannot be trusted (a host held up for seconds) never make a complete scan.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "../../../hardware/src/scan_assembler.h"
#include "clearway/hardware/turntable_protocol.h"

namespace clearway::hardware {
namespace {

constexpr double kLinePeriodUs = 1e6 / 37.5;  // the LMS200's 37.5 lines/s
constexpr double kSamplePeriodUs = 20'000.0;  // the table's angle samples
constexpr double kTableDegPerS = 40.0;
// A full turn: 360 / 40 = 9 s, 337.5 lines.
constexpr double kTurnUs = 360.0 / kTableDegPerS * 1e6;

// Feeds what the host read between `from_us` and `to_us` (measured times), every line and sample
// arriving `late_us` after it was measured, or at `read_at_us` when that is later (a backlog read
// in one burst). Lines are numbered from the start of the scan, as the laser sends them.
void feed(detail::ScanAssembler& assembler, double from_us, double to_us, double read_at_us = 0.0) {
  constexpr double kLateUs = 2'000.0;
  for (double t = std::ceil(from_us / kSamplePeriodUs) * kSamplePeriodUs; t < to_us;
       t += kSamplePeriodUs)
    assembler.addAngle({std::int64_t(std::max(t + kLateUs, read_at_us)),
                        std::fmod(kTableDegPerS * t / 1e6, 360.0)});
  for (double t = std::ceil(from_us / kLinePeriodUs) * kLinePeriodUs; t < to_us;
       t += kLinePeriodUs) {
    assembler.addLine(std::int64_t(std::max(t + kLateUs, read_at_us)),
                      detail::LineRanges(detail::kRosiPoints, 3.0));
    assembler.place();
  }
}

TEST(ScanAssembly, AnUndisturbedTurnIsOneSweep) {
  detail::ScanAssembler assembler(0);
  feed(assembler, 0.0, kTurnUs + 2e6);
  ASSERT_TRUE(assembler.complete());
  assembler.refine();
  EXPECT_EQ(assembler.sweepProblem(), "");
}

// A table that takes a moment to start holds the first lines at one angle: still one sweep.
TEST(ScanAssembly, ATableStartingToTurnIsStillOneSweep) {
  detail::ScanAssembler assembler(0);
  constexpr double kStartsAtUs = 300'000.0;
  auto angle = [](double t) { return std::max(0.0, kTableDegPerS * (t - kStartsAtUs) / 1e6); };
  const double end_us = kStartsAtUs + kTurnUs + 2e6;
  for (double t = 0.0, line = 0.0; t < end_us; t += kSamplePeriodUs) {
    assembler.addAngle({std::int64_t(t + 2'000.0), std::fmod(angle(t), 360.0)});
    for (; line < t; line += kLinePeriodUs) {
      assembler.addLine(std::int64_t(line + 2'000.0), detail::LineRanges(detail::kRosiPoints, 3.0));
      assembler.place();
    }
  }
  ASSERT_TRUE(assembler.complete());
  assembler.refine();
  EXPECT_EQ(assembler.sweepProblem(), "");
}

// The last kStampLag lines of a turn wait for later telegrams to be stamped: a laser that fell
// silent just after the turn left them waiting, and the turn was saved as a partial scan.
TEST(ScanAssembly, AFullTurnWhoseLastLinesAwaitTheirStampsIsComplete) {
  detail::ScanAssembler assembler(0);
  // Every line up to a few past the turn, the angles on for a second more.
  feed(assembler, 0.0, kTurnUs + 3 * kLinePeriodUs);
  for (double t = kTurnUs + 4 * kLinePeriodUs; t < kTurnUs + 1e6; t += kSamplePeriodUs)
    assembler.addAngle({std::int64_t(t + 2'000.0), std::fmod(kTableDegPerS * t / 1e6, 360.0)});
  assembler.place();
  ASSERT_FALSE(assembler.complete()) << "the last lines wait for their stamps";
  EXPECT_TRUE(assembler.finishIncomplete());
  EXPECT_TRUE(assembler.complete());
  EXPECT_GE(assembler.turnedDeg(), 360.0);
}

// The same silence before the turn is done: the lines are placed, and the scan is not complete.
TEST(ScanAssembly, ATurnCutShortIsNotCompletedByItsWaitingLines) {
  detail::ScanAssembler assembler(0);
  feed(assembler, 0.0, kTurnUs - 40 * kLinePeriodUs);
  EXPECT_FALSE(assembler.finishIncomplete());
  EXPECT_FALSE(assembler.complete());
}

// The host held up for 6 s (a paused or overloaded computer): nothing was read meanwhile, the
// laser's and the table's buffered output came in one burst after it. The lines read then cannot
// be placed; 157 lines with a 113 deg jump back were saved as a complete turn.
TEST(ScanAssembly, AHostHeldUpForSecondsLeavesNoCompleteSweep) {
  detail::ScanAssembler assembler(0);
  constexpr double kHeldFromUs = 3e6, kHeldForUs = 6e6;
  feed(assembler, 0.0, kHeldFromUs);
  // What the devices' buffers kept of the pause (its last half second), read at its end; then on.
  feed(assembler, kHeldFromUs + kHeldForUs - 0.5e6, kHeldFromUs + kHeldForUs,
       kHeldFromUs + kHeldForUs);
  feed(assembler, kHeldFromUs + kHeldForUs, 2 * kTurnUs);
  if (!assembler.complete()) assembler.finishIncomplete();
  assembler.refine();
  const std::string problem = assembler.sweepProblem();
  EXPECT_NE(problem, "");
  EXPECT_NE(problem.find("after line"), std::string::npos) << problem;
}

// The host was busy for the first 300 ms after START (it started the laser's output and created
// the journal): its first read held every angle sample since, and the laser's first lines. Each
// sample of that read was stamped with the read's time, so the oldest angle stood at the newest
// time: the first lines were placed tens of degrees off (and a "full turn" of 12 lines was saved).
TEST(ScanAssembly, TheFirstLinesGetTheirAngleWhenTheFirstReadHoldsManySamples) {
  constexpr double kTableClockUs = -7e6;  // the table's own clock runs 7 s behind the host's
  constexpr double kLateUs = 2'000.0;     // each sample and line arrives this long after it
  constexpr double kFirstReadUs = 300'000.0, kLinesFromUs = 100'000.0;
  turntable::TableClock clock;
  detail::ScanAssembler assembler(0);
  std::vector<double> measured_us;  // when each line was measured
  double sample_us = 0.0, line_us = kLinesFromUs;
  // After the first read, the host reads whatever arrives when it arrives.
  while (!assembler.complete() && sample_us < kTurnUs + 2e6) {
    const double read_us = std::max(kFirstReadUs, std::min(sample_us, line_us) + kLateUs);
    std::vector<turntable::AngleSample> samples;
    for (; sample_us + kLateUs <= read_us; sample_us += kSamplePeriodUs)
      samples.push_back({std::int64_t(sample_us + kTableClockUs),
                         std::fmod(kTableDegPerS * sample_us / 1e6, 360.0)});
    for (const turntable::AngleSample& sample : clock.toHost(samples, std::int64_t(read_us)))
      assembler.addAngle(sample);
    for (; line_us + kLateUs <= read_us; line_us += kLinePeriodUs) {
      assembler.addLine(std::int64_t(read_us), detail::LineRanges(detail::kRosiPoints, 3.0));
      measured_us.push_back(line_us);
    }
    assembler.place();
  }
  ASSERT_TRUE(assembler.complete());
  assembler.refine();
  EXPECT_EQ(assembler.sweepProblem(), "");
  EXPECT_EQ(assembler.untagged(), 0u);
  const std::vector<ScanLine>& lines = assembler.scan().lines;
  EXPECT_GE(lines.size(), 330u);  // a full turn is 337.5 lines
  // The first read's samples are stamped as late as its newest (taken 20 ms before the read,
  // the others' 2 ms): 0.7 deg at 40 deg/s.
  for (std::size_t l = 0; l < lines.size(); ++l)
    ASSERT_NEAR(lines[l].beta * 180.0 / std::numbers::pi, kTableDegPerS * measured_us[l] / 1e6, 1.0)
        << "line " << l << " of " << lines.size();
}

// The host held up for 3 s near the end of the turn: the laser's lines of that time came in one
// burst, the table's angles kept their own stamps. The turn was found complete by the lines'
// stamps while it ran; stamped again at its end they covered 319 deg, one step each, and 299
// lines were saved as a complete turn.
TEST(ScanAssembly, AHostHeldUpAtTheEndOfTheTurnLeavesNoCompleteSweep) {
  constexpr double kLateUs = 2'000.0, kHeldFromUs = 7e6, kHeldForUs = 3e6;
  turntable::TableClock clock;
  detail::ScanAssembler assembler(0);
  double sample_us = 0.0, line_us = 0.0;
  while (!assembler.complete() && sample_us < kTurnUs + 4e6) {
    double read_us = std::min(sample_us, line_us) + kLateUs;
    if (read_us > kHeldFromUs && read_us < kHeldFromUs + kHeldForUs)
      read_us = kHeldFromUs + kHeldForUs;
    std::vector<turntable::AngleSample> samples;
    for (; sample_us + kLateUs <= read_us; sample_us += kSamplePeriodUs)
      samples.push_back(
          {std::int64_t(sample_us), std::fmod(kTableDegPerS * sample_us / 1e6, 360.0)});
    for (const turntable::AngleSample& sample : clock.toHost(samples, std::int64_t(read_us)))
      assembler.addAngle(sample);
    for (; line_us + kLateUs <= read_us; line_us += kLinePeriodUs)
      assembler.addLine(std::int64_t(read_us), detail::LineRanges(detail::kRosiPoints, 3.0));
    assembler.place();
  }
  if (!assembler.complete()) assembler.finishIncomplete();
  assembler.refine();
  const std::vector<ScanLine>& lines = assembler.scan().lines;
  ASSERT_GE(lines.size(), 3u);
  const double covered_deg = (lines.back().beta - lines.front().beta) * 180.0 / std::numbers::pi;
  if (assembler.complete() && covered_deg >= 360.0) return;  // a full turn after all
  const std::string problem = assembler.sweepProblem();
  EXPECT_NE(problem, "") << lines.size() << " lines over " << covered_deg << " deg";
}

// The table turns one way: a sample 228 deg on (a host held up for 6 s) has moved on, not 132 deg
// back.
TEST(ScanAssembly, TheTablesAngleMovesOnHoweverFar) {
  turntable::AngleTrack track;
  track.add({0, 300.0});
  track.add({20'000, 300.8});
  track.add({6'000'000, 168.8});  // 228 deg on, past 360
  EXPECT_NEAR(*track.angleAt(6'000'000), 528.8, 1e-9);
  track.add({6'020'000, 168.7});  // a reading's jitter back
  EXPECT_NEAR(*track.angleAt(6'020'000), 528.7, 1e-9);
  track.add({6'040'000, 169.5});
  EXPECT_NEAR(*track.angleAt(6'040'000), 529.5, 1e-9);
}

}  // namespace
}  // namespace clearway::hardware
