#pragma once

// The acquisition journal (docs/JOURNAL.md): every measured-values line and every turntable angle
// is appended to SCAN.journal as it arrives, so a crash, kill -9 or power cut keeps what was
// received. Each record is one text line written with a single write(); the file is fsynced
// every kSyncEveryLines lines or kSyncPeriodMs, whichever comes first. A clean finish turns the
// journal into the PCD and removes it; `clearway-cli acquire --recover` turns a journal left by a
// crash into a partial scan through the same assembly as the live acquisition.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "clearway/hardware/pose_source.h"
#include "clearway/hardware/serial_acquisition.h"
#include "clearway/hardware/turntable_protocol.h"

namespace clearway::hardware {

class ScanJournal {
 public:
  static constexpr int kSyncEveryLines = 32;  // about 1 s of lines at the LMS200's 37.5 lines/s
  static constexpr int kSyncPeriodMs = 500;

  // Creates `path`; refuses one that exists (it may hold a scan not yet recovered). error() says
  // why the journal cannot be written; the acquisition then runs without one and says so.
  ScanJournal(std::filesystem::path path, int target_lines);
  ~ScanJournal();  // closes; never removes
  ScanJournal(const ScanJournal&) = delete;
  ScanJournal& operator=(const ScanJournal&) = delete;

  const std::string& error() const { return error_; }
  const std::filesystem::path& path() const { return path_; }

  void pose(const PoseReading& reading);
  void angle(const turntable::AngleSample& sample);
  // `ranges`: the RoSi's 180 ranges [m], none for no echo.
  void line(std::int64_t time_us, const std::vector<std::optional<double>>& ranges);
  void dropped(const std::string& reason);
  void end(bool complete, const std::string& reason);
  void sync();
  // After the scan was saved: the journal is no longer needed.
  void remove();

 private:
  void record(const std::string& text, bool is_line);
  std::filesystem::path path_;
  std::string error_;
  int fd_ = -1;
  int lines_since_sync_ = 0;
  std::chrono::steady_clock::time_point last_sync_;
};

// Replays a journal into the scan it holds (incomplete unless the journal says it ended
// complete). Throws ScanError naming the file for a file that is no journal or is corrupt before
// its last line; a torn last line (the crash cut it) is ignored.
Acquisition recoverJournal(const std::filesystem::path& journal);

}  // namespace clearway::hardware
