#include "clearway/hardware/scan_journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"
#include "scan_assembler.h"

namespace clearway::hardware {
namespace {

constexpr const char* kMagic = "CLEARWAY-JOURNAL 1";
constexpr double kMillimetres = 1000.0;
// A journal line holds at most 180 ranges of 6 characters: anything much longer is corrupt.
constexpr std::size_t kMaxRecord = 4096;
// No LMS200 range reaches this far (81.91 m in its centimetre mode) [mm]: a larger one is no
// measurement (99999999999999999999 overflowed and was read).
constexpr long kFarthestRangeMm = 100'000;

}  // namespace

ScanJournal::ScanJournal(std::filesystem::path path, int target_lines) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    error_ = errno == EEXIST
                 ? path_.string() +
                       " exists: it may hold a scan not yet recovered (clearway-cli "
                       "acquire --recover " +
                       path_.string() + " -o SCAN.pcd), or remove it"
                 : "cannot create the journal " + path_.string() + ": " + std::strerror(errno);
    return;
  }
  record(std::string(kMagic) + "\nTARGET " + std::to_string(target_lines) + "\n");
  sync();
  fd_for_sync_ = fd_;
  syncer_ = std::thread([this] {
    std::unique_lock lock(sync_mutex_);
    while (!sync_wake_.wait_for(lock, std::chrono::milliseconds(kSyncPeriodMs),
                                [this] { return stopping_; }))
      if (const int fd = fd_for_sync_; fd >= 0) ::fdatasync(fd);
  });
}

void ScanJournal::stopSyncing() {
  {
    const std::lock_guard lock(sync_mutex_);
    stopping_ = true;
  }
  sync_wake_.notify_all();
  if (syncer_.joinable()) syncer_.join();
  fd_for_sync_ = -1;
}

ScanJournal::~ScanJournal() {
  stopSyncing();
  if (fd_ >= 0) {
    ::fsync(fd_);
    ::close(fd_);
  }
}

bool ScanJournal::record(const std::string& text) {
  if (fd_ < 0 || !error_.empty()) return false;
  // One write() per record: after kill -9 the kernel holds every record written, whole or not at
  // all but the last (a torn last record is ignored when recovering).
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      // A write of nothing to a regular file means no space.
      error_ = "cannot write the journal " + path_.string() + ": " +
               std::strerror(n < 0 ? errno : ENOSPC);
      return false;
    }
    done += std::size_t(n);
  }
  return true;
}

void ScanJournal::sync() {
  if (fd_ < 0) return;
  ::fdatasync(fd_);
}

void ScanJournal::pose(const PoseReading& reading) {
  const RigidPose& p = reading.world_from_scanner;
  std::ostringstream text;
  text.precision(12);
  text << "POSE " << reading.source << ' ' << p.translation.x() << ' ' << p.translation.y() << ' '
       << p.translation.z() << ' ' << p.rotation.w() << ' ' << p.rotation.x() << ' '
       << p.rotation.y() << ' ' << p.rotation.z() << ' ';
  if (reading.arm_tilt_deg)
    text << *reading.arm_tilt_deg;
  else
    text << '-';
  text << ' ';
  if (reading.arm_roll_deg)
    text << *reading.arm_roll_deg;
  else
    text << '-';
  text << ' ' << (reading.time.empty() ? std::string("-") : reading.time) << '\n';
  record(text.str());
}

void ScanJournal::angle(const turntable::AngleSample& sample) {
  std::ostringstream text;
  text << "A " << sample.time_us << ' ' << std::lround(sample.angle_deg * 1000.0) << '\n';
  record(text.str());
}

void ScanJournal::line(std::int64_t time_us, const std::vector<std::optional<double>>& ranges) {
  std::string text = "L ";
  text.reserve(ranges.size() * 6 + 24);
  text += std::to_string(time_us);
  for (const auto& range : ranges) {
    text += ' ';
    if (range)
      text += std::to_string(std::lround(*range * kMillimetres));
    else
      text += '-';
  }
  text += '\n';
  if (record(text)) ++lines_;
}

