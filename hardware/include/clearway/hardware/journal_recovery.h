#pragma once

// Journals left by acquisitions that did not finish (a crash, kill -9, a power cut, a disk that
// refused the scan): found in a scans folder and turned into scans, by `clearway-cli acquire
// --recover` and by the console (File > Recover interrupted acquisitions). docs/JOURNAL.md.

#include <filesystem>
#include <string>
#include <vector>

#include "clearway/hardware/serial_acquisition.h"

namespace clearway::hardware {

// The *.journal files directly in `folder`, oldest first; none when it is not a folder.
std::vector<std::filesystem::path> unfinishedJournals(const std::filesystem::path& folder);

// Where the console saves a recovered journal: SCAN-recovered.pcd beside SCAN.journal (a name no
// acquisition gives, so a recovery never overwrites a scan).
std::filesystem::path recoveredScanPathFor(const std::filesystem::path& journal);

// Replays `journal` and saves what it holds to `scan` (with its pose sidecar and report), then
// removes the journal. Throws ScanError naming the journal when it holds no line that could be
// placed or is corrupt, and naming the file that could not be written (the journal is then kept).
Acquisition recoverJournalInto(const std::filesystem::path& journal,
                               const std::filesystem::path& scan);

// "N lines in the scan, M received[, K dropped (corrupt telegrams)][, J without a turntable angle]"
std::string describeLines(const Acquisition& acquisition);

}  // namespace clearway::hardware
