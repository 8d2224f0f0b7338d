#include <gtest/gtest.h>

#include "clearway/hardware/turntable_protocol.h"

namespace clearway::hardware::turntable {
namespace {

TEST(TurntableProtocol, CommandsAreOneLineEach) {
  EXPECT_EQ(homeCommand(), "HOME\n");
  EXPECT_EQ(speedCommand(45.0), "SPEED 45\n");
  EXPECT_EQ(startCommand(), "START\n");
  EXPECT_EQ(stopCommand(), "STOP\n");
  EXPECT_EQ(statusCommand(), "STATUS\n");
}

TEST(TurntableProtocol, RepliesParseAndNoiseDoesNot) {
  const auto angle = parseReply("ANGLE 1500000 359500");
  ASSERT_TRUE(angle && std::holds_alternative<AngleSample>(*angle));
  EXPECT_EQ(std::get<AngleSample>(*angle).time_us, 1500000);
  EXPECT_DOUBLE_EQ(std::get<AngleSample>(*angle).angle_deg, 359.5);
  const auto status = parseReply("STATUS turning 90000 45");
  ASSERT_TRUE(status && std::holds_alternative<Status>(*status));
  EXPECT_EQ(std::get<Status>(*status).state, "turning");
  EXPECT_DOUBLE_EQ(std::get<Status>(*status).speed_deg_s, 45.0);
  const auto error = parseReply("ERR motor stalled");
  ASSERT_TRUE(error && std::holds_alternative<Error>(*error));
  EXPECT_EQ(std::get<Error>(*error).reason, "motor stalled");
  EXPECT_TRUE(std::holds_alternative<Ok>(*parseReply("OK START")));
  EXPECT_FALSE(parseReply(""));
  EXPECT_FALSE(parseReply("ANGLE 12"));
  EXPECT_FALSE(parseReply("ANGLE 12 400000"));  // beyond a full turn
  EXPECT_FALSE(parseReply("HELLO"));
}

TEST(TurntableProtocol, LinesSurviveFragmentationAndOverlongNoise) {
  LineSplitter splitter;
  EXPECT_TRUE(splitter.feed("ANGLE 10 ").empty());
  const auto lines = splitter.feed("5000\r\nOK HOME\n");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "ANGLE 10 5000");
  EXPECT_EQ(lines[1], "OK HOME");
  splitter.feed(std::string(1000, 'x'));
  const auto after_noise = splitter.feed("\nOK STOP\n");
  EXPECT_EQ(after_noise.back(), "OK STOP");
}

TEST(TurntableProtocol, AnglesAreInterpolatedAtLineTimesAcrossTheWrap) {
  AngleTrack track;
  track.add({0, 350.0});
  track.add({100'000, 355.0});
  track.add({200'000, 0.0});  // wrapped past 360
  track.add({300'000, 5.0});
  track.add({300'000, 7.0});  // same time again: ignored
  ASSERT_EQ(track.size(), 4u);
  EXPECT_NEAR(*track.angleAt(50'000), 352.5, 1e-9);
  EXPECT_NEAR(*track.angleAt(150'000), 357.5, 1e-9);
  EXPECT_NEAR(*track.angleAt(250'000), 362.5, 1e-9);
  EXPECT_FALSE(track.angleAt(-1));
  EXPECT_FALSE(track.angleAt(300'001));
  // Before the first sample is never answerable; after the last may be, once the next arrives.
  EXPECT_TRUE(track.before(-1));
  EXPECT_FALSE(track.before(0));
  EXPECT_FALSE(track.before(300'001));
  EXPECT_FALSE(AngleTrack{}.before(0));
}

// The first read of a scan holds every sample since START (the host was busy starting the laser's
// output): read at one moment, each was taken at its own. Each was stamped with the read's time;
// all but the first were then dropped as out of order, and the oldest angle stood at the newest
// time.
TEST(TurntableProtocol, SamplesReadTogetherKeepTheTablesSpacing) {
  TableClock clock;
  const auto burst =
      clock.toHost({{1'000'000, 0.0}, {1'020'000, 0.9}, {1'040'000, 1.8}}, 8'043'000);
  ASSERT_EQ(burst.size(), 3u);
  // The newest sample is the least delayed of the read: 3 ms.
  EXPECT_EQ(burst[0].time_us, 8'003'000);
  EXPECT_EQ(burst[1].time_us, 8'023'000);
  EXPECT_EQ(burst[2].time_us, 8'043'000);
  // A later sample less delayed (1 ms) maps what follows.
  EXPECT_EQ(clock.toHost({{1'060'000, 2.7}}, 8'061'000).at(0).time_us, 8'061'000);
  EXPECT_EQ(clock.toHost({{1'080'000, 3.6}}, 8'095'000).at(0).time_us, 8'081'000);
  // A clock that restarts within a read: each side mapped by its own samples.
  const auto restarted = clock.toHost({{1'100'000, 4.5}, {2'000, 5.4}, {22'000, 6.3}}, 8'124'000);
  ASSERT_EQ(restarted.size(), 3u);
  EXPECT_EQ(restarted[0].time_us, 8'101'000);
  EXPECT_EQ(restarted[1].time_us, 8'104'000);
  EXPECT_EQ(restarted[2].time_us, 8'124'000);
}

}  // namespace
}  // namespace clearway::hardware::turntable
