#pragma once

// The SICK LMS200 serial telegram protocol as pure functions (no I/O), so it can be tested byte
// by byte. Telegram: STX 0x02, address (0x00 to the scanner, 0x80 from it), length (16-bit
// little-endian, bytes of command + data), command, data, [status in replies], CRC-16 (SICK's,
// little-endian) over everything before it. The scanner acknowledges a request with ACK 0x06 or
// NAK 0x15 before its reply.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace clearway::hardware::lms200 {

using Bytes = std::vector<std::uint8_t>;

inline constexpr std::uint8_t kStx = 0x02;
inline constexpr std::uint8_t kAck = 0x06;
inline constexpr std::uint8_t kNak = 0x15;
inline constexpr std::uint8_t kToScanner = 0x00;
inline constexpr std::uint8_t kFromScanner = 0x80;
// The longest telegram the LMS200 sends is well under this; longer lengths mean corruption.
inline constexpr std::size_t kMaxPayload = 1024;

// Commands and replies used by Clearway.
inline constexpr std::uint8_t kChangeOperatingMode = 0x20;
inline constexpr std::uint8_t kRequestStatus = 0x31;
inline constexpr std::uint8_t kSwitchVariant = 0x3B;
inline constexpr std::uint8_t kMeasuredValuesReply = 0xB0;

// Operating modes (argument of kChangeOperatingMode).
inline constexpr std::uint8_t kModeInstallation = 0x00;      // needs the password
inline constexpr std::uint8_t kModeContinuousOutput = 0x24;  // all measured values, continuously
inline constexpr std::uint8_t kModeValuesOnRequest = 0x25;   // stops continuous output
inline constexpr std::uint8_t kModeBaud38400 = 0x40;
inline constexpr std::uint8_t kModeBaud19200 = 0x41;
inline constexpr std::uint8_t kModeBaud9600 = 0x42;
inline constexpr std::uint8_t kModeBaud500k = 0x48;

// SICK's CRC-16 (generator 0x8005, shifted over pairs of bytes) of a byte range.
std::uint16_t crc16(const std::uint8_t* data, std::size_t size);

// A complete telegram for `command` with `data`, to `address`.
Bytes encode(std::uint8_t command, const Bytes& data, std::uint8_t address = kToScanner);

// Ready-made requests.
Bytes changeOperatingMode(std::uint8_t mode);
Bytes enterInstallationMode(const std::string& password = "SICK_LMS");
// Scan angle [deg] and angular resolution [1/100 deg]: the RoSi uses 180 deg at 0.5 deg (50).
Bytes switchVariant(std::uint16_t angle_deg, std::uint16_t resolution_centidegrees);
Bytes requestStatus();

struct Telegram {
  std::uint8_t address = 0;
  std::uint8_t command = 0;
  Bytes data;  // for replies from the scanner, the status byte is the last byte
};

// What the parser found in the byte stream, in order.
struct ParseEvent {
  enum class Kind { kTelegram, kAcknowledged, kRefused, kBadCrc, kSkipped } kind = Kind::kSkipped;
  Telegram telegram;        // for kTelegram
  std::size_t skipped = 0;  // bytes dropped: garbage (kSkipped), the corrupt telegram (kBadCrc)
};

// Incremental parser: feed whatever the serial port delivered; complete telegrams come out,
// fragments wait for more bytes, garbage and corrupt telegrams are skipped and reported. One
// corrupt telegram is one kBadCrc: when its header is plausible (address 0x00 or 0x80, a length
// up to kMaxPayload) and the bytes after it start another such header or are an ACK/NAK, its
// length was right and it is skipped whole, so 0x02 bytes in its data are never taken for
// telegrams (it is reported once those first bytes after it have arrived). Otherwise the parser
// resynchronises byte by byte, and the telegram starts that fail on the way, and ACK/NAK bytes,
// are skipped bytes until a telegram arrives whole or a corrupt one is found whole. How the
// bytes are split between calls changes only how skipped bytes are grouped, no other event.
class Parser {
 public:
  std::vector<ParseEvent> feed(const std::uint8_t* data, std::size_t size);
  std::vector<ParseEvent> feed(const Bytes& bytes) { return feed(bytes.data(), bytes.size()); }
  std::size_t pending() const { return buffer_.size(); }

 private:
  Bytes buffer_;
  bool resynchronising_ = false;  // a corrupt telegram of unknown end was reported
};

// Distances of a measured-values reply (0xB0). Values the scanner flags as not measurable
// (dazzle, no echo, out of range) come back empty.
struct MeasuredValues {
  double unit_m = 0.01;                       // 1 cm or 1 mm per count
  std::vector<std::optional<double>> ranges;  // metres
  std::uint8_t status = 0;
};
// Throws std::invalid_argument when the data is not a well-formed measured-values reply.
MeasuredValues decodeMeasuredValues(const Telegram& reply);

}  // namespace clearway::hardware::lms200
