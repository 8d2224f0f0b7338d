#include "clearway/hardware/remote_protocol.h"

#include <QtEndian>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

namespace clearway::hardware::remote {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// Ranges travel in millimetres as the LMS200 sends them; 0 means "no finite point".
constexpr double kMetresPerUnit = 0.001;
constexpr std::uint16_t kMaxRangeUnits = 65535;
// Alpha start and step are rounded to this many degrees, so a float alpha of 0.5 deg is 0.5.
constexpr double kAlphaRoundingDeg = 1e-4;

// Appends big-endian fields to a payload.
class Writer {
 public:
  void u8(std::uint8_t v) { bytes_.append(char(v)); }
  void u16(std::uint16_t v) { raw(qToBigEndian(quint16(v))); }
  void u32(std::uint32_t v) { raw(qToBigEndian(quint32(v))); }
  void u64(std::uint64_t v) { raw(qToBigEndian(quint64(v))); }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void text(const QString& s) {
    QByteArray utf8 = s.toUtf8();
    if (utf8.size() > kMaxTextBytes) utf8.truncate(kMaxTextBytes);
    u16(std::uint16_t(utf8.size()));
    bytes_.append(utf8);
  }
  void bytes(const QByteArray& b) { bytes_.append(b); }
  QByteArray take() { return std::move(bytes_); }

