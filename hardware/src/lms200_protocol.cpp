#include "clearway/hardware/lms200_protocol.h"

#include <stdexcept>

namespace clearway::hardware::lms200 {
namespace {

constexpr std::uint16_t kGenerator = 0x8005;
// Measured values: the low 13 bits are the distance; counts from here on are error codes.
constexpr std::uint16_t kDistanceMask = 0x1FFF;
constexpr std::uint16_t kFirstErrorCode = 0x1FF7;

void putLittleEndian16(Bytes& out, std::uint16_t value) {
  out.push_back(std::uint8_t(value & 0xFF));
  out.push_back(std::uint8_t(value >> 8));
}

std::uint16_t littleEndian16(const std::uint8_t* at) {
  return std::uint16_t(at[0] | (at[1] << 8));
}

bool plausibleLength(std::size_t length) {
  return length > 0 && length <= kMaxPayload;
}

bool isAddress(std::uint8_t byte) {
  return byte == kToScanner || byte == kFromScanner;
}

// Whether the bytes at `at` begin what follows a telegram on the line: another telegram's header
// (STX, address, plausible length; 4 bytes there when it is an STX) or an ACK/NAK.
bool startsSomething(const std::uint8_t* at) {
  if (at[0] == kAck || at[0] == kNak) return true;
  return at[0] == kStx && isAddress(at[1]) && plausibleLength(littleEndian16(at + 2));
}

}  // namespace

std::uint16_t crc16(const std::uint8_t* data, std::size_t size) {
  // SICK's variant: the register is shifted once per byte and XORed with the current and the
  // previous byte together.
  std::uint16_t crc = 0;
  std::uint8_t previous = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const std::uint8_t current = data[i];
    crc = (crc & 0x8000) ? std::uint16_t(((crc & 0x7FFF) << 1) ^ kGenerator)
                         : std::uint16_t(crc << 1);
    crc ^= std::uint16_t(current | (previous << 8));
    previous = current;
  }
  return crc;
}

Bytes encode(std::uint8_t command, const Bytes& data, std::uint8_t address) {
  Bytes out;
  out.reserve(6 + data.size());  // one allocation (and no GCC 12 -Warray-bounds false alarm)
  out.push_back(kStx);
  out.push_back(address);
  putLittleEndian16(out, std::uint16_t(1 + data.size()));
  out.push_back(command);
  out.insert(out.end(), data.begin(), data.end());
  putLittleEndian16(out, crc16(out.data(), out.size()));
  return out;
}

Bytes changeOperatingMode(std::uint8_t mode) {
  return encode(kChangeOperatingMode, Bytes(1, mode));
}

Bytes enterInstallationMode(const std::string& password) {
  Bytes data;
  data.reserve(1 + password.size());
  data.push_back(kModeInstallation);
  data.insert(data.end(), password.begin(), password.end());
  return encode(kChangeOperatingMode, data);
}

Bytes switchVariant(std::uint16_t angle_deg, std::uint16_t resolution_centidegrees) {
  Bytes data;
  data.reserve(4);
  putLittleEndian16(data, angle_deg);
  putLittleEndian16(data, resolution_centidegrees);
  return encode(kSwitchVariant, data);
}

Bytes requestStatus() {
  return encode(kRequestStatus, {});
}

