// Bounded memory for any input (issue #12.6): each case runs in a child process whose peak
// resident memory is measured, so a loader that reads a gigabyte of garbage or a Hough accumulator
// that grows with one far point fails the test instead of the machine.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>

#include "clearway/io/scan_io.h"
#include "clearway/segmentation/line_segments.h"
#include "test_support.h"

namespace clearway {
namespace {

// Peak resident memory a child may reach for work that needs a few megabytes [MB]. A gtest
// process starts near 20 MB; AddressSanitizer adds its shadow memory.
constexpr long kBoundMb = 300;

struct ChildOutcome {
  bool finished = false;  // exited normally (not killed by a signal)
  long peak_mb = -1;
  std::string message;  // what the work reported (an error message or a count)
};

// Runs `work` in a forked child and reports its peak resident memory.
ChildOutcome runInChild(const std::function<std::string()>& work) {
  int channel[2];
  if (::pipe(channel) != 0) return {};
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(channel[0]);
    std::string message;
    try {
      message = work();
    } catch (const std::exception& error) {
      message = error.what();
    }
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    const std::string report = std::to_string(usage.ru_maxrss / 1024) + "\n" + message;
    [[maybe_unused]] const auto written = ::write(channel[1], report.data(), report.size());
    ::_exit(0);
  }
  ::close(channel[1]);
  std::string report;
  char buffer[4096];
  for (::ssize_t n; (n = ::read(channel[0], buffer, sizeof buffer)) > 0;)
    report.append(buffer, std::size_t(n));
  ::close(channel[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  ChildOutcome outcome;
  outcome.finished = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (const auto newline = report.find('\n'); newline != std::string::npos) {
    outcome.peak_mb = std::stol(report.substr(0, newline));
    outcome.message = report.substr(newline + 1);
  }
  return outcome;
}

// A file of `bytes` that starts with `head` and is sparse after it (zeros, no disk used).
std::filesystem::path sparseFile(const test::TemporaryDirectory& directory, const std::string& name,
                                 const std::string& head, std::uintmax_t bytes) {
  const auto file = directory / name;
  test::writeBytes(file, head);
  std::filesystem::resize_file(file, bytes);
  return file;
}

constexpr std::uintmax_t kGigabyte = 1ULL << 30;

TEST(BoundedMemory, AGigabyteOfGarbageNamedXyzIsRefusedFromItsFirstBytes) {
  test::TemporaryDirectory directory;
  const auto file =
      sparseFile(directory, "garbage.xyz", "PK\x03\x04 not a point list\n", kGigabyte);
  const ChildOutcome outcome = runInChild([&] {
    loadScan(file);
    return std::string("loaded");
  });
  ASSERT_TRUE(outcome.finished);
  EXPECT_NE(outcome.message.find(file.string()), std::string::npos) << outcome.message;
  EXPECT_LT(outcome.peak_mb, kBoundMb) << "the whole file was read before its format was checked";
}

TEST(BoundedMemory, AGigabyteOfGarbageNamedPlyIsRefusedFromItsFirstBytes) {
  test::TemporaryDirectory directory;
  const auto file = sparseFile(directory, "garbage.ply", "PK\x03\x04 not a ply\n", kGigabyte);
  const ChildOutcome outcome = runInChild([&] {
    loadScan(file);
    return std::string("loaded");
  });
  ASSERT_TRUE(outcome.finished);
  EXPECT_NE(outcome.message.find("not a PLY file"), std::string::npos) << outcome.message;
  EXPECT_LT(outcome.peak_mb, kBoundMb) << "the whole file was read before its format was checked";
}

// 60 scan lines of a wall 3 m ahead; line 0 also holds one return `far_metres` away.
Scan wallWithOneFarPoint(double far_metres) {
  Scan scan;
  constexpr double kDeg = std::numbers::pi / 180.0;
  for (int l = 0; l < 60; ++l) {
    const double beta = (l - 30) * 0.5 * kDeg;
    scan.lines.push_back({scan.size(), 180, beta});
    for (int k = 0; k < 180; ++k) {
      const double alpha = (k - 90) * 0.5 * kDeg;
      const double range = 3.0 / (std::cos(alpha) * std::cos(beta));
      scan.points.push_back({float(range * std::cos(alpha) * std::cos(beta)),
                             float(range * std::cos(alpha) * std::sin(beta)),
                             float(range * std::sin(alpha))});
      scan.status.push_back(PointStatus::kValid);
    }
  }
  scan.points[90] = {float(far_metres), 0.0F, 0.0F};
  return scan;
}

// Issue #12.6: one point 100 km away made the accumulator 3.6 GB (1,000 km: out of memory).
TEST(BoundedMemory, HoughAccumulatorStaysSmallWithAPointFarAway) {
  for (const double far : {1.0e5, 1.0e6}) {
    const ChildOutcome outcome = runInChild([&] {
#if !defined(__SANITIZE_ADDRESS__)
      // Without the bound this child would take gigabytes; fail it early instead.
      const rlimit limit{std::uint64_t(2) << 30, std::uint64_t(2) << 30};
      ::setrlimit(RLIMIT_AS, &limit);
#endif
      LineParams params;
      params.method = LineMethod::kHough;
      const auto segments = detectLineSegments(wallWithOneFarPoint(far), params, 1);
      return std::to_string(segments.size());
    });
    ASSERT_TRUE(outcome.finished) << far;
    EXPECT_LT(outcome.peak_mb, kBoundMb) << far;
    // The wall is still found on every line.
    EXPECT_GE(std::atol(outcome.message.c_str()), 60) << far << ": " << outcome.message;
  }
}

}  // namespace
}  // namespace clearway
