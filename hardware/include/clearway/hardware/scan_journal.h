#pragma once

// The acquisition journal (docs/JOURNAL.md): every measured-values line and every turntable angle
// is appended to SCAN.journal as it arrives, so a crash, kill -9 or power cut keeps what was
// received. Each record is one text line written with a single write(); a thread of the journal's
// own fdatasyncs the file every kSyncPeriodMs, so a slow disk never holds up reading the devices
// (a late read would make late line stamps). A clean finish turns the
// journal into the PCD and removes it; `clearway-cli acquire --recover` turns a journal left by a
// crash into a partial scan through the same assembly as the live acquisition.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "clearway/hardware/pose_source.h"
#include "clearway/hardware/serial_acquisition.h"
#include "clearway/hardware/turntable_protocol.h"

namespace clearway::hardware {

class ScanJournal {
 public:
  static constexpr int kSyncPeriodMs = 500;  // a power cut costs at most this much

  // Creates `path`; refuses one that exists (it may hold a scan not yet recovered). error() says
  // why the journal cannot be written; the acquisition then runs without one and says so.
  ScanJournal(std::filesystem::path path, int target_lines);
  ~ScanJournal();  // closes; never removes
  ScanJournal(const ScanJournal&) = delete;
  ScanJournal& operator=(const ScanJournal&) = delete;

  // Why the journal could not be created, or why a write failed (a full disk), with the system's
  // words; empty while all is written. After a failed write nothing more is written: a record
  // appended once space came back would follow a torn one and make the journal corrupt, so it
  // keeps the records before the failure, recoverable.
  const std::string& error() const { return error_; }
  // Measured-values lines the journal holds whole: every line given, until a write failed.
  std::size_t lines() const { return lines_; }
  const std::filesystem::path& path() const { return path_; }

  void pose(const PoseReading& reading);
  void angle(const turntable::AngleSample& sample);
  // `ranges`: the RoSi's 180 ranges [m], none for no echo.
  void line(std::int64_t time_us, const std::vector<std::optional<double>>& ranges);
  // A telegram lost to corruption, read at `time_us`.
  void dropped(std::int64_t time_us, const std::string& reason);
  void end(bool complete, const std::string& reason);
  void sync();
  // After the scan was saved: the journal is no longer needed.
  void remove();

 private:
  bool record(const std::string& text);  // false: not written (now or before)
  std::filesystem::path path_;
  std::string error_;
  std::size_t lines_ = 0;
  int fd_ = -1;
  std::atomic<int> fd_for_sync_{-1};
  std::mutex sync_mutex_;
  std::condition_variable sync_wake_;
  bool stopping_ = false;
  std::thread syncer_;
  void stopSyncing();
};

// Replays a journal into the scan it holds (incomplete unless the journal says it ended
// complete). Throws ScanError naming the file for a file that is no journal or is corrupt before
// its last line; a torn last line (the crash cut it) is ignored.
Acquisition recoverJournal(const std::filesystem::path& journal);

}  // namespace clearway::hardware