void ScanJournal::dropped(std::int64_t time_us, const std::string& reason) {
  std::string text = "D ";
  text += std::to_string(time_us);
  text += ' ';
  text += reason;
  text += '\n';
  record(text);
}

void ScanJournal::end(bool complete, const std::string& reason) {
  std::string text = complete ? "END complete" : "END incomplete";
  if (!reason.empty()) {
    text += ' ';
    text += reason;
  }
  text += '\n';
  record(text);
  sync();
}

void ScanJournal::remove() {
  stopSyncing();
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  std::error_code ignored;
  std::filesystem::remove(path_, ignored);
}

namespace {

[[noreturn]] void corrupt(const std::filesystem::path& file, std::size_t line_number,
                          const std::string& what) {
  throw ScanError(
      file, "line " + std::to_string(line_number) + " of the journal is corrupt (" + what + ")");
}

PoseReading parsePoseRecord(std::istringstream& words, const std::filesystem::path& file,
                            std::size_t number) {
  PoseReading reading;
  double v[7];
  std::string tilt, roll;
  if (!(words >> reading.source >> v[0] >> v[1] >> v[2] >> v[3] >> v[4] >> v[5] >> v[6] >> tilt >>
        roll >> reading.time))
    corrupt(file, number, "a POSE record needs a source, 7 numbers, tilt, roll and a time");
  reading.world_from_scanner.translation = {v[0], v[1], v[2]};
  reading.world_from_scanner.rotation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]);
  reading.source = printableText(reading.source);
  reading.time = printableText(reading.time);  // written into JSON, which needs UTF-8
  if (!reading.world_from_scanner.translation.allFinite() ||
      std::abs(reading.world_from_scanner.rotation.norm() - 1.0) > 1e-3)
    corrupt(file, number, "the POSE is not a finite rigid transform");
  reading.world_from_scanner.rotation.normalize();
  try {
    if (tilt != "-") reading.arm_tilt_deg = std::stod(tilt);
    if (roll != "-") reading.arm_roll_deg = std::stod(roll);
  } catch (const std::exception&) {
    corrupt(file, number, "the arm's tilt or roll is not a number");
  }
  if (reading.time == "-") reading.time.clear();
  return reading;
}

}  // namespace

