#include <iostream>
#include <stdexcept>

#include "arguments.h"
#include "clearway/hardware/acquisition_files.h"
#include "clearway/hardware/journal_recovery.h"
#include "clearway/hardware/pose_source.h"
#include "clearway/hardware/scan_journal.h"
#include "clearway/hardware/serial_acquisition.h"
#include "clearway/io/scan_error.h"
#include "commands.h"
#include "mount_options.h"
#include "stop_signals.h"

namespace clearway::cli {
namespace {

constexpr const char* kUsage =
    "clearway-cli acquire --lms PORT --turntable PORT [--arm PORT] [--mount POSE] [--lines N] "
    "-o SCAN.pcd, or acquire --recover SCAN.journal -o SCAN.pcd";

// How many of the lines received the journal holds, once it failed: what a crash, or a save
// that fails too, leaves of the scan.
std::string journalHolds(const hardware::Acquisition& acquisition) {
  return "the journal holds " + std::to_string(acquisition.lines_journaled) + " of the " +
         std::to_string(acquisition.lines_received) + " lines received (" +
         acquisition.journal_error + ")";
}

// The scan could not be saved to `target` (a full disk, say): where its lines are, if anywhere.
void sayWhereTheLinesAre(const hardware::Acquisition& acquisition,
                         const std::filesystem::path& target, const std::filesystem::path& journal,
                         const std::string& error) {
  std::cerr << "clearway-cli acquire: " << error << "\n";
  // Written atomically: a scan file that exists is whole; what failed came after it.
  if (std::filesystem::exists(target)) {
    std::cerr << "clearway-cli acquire: the " << acquisition.scan.lines.size()
              << " lines of the scan are in " << target.string() << "; " << journal.string()
              << " is kept as well\n";
    return;
  }
  const std::string recover =
      ": recover them with clearway-cli acquire --recover " + journal.string() + " -o SCAN.pcd";
  if (!std::filesystem::exists(journal)) {
    std::cerr << "clearway-cli acquire: the " << acquisition.lines_received
              << " lines received could not be saved\n";
  } else if (acquisition.journal_error.empty()) {
    std::cerr << "clearway-cli acquire: all " << acquisition.lines_received
              << " lines received are kept in " << journal.string() << recover << "\n";
  } else {
    // Neither file could take them: the lines after the journal's failure end with the process.
    std::cerr << "clearway-cli acquire: only " << acquisition.lines_journaled << " of the "
              << acquisition.lines_received << " lines received are kept, in " << journal.string()
              << recover << "; the other "
              << acquisition.lines_received - acquisition.lines_journaled
              << " could not be saved: the journal stopped (" << acquisition.journal_error
              << ") and the scan could not be written\n";
  }
}

// Saves what the acquisition holds; the journal is removed only once the scan is safely on disk.
int finish(const hardware::Acquisition& acquisition, const std::filesystem::path& output,
           const std::filesystem::path& journal, bool partial_beside) {
  const bool journal_failed = !acquisition.journal_error.empty();
  if (acquisition.complete) {
    try {
      hardware::saveAcquisition(acquisition, output);
    } catch (const ScanError& error) {
      sayWhereTheLinesAre(acquisition, output, journal, error.what());
      return 1;
    }
    std::filesystem::remove(journal);
    std::cout << "acquired " << acquisition.scan.lines.size()
              << " lines x 180 points: " << output.string() << "\n";
    if (journal_failed)
      std::cerr << "clearway-cli acquire: " << journalHolds(acquisition) << "; the scan's "
                << acquisition.scan.lines.size() << " lines are all in " << output.string() << "\n";
    return 0;
  }
  std::cerr << "clearway-cli acquire: " << acquisition.error << " ("
            << hardware::describeLines(acquisition) << ")\n";
  if (journal_failed) std::cerr << "clearway-cli acquire: " << journalHolds(acquisition) << "\n";
  if (acquisition.scan.empty()) {
    // Lines came but none could be placed (no turntable angle, say): the journal holds them as
    // they came, so it stays.
    if (acquisition.lines_received > 0 && std::filesystem::exists(journal)) {
      std::cerr << "clearway-cli acquire: no line could be placed in a scan; the "
                << (journal_failed ? acquisition.lines_journaled : acquisition.lines_received)
                << " lines the journal holds are kept as they came in " << journal.string()
                << " (move it away before acquiring to this name again)\n";
      return 1;
    }
    std::filesystem::remove(journal);
    return 1;
  }
  // Nothing the operator acquired is lost: the lines that arrived are kept, marked partial.
  const std::filesystem::path partial = partial_beside ? hardware::partialPathFor(output) : output;
  try {
    hardware::saveAcquisition(acquisition, partial);
  } catch (const ScanError& error) {
    sayWhereTheLinesAre(acquisition, partial, journal, error.what());
    return 1;
  }
  std::filesystem::remove(journal);
  std::cerr << "clearway-cli acquire: the " << acquisition.scan.lines.size()
            << " lines that arrived are in " << partial.string() << " (incomplete)\n";
  return 1;
}

int recover(const std::filesystem::path& journal, const std::filesystem::path& output) {
  const hardware::Acquisition acquisition = hardware::recoverJournalInto(journal, output);
  std::cout << "recovered " << hardware::describeLines(acquisition) << " from " << journal.string()
            << ": " << output.string() << (acquisition.complete ? "\n" : " (incomplete)\n");
  return acquisition.complete ? 0 : 1;
}

}  // namespace

int runAcquire(const std::vector<std::string>& words) {
  for (const std::string& word : words)
    if (word == "--remote" || word.starts_with("--remote=")) return runRemoteAcquire(words);
  const Arguments arguments(words, {},
                            {"lms", "turntable", "arm", "mount", "lines", "speed", "timeout",
                             "baud", "o", "output", "recover"});
  arguments.expectPositional(0, kUsage);
  const auto output_option =
      arguments.option("o") ? arguments.option("o") : arguments.option("output");
  if (!output_option) throw UsageError(std::string("-o SCAN.pcd is required: ") + kUsage);
  const std::filesystem::path output = *output_option;
  // Checked before anything starts, so a typo never costs a scan.
  if (const std::string problem = hardware::checkOutputPath(output); !problem.empty())
    throw UsageError(problem);
  if (const auto journal = arguments.option("recover")) return recover(*journal, output);

  const auto lms = arguments.option("lms"), table = arguments.option("turntable");
  if (!lms || !table) throw UsageError(std::string("--lms PORT and --turntable PORT: ") + kUsage);
  // Before any port is opened: one port named twice would be "in use by another program".
  if (const std::string problem = hardware::checkDistinctPorts(namedPorts(arguments));
      !problem.empty())
    throw UsageError(problem);
  hardware::AcquisitionOptions options;
  options.lines = int(arguments.integer("lines", 0, 0, 100000));
  options.turntable_speed_deg_s =
      arguments.number("speed", options.turntable_speed_deg_s, 0.1, 360.0);
  options.answer_timeout_ms =
      int(arguments.integer("timeout", options.answer_timeout_ms, 50, 60000));
  options.baud = int(arguments.integer("baud", options.baud, 1, 10'000'000));
  if (options.baud != 9600 && options.baud != 19200 && options.baud != 38400 &&
      options.baud != 500000)
    throw UsageError("--baud " + std::to_string(options.baud) +
                     ": the LMS200 runs at 9600, 19200, 38400 or 500000 baud");

  // Where the scanner is: the arm's pose composed with the RoSi's mounting on the tool, or,
  // without an arm, a fixed mounting on the robot.
  if (const auto source = poseSourceOption(arguments)) {
    const hardware::PoseReading reading = source->read(options.answer_timeout_ms);
    if (!reading.ok()) {
      std::cerr << "clearway-cli acquire: " << reading.error << " (no scan started)\n";
      return 1;
    }
    options.pose = reading;
  }

  const std::filesystem::path journal = hardware::journalPathFor(output);
  if (std::filesystem::exists(journal)) {
    // Left by an acquisition that crashed: its lines are only there. Never overwrite them.
    std::cerr << "clearway-cli acquire: " << journal.string()
              << " exists: it holds the lines of an acquisition that did not finish. Recover "
                 "them with: clearway-cli acquire --recover "
              << journal.string() << " -o SCAN.pcd (or remove it). No scan started.\n";
    return 1;
  }
  options.journal = journal;
  // Said while the scan runs, so the operator can make space or stop it; the lines go on into
  // memory and are saved when it ends.
  options.journal_failed = [&output](const std::string& reason, std::size_t lines_journaled) {
    std::cerr << "clearway-cli acquire: " << reason << ": it holds the first " << lines_journaled
              << " lines. The scan goes on, every line kept in memory until it is saved to "
              << output.string() << " at its end: make space there now\n";
  };
  const StopSignals signals;
  options.stop_fd = signals.descriptor();
  hardware::Acquisition acquisition = hardware::acquireRosiScan(*lms, *table, options);
  if (acquisition.stopped)
    acquisition.error = std::string("interrupted by ") + signals.lastSignalName() +
                        ": the devices were stopped after " +
                        std::to_string(acquisition.lines_received) + " lines";
  if (!std::filesystem::exists(journal) && acquisition.lines_received == 0 &&
      !acquisition.error.empty()) {
    // Refused before streaming (busy port, a journal left by a crash, no device): nothing to save.
    std::cerr << "clearway-cli acquire: " << acquisition.error << "\n";
    return 1;
  }
  return finish(acquisition, output, journal, true);
}

}  // namespace clearway::cli
