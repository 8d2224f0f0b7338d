// The journal keeps every line received and its replay is the scan the acquisition made; a
// journal cut by a crash still gives its lines; a file that is no journal is refused by name.

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "../../support/file_size_limit.h"
#include "clearway/hardware/rosi_emulator.h"
#include "clearway/hardware/scan_journal.h"
#include "clearway/hardware/serial_acquisition.h"
#include "clearway/io/scan_error.h"
#include "clearway/sim/builtin_scenes.h"

namespace clearway::hardware {
namespace {

namespace fs = std::filesystem;
using test::FileSizeLimit;

std::string readAll(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

class JournalFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("clearway-journal-" + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  // Acquires `lines` lines of the emulated garage with a journal, which the acquisition leaves for
  // its caller to remove; returns the journal's text.
  std::string acquireWithJournal(int lines) {
    RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
    AcquisitionOptions options;
    options.lines = lines;
    options.journal = journal();
    const Acquisition acquired =
        acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options);
    EXPECT_TRUE(acquired.complete) << acquired.error;
    return readAll(options.journal);
  }
  fs::path journal() const { return folder_ / "scan.journal"; }
  fs::path folder_;
};

TEST_F(JournalFolder, TheReplayedJournalIsTheAcquiredScan) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  AcquisitionOptions options;
  options.lines = 120;
  options.journal = folder_ / "scan.journal";
  PoseReading pose;
  pose.source = "mounting";
  pose.world_from_scanner.translation = {0.5, -0.5, 1.2};
  pose.time = "2026-11-22T21:00:00Z";
  options.pose = pose;
  const Acquisition live = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options);
  ASSERT_TRUE(live.complete) << live.error;
  ASSERT_TRUE(fs::exists(options.journal));  // the caller removes it once the scan is saved

  const Acquisition replayed = recoverJournal(options.journal);
  EXPECT_TRUE(replayed.complete) << replayed.error;
  ASSERT_EQ(replayed.scan.lines.size(), live.scan.lines.size());
  EXPECT_EQ(replayed.lines_received, live.lines_received);
  for (std::size_t i = 0; i < live.scan.lines.size(); ++i)
    ASSERT_DOUBLE_EQ(replayed.scan.lines[i].beta, live.scan.lines[i].beta) << "line " << i;
  for (std::size_t i = 0; i < live.scan.size(); ++i) {
    ASSERT_EQ(replayed.scan.status[i], live.scan.status[i]) << "point " << i;
    if (live.scan.isValid(i)) {
      ASSERT_FLOAT_EQ(replayed.scan.points[i].x, live.scan.points[i].x);
    }
  }
  ASSERT_TRUE(replayed.pose);
  EXPECT_EQ(replayed.pose->source, "mounting");
  EXPECT_DOUBLE_EQ(replayed.pose->world_from_scanner.translation.z(), 1.2);
  ASSERT_TRUE(replayed.scan.sensor_pose);
  EXPECT_DOUBLE_EQ(replayed.scan.sensor_pose->position[0], 0.5);
}

TEST_F(JournalFolder, AJournalCutByACrashGivesEveryWholeLine) {
  // Cut the file in the middle of its 50th line record, as a crash during a write would.
  const std::string text = acquireWithJournal(80);
  AcquisitionOptions options;
  options.journal = journal();
  std::size_t at = 0;
  for (int lines = 0; lines < 50; ++lines)
    at = text.find("\nL ", at + 1);
  ASSERT_NE(at, std::string::npos);
  {
    std::ofstream out(options.journal, std::ios::binary | std::ios::trunc);
    out << text.substr(0, at + 40);
  }
  const Acquisition recovered = recoverJournal(options.journal);
  EXPECT_FALSE(recovered.complete);
  EXPECT_EQ(recovered.lines_received, 49u);
  EXPECT_EQ(recovered.scan.lines.size(), 49u);
  EXPECT_NE(recovered.error.find("ended without finishing"), std::string::npos) << recovered.error;
}

