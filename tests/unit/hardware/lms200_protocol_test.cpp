// The LMS200 telegram codec, byte-exact: published telegrams, CRC, fragmentation, garbage before
// STX, corrupt telegrams, ACK/NAK and measured values.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

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

// A measured-values telegram like the RoSi's (361 values in centimetres), its values varied with
// `seed`, holding 0x02 bytes as real lines do (every range from 5.12 to 7.67 m has one).
Bytes measuredValuesTelegram(unsigned seed) {
  constexpr std::uint16_t kValues = 361;
  Bytes data = {std::uint8_t(kValues & 0xFF), std::uint8_t(kValues >> 8)};
  for (std::uint16_t k = 0; k < kValues; ++k) {
    const std::uint16_t value = std::uint16_t((seed * 131u + k * 37u) % 0x1FF6u);
    data.push_back(std::uint8_t(value & 0xFF));
    data.push_back(std::uint8_t(value >> 8));
  }
  data.push_back(0x10);  // status
  return encode(kMeasuredValuesReply, data, kFromScanner);
}

// Corruptions of a telegram's data, as a noisy line makes them: a flipped bit, an STX, an STX with
// a header after it, a whole valid telegram, ACK and NAK bytes.
void corruptData(Bytes& telegram, unsigned which) {
  const Bytes before = telegram;
  const Bytes inner = encode(0xA0, {0x00, 0x10}, kFromScanner);
  switch (which % 5) {
    case 0:
      telegram[10] ^= 0x04;  // what the emulator's --corrupt-every does
      break;
    case 1:
      telegram[200] = kStx;
      break;
    case 2:  // a header of a 16-byte telegram inside the data
      std::copy_n(Bytes{kStx, kFromScanner, 0x10, 0x00}.begin(), 4, telegram.begin() + 300);
      break;
    case 3:  // a complete telegram inside the data: never delivered
      std::copy(inner.begin(), inner.end(), telegram.begin() + 400);
      break;
    default:
      telegram[50] = kAck;
      telegram[51] = kNak;
      telegram[52] = kStx;
      break;
  }
  if (telegram == before) telegram[10] ^= 0x04;  // the byte was already what was put there
}

std::vector<ParseEvent> feedInPieces(const Bytes& stream, std::size_t piece) {
  Parser parser;
  std::vector<ParseEvent> events;
  for (std::size_t at = 0; at < stream.size(); at += piece) {
    auto more = parser.feed(stream.data() + at, std::min(piece, stream.size() - at));
    events.insert(events.end(), more.begin(), more.end());
  }
  EXPECT_EQ(parser.pending(), 0u);
  return events;
}

// One corrupt telegram is one lost line: the line clock counts a lost telegram per bad CRC, and
// each extra one shifted every later line's angle. A corrupt telegram whose data held 0x02 bytes
// gave several (the parser searched its data for telegram starts after the bad checksum).
TEST(Lms200Protocol, EveryCorruptTelegramInAStreamIsExactlyOneBadCrc) {
  constexpr unsigned kTelegrams = 100;
  for (const unsigned every : {1u, 2u, 3u, 7u}) {
    Bytes stream;
    std::vector<Bytes> good;
    for (unsigned n = 1; n <= kTelegrams; ++n) {
      Bytes telegram = measuredValuesTelegram(n);
      if (n % every == 0) {
        corruptData(telegram, n / every);
      } else {
        good.push_back(Bytes(telegram.begin() + 5, telegram.end() - 2));
      }
      stream.insert(stream.end(), telegram.begin(), telegram.end());
    }
    const Bytes last = measuredValuesTelegram(0);  // tells where the last corrupt one ended
    good.push_back(Bytes(last.begin() + 5, last.end() - 2));
    stream.insert(stream.end(), last.begin(), last.end());
    for (const std::size_t piece :
         {stream.size(), std::size_t(1), std::size_t(7), std::size_t(733)}) {
      SCOPED_TRACE("every " + std::to_string(every) + "th corrupt, fed " + std::to_string(piece) +
                   " bytes at a time");
      const std::vector<ParseEvent> events = feedInPieces(stream, piece);
      std::size_t bad = 0;
      std::vector<Bytes> delivered;
      for (const ParseEvent& event : events) {
        if (event.kind == Kind::kBadCrc) ++bad;
        if (event.kind == Kind::kTelegram) delivered.push_back(event.telegram.data);
        EXPECT_TRUE(event.kind == Kind::kBadCrc || event.kind == Kind::kTelegram)
            << "an event of kind " << int(event.kind) << " from a stream of telegrams";
      }
      EXPECT_EQ(bad, kTelegrams / every);
      EXPECT_EQ(delivered, good);  // the good telegrams, in order, intact, and nothing else
    }
  }
}

// A corrupt length says nothing of where the telegram ends: the parser resynchronises byte by
// byte, still one bad CRC, and the next telegram arrives.
TEST(Lms200Protocol, ACorruptLengthIsOneBadCrcAndTheNextTelegramArrives) {
  for (const std::uint8_t length_high : {std::uint8_t(0x01), std::uint8_t(0x03)}) {
    Bytes stream = measuredValuesTelegram(1);
    stream[3] = length_high;  // 0x2D7 bytes: now 0x1D7 or 0x3D7
    const Bytes next = measuredValuesTelegram(2);
    stream.insert(stream.end(), next.begin(), next.end());
    const Bytes after = measuredValuesTelegram(3);
    stream.insert(stream.end(), after.begin(), after.end());
    for (const std::size_t piece : {stream.size(), std::size_t(1)}) {
      const std::vector<ParseEvent> events = feedInPieces(stream, piece);
      std::vector<Kind> kinds;
      for (const ParseEvent& event : events)
        if (event.kind != Kind::kSkipped) kinds.push_back(event.kind);
      EXPECT_EQ(kinds, (std::vector<Kind>{Kind::kBadCrc, Kind::kTelegram, Kind::kTelegram}))
          << "length high byte " << int(length_high) << ", " << piece << " bytes at a time";
    }
  }
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
