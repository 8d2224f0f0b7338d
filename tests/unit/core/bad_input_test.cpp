// Bad files get a ScanError whose one-line message names the file and the problem; never a crash,
// never a partial scan.

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstring>
#include <limits>

#include "clearway/io/scan_io.h"
#include "test_support.h"

namespace clearway {
namespace {

// Expects loadScan(file) to throw ScanError mentioning the file and `fragment`.
void expectScanError(const std::filesystem::path& file, const std::string& fragment,
                     const LoadOptions& options = {}) {
  try {
    const Scan scan = loadScan(file, options);
    ADD_FAILURE() << file << " loaded " << scan.size() << " points instead of failing";
  } catch (const ScanError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  }
}

std::string pcdHeader(const std::string& data, const std::string& width, const std::string& height,
                      const std::string& points) {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
         width + "\nHEIGHT " + height + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + points + "\nDATA " +
         data + "\n";
}

std::string floats(int count, float value) {
  std::string bytes;
  for (int i = 0; i < count; ++i)
    bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
  return bytes;
}

class BadInput : public test::FileFolderTest {};

TEST_F(BadInput, MissingFile) {
  expectScanError(directory / "nope.pcd", "no such file");
}

TEST_F(BadInput, Directory) {
  std::filesystem::create_directory(directory / "folder.pcd");
  expectScanError(directory / "folder.pcd", "directory");
  // Named for what it is, not for its missing extension.
  std::filesystem::create_directory(directory / "folder");
  expectScanError(directory / "folder", "is a directory, not a file to read");
}

// A pipe or a device named like a scan, and a link loop, said as such (they read "cannot read its
// size: Operation not supported" and "no such file").
TEST_F(BadInput, NotARegularFileOrUnreachable) {
  ASSERT_EQ(::mkfifo((directory / "pipe.pcd").c_str(), 0600), 0);
  expectScanError(directory / "pipe.pcd", "not a regular file");
  expectScanError("/dev/null", "not a regular file");
  std::filesystem::create_symlink(directory / "b.pcd", directory / "a.pcd");
  std::filesystem::create_symlink(directory / "a.pcd", directory / "b.pcd");
  expectScanError(directory / "a.pcd", "cannot reach it");
}

TEST_F(BadInput, UnreadableFile) {
  if (::geteuid() == 0) GTEST_SKIP() << "root reads any file; permissions cannot be tested";
  const auto file = write("locked.xyz", "1 2 3\n");
  ::chmod(file.c_str(), 0);
  expectScanError(file, "cannot open");
}

TEST_F(BadInput, EmptyFile) {
  expectScanError(write("empty.pcd", ""), "empty file");
}

TEST_F(BadInput, UnknownExtension) {
  expectScanError(write("scan.las", "1 2 3\n"), "unknown extension");
}

TEST_F(BadInput, NotAPcd) {
  expectScanError(write("text.pcd", "hello world\nthis is no pcd\n"), "not a PCD");
}

TEST_F(BadInput, BinaryBytesNamedPcdAreNotEchoed) {
  std::string bytes = "\x01\x9b[2J\x07garbage\xff\x00tail\n";
  bytes[9] = '\xfe';
  try {
    loadScan(write("random.pcd", bytes));
    FAIL() << "loaded random bytes";
  } catch (const ScanError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("not a PCD"), std::string::npos) << message;
    // Nothing of the file reaches the terminal but printable characters (no escape sequences).
    for (const char c : message)
      EXPECT_TRUE(c >= ' ' && c <= '~') << "byte " << int(static_cast<unsigned char>(c));
  }
}

TEST_F(BadInput, PcdWithoutXyz) {
  const std::string header =
      "VERSION 0.7\nFIELDS a b\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA "
      "ascii\n1 2\n";
  expectScanError(write("noxyz.pcd", header), "no 'x' field");
}

// PCL's reader parses the header again and reads the line after DATA as a header line too: an
// ascii body starting "COLUMNS" (v0.5's FIELDS) replaced the field list and the reader
// dereferenced a null x field; a binary one made PCL size a string by the bytes after it and read
// beyond its buffer (sometimes std::length_error, sometimes a crash). Both found by
// fuzz_pcd_reader; such a body is refused before PCL reads it.
TEST_F(BadInput, PcdBodyStartingWithAHeaderKeyword) {
  expectScanError(
      write("columns.pcd", pcdHeader("ascii", "3", "1", "3") + "COLUMNS1 2 3\n4 5 6\n7 8 9\n"),
      "PCD body starts with the header keyword 'COLUMNS'");
  std::string body = "COLUMNS";
  for (int byte = 200; byte < 236; ++byte)
    body += char(byte);
  body += "\n" + std::string(40, '\0');
  expectScanError(write("columns_binary.pcd", pcdHeader("binary", "3", "1", "3") + body),
                  "PCD body starts with the header keyword 'COLUMNS'");
  // Further down the body a keyword is only data, to PCL too.
  const Scan scan = loadScan(
      write("columns_later.pcd", pcdHeader("ascii", "3", "1", "3") + "1 2 3\n4 5 6\n7 8 9\n"));
  EXPECT_EQ(scan.size(), 3U);
}

TEST_F(BadInput, PcdHeaderClaimingATrillionPoints) {
  expectScanError(write("huge.pcd", pcdHeader("binary", "1000000", "1000000", "1000000000000") +
                                        floats(30, 1.0F)),
                  "more than the limit");
}

TEST_F(BadInput, PcdPointsDisagreeWithWidthTimesHeight) {
  expectScanError(write("mismatch.pcd", pcdHeader("ascii", "2", "1", "5") + "1 2 3\n4 5 6\n"),
                  "not WIDTH x HEIGHT");
}

TEST_F(BadInput, TruncatedBinaryPcd) {
  expectScanError(write("short.pcd", pcdHeader("binary", "100", "1", "100") + floats(150, 1.0F)),
                  "truncated");
}

TEST_F(BadInput, TruncatedAsciiPcd) {
  expectScanError(write("short_ascii.pcd", pcdHeader("ascii", "10", "1", "10") + "1 2 3\n4 5 6\n"),
                  "PCD");
}

// PCL's ASCII reader made a point of a row cut short, read a word as a number and dropped the
// rows beyond POINTS, all without a word.
TEST_F(BadInput, AsciiPcdRowCutShort) {
  expectScanError(write("cut.pcd", pcdHeader("ascii", "3", "1", "3") +
                                       "1.25 2.25 3.25\n4.25 5.25 6.25\n7.25 8.25"),
                  "PCD line 14: 2 numbers where the header's fields take 3");
}

TEST_F(BadInput, AsciiPcdWordWhereANumberBelongs) {
  expectScanError(write("word.pcd", pcdHeader("ascii", "3", "1", "3") + "1 2 3\nfoo 5 6\n7 8 9\n"),
                  "PCD line 13: 'foo' is not a number");
}

TEST_F(BadInput, AsciiPcdWithMoreRowsThanPoints) {
  expectScanError(write("more.pcd", pcdHeader("ascii", "2", "1", "2") + "1 2 3\n4 5 6\n7 8 9\n"),
                  "more rows than its header's POINTS 2 (line 14)");
}

TEST_F(BadInput, AsciiPcdAsPclWritesItLoads) {
  // Exponents, signs, nan, CRLF line ends and a blank line are all PCL's own ASCII.
  const Scan scan =
      loadScan(write("fine.pcd", pcdHeader("ascii", "4", "1", "4") +
                                     "1 2 3\r\n-4.5e-1 +5 6E2\r\n\nnan nan nan\r\n7\t8 9\n"));
  ASSERT_EQ(scan.size(), 4U);
  EXPECT_FLOAT_EQ(scan.points[1].x, -0.45F);
  EXPECT_FLOAT_EQ(scan.points[1].z, 600.0F);
  EXPECT_FALSE(scan.isValid(2));
  EXPECT_FLOAT_EQ(scan.points[3].y, 8.0F);
}

// "DATA binary" over a text body read its digits as floats (coordinates of 1e28) and left the
// rest of the file unread.
TEST_F(BadInput, BinaryPcdWhoseBodyIsText) {
  std::string rows;
  for (int i = 0; i < 100; ++i)
    rows += std::to_string(i) + ".125 " + std::to_string(2 * i) + ".5 -3.75\n";
  expectScanError(write("text.pcd", pcdHeader("binary", "100", "1", "100") + rows),
                  "body reads as rows of numbers in text: is it DATA ascii?");
}

// A zero VIEWPOINT quaternion was read as the identity.
TEST_F(BadInput, ZeroViewpointQuaternion) {
  std::string bytes = pcdHeader("ascii", "2", "1", "2") + "1 2 3\n4 5 6\n";
  bytes.replace(bytes.find("VIEWPOINT 0 0 0 1 0 0 0"), 23, "VIEWPOINT 0 0 0 0 0 0 0");
  expectScanError(write("zero_viewpoint.pcd", bytes), "VIEWPOINT's rotation (qw qx qy qz) is zero");
}

TEST_F(BadInput, TruncatedCompressedPcd) {
  test::TemporaryDirectory scratch;
  Scan scan;
  for (int i = 0; i < 2000; ++i) {
    scan.points.push_back({float(i % 37) + 1.0F, float(i % 11), float(i % 5)});
    scan.status.push_back(PointStatus::kValid);
  }
  scan.lines = {{0, scan.size()}};
  saveRosiPcd(scan, scratch / "full.pcd");
  const std::string bytes = test::readBytes(scratch / "full.pcd");
  // Cut the compressed block in half (PCL pads the file, so cutting its tail is not enough).
  const std::size_t data = bytes.find("DATA binary_compressed\n") + 23;
  std::uint32_t compressed = 0;
  std::memcpy(&compressed, bytes.data() + data, sizeof compressed);
  expectScanError(write("cut.pcd", bytes.substr(0, data + 8 + compressed / 2)), "truncated");
}

TEST_F(BadInput, CorruptCompressedSizes) {
  std::string bytes = pcdHeader("binary_compressed", "10", "1", "10");
  const std::uint32_t sizes[2] = {16, 4'000'000'000U};
  bytes.append(reinterpret_cast<const char*>(sizes), sizeof sizes);
  bytes.append(16, 'x');
  expectScanError(write("corrupt.pcd", bytes), "corrupt");
}

TEST_F(BadInput, AllNaNCloud) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  expectScanError(write("nan.pcd", pcdHeader("binary", "50", "1", "50") + floats(150, nan)),
                  "no valid points");
  expectScanError(write("nan.xyz", "nan nan nan\nnan nan nan\n"),
                  "no valid points: all 2 are 2 no returns");
}

// A 3DTK scan all at one range is saturated, not empty of returns: said by kind.
TEST_F(BadInput, AScanAllAtMaxRangeSaysSo) {
  write("scan007.pose", "0 0 0\n0 0 0\n");
  std::string rows;
  for (int i = 0; i < 200; ++i)
    rows += "370 0 0\n";
  expectScanError(write("scan007.3d", rows), "are 200 at max range");
}

TEST_F(BadInput, XyzWithGarbageLine) {
  expectScanError(write("garbage.xyz", "1 2 3\n4 5 6\n7 eight 9\n"), "line 3");
}

TEST_F(BadInput, XyzWithTooFewColumns) {
  expectScanError(write("short.xyz", "1 2 3\n4 5\n"), "line 2");
}

TEST_F(BadInput, BinaryBytesInATextFormat) {
  expectScanError(write("binary.xyz", std::string("1 2 3\n\0\0\0\x01", 10)), "binary data");
}

TEST_F(BadInput, KittiFileOfBrokenLength) {
  expectScanError(write("broken.bin", floats(4 * 10, 1.0F) + "abc"), "truncated");
}

TEST_F(BadInput, PlyWithoutEndHeader) {
  expectScanError(write("open.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"), "no end_header");
}

TEST_F(BadInput, PlyClaimingMoreVerticesThanTheFileHolds) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 100000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  expectScanError(write("claims.ply", header + floats(30, 1.0F)), "do not fit");
}

