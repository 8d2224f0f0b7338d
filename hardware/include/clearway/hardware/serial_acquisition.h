#pragma once

// Acquiring one RoSi scan from the real devices (or the emulator) over serial ports: the LMS200
// is put into installation mode, switched to 180 deg / 0.5 deg and continuous output; the turntable
// is homed and started; every measured-values line is tagged with the turntable angle interpolated
// at its arrival and kept until one revolution (or the requested lines) is complete. Blocking:
// the console runs it on a worker thread; clearway-cli acquire calls it directly.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "clearway/hardware/pose_source.h"
#include "clearway/progress.h"
#include "clearway/scan.h"

namespace clearway::hardware {

struct AcquisitionOptions {
  int lines = 0;  // 0 = one full revolution
  double turntable_speed_deg_s = 45.0;
  // The watchdog: a laser that sends no line, or a turntable that sends no angle or whose angle
  // does not change, for this long ends the acquisition with a reason (the lines kept).
  int answer_timeout_ms = 1000;
  // The LMS200 starts at 9600 baud; after setup it is switched to this: 9600, 19200, 38400 or
  // 500000 (the last needs an RS-422 interface).
  int baud = 38400;
  int max_bad_telegrams = 20;  // this many corrupt telegrams in a row: the link is unusable
  // Called with the scan so far every `lines_arrived_every` lines (on the acquiring thread).
  std::function<void(const Scan&)> lines_arrived;
  int lines_arrived_every = 16;
  // Every line and angle is appended here as it arrives (scan_journal.h); empty: no journal.
  std::filesystem::path journal;
  // Called once, on the acquiring thread, when a write to the journal first fails (its disk
  // full): `reason` names the journal and the cause, `lines_journaled` is how many lines it holds.
  // The acquisition goes on with every line in memory; the operator is to be told now, while the
  // scan can still be stopped or space made, not when it ends.
  std::function<void(const std::string& reason, std::size_t lines_journaled)> journal_failed;
  // Readable = stop now, as the operator asked (a self-pipe written by a signal handler); -1: none.
  int stop_fd = -1;
  // Where the scanner is for this scan: becomes the scan's sensor_pose (PCD VIEWPOINT).
  std::optional<PoseReading> pose;
};

struct Acquisition {
  Scan scan;  // organised: one row of 180 points per line, beta per line
  // False: `error` says why; `scan` holds the lines that arrived. Never true when a line was
  // dropped.
  bool complete = false;
  std::string error;
  std::size_t lines_received = 0;   // measured-values lines that arrived intact
  std::size_t dropped_lines = 0;    // telegrams lost to corruption (bad checksum, malformed)
  std::size_t untagged_lines = 0;   // arrived, but no turntable angle could be given to them
  bool stopped = false;             // ended by the stop descriptor (a signal)
  std::string journal_error;        // the journal could not be written (the scan is in memory)
  std::size_t lines_journaled = 0;  // lines the journal holds: all received, but after an error
  std::optional<PoseReading> pose;
};

// Never throws for device trouble: it is reported in `error`, with what arrived kept. When
// `progress` asks to stop, the devices are stopped and the lines so far come back, incomplete.
Acquisition acquireRosiScan(const std::string& lms_port, const std::string& turntable_port,
                            const AcquisitionOptions& options = {},
                            const ProgressCallback& progress = {});

class Turntable;
// The same with any turntable controller behind the Turntable interface.
Acquisition acquireRosiScan(const std::string& lms_port, Turntable& turntable,
                            const AcquisitionOptions& options = {},
                            const ProgressCallback& progress = {});

}  // namespace clearway::hardware
