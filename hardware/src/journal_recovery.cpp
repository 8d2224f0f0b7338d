#include "clearway/hardware/journal_recovery.h"

#include <algorithm>
#include <system_error>

#include "clearway/hardware/acquisition_files.h"
#include "clearway/hardware/scan_journal.h"
#include "clearway/io/scan_error.h"

namespace clearway::hardware {

std::vector<std::filesystem::path> unfinishedJournals(const std::filesystem::path& folder) {
  std::vector<std::pair<std::filesystem::file_time_type, std::filesystem::path>> found;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.path().extension() != ".journal" || !entry.is_regular_file(error)) continue;
    found.emplace_back(entry.last_write_time(error), entry.path());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::filesystem::path> journals;
  for (auto& [time, path] : found)
    journals.push_back(std::move(path));
  return journals;
}

std::filesystem::path recoveredScanPathFor(const std::filesystem::path& journal) {
  std::filesystem::path scan = journal;
  return scan.replace_filename(journal.stem().string() + "-recovered.pcd");
}

Acquisition recoverJournalInto(const std::filesystem::path& journal,
                               const std::filesystem::path& scan) {
  const Acquisition acquisition = recoverJournal(journal);
  if (acquisition.scan.empty())
    throw ScanError(journal, "the journal holds no line that could be placed (" +
                                 describeLines(acquisition) + ")");
  saveAcquisition(acquisition, scan);
  // Only once the scan is safely on disk.
  std::filesystem::remove(journal);
  return acquisition;
}

std::string describeLines(const Acquisition& acquisition) {
  std::string text = std::to_string(acquisition.scan.lines.size()) + " lines in the scan, " +
                     std::to_string(acquisition.lines_received) + " received";
  if (acquisition.dropped_lines > 0)
    text += ", " + std::to_string(acquisition.dropped_lines) + " dropped (corrupt telegrams)";
  if (acquisition.untagged_lines > 0)
    text += ", " + std::to_string(acquisition.untagged_lines) + " without a turntable angle";
  return text;
}

}  // namespace clearway::hardware