std::vector<ParseEvent> Parser::feed(const std::uint8_t* data, std::size_t size) {
  buffer_.insert(buffer_.end(), data, data + size);
  std::vector<ParseEvent> events;
  std::size_t position = 0;
  std::size_t skipped = 0;
  auto flushSkipped = [&] {
    if (skipped == 0) return;
    events.push_back({ParseEvent::Kind::kSkipped, {}, skipped});
    skipped = 0;
  };
  while (position < buffer_.size()) {
    const std::uint8_t byte = buffer_[position];
    if ((byte == kAck || byte == kNak) && resynchronising_) {
      ++skipped;  // a byte of the corrupt telegram's data, not an answer
      ++position;
      continue;
    }
    if (byte == kAck || byte == kNak) {
      flushSkipped();
      events.push_back(
          {byte == kAck ? ParseEvent::Kind::kAcknowledged : ParseEvent::Kind::kRefused, {}, 0});
      ++position;
      continue;
    }
    if (byte != kStx) {
      ++skipped;
      ++position;
      continue;
    }
    if (buffer_.size() - position < 4) break;  // the header is still arriving
    const std::size_t length = littleEndian16(&buffer_[position + 2]);
    if (!plausibleLength(length)) {  // not a telegram start after all
      ++skipped;
      ++position;
      continue;
    }
    const std::size_t total = 4 + length + 2;
    if (buffer_.size() - position < total) break;  // wait for the rest
    const std::uint16_t expected = littleEndian16(&buffer_[position + 4 + length]);
    if (crc16(&buffer_[position], 4 + length) != expected) {
      // Corrupt, or an STX inside other data. When its header is plausible and the bytes after it
      // start a telegram (or are an ACK/NAK), its length was right: the whole telegram is one
      // corrupt telegram, skipped at once, and the 0x02 bytes in its data are never taken for
      // telegram starts. Wait for those bytes.
      const std::size_t end = position + total;
      const bool plausible = isAddress(buffer_[position + 1]);
      if (plausible && buffer_.size() == end) break;
      if (plausible && buffer_[end] == kStx && buffer_.size() - end < 4) break;
      if (plausible && startsSomething(&buffer_[end])) {
        flushSkipped();
        events.push_back({ParseEvent::Kind::kBadCrc, {}, total});
        resynchronising_ = false;
        position = end;
        continue;
      }
      // Where it ends is unknown: drop this STX and look again from the next byte. Until a
      // telegram arrives whole (or a corrupt one is found whole), the telegram starts that fail on
      // the way, in the corrupt telegram's data, are skipped bytes: one corruption, one bad CRC.
      if (resynchronising_) {
        ++skipped;
      } else {
        flushSkipped();
        events.push_back({ParseEvent::Kind::kBadCrc, {}, 1});
        resynchronising_ = true;
      }
      ++position;
      continue;
    }
    flushSkipped();
    resynchronising_ = false;
    ParseEvent event{ParseEvent::Kind::kTelegram, {}, 0};
    event.telegram.address = buffer_[position + 1];
    event.telegram.command = buffer_[position + 4];
    event.telegram.data.assign(buffer_.begin() + std::ptrdiff_t(position + 5),
                               buffer_.begin() + std::ptrdiff_t(position + 4 + length));
    events.push_back(std::move(event));
    position += total;
  }
  flushSkipped();
  buffer_.erase(buffer_.begin(), buffer_.begin() + std::ptrdiff_t(position));
  return events;
}

MeasuredValues decodeMeasuredValues(const Telegram& reply) {
  if (reply.command != kMeasuredValuesReply)
    throw std::invalid_argument("not a measured-values reply (0xB0)");
  if (reply.data.size() < 3) throw std::invalid_argument("measured-values reply too short");
  const std::uint16_t header = littleEndian16(reply.data.data());
  const std::size_t count = header & 0x3FF;
  const unsigned unit = (header >> 14) & 0x3;
  if (reply.data.size() != 2 + 2 * count + 1)
    throw std::invalid_argument("measured-values reply of " + std::to_string(reply.data.size()) +
                                " bytes does not hold " + std::to_string(count) +
                                " values and a status");
  MeasuredValues values;
  values.unit_m = unit == 1 ? 0.001 : 0.01;
  values.status = reply.data.back();
  values.ranges.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint16_t raw = littleEndian16(&reply.data[2 + 2 * k]) & kDistanceMask;
    if (raw >= kFirstErrorCode) {
      values.ranges.emplace_back(std::nullopt);
    } else {
      values.ranges.emplace_back(raw * values.unit_m);
    }
  }
  return values;
}

}  // namespace clearway::hardware::lms200