TEST_F(BadInput, TruncatedAsciiPly) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n";
  expectScanError(write("short.ply", header), "truncated");
}

// A PLY header says what its body holds: a count that is not a whole number, a word where a vertex
// belongs, a vertex row with more values than properties and bytes beyond the last vertex were read
// as fewer points, or past, without a word.
TEST_F(BadInput, PlyWhoseBodyIsNotWhatItsHeaderSays) {
  const std::string properties =
      "property float x\nproperty float y\nproperty float z\nend_header\n";
  expectScanError(write("fraction.ply", "ply\nformat ascii 1.0\nelement vertex 1.5\n" + properties +
                                            "1 2 3\n4 5 6\n"),
                  "count '1.5' is not a whole number");
  expectScanError(write("word.ply", "ply\nformat ascii 1.0\nelement vertex 2\n" + properties +
                                        "foo bar baz\n1 2 3\n4 5 6\n"),
                  "line 8: expected at least 3 numbers, got 'foo bar baz'");
  expectScanError(write("wide.ply", "ply\nformat ascii 1.0\nelement vertex 2\n" + properties +
                                        "1 2 3 4 5\n4 5 6\n"),
                  "PLY vertex 0 has 5 values where its 3 properties take one each");
  expectScanError(write("more.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 2\n" +
                                        properties + floats(12, 1.0F)),
                  "PLY holds 24 bytes after its last vertex");
  // Rows of more than four properties are held to the same: a short row is not completed with
  // the next row's values.
  const std::string five =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty float nx\nproperty float intensity\nend_header\n";
  expectScanError(write("short_row.ply", five + "1 2 3 0\n4 5 6 0 7\n8 9\n"),
                  "line 10: PLY vertex 0 is not 5 numbers, one per property");
  const Scan five_columns = loadScan(write("five.ply", five + "1 2 3 0 0.5\n\n4 5 6 0 0.25\n"));
  ASSERT_EQ(five_columns.size(), 2U);
  EXPECT_FLOAT_EQ(five_columns.intensity[1], 0.25F);
  // Faces after the vertices are rows of another shape, and are no error.
  const Scan with_faces = loadScan(
      write("faces.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" +
                             properties.substr(0, properties.size() - 11) +
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "1 2 3\n4 5 6\n7 8 9\n3 0 1 2\n"));
  EXPECT_EQ(with_faces.size(), 3U);
}