TEST_F(JournalFolder, AnExistingJournalIsNeverOverwritten) {
  const fs::path file = folder_ / "scan.journal";
  { std::ofstream(file) << "CLEARWAY-JOURNAL 1\nTARGET 0\n"; }
  const ScanJournal journal(file, 0);
  EXPECT_NE(journal.error().find("exists"), std::string::npos) << journal.error();
  EXPECT_EQ(readAll(file), "CLEARWAY-JOURNAL 1\nTARGET 0\n");
}

TEST_F(JournalFolder, WhatIsNoJournalIsRefusedByName) {
  const fs::path file = folder_ / "notes.journal";
  { std::ofstream(file) << "hello\n"; }
  try {
    recoverJournal(file);
    FAIL() << "accepted";
  } catch (const ScanError& error) {
    EXPECT_NE(std::string(error.what()).find("notes.journal"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("not a Clearway acquisition journal"),
              std::string::npos);
  }
  { std::ofstream(file) << "CLEARWAY-JOURNAL 1\r\nTARGET 0\r\n"; }  // re-saved by an editor
  try {
    recoverJournal(file);
    FAIL() << "accepted";
  } catch (const ScanError& error) {
    EXPECT_NE(std::string(error.what()).find("re-saved by an editor"), std::string::npos)
        << error.what();
  }
  { std::ofstream(file) << "CLEARWAY-JOURNAL 1\nTARGET 0\nL 12 oops\nA 1 2\n"; }
  try {
    recoverJournal(file);
    FAIL() << "accepted";
  } catch (const ScanError& error) {
    EXPECT_NE(std::string(error.what()).find("line 3"), std::string::npos) << error.what();
  }
}

// A journal is written in one order (TARGET, POSE, the scan's records, END). Recovery took what
// it found: "END complete" after 49 of 80 lines was a complete scan, records after END and a
// second TARGET were read, a range of 10^20 mm overflowed into a number, a pipe was waited on
// for ever, and a byte that is not UTF-8 in END's reason broke the JSON written after the scan.
TEST_F(JournalFolder, AJournalOutOfItsOrderOrRangeIsNotTakenAsItComes) {
  const std::string text = acquireWithJournal(80);
  AcquisitionOptions options;
  options.journal = journal();
  const std::size_t end_record = text.rfind("END ");
  ASSERT_NE(end_record, std::string::npos);
  auto recoverFrom = [&](const std::string& journal) {
    { std::ofstream(options.journal, std::ios::binary | std::ios::trunc) << journal; }
    return recoverJournal(options.journal);
  };
  auto refusal = [&](const std::string& journal) {
    try {
      recoverFrom(journal);
    } catch (const ScanError& error) {
      return std::string(error.what());
    }
    return std::string("recovered");
  };
  std::size_t at = 0;
  for (int lines = 0; lines < 50; ++lines)
    at = text.find("\nL ", at + 1);
  const Acquisition cut = recoverFrom(text.substr(0, at + 1) + "END complete\n");
  EXPECT_FALSE(cut.complete);
  EXPECT_NE(cut.error.find("ends 'complete' after 49 of its 80 lines"), std::string::npos)
      << cut.error;
  EXPECT_NE(refusal(text + "A 1 2\n").find("a record after END"), std::string::npos);
  const std::size_t first_line = text.find("\nL ");
  EXPECT_NE(refusal(text.substr(0, first_line + 1) + "TARGET 80\n" + text.substr(first_line + 1))
                .find("a second TARGET"),
            std::string::npos);
  std::string far = text;
  const std::size_t range = far.find(' ', far.find(' ', first_line + 3) + 1) + 1;
  far.replace(range, far.find(' ', range) - range, "99999999999999999999");
  EXPECT_NE(refusal(far).find("beyond any LMS200's reach"), std::string::npos) << refusal(far);
  const Acquisition odd = recoverFrom(text.substr(0, end_record) + "END failed \xFF\x1b[2J\n");
  EXPECT_EQ(odd.error.find('\xFF'), std::string::npos);
  EXPECT_EQ(odd.error.find('\x1b'), std::string::npos);
  const fs::path pipe = folder_ / "pipe.journal";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  try {
    recoverJournal(pipe);
    FAIL() << "a pipe was read";
  } catch (const ScanError& error) {
    EXPECT_NE(std::string(error.what()).find("not a regular file"), std::string::npos);
  }
}

// The journal's disk fills up: the lines written before stay whole and recoverable, and the
// journal says why and how many it holds. Records given after the failure are not written: once
// space came back they were appended after the torn record, and the journal could not be
// recovered at all (a corrupt line in its middle).
TEST_F(JournalFolder, AFailedWriteKeepsTheLinesBeforeItRecoverable) {
  const std::vector<std::optional<double>> ranges(std::size_t(180), 2.5);
  std::size_t given = 0, held = 0;
  {
    ScanJournal writer(journal(), 0);
    ASSERT_TRUE(writer.error().empty()) << writer.error();
    FileSizeLimit limit(16 * 1024);  // about 15 lines
    ASSERT_TRUE(limit.ok());
    for (; given < 100 && writer.error().empty(); ++given) {
      writer.angle({std::int64_t(given) * 26'000, double(given) * 1.2});
      writer.line(std::int64_t(given) * 26'000 + 1000, ranges);
    }
    ASSERT_FALSE(writer.error().empty()) << "the limit was never reached";
    EXPECT_NE(writer.error().find("cannot write the journal " + journal().string()),
              std::string::npos)
        << writer.error();
    EXPECT_NE(writer.error().find("File too large"), std::string::npos) << writer.error();
    held = writer.lines();
    EXPECT_GT(held, 0u);
    EXPECT_LT(held, given);
    limit.lift();
    for (std::size_t more = 0; more < 20; ++more, ++given) {
      writer.angle({std::int64_t(given) * 26'000, double(given % 300) * 1.2});
      writer.line(std::int64_t(given) * 26'000 + 1000, ranges);
    }
    writer.end(true, "");
    EXPECT_EQ(writer.lines(), held);
  }
  const Acquisition recovered = recoverJournal(journal());
  EXPECT_EQ(recovered.lines_received, held);
  EXPECT_FALSE(recovered.complete);
}

// The disk fills up mid-scan: the acquisition says so at once, once, with the cause and how
// many lines the journal holds, and goes on with every line in memory. It said nothing until
// the scan ended.
TEST_F(JournalFolder, AJournalThatFailsMidScanIsToldAtOnceAndTheScanGoesOn) {
  RosiEmulator emulator(*sim::builtinScene("garage"), {20.0, 3});
  AcquisitionOptions options;
  options.lines = 120;
  options.journal = journal();
  std::size_t placed = 0, placed_when_told = 0;
  options.lines_arrived_every = 1;
  options.lines_arrived = [&](const Scan& so_far) { placed = so_far.lines.size(); };
  std::vector<std::pair<std::string, std::size_t>> told;
  options.journal_failed = [&](const std::string& reason, std::size_t lines_journaled) {
    told.emplace_back(reason, lines_journaled);
    placed_when_told = placed;
  };
  Acquisition acquired;
  {
    FileSizeLimit limit(16 * 1024);  // about 15 of the 120 lines
    ASSERT_TRUE(limit.ok());
    acquired = acquireRosiScan(emulator.lmsPort(), emulator.turntablePort(), options);
  }
  EXPECT_TRUE(acquired.complete) << acquired.error;
  EXPECT_EQ(acquired.scan.lines.size(), 120u) << "every line is kept in memory";
  ASSERT_EQ(told.size(), 1u);
  EXPECT_NE(told[0].first.find("File too large"), std::string::npos) << told[0].first;
  EXPECT_EQ(told[0].first, acquired.journal_error);
  EXPECT_EQ(told[0].second, acquired.lines_journaled);
  EXPECT_GT(acquired.lines_journaled, 0u);
  EXPECT_LT(acquired.lines_journaled, 60u);
  EXPECT_LT(placed_when_told, 60u) << "told long after the journal failed";
  EXPECT_EQ(recoverJournal(journal()).lines_received, acquired.lines_journaled);
}

}  // namespace
}  // namespace clearway::hardware