Acquisition recoverJournal(const std::filesystem::path& file) {
  requireRegularFile(file);  // a pipe waited for ever, /dev/zero filled the memory
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ScanError(file, std::string("cannot open the journal: ") + std::strerror(errno));
  std::string text;
  // A journal's first line, read from a copy an editor re-saved (a byte-order mark, CRLF line
  // ends), was "not a journal": said as what it is.
  if (std::getline(in, text) && (text.starts_with("\xEF\xBB\xBF") || text.ends_with('\r')))
    throw ScanError(file,
                    "the journal was re-saved by an editor (a byte-order mark or CRLF line "
                    "ends): recover it from the original file");
  if (text != kMagic)
    throw ScanError(
        file, std::string("not a Clearway acquisition journal (it does not start with '") + kMagic +
                  "')");
  Acquisition result;
  std::optional<detail::ScanAssembler> assembler;
  std::size_t number = 1;
  bool ended = false;
  int target = 0;
  bool measured = false;  // an angle, line or dropped-line record was read
  while (std::getline(in, text)) {
    ++number;
    // A last line without its '\n' was cut by the crash: ignore it.
    if (in.eof()) break;
    if (text.size() > kMaxRecord) corrupt(file, number, "overlong record");
    // The journal is written in one order: TARGET, POSE, the scan's records, END. A record out
    // of it was taken as it came (a second TARGET dropped the lines before it, a POSE after the
    // lines replaced the pose the scan started with, records after END were added).
    if (ended) corrupt(file, number, "a record after END");
    std::istringstream words(text);
    std::string kind;
    words >> kind;
    if (kind == "TARGET") {
      if (assembler) corrupt(file, number, "a second TARGET");
      if (!(words >> target) || target < 0) corrupt(file, number, "TARGET needs a line count");
      assembler.emplace(target);
      continue;
    }
    if (!assembler) corrupt(file, number, "records before TARGET");
    if (kind == "POSE") {
      if (result.pose || measured) corrupt(file, number, "a POSE after the scan's first records");
      result.pose = parsePoseRecord(words, file, number);
      continue;
    }
    measured = measured || kind == "A" || kind == "L" || kind == "D";
    if (kind == "A") {
      turntable::AngleSample sample;
      std::int64_t millidegrees = 0;
      if (!(words >> sample.time_us >> millidegrees) || millidegrees < 0 || millidegrees >= 360000)
        corrupt(file, number, "an angle record needs a time and 0 .. 359999 millidegrees");
      sample.angle_deg = double(millidegrees) / 1000.0;
      assembler->addAngle(sample);
      assembler->place();
    } else if (kind == "L") {
      std::int64_t time_us = 0;
      if (!(words >> time_us)) corrupt(file, number, "a line record needs a time");
      detail::LineRanges ranges;
      std::string value;
      while (words >> value) {
        if (value == "-") {
          ranges.emplace_back();
          continue;
        }
        char* end = nullptr;
        errno = 0;
        const long millimetres = std::strtol(value.c_str(), &end, 10);
        if (*end != '\0' || millimetres < 0) corrupt(file, number, "a range is not a number");
        if (errno == ERANGE || millimetres > kFarthestRangeMm)
          corrupt(file, number, "a range of " + value + " mm, beyond any LMS200's reach");
        ranges.emplace_back(double(millimetres) / kMillimetres);
      }
      if (ranges.size() != std::size_t(detail::kRosiPoints))
        corrupt(file, number, "a line record needs 180 ranges");
      ++result.lines_received;
      assembler->addLine(time_us, std::move(ranges));
      assembler->place();
    } else if (kind == "D") {
      std::int64_t time_us = 0;
      if (!(words >> time_us)) corrupt(file, number, "a dropped-line record needs a time");
      ++result.dropped_lines;
      assembler->addLostTelegram(time_us);
      assembler->place();
    } else if (kind == "END") {
      std::string state;
      words >> state;
      result.complete = state == "complete";
      std::getline(words >> std::ws, result.error);
      result.error = printableText(result.error);  // written into JSON, which needs UTF-8
      ended = true;
    } else {
      corrupt(file, number, "unknown record '" + kind + "'");
    }
  }
  if (!assembler) throw ScanError(file, "the journal holds no scan (it ends before TARGET)");
  // The lines still waiting for their stamps are placed as the acquisition placed them at its end
  // (a turn completed by them was saved as complete).
  const bool lines_complete = assembler->complete() || assembler->finishIncomplete();
  assembler->refine();
  // The acquisition that wrote the journal judged its lines as these are judged here.
  if (const std::string problem = assembler->sweepProblem(); result.complete && !problem.empty()) {
    result.complete = false;
    result.error = problem;
  }
  result.untagged_lines = assembler->untagged();
  result.scan = std::move(assembler->scan());
  if (result.pose) result.scan.sensor_pose = sensorPoseOf(result.pose->world_from_scanner);
  if (!ended)
    result.error = "recovered from " + file.filename().string() +
                   ": the acquisition ended without "
                   "finishing (a crash, a kill, or the journal's disk full) after " +
                   std::to_string(result.lines_received) + " lines";
  // "END complete" over fewer lines than the target is not a complete scan (159 of 400 lines were
  // recovered as complete).
  if (result.complete && result.lines_received < std::size_t(target)) {
    result.error = "the journal ends 'complete' after " + std::to_string(result.lines_received) +
                   " of its " + std::to_string(target) + " lines";
    result.complete = false;
  }
  if (result.complete && !lines_complete) {
    result.error = "the journal ends 'complete' but its lines make no complete scan";
    result.complete = false;
  }
  result.complete = result.complete && result.dropped_lines == 0 && ended;
  return result;
}

}  // namespace clearway::hardware