// The first row of an .xyz may be a column header; a byte-order mark or a number too large for a
// double made the first point that header, and it was dropped.
TEST_F(BadInput, XyzFirstRowIsAPointWhateverItsNumbers) {
  const Scan marked = loadScan(write("bom.xyz",
                                     "\xEF\xBB\xBF"
                                     "1 2 3\n4 5 6\n7 8 9\n"));
  EXPECT_EQ(marked.size(), 3U);
  const Scan huge = loadScan(write("huge.xyz", "1e400 0 0\n4 5 6\n7 8 9\n"));
  ASSERT_EQ(huge.size(), 3U);
  EXPECT_FALSE(huge.isValid(0));
  const Scan headed = loadScan(write("headed.xyz", "x y z\n4 5 6\n7 8 9\n"));
  EXPECT_EQ(headed.size(), 2U);
}

// Issue #12.6: PCL's reader allocated 2.4 GB for this 300-byte file before failing.
TEST_F(BadInput, TinyAsciiPcdClaimingTwoHundredMillionPoints) {
  expectScanError(
      write("claims.pcd", pcdHeader("ascii", "200000000", "1", "200000000") + "1 2 3\n4 5 6\n"),
      "truncated: PCD header promises 200000000 points");
}

TEST_F(BadInput, AsciiPlyClaimingMoreVerticesThanItsTextCanHold) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n";
  expectScanError(write("claims_ascii.ply", header), "need at least 599999999 bytes");
}

