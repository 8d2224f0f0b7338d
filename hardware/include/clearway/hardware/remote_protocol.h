#pragma once

// The Clearway remote protocol (docs/PROTOCOL.md) between `clearway-cli serve` on the robot and a
// console: length-prefixed, versioned frames, each encoded and decoded by pure functions that
// validate every field. Nothing here touches a socket; the server and RemoteRosi feed bytes in and
// take bytes out. A decoder throws ProtocolError with a readable reason for anything malformed.

#include <QByteArray>
#include <QString>
#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

#include "clearway/scan.h"

namespace clearway::hardware::remote {

// Version 1 is the first; a frame of any other version is refused with a reason.
// Version 2: ScanStarted carries the scan's pose once the robot knows it (a console that loses the
// link mid-scan keeps its partial scan with the pose). A peer of another version is refused with
// both versions named.
constexpr std::uint16_t kProtocolVersion = 2;
// Bytes before a frame's payload: uint32 length (of version + type + payload), uint16 version,
// uint8 type. All integers big-endian.
constexpr int kLengthBytes = 4;
constexpr int kFrameHeaderBytes = 3;  // version + type, counted in the length
// No frame may be longer: a Lines frame of kMaxLinesPerFrame full lines needs about 15 kB, so
// anything near this limit is an attack or a bug, refused before it is buffered.
constexpr std::uint32_t kMaxFrameBytes = 64 * 1024;
constexpr int kMaxLinesPerFrame = 16;
constexpr int kMaxPointsPerLine = 1024;  // the LMS200 gives at most 401 values per telegram
constexpr int kMaxTextBytes = 1024;      // descriptions, reasons, names
constexpr int kSessionTokenBytes = 16;
constexpr std::uint32_t kMaxLinesPerScan = 100000;  // the same bound `acquire --lines` has

class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class MessageType : std::uint8_t {
  // console -> robot
  kHello = 1,
  kStartScan = 2,
  kCancel = 3,
  kResume = 4,
  kPing = 5,
  // robot -> console
  kWelcome = 16,
  kRefused = 17,
  kScanStarted = 18,
  kLines = 19,
  kScanFinished = 20,
  kPong = 21,
  kNotice = 22,
};
QString messageTypeName(MessageType type);

enum class Role : std::uint8_t { kControl = 0, kWatch = 1 };

struct Frame {
  std::uint16_t version = kProtocolVersion;
  MessageType type = MessageType::kPing;
  QByteArray payload;
};

// The bytes of one frame on the wire.
QByteArray encodeFrame(const Frame& frame);

// Splits a byte stream into frames. A length outside [kFrameHeaderBytes, kMaxFrameBytes] or an
// unknown message type throws ProtocolError at once, before the payload is buffered, so a peer can
// never make the buffer grow beyond one frame. Version checks are the caller's (to answer with a
// reason).
class FrameParser {
 public:
  void feed(const QByteArray& bytes) { buffer_.append(bytes); }
  // The next complete frame, or nothing while it is incomplete.
  std::optional<Frame> next();
  qsizetype buffered() const { return buffer_.size(); }

 private:
  QByteArray buffer_;
};

// --- messages -----------------------------------------------------------------------------------

struct Hello {
  Role role = Role::kControl;
  QByteArray session_token;  // kSessionTokenBytes random bytes; a reconnect sends the same
  QString client_name;
};

struct Welcome {
  Role granted = Role::kWatch;
  QString robot;                  // the device's description
  QString note;                   // e.g. why control was not granted
  std::uint64_t active_scan = 0;  // 0: no scan running
};

struct StartScan {
  std::uint32_t lines = 0;  // 0: one revolution at the device's default
  double turntable_speed_deg_s = 0.0;
};

struct Resume {
  std::uint64_t scan_id = 0;
  std::uint32_t from_line = 0;
};

struct ScanStarted {
  std::uint64_t scan_id = 0;
  std::uint32_t expected_lines = 0;
  // The scan's sensor pose, once the robot knows it: it is repeated, with the pose, before the
  // first lines (a serial RoSi reads it from the arm as the scan starts) and on a Resume.
  std::optional<SensorPose> pose;
};

// One scan line as the wire carries it, at the LMS200's own resolution: ranges in millimetres,
// alpha as start + k * step, beta exact.
struct LineRecord {
  double beta = 0.0;             // turntable angle [rad]
  double alpha_first_deg = 0.0;  // measurement angle of the first point
  double alpha_step_deg = 0.5;
  std::vector<std::uint16_t> range_mm;   // 0 when the point has no finite coordinates
  std::vector<std::uint16_t> intensity;  // remission, rounded
  std::vector<std::uint8_t> status;      // PointStatus
};

struct Lines {
  std::uint64_t scan_id = 0;
  std::uint32_t first_line = 0;
  std::vector<LineRecord> lines;
};

struct ScanFinished {
  std::uint64_t scan_id = 0;
  std::uint32_t total_lines = 0;
  bool complete = false;
  std::optional<SensorPose> pose;
  QString saved_as;  // the file on the robot
  QString reason;    // why it is incomplete
};

Frame encode(const Hello& message);
Frame encode(const Welcome& message);
Frame encode(const StartScan& message);
Frame encode(const Resume& message);
Frame encode(const ScanStarted& message);
Frame encode(const Lines& message);
Frame encode(const ScanFinished& message);
Frame encodeText(MessageType type, const QString& text);   // kRefused, kNotice
Frame encodeEmpty(MessageType type);                       // kCancel
Frame encodeStamp(MessageType type, std::uint64_t stamp);  // kPing, kPong

// Each decoder checks the frame's type, every field's range and that the payload is consumed
// exactly; anything else throws ProtocolError.
Hello decodeHello(const Frame& frame);
Welcome decodeWelcome(const Frame& frame);
StartScan decodeStartScan(const Frame& frame);
Resume decodeResume(const Frame& frame);
ScanStarted decodeScanStarted(const Frame& frame);
Lines decodeLines(const Frame& frame);
ScanFinished decodeScanFinished(const Frame& frame);
QString decodeText(const Frame& frame);
std::uint64_t decodeStamp(const Frame& frame);
void decodeEmpty(const Frame& frame);

// --- scans ↔ line records
// ---------------------------------------------------------------------------

// Lines [first, first + count) of `scan` at wire resolution.
std::vector<LineRecord> encodeScanLines(const Scan& scan, std::size_t first, std::size_t count);
// Appends decoded lines to `scan` (points as the RoSi computes them from range, alpha and beta).
void appendLineRecords(Scan& scan, const std::vector<LineRecord>& lines);
// A whole scan from its records.
Scan scanFromLineRecords(const std::vector<LineRecord>& lines,
                         const std::optional<SensorPose>& pose);
// Wire bytes of the Lines frames that carry `lines`, kLinesPerFrame to a frame.
std::size_t wireBytesForLines(const std::vector<LineRecord>& lines, int lines_per_frame);

}  // namespace clearway::hardware::remote
