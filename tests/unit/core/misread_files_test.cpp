// Files that loaded as something they are not, or were refused for the wrong reason: a header
// whose count is wrong, numbers in another locale, records of another layout, a value its field
// cannot hold, one point written again and again, bytes that would drive the operator's
// terminal. Each gets a ScanError naming what is wrong, or loads as it is.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <tuple>

#include "clearway/io/scan_io.h"
#include "clearway/pipeline.h"
#include "test_support.h"

namespace clearway {
namespace {

class MisreadFiles : public test::FileFolderTest {
 protected:
  // The ScanError loading `file` gives; fails the test when it loads.
  static std::string errorOf(const std::filesystem::path& file, const LoadOptions& options = {}) {
    try {
      const Scan scan = loadScan(file, options);
      ADD_FAILURE() << file << " loaded " << scan.size() << " points instead of failing";
    } catch (const ScanError& error) {
      return error.what();
    }
    return {};
  }
};

std::string pcdHeader(const std::string& fields, const std::string& sizes, const std::string& types,
                      std::size_t points, const std::string& data,
                      const std::string& viewpoint = "0 0 0 1 0 0 0") {
  const std::string count = std::to_string(points);
  return "VERSION 0.7\nFIELDS " + fields + "\nSIZE " + sizes + "\nTYPE " + types + "\nWIDTH " +
         count + "\nHEIGHT 1\nVIEWPOINT " + viewpoint + "\nPOINTS " + count + "\nDATA " + data +
         "\n";
}

std::string floatRecords(std::size_t records, std::size_t floats_per_record) {
  std::string bytes;
  for (std::size_t i = 0; i < records; ++i)
    for (std::size_t k = 0; k < floats_per_record; ++k) {
      // x forward 4-8 m, y either side, z under the sensor, reflectance 0.25: a frame's values.
      const float value = k == 0 ? 4.0F + 0.01F * float(i)
                                 : (k == 1 ? (i % 2 ? -1.5F : 1.5F) : (k == 2 ? -1.7F : 0.25F));
      bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
    }
  return bytes;
}

TEST(PrintableText, TerminalControlsAndBrokenUtf8BecomeQuestionMarks) {
  EXPECT_EQ(printableText("a\x1b[2Jb"), "a?[2Jb");
  EXPECT_EQ(printableText("tab\there\nnext"), "tab?here?next");
  EXPECT_EQ(printableText("0.5 \xC2\xB0 and \xE2\x89\xA4"), "0.5 \xC2\xB0 and \xE2\x89\xA4");
  EXPECT_EQ(printableText("CSI \xC2\x9B"), "CSI ?");  // U+009B, a terminal's CSI
  EXPECT_EQ(printableText("stray \x80\xFF end"), "stray ?? end");
  EXPECT_EQ(printableText("cut \xE2\x89"), "cut ??");  // a sequence cut short
  EXPECT_EQ(printableText("overlong \xC0\xAF"), "overlong ??");
}

// A garbled row quoted in the message cleared and recoloured the operator's terminal.
TEST_F(MisreadFiles, ErrorsQuoteNoTerminalControls) {
  for (const auto& [name, bytes] :
       {std::pair{"escape.xyz", std::string("1 2 3\n4 5 \x1b[2J\x1b[31mBOOM\n")},
        std::pair{"escape.ply", std::string("ply\nformat ascii 1.0\nelement vertex 2\nproperty "
                                            "float x\nproperty float y\nproperty float z\n"
                                            "end_header\n1 2 3\n1 2 \x1b[2JX\n")}}) {
    const std::string message = errorOf(write(name, bytes));
    EXPECT_EQ(message.find('\x1b'), std::string::npos) << message;
    EXPECT_NE(message.find("?[2J"), std::string::npos) << message;
  }
  write("posed.3d", "100 50 300\n200 50 300\n");
  write("posed.pose", "\x1b[2J 0 0\n0 0 0\n");
  const std::string message = errorOf(directory / "posed.3d");
  EXPECT_EQ(message.find('\x1b'), std::string::npos) << message;
}

// A binary body holding more records than the header's count was read up to that count, the
// rest dropped without a word (100 points of 7,200 "loaded").
TEST_F(MisreadFiles, BinaryPcdBodyLongerThanItsHeaderSays) {
  const std::string header = pcdHeader("x y z", "4 4 4", "F F F", 10, "binary");
  const std::string message = errorOf(write("more.pcd", header + floatRecords(30, 3)));
  EXPECT_NE(message.find("promises 10 points (120 bytes) but 360 bytes follow"), std::string::npos)
      << message;
  // Less than a record beyond is no point: a writer's trailing newline.
  EXPECT_EQ(loadScan(write("newline.pcd", header + floatRecords(10, 3) + "\n")).size(), 10U);
}

// SIZE and COUNT of 2^32 + 4 were narrowed to 4 and passed the check; PCL then ran out of memory
// ("std::bad_alloc"). A missing POINTS line failed in PCL as "corrupt or shorter"; a second WIDTH
// line was taken over the first.
TEST_F(MisreadFiles, PcdHeaderValuesThatWrapOrLack) {
  const std::string points = floatRecords(4, 3);
  EXPECT_NE(errorOf(write("size.pcd",
                          pcdHeader("x y z", "4294967300 4 4", "F F F", 4, "binary") + points))
                .find("field 'x' has an unsupported size/count"),
            std::string::npos);
  std::string counted = pcdHeader("x y z", "4 4 4", "F F F", 4, "binary");
  counted.insert(counted.find("WIDTH"), "COUNT 4294967297 1 1\n");
  EXPECT_NE(errorOf(write("count.pcd", counted + points)).find("unsupported size/count"),
            std::string::npos);
  std::string pointless = pcdHeader("x y z", "4 4 4", "F F F", 4, "binary");
  pointless.erase(pointless.find("POINTS"), std::string("POINTS 4\n").size());
  EXPECT_NE(errorOf(write("pointless.pcd", pointless + points)).find("has no POINTS line"),
            std::string::npos);
  std::string twice = pcdHeader("x y z", "4 4 4", "F F F", 4, "binary");
  twice.insert(twice.find("HEIGHT"), "WIDTH 2\n");
  EXPECT_NE(errorOf(write("twice.pcd", twice + points)).find("PCD header gives WIDTH twice"),
            std::string::npos);
}

// Lines of a vertical tab, or of tabs alone, before "# .PCD v0.7" passed our header check (blank
// to it) and crashed PCL's reader (found by scripts/fuzz).
TEST_F(MisreadFiles, PcdHeaderWithControlCharactersIsRefusedBeforePclReadsIt) {
  const std::string header = pcdHeader("x y z", "4 4 4", "F F F", 4, "binary");
  for (const std::string& prefix : {std::string("\n\v\n"), std::string("\f\n")}) {
    const std::string message = errorOf(write("control.pcd", prefix + header + floatRecords(4, 3)));
    EXPECT_NE(message.find("holds a control character"), std::string::npos) << message;
  }
  // So did a line of nothing but spaces, tabs or a carriage return (an empty one it skips).
  for (const std::string& prefix : {std::string("\t\n"), std::string(" \n"), std::string("\r\n")}) {
    const std::string message = errorOf(write("blank.pcd", prefix + header + floatRecords(4, 3)));
    EXPECT_NE(message.find("nothing but spaces or tabs"), std::string::npos) << message;
  }
  EXPECT_EQ(loadScan(write("plain.pcd", "\n" + header + floatRecords(4, 3))).size(), 4U);
}

// A quaternion of 1e200 components overflowed its norm and became the identity.
TEST_F(MisreadFiles, ViewpointOfHugeComponentsIsTheRotationItSays) {
  const std::string rows = "1 2 3\n4 5 6\n";
  const Scan huge = loadScan(
      write("huge.pcd",
            pcdHeader("x y z", "4 4 4", "F F F", 2, "ascii", "0 0 0 1e200 1e200 0 0") + rows));
  const Scan unit = loadScan(
      write("unit.pcd",
            pcdHeader("x y z", "4 4 4", "F F F", 2, "ascii", "0 0 0 0.7071 0.7071 0 0") + rows));
  ASSERT_TRUE(huge.sensor_pose && unit.sensor_pose);
  for (std::size_t k = 0; k < 9; ++k)
    EXPECT_NEAR(huge.sensor_pose->rotation[k], unit.sensor_pose->rotation[k], 1e-4) << k;
  EXPECT_NEAR(huge.sensor_pose->rotation[5], -1.0, 1e-9);  // 90 deg about x: y turns into z
}

// An integer field's "nan", 300 in one byte or 2.5 were wrapped or cut by PCL's cast: a ring
// field of one ring.
TEST_F(MisreadFiles, AsciiPcdIntegerFieldHoldsOnlyWholeNumbersItsTypeHolds) {
  const std::string header = pcdHeader("x y z ring", "4 4 4 1", "F F F U", 2, "ascii");
  for (const char* value : {"nan", "300", "-1", "2.5", "1e10"}) {
    const std::string message =
        errorOf(write("ring.pcd", header + "1 2 3 0\n4 5 6 " + std::string(value) + "\n"));
    EXPECT_NE(message.find("line 11: field 'ring' (TYPE U SIZE 1) holds '" + std::string(value) +
                           "', not a whole number from 0 to 255"),
              std::string::npos)
        << message;
  }
  const std::string wide = pcdHeader("x y z t", "4 4 4 8", "F F F I", 2, "ascii");
  EXPECT_EQ(loadScan(write("wide.pcd", wide + "1 2 3 -9007199254740992\n4 5 6 7\n")).size(), 2U);
}

// A count below the rows read the first rows only; rows of an element after the vertices (edges
// of two numbers) were refused as short vertices; list properties on vertices were neither read
// nor refused, and a vertex without properties underflowed the size check.
TEST_F(MisreadFiles, AsciiPlyVerticesAreWhatTheHeaderCounts) {
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  const std::string message =
      errorOf(write("short_count.ply", "ply\nformat ascii 1.0\nelement vertex 2\n" + xyz +
                                           "end_header\n1 2 3\n4 5 6\n7 8 9\n"));
  EXPECT_NE(message.find("PLY holds 1 rows after its 2 vertices"), std::string::npos) << message;
  const Scan with_edges = loadScan(write(
      "edges.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                       "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n"
                       "1 2 3\n4 5 6\n7 8 9\n0 1\n1 2\n"));
  EXPECT_EQ(with_edges.size(), 3U);
  EXPECT_NE(errorOf(write("list.ply", "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz +
                                          "property list uchar float extra\nend_header\n"
                                          "1 2 3 2 0.5 0.5\n"))
                .find("list properties on vertices are not supported"),
            std::string::npos);
  EXPECT_NE(
      errorOf(write("bare.ply", "ply\nformat ascii 1.0\nelement vertex 100\nend_header\n1 2 3\n"))
          .find("PLY vertices have no x, y, z"),
      std::string::npos);
}

// "1,48 0,00 0,06" read with the comma as a separator gave six numbers: x a whole number, the
// fractions y, z and intensity.
TEST_F(MisreadFiles, DecimalCommasAreRefusedNotReadAsSeparators) {
  for (const auto& [name, text] :
       {std::pair{"spaces.xyz", "1,48 0,00 0,06\n2,50 1,25 0,06\n"},
        std::pair{"semicolons.txt", "x;y;z\n1,5;0,0;0,1\n2,5;1,0;0,1\n"}}) {
    const std::string message = errorOf(write(name, text));
    EXPECT_NE(message.find("writes its numbers with decimal commas"), std::string::npos) << message;
  }
  // Commas between numbers with a decimal point, and whole numbers apart by commas, are rows.
  EXPECT_EQ(loadScan(write("csv.txt", "1.5,0.0,0.1\n2.5,1.0,0.1\n")).size(), 2U);
  EXPECT_EQ(loadScan(write("whole.txt", "1,2,3\n4,5,6\n")).size(), 2U);
}

// Rows of x y z intensity after rows of x y z lost their intensity (the first row decided), and
// rows of x y z after rows with intensity were given 0: a text scan's rows must all hold as many
// numbers, or it is refused naming the line and both counts.
TEST_F(MisreadFiles, TextRowsOfAnotherColumnCountAreRefused) {
  for (const auto& [name, text, expected] :
       {std::tuple{"three_then_four.xyz", std::string("1 2 3\n4 5 6\n7 8 9 0.5\n"),
                   "line 3 holds 4 numbers where line 1, the first row, holds 3"},
        std::tuple{"four_then_three.txt", std::string("x y z i\n# note\n1 2 3 0.5\n\n4 5 6\n"),
                   "line 5 holds 3 numbers where line 3, the first row, holds 4"},
        std::tuple{"four_then_three.3d", std::string("100 50 300 7\n200 50 300\n"),
                   "line 2 holds 3 numbers where line 1, the first row, holds 4"}}) {
    const std::string message = errorOf(write(name, text));
    EXPECT_NE(message.find(expected), std::string::npos) << name << ": " << message;
  }
  // Beyond the first 64 kB the whole file's reading finds it too.
  std::string rows;
  for (int i = 0; i < 5000; ++i)
    rows += std::to_string(1.0 + 0.001 * i) + " 2.0 0.5\n";
  const std::string late = errorOf(write("late.xyz", rows + "1 2 3 0.5\n"));
  EXPECT_NE(late.find("line 5001 holds 4 numbers where line 1, the first row, holds 3"),
            std::string::npos)
      << late;
  // Comments, blank lines and a header between rows of one count stay what they were.
  const Scan kept =
      loadScan(write("kept.xyz", "x y z i\n1 2 3 0.5 # first\n\n# gap\n4 5 6 0.25\n"));
  ASSERT_EQ(kept.size(), 2U);
  ASSERT_EQ(kept.intensity.size(), 2U);
  EXPECT_FLOAT_EQ(kept.intensity[1], 0.25F);
}

// x y z alone (12 bytes a point), five floats a point, or text, named .bin: loaded as a frame of
// meaningless points ("rotating 2D", thousands of lines; "all 13400 are self hits").
TEST_F(MisreadFiles, BinFilesOfAnotherLayoutAreNoVelodyneFrame) {
  for (const auto& [name, bytes] :
       {std::pair{"xyz_only.bin", floatRecords(400, 3)},
        std::pair{"five_floats.bin", floatRecords(400, 5) + floatRecords(100, 4)},
        std::pair{"text.bin", std::string(16 * 64, ' ').replace(0, 15, "1.48 0.00 0.06\n")}}) {
    const std::string message = errorOf(write(name, bytes));
    EXPECT_NE(message.find("not a Velodyne frame"), std::string::npos) << name << ": " << message;
  }
  EXPECT_EQ(loadScan(write("frame.bin", floatRecords(400, 4))).size(), 400U);
}

// A file of one point written again and again was "the scan has one scan line: give its rings".
TEST_F(MisreadFiles, PointsAllAtOnePlaceAreNoScan) {
  std::string rows;
  for (int i = 0; i < 500; ++i)
    rows += "1.5 2.5 0.5\n";
  const std::string message = errorOf(write("one_place.xyz", rows));
  EXPECT_NE(message.find("all 500 valid points lie at one place, (1.500, 2.500, 0.500)"),
            std::string::npos)
      << message;
  EXPECT_EQ(loadScan(write("two_places.xyz", rows + "1.6 2.5 0.5\n")).size(), 501U);
}

// Editors on Windows start a file with a byte-order mark; the pose file's was "found '0'".
TEST_F(MisreadFiles, PoseFileWithAByteOrderMarkIsRead) {
  write("marked.3d", "100 50 300\n200 50 300\n");
  write("marked.pose",
        "\xEF\xBB\xBF"
        "0 0 0\r\n0 90 0\r\n");
  const Scan scan = loadScan(directory / "marked.3d");
  ASSERT_TRUE(scan.sensor_pose);
  EXPECT_NEAR(scan.sensor_pose->rotation[0], 0.0, 1e-9);  // turned 90 deg about the vertical
}

// A file claiming more points than the memory there is to load and segment them in was loaded
// until the kernel killed the process (10 GB resident for 100 million points of zeros).
TEST_F(MisreadFiles, ScanLargerThanTheMemoryForItIsRefusedBeforeLoading) {
  LoadOptions options;
  options.memory_budget = 10'000'000;  // 10 MB: 40,000 points at 250 bytes each
  const std::size_t points = 100'000;
  const auto file = write("large.pcd", pcdHeader("x y z", "4 4 4", "F F F", points, "binary") +
                                           floatRecords(points, 3));
  const std::string message = errorOf(file, options);
  EXPECT_NE(
      message.find(
          "100000 points: loading and segmenting them takes about 26 MB, and 10 MB is available"),
      std::string::npos)
      << message;
  options.memory_budget = 100'000'000;
  EXPECT_EQ(loadScan(file, options).size(), points);
}

// A scan too sparse to segment said pose "none" with a confidence of 1 in report.json while the
// console said "pose: file".
TEST(SparseScanPose, IsTheFilesPoseAsForAnyScan) {
  Scan scan;
  for (int i = 0; i < 3; ++i) {
    scan.points.push_back({float(i), 1.0F, 0.0F});
    scan.status.push_back(PointStatus::kValid);
  }
  scan.lines.push_back({0, 3});
  const PipelineResult unposed = runPipeline(scan, SegmentationParams{});
  EXPECT_EQ(unposed.analysis->pose_source, PoseSource::kNone);
  EXPECT_EQ(unposed.analysis->up_confidence, 0.0);
  scan.sensor_pose = SensorPose{};
  const PipelineResult posed = runPipeline(scan, SegmentationParams{});
  EXPECT_FALSE(posed.trusted());
  EXPECT_EQ(posed.analysis->pose_source, PoseSource::kFile);
  EXPECT_EQ(posed.analysis->up_confidence, 1.0);
}

}  // namespace
}  // namespace clearway