// Issue #12.8: a NaN sensor pose placed the scan nowhere, silently.
TEST_F(BadInput, NonFiniteViewpoint) {
  std::string bytes = pcdHeader("ascii", "2", "1", "2") + "1 2 3\n4 5 6\n";
  bytes.replace(bytes.find("VIEWPOINT 0 0 0 1 0 0 0"), 23, "VIEWPOINT 0 0 nan 1 0 0 0");
  expectScanError(write("nan_viewpoint.pcd", bytes),
                  "VIEWPOINT value 'nan' is not a finite number");
  bytes.replace(bytes.find("nan"), 3, "1e999");
  expectScanError(write("huge_viewpoint.pcd", bytes), "VIEWPOINT value '1e999'");
}

// Issue #12.8: trailing garbage, NaN and an unreadable .pose were accepted silently.
TEST_F(BadInput, GarbledOrUnreadablePoseFile) {
  const auto scan = write("scan003.3d", "100 50 300\n200 50 300\n");
  const auto pose = directory / "scan003.pose";
  auto expectPoseError = [&](const std::string& fragment) {
    try {
      loadScan(scan);
      ADD_FAILURE() << "the pose file was accepted";
    } catch (const ScanError& error) {
      EXPECT_NE(std::string(error.what()).find(pose.string()), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
    }
  };
  test::writeBytes(pose, "1 2 3\n4 5 6 trailing garbage\n");
  expectPoseError("'trailing'");
  test::writeBytes(pose, "1 2 nan\n4 5 6\n");
  expectPoseError("six finite numbers");
  test::writeBytes(pose, "1 2 3\n4 5 6\n0\n");  // it named the '0', not the count
  expectPoseError("found more than six");
  std::filesystem::remove(pose);
  std::filesystem::create_directory(pose);
  expectPoseError("directory");
}

TEST_F(BadInput, MaxPointsLimitAppliesToText) {
  LoadOptions options;
  options.max_points = 2;
  expectScanError(write("three.xyz", "1 2 3\n4 5 6\n7 8 9\n"), "limit", options);
}

TEST_F(BadInput, BrokenPoseFile) {
  write("scan002.3d", "100 50 300\n");
  write("scan002.pose", "1 2\n");
  try {
    loadScan(directory / "scan002.3d");
    ADD_FAILURE() << "a broken pose file was accepted";
  } catch (const ScanError& error) {
    EXPECT_NE(std::string(error.what()).find("scan002.pose"), std::string::npos) << error.what();
  }
}

TEST_F(BadInput, RandomBytesNeverCrashAnyReader) {
  std::string noise(4096, '\0');
  unsigned state = 12345;
  for (char& c : noise)
    c = char((state = state * 1103515245 + 12345) >> 16);
  for (const char* name : {"noise.pcd", "noise.ply", "noise.xyz", "noise.3d"}) {
    const auto file = write(name, noise);
    EXPECT_THROW(loadScan(file), ScanError) << name;
  }
  // Random bytes of a whole number of 16-byte records: the format has no header, but the floats
  // say it is no Velodyne frame.
  expectScanError(write("noise.bin", noise), "not a Velodyne frame");
}

// Folders of scans hold notes too: the console's Previous/Next must not offer them.
TEST_F(BadInput, TextNotesInAScanFolderAreNoScans) {
  EXPECT_FALSE(looksLikeScanFile(write("SOURCE.txt",
                                       "Source: KITTI raw data, drive 0001.\n"
                                       "Licence: CC BY-NC-SA 3.0.\n")));
  EXPECT_FALSE(looksLikeScanFile(write("README.txt", "see the paper\n")));
  EXPECT_FALSE(looksLikeScanFile(write("notes.md", "1 2 3\n")));  // not a scan extension
  EXPECT_TRUE(looksLikeScanFile(write("points.txt", "# x y z\n1 2 3\n4 5 6\n")));
  EXPECT_TRUE(looksLikeScanFile(write("header.xyz", "X Y Z\n1,2,3\n")));
  EXPECT_TRUE(looksLikeScanFile(write("scan.pcd", "whatever: loadScan judges it")));
}

// A binary body of other bytes (random, or the wrong DATA type) reads as floats whatever it
// holds; most such points lie farther away than any scanner measures. They had loaded silently.
TEST_F(BadInput, BinaryBodiesOfOtherBytesAreNoScans) {
  constexpr int kPoints = 1000;
  std::string noise(kPoints * 12, '\0');
  unsigned state = 2026;
  for (char& c : noise)
    c = char((state = state * 1103515245 + 12345) >> 16);
  expectScanError(write("noise_body.pcd", pcdHeader("binary", "1000", "1", "1000") + noise),
                  "points are not range measurements");
  expectScanError(write("noise_body.ply",
                        "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty "
                        "float x\nproperty float y\nproperty float z\nend_header\n" +
                            noise),
                  "lie over 10 km from the sensor");
}

// A few points beyond any scanner's reach among real ones are corrupt records: no-returns, and
// the scan says how many.
TEST_F(BadInput, AFewPointsBeyondAnyScannersReachAreNoReturnsAndSaidSo) {
  std::string rows;
  constexpr int kRows = 400;
  for (int i = 0; i < kRows; ++i)
    rows += (i % 200 == 3 ? "3e12 1 -1" : std::to_string(2.0 + 0.01 * i) + " 9000 -1.2") + "\n";
  const Scan scan = loadScan(write("two_far.xyz", rows));
  ASSERT_EQ(scan.size(), std::size_t(kRows));
  EXPECT_EQ(scan.validCount(), std::size_t(kRows - 2));  // 9 km away is still a measurement
  EXPECT_FALSE(scan.isValid(3));
  EXPECT_NE(scan.metadata.caution.find("2 of 400 points lie over 10 km"), std::string::npos)
      << scan.metadata.caution;
}

TEST_F(BadInput, KittiFileWithAbsurdCoordinates) {
  // One record in ten at 1e30 m, the rest a plausible frame.
  std::string bytes;
  for (int i = 0; i < 100; ++i) {
    const float record[4] = {i % 10 == 0 ? 1e30F : 5.0F + 0.01F * float(i), 2.0F, -1.7F, 0.3F};
    bytes.append(reinterpret_cast<const char*>(record), sizeof record);
  }
  expectScanError(write("far.bin", bytes), "not a Velodyne frame");
}

TEST_F(BadInput, AFewAbsurdKittiRecordsAreNoReturnsNotPoints) {
  // One record in two hundred at 1e30 m (under the refusal's share), the rest a plausible frame.
  std::string bytes;
  constexpr int kRecords = 400;
  for (int i = 0; i < kRecords; ++i) {
    const float record[4] = {i % 200 == 7 ? 1e30F : 5.0F + 0.01F * float(i), 2.0F, -1.7F, 0.3F};
    bytes.append(reinterpret_cast<const char*>(record), sizeof record);
  }
  const Scan scan = loadScan(write("two-absurd.bin", bytes));
  ASSERT_EQ(scan.size(), std::size_t(kRecords));
  EXPECT_EQ(scan.validCount(), std::size_t(kRecords - 2));
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.isValid(i)) continue;
    EXPECT_LT(std::abs(scan.points[i].x), 10.0F) << i;
  }
}

TEST_F(BadInput, KittiFrameOfPlausibleRecordsLoads) {
  std::string bytes;
  for (int i = 0; i < 100; ++i) {
    const float record[4] = {5.0F + 0.01F * float(i), 2.0F, -1.7F, 0.3F};
    bytes.append(reinterpret_cast<const char*>(record), sizeof record);
  }
  EXPECT_EQ(loadScan(write("frame.bin", bytes)).size(), 100U);
}

}  // namespace
}  // namespace clearway