 private:
  template <typename T>
  void raw(T v) {
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  QByteArray bytes_;
};

// Reads big-endian fields from a payload; running past its end throws.
class Reader {
 public:
  Reader(const Frame& frame, MessageType expected) : data_(frame.payload) {
    if (frame.type != expected)
      throw ProtocolError("expected a " + messageTypeName(expected).toStdString() + " frame, got " +
                          messageTypeName(frame.type).toStdString());
  }
  std::uint8_t u8() { return std::uint8_t(take(1)[0]); }
  std::uint16_t u16() { return qFromBigEndian<std::uint16_t>(take(2)); }
  std::uint32_t u32() { return qFromBigEndian<std::uint32_t>(take(4)); }
  std::uint64_t u64() { return qFromBigEndian<quint64>(take(8)); }
  double f64() {
    const std::uint64_t bits = u64();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  double finite(const char* field) {
    const double v = f64();
    if (!std::isfinite(v)) throw ProtocolError(std::string(field) + " is not a finite number");
    return v;
  }
  QString text(const char* field) {
    const std::uint16_t size = u16();
    if (size > kMaxTextBytes)
      throw ProtocolError(std::string(field) + " is longer than " + std::to_string(kMaxTextBytes) +
                          " bytes");
    const char* p = take(size);
    return QString::fromUtf8(p, size);
  }
  QByteArray bytes(int size) { return QByteArray(take(size), size); }
  void end() const {
    if (offset_ != data_.size())
      throw ProtocolError(std::to_string(data_.size() - offset_) + " unexpected bytes after the " +
                          "message");
  }

 private:
  const char* take(qsizetype size) {
    if (size < 0 || data_.size() - offset_ < size) throw ProtocolError("the message is truncated");
    const char* p = data_.constData() + offset_;
    offset_ += size;
    return p;
  }
  const QByteArray& data_;
  qsizetype offset_ = 0;
};

bool knownType(std::uint8_t type) {
  return (type >= 1 && type <= 5) || (type >= 16 && type <= 22);
}

Frame frameOf(MessageType type, Writer& writer) {
  return Frame{kProtocolVersion, type, writer.take()};
}

Role roleOf(std::uint8_t value) {
  if (value > std::uint8_t(Role::kWatch))
    throw ProtocolError("role " + std::to_string(value) + " is not a role");
  return Role(value);
}

double roundAlpha(double degrees) {
  return std::round(degrees / kAlphaRoundingDeg) * kAlphaRoundingDeg;
}

}  // namespace

QString messageTypeName(MessageType type) {
  switch (type) {
    case MessageType::kHello:
      return "Hello";
    case MessageType::kStartScan:
      return "StartScan";
    case MessageType::kCancel:
      return "Cancel";
    case MessageType::kResume:
      return "Resume";
    case MessageType::kPing:
      return "Ping";
    case MessageType::kWelcome:
      return "Welcome";
    case MessageType::kRefused:
      return "Refused";
    case MessageType::kScanStarted:
      return "ScanStarted";
    case MessageType::kLines:
      return "Lines";
    case MessageType::kScanFinished:
      return "ScanFinished";
    case MessageType::kPong:
      return "Pong";
    case MessageType::kNotice:
      return "Notice";
  }
  return QString("type %1").arg(int(type));
}

QByteArray encodeFrame(const Frame& frame) {
  Writer writer;
  writer.u32(std::uint32_t(kFrameHeaderBytes + frame.payload.size()));
  writer.u16(frame.version);
  writer.u8(std::uint8_t(frame.type));
  writer.bytes(frame.payload);
  return writer.take();
}

std::optional<Frame> FrameParser::next() {
  if (buffer_.size() < kLengthBytes + kFrameHeaderBytes) return std::nullopt;
  const auto* p = reinterpret_cast<const uchar*>(buffer_.constData());
  const std::uint32_t length = qFromBigEndian<std::uint32_t>(p);
  if (length < std::uint32_t(kFrameHeaderBytes) || length > kMaxFrameBytes)
    throw ProtocolError("frame length " + std::to_string(length) + " outside 3.." +
                        std::to_string(kMaxFrameBytes));
  const std::uint8_t type = p[6];
  if (!knownType(type)) throw ProtocolError("unknown message type " + std::to_string(type));
  if (std::uint64_t(buffer_.size()) < kLengthBytes + std::uint64_t(length)) return std::nullopt;
  Frame frame;
  frame.version = qFromBigEndian<std::uint16_t>(p + kLengthBytes);
  frame.type = MessageType(type);
  frame.payload = buffer_.mid(kLengthBytes + kFrameHeaderBytes, length - kFrameHeaderBytes);
  buffer_.remove(0, kLengthBytes + int(length));
  return frame;
}

// --- encoders -----------------------------------------------------------------------------------

Frame encode(const Hello& message) {
  Writer w;
  w.u8(std::uint8_t(message.role));
  w.bytes(message.session_token.leftJustified(kSessionTokenBytes, '\0', true));
  w.text(message.client_name);
  return frameOf(MessageType::kHello, w);
}

Frame encode(const Welcome& message) {
  Writer w;
  w.u8(std::uint8_t(message.granted));
  w.text(message.robot);
  w.text(message.note);
  w.u64(message.active_scan);
  return frameOf(MessageType::kWelcome, w);
}

Frame encode(const StartScan& message) {
  Writer w;
  w.u32(message.lines);
  w.f64(message.turntable_speed_deg_s);
  return frameOf(MessageType::kStartScan, w);
}

Frame encode(const Resume& message) {
  Writer w;
  w.u64(message.scan_id);
  w.u32(message.from_line);
  return frameOf(MessageType::kResume, w);
}

namespace {

// A pose on the wire: has pose u8, then position 3 x f64 and rotation 9 x f64 row-major.
void writePose(Writer& w, const std::optional<SensorPose>& pose) {
  w.u8(pose ? 1 : 0);
  if (!pose) return;
  for (const double v : pose->position)
    w.f64(v);
  for (const double v : pose->rotation)
    w.f64(v);
}

}  // namespace

Frame encode(const ScanStarted& message) {
  Writer w;
  w.u64(message.scan_id);
  w.u32(message.expected_lines);
  writePose(w, message.pose);
  return frameOf(MessageType::kScanStarted, w);
}

Frame encode(const Lines& message) {
  Writer w;
  w.u64(message.scan_id);
  w.u32(message.first_line);
  w.u16(std::uint16_t(message.lines.size()));
  for (const LineRecord& line : message.lines) {
    w.f64(line.beta);
    w.f64(line.alpha_first_deg);
    w.f64(line.alpha_step_deg);
    w.u16(std::uint16_t(line.range_mm.size()));
    for (const std::uint16_t v : line.range_mm)
      w.u16(v);
    for (const std::uint16_t v : line.intensity)
      w.u16(v);
    for (const std::uint8_t v : line.status)
      w.u8(v);
  }
  return frameOf(MessageType::kLines, w);
}

Frame encode(const ScanFinished& message) {
  Writer w;
  w.u64(message.scan_id);
  w.u32(message.total_lines);
  w.u8(message.complete ? 1 : 0);
  writePose(w, message.pose);
  w.text(message.saved_as);
  w.text(message.reason);
  return frameOf(MessageType::kScanFinished, w);
}

Frame encodeText(MessageType type, const QString& text) {
  Writer w;
  w.text(text);
  return frameOf(type, w);
}

Frame encodeEmpty(MessageType type) {
  Writer w;
  return frameOf(type, w);
}

Frame encodeStamp(MessageType type, std::uint64_t stamp) {
  Writer w;
  w.u64(stamp);
  return frameOf(type, w);
}

// --- decoders -----------------------------------------------------------------------------------

Hello decodeHello(const Frame& frame) {
  Reader r(frame, MessageType::kHello);
  Hello message;
  message.role = roleOf(r.u8());
  message.session_token = r.bytes(kSessionTokenBytes);
  message.client_name = r.text("the client name");
  r.end();
  return message;
}

Welcome decodeWelcome(const Frame& frame) {
  Reader r(frame, MessageType::kWelcome);
  Welcome message;
  message.granted = roleOf(r.u8());
  message.robot = r.text("the robot description");
  message.note = r.text("the note");
  message.active_scan = r.u64();
  r.end();
  return message;
}

StartScan decodeStartScan(const Frame& frame) {
  Reader r(frame, MessageType::kStartScan);
  StartScan message;
  message.lines = r.u32();
  if (message.lines > kMaxLinesPerScan)
    throw ProtocolError(std::to_string(message.lines) + " lines is more than a scan may have (" +
                        std::to_string(kMaxLinesPerScan) + ")");
  message.turntable_speed_deg_s = r.finite("the turntable speed");
  if (message.turntable_speed_deg_s < 0.0 || message.turntable_speed_deg_s > 360.0)
    throw ProtocolError("turntable speed outside 0..360 deg/s");
  r.end();
  return message;
}

Resume decodeResume(const Frame& frame) {
  Reader r(frame, MessageType::kResume);
  Resume message;
  message.scan_id = r.u64();
  message.from_line = r.u32();
  if (message.from_line > kMaxLinesPerScan) throw ProtocolError("resume line out of range");
  r.end();
  return message;
}

namespace {

// The pose writePose() wrote.
std::optional<SensorPose> readPose(Reader& r) {
  const std::uint8_t has_pose = r.u8();
  if (has_pose > 1) throw ProtocolError("a flag is neither 0 nor 1");
  if (has_pose == 0) return std::nullopt;
  SensorPose pose;
  for (double& v : pose.position)
    v = r.finite("the pose");
  for (double& v : pose.rotation)
    v = r.finite("the pose");
  return pose;
}

}  // namespace

ScanStarted decodeScanStarted(const Frame& frame) {
  Reader r(frame, MessageType::kScanStarted);
  ScanStarted message;
  message.scan_id = r.u64();
  message.expected_lines = r.u32();
  if (message.expected_lines > kMaxLinesPerScan) throw ProtocolError("expected lines out of range");
  message.pose = readPose(r);
  r.end();
  return message;
}

Lines decodeLines(const Frame& frame) {
  Reader r(frame, MessageType::kLines);
  Lines message;
  message.scan_id = r.u64();
  message.first_line = r.u32();
  const std::uint16_t count = r.u16();
  if (count == 0 || count > kMaxLinesPerFrame)
    throw ProtocolError("a Lines frame must carry 1.." + std::to_string(kMaxLinesPerFrame) +
                        " lines, not " + std::to_string(count));
  if (std::uint64_t(message.first_line) + count > kMaxLinesPerScan)
    throw ProtocolError("line index out of range");
  message.lines.resize(count);
  for (LineRecord& line : message.lines) {
    line.beta = r.finite("beta");
    line.alpha_first_deg = r.finite("alpha");
    line.alpha_step_deg = r.finite("the alpha step");
    if (std::abs(line.alpha_first_deg) > 360.0 || std::abs(line.alpha_step_deg) > 10.0)
      throw ProtocolError("alpha outside the LMS200's field of view");
    const std::uint16_t points = r.u16();
    if (points == 0 || points > kMaxPointsPerLine)
      throw ProtocolError("a line must have 1.." + std::to_string(kMaxPointsPerLine) +
                          " points, not " + std::to_string(points));
    line.range_mm.resize(points);
    line.intensity.resize(points);
    line.status.resize(points);
    for (auto& v : line.range_mm)
      v = r.u16();
    for (auto& v : line.intensity)
      v = r.u16();
    for (auto& v : line.status) {
      v = r.u8();
      if (v > std::uint8_t(PointStatus::kSelfHit))
        throw ProtocolError("point status " + std::to_string(v) + " is not a status");
    }
  }
  r.end();
  return message;
}

ScanFinished decodeScanFinished(const Frame& frame) {
  Reader r(frame, MessageType::kScanFinished);
  ScanFinished message;
  message.scan_id = r.u64();
  message.total_lines = r.u32();
  if (message.total_lines > kMaxLinesPerScan) throw ProtocolError("total lines out of range");
  const std::uint8_t complete = r.u8();
  if (complete > 1) throw ProtocolError("a flag is neither 0 nor 1");
  message.complete = complete == 1;
  message.pose = readPose(r);
  message.saved_as = r.text("the saved file");
  message.reason = r.text("the reason");
  r.end();
  return message;
}

QString decodeText(const Frame& frame) {
  if (frame.type != MessageType::kRefused && frame.type != MessageType::kNotice)
    throw ProtocolError("expected a Refused or Notice frame, got " +
                        messageTypeName(frame.type).toStdString());
  Frame copy = frame;
  copy.type = MessageType::kNotice;
  Reader r(copy, MessageType::kNotice);
  QString text = r.text("the text");
  r.end();
  return text;
}

std::uint64_t decodeStamp(const Frame& frame) {
  if (frame.type != MessageType::kPing && frame.type != MessageType::kPong)
    throw ProtocolError("expected a Ping or Pong frame, got " +
                        messageTypeName(frame.type).toStdString());
  Reader r(frame, frame.type);
  const std::uint64_t stamp = r.u64();
  r.end();
  return stamp;
}

void decodeEmpty(const Frame& frame) {
  Reader r(frame, frame.type);
  r.end();
}

// --- scans
// ----------------------------------------------------------------------------------------

std::vector<LineRecord> encodeScanLines(const Scan& scan, std::size_t first, std::size_t count) {
  std::vector<LineRecord> records;
  records.reserve(count);
  for (std::size_t l = first; l < first + count && l < scan.lines.size(); ++l) {
    const ScanLine& line = scan.lines[l];
    LineRecord record;
    record.beta = std::isfinite(line.beta) ? line.beta : 0.0;
    if (!scan.alpha.empty() && line.count > 0) {
      record.alpha_first_deg = roundAlpha(scan.alpha[line.first] / kDeg);
      if (line.count > 1)
        record.alpha_step_deg =
            roundAlpha((scan.alpha[line.first + 1] - scan.alpha[line.first]) / kDeg);
    }
    record.range_mm.resize(line.count);
    record.intensity.resize(line.count);
    record.status.resize(line.count);
    for (std::size_t k = 0; k < line.count; ++k) {
      const std::size_t i = line.first + k;
      const Point3f& p = scan.points[i];
      const double range =
          std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z) / kMetresPerUnit;
      record.range_mm[k] =
          std::isfinite(range)
              ? std::uint16_t(std::clamp(std::lround(range), 1L, long(kMaxRangeUnits)))
              : 0;
      const float intensity = scan.intensity.empty() ? 0.0F : scan.intensity[i];
      record.intensity[k] = std::isfinite(intensity)
                                ? std::uint16_t(std::clamp(std::lround(intensity), 0L, 65535L))
                                : 0;
      record.status[k] = std::uint8_t(scan.status[i]);
      if (record.range_mm[k] == 0) record.status[k] = std::uint8_t(PointStatus::kNoReturn);
    }
    records.push_back(std::move(record));
  }
  return records;
}

void appendLineRecords(Scan& scan, const std::vector<LineRecord>& lines) {
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  for (const LineRecord& record : lines) {
    scan.lines.push_back({scan.size(), record.range_mm.size(), record.beta});
    for (std::size_t k = 0; k < record.range_mm.size(); ++k) {
      // The RoSi's own formula (paper eq. 1-3), in the same order as the acquisition computes it.
      const double alpha = (record.alpha_first_deg + double(k) * record.alpha_step_deg) * kDeg;
      scan.alpha.push_back(float(alpha));
      scan.intensity.push_back(float(record.intensity[k]));
      if (record.range_mm[k] == 0) {
        scan.points.push_back({nan, nan, nan});
        scan.status.push_back(PointStatus::kNoReturn);
        continue;
      }
      const double d = record.range_mm[k] * kMetresPerUnit;
      scan.points.push_back({float(std::cos(record.beta) * std::cos(alpha) * d),
                             float(std::sin(record.beta) * std::cos(alpha) * d),
                             float(std::sin(alpha) * d)});
      scan.status.push_back(PointStatus(record.status[k]));
    }
  }
}

Scan scanFromLineRecords(const std::vector<LineRecord>& lines,
                         const std::optional<SensorPose>& pose) {
  Scan scan;
  appendLineRecords(scan, lines);
  scan.sensor_pose = pose;
  scan.metadata.format = "clearway remote protocol v" + std::to_string(kProtocolVersion);
  return scan;
}

std::size_t wireBytesForLines(const std::vector<LineRecord>& lines, int lines_per_frame) {
  std::size_t bytes = 0;
  for (std::size_t first = 0; first < lines.size(); first += std::size_t(lines_per_frame)) {
    Lines message;
    message.first_line = std::uint32_t(first);
    const std::size_t end = std::min(lines.size(), first + std::size_t(lines_per_frame));
    message.lines.assign(lines.begin() + std::ptrdiff_t(first),
                         lines.begin() + std::ptrdiff_t(end));
    bytes += std::size_t(encodeFrame(encode(message)).size());
  }
  return bytes;
}

}  // namespace clearway::hardware::remote
