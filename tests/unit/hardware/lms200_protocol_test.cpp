// The LMS200 telegram codec, byte-exact: published telegrams, CRC, fragmentation, garbage before
// STX, corrupt telegrams, ACK/NAK and measured values.

#include <gtest/gtest.h>

#include "clearway/hardware/lms200_protocol.h"

namespace clearway::hardware::lms200 {
namespace {

using Kind = ParseEvent::Kind;

TEST(Lms200Protocol, EncodesThePublishedTelegramsByteForByte) {
  // From SICK's telegram listing: continuous output, stop, and installation mode with password.
  EXPECT_EQ(changeOperatingMode(kModeContinuousOutput),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x24, 0x34, 0x08}));
  EXPECT_EQ(changeOperatingMode(kModeValuesOnRequest),
            (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x25, 0x35, 0x08}));
  EXPECT_EQ(enterInstallationMode(), (Bytes{0x02, 0x00, 0x0A, 0x00, 0x20, 0x00, 'S', 'I', 'C', 'K',
                                            '_', 'L', 'M', 'S', 0xBE, 0xC5}));
}

TEST(Lms200Protocol, VariantAndStatusRequestsCarryTheirArguments) {
  const Bytes variant = switchVariant(180, 50);
  ASSERT_EQ(variant.size(), 11u);
  EXPECT_EQ(variant[2], 5);  // command + 4 data bytes
  EXPECT_EQ(variant[4], kSwitchVariant);
  EXPECT_EQ(variant[5], 180);
  EXPECT_EQ(variant[7], 50);
  EXPECT_EQ(crc16(variant.data(), variant.size() - 2),
            std::uint16_t(variant[9] | variant[10] << 8));
  EXPECT_EQ(requestStatus().size(), 7u);
}

TEST(Lms200Protocol, ParsesATelegramDeliveredOneByteAtATime) {
  const Bytes reply = encode(0xA0, {0x00, 0x10}, kFromScanner);
  Parser parser;
  std::vector<ParseEvent> events;
  for (std::uint8_t byte : reply) {
    auto more = parser.feed(&byte, 1);
    events.insert(events.end(), more.begin(), more.end());
  }
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::kTelegram);
  EXPECT_EQ(events[0].telegram.address, kFromScanner);
  EXPECT_EQ(events[0].telegram.command, 0xA0);
  EXPECT_EQ(events[0].telegram.data, (Bytes{0x00, 0x10}));
  EXPECT_EQ(parser.pending(), 0u);
}

TEST(Lms200Protocol, SkipsGarbageAndReportsAcknowledgements) {
  Bytes stream = {0x55, 0xAA, 0x13};
  stream.push_back(kAck);
  const Bytes reply = encode(0xA0, {0x01}, kFromScanner);
  stream.insert(stream.end(), reply.begin(), reply.end());
  stream.push_back(kNak);
  Parser parser;
  const auto events = parser.feed(stream);
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[0].kind, Kind::kSkipped);
  EXPECT_EQ(events[0].skipped, 3u);
  EXPECT_EQ(events[1].kind, Kind::kAcknowledged);
  EXPECT_EQ(events[2].kind, Kind::kTelegram);
  EXPECT_EQ(events[3].kind, Kind::kRefused);
}

TEST(Lms200Protocol, ACorruptTelegramIsReportedAndTheNextOneStillArrives) {
  Bytes corrupt = encode(0xA0, {0x01, 0x02, 0x03}, kFromScanner);
  corrupt[6] ^= 0x40;  // a bit error
  const Bytes good = encode(0xB1, {0x09}, kFromScanner);
  Bytes stream = corrupt;
  stream.insert(stream.end(), good.begin(), good.end());
  Parser parser;
  const auto events = parser.feed(stream);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().kind, Kind::kBadCrc);
  ASSERT_EQ(events.back().kind, Kind::kTelegram);
  EXPECT_EQ(events.back().telegram.command, 0xB1);
}

TEST(Lms200Protocol, AnAbsurdLengthIsNotTakenForATelegram) {
  Bytes stream = {kStx, 0x80, 0xFF, 0xFF, 0x20};
  const Bytes good = encode(0xA0, {0x00}, kFromScanner);
  stream.insert(stream.end(), good.begin(), good.end());
  Parser parser;
  const auto events = parser.feed(stream);
  ASSERT_EQ(events.back().kind, Kind::kTelegram);
  EXPECT_EQ(parser.pending(), 0u);
}

TEST(Lms200Protocol, DecodesMeasuredValuesInMillimetresWithErrorsAsNoReturn) {
  Bytes data;
  const std::uint16_t header = 3 | (1 << 14);  // three values, millimetres
  data = {std::uint8_t(header & 0xFF), std::uint8_t(header >> 8)};
  for (std::uint16_t value : {std::uint16_t(1500), std::uint16_t(0x1FFF), std::uint16_t(8000)}) {
    data.push_back(std::uint8_t(value & 0xFF));
    data.push_back(std::uint8_t(value >> 8));
  }
  data.push_back(0x10);  // status
  const MeasuredValues values = decodeMeasuredValues({kFromScanner, kMeasuredValuesReply, data});
  ASSERT_EQ(values.ranges.size(), 3u);
  EXPECT_DOUBLE_EQ(*values.ranges[0], 1.5);
  EXPECT_FALSE(values.ranges[1].has_value());
  EXPECT_DOUBLE_EQ(*values.ranges[2], 8.0);
  EXPECT_EQ(values.status, 0x10);
  data.pop_back();
  data.pop_back();
  EXPECT_THROW(decodeMeasuredValues({kFromScanner, kMeasuredValuesReply, data}),
               std::invalid_argument);
  EXPECT_THROW(decodeMeasuredValues({kFromScanner, 0xA0, {}}), std::invalid_argument);
}

}  // namespace
}  // namespace clearway::hardware::lms200
