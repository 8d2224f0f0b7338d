// The files beside a scan and the values given with it, read as strictly as the scan: a pose
// sidecar that cannot be the scanner's, a parameter file with a key given twice, a direction of
// huge components, a pipe where a file belongs. Found by a helper's 480 runs on malformed side
// files (twenty-third session).

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <functional>
#include <stdexcept>

#include "clearway/io/scan_error.h"
#include "clearway/pose.h"
#include "clearway/segmentation/params.h"
#include "clearway/sim/ground_truth_io.h"
#include "clearway/sim/scene_io.h"
#include "test_support.h"

namespace clearway {
namespace {

namespace fs = std::filesystem;

// The message of what `read` throws; "read" when it throws nothing.
std::string messageOf(const std::function<void()>& read) {
  try {
    read();
  } catch (const std::exception& error) {
    return error.what();
  }
  return "read";
}

std::string sidecar(const std::string& translation, const std::string& rotation) {
  return R"({"version": 1, "world_from_scanner": {"translation": )" + translation +
         R"(, "rotation_wxyz": )" + rotation + "}}";
}

// Translations of 1e308 m put the robot off the map and every cell out of reach, under "Ground
// found"; quaternions of length 2 or 1e-8 were normalised without a word; a sidecar that is a
// broken link was no sidecar at all.
TEST(MisreadSideFiles, APoseSidecarMustBeAScannersPose) {
  test::TemporaryDirectory directory;
  const fs::path file = directory / "scan.pose.json";
  auto read = [&](const std::string& text) {
    test::writeBytes(file, text);
    return messageOf([&] { readPoseSidecar(file); });
  };
  EXPECT_EQ(read(sidecar("[0.5, -0.5, 1.2]", "[1, 0, 0, 0]")), "read");
  EXPECT_EQ(read(sidecar("[0.5, -0.5, 1.2]", "[0.70711, 0.70711, 0, 0]")), "read");  // rounded
  EXPECT_NE(read(sidecar("[0, 0, 1e308]", "[1, 0, 0, 0]")).find("more than 10 km away"),
            std::string::npos);
  for (const char* rotation : {"[2, 0, 0, 0]", "[1e-8, 0, 0, 0]", "[1e308, 1e308, 0, 0]"})
    EXPECT_NE(read(sidecar("[0, 0, 1]", rotation)).find("not 1: not a rotation as written"),
              std::string::npos)
        << rotation;
  const std::string nested = read(
      sidecar("[0, 0, " + std::string(2000, '[') + std::string(2000, ']') + "]", "[1, 0, 0, 0]"));
  EXPECT_LT(nested.size(), 300u) << "a 60 kB message line";
  fs::remove(file);
  const fs::path scan = directory / "scan.pcd";
  fs::create_symlink(directory / "gone.json", file);
  EXPECT_EQ(findPoseSidecar(scan), file);  // found, so that reading it says what is wrong
  EXPECT_NE(messageOf([&] { readPoseSidecar(file); }).find("no such file"), std::string::npos);
}

// "--up 1e200,0,0" overflowed its norm into the zero vector, accepted with confidence 1.
TEST(MisreadSideFiles, DirectionsOfHugeComponentsKeepTheirDirection) {
  const Eigen::Vector3d up = parseUpText("1e200,0,0");
  EXPECT_DOUBLE_EQ(up.x(), 1.0);
  EXPECT_DOUBLE_EQ(up.norm(), 1.0);
  const auto diagonal = unitDirection({1e300, 1e300, 1e300});
  ASSERT_TRUE(diagonal);
  EXPECT_NEAR(diagonal->x(), 1.0 / std::sqrt(3.0), 1e-12);
  EXPECT_FALSE(unitDirection({0, 0, 0}));
  EXPECT_FALSE(unitDirection({NAN, 0, 1}));
  EXPECT_THROW(parseUpText("0,0,0"), std::invalid_argument);
}

// {"robot": {"width": 0.5, "width": 3}} ran with a 3 m robot; an unknown section was "must be an
// object", an unknown key given text "must be a number", a name given a number a bare
// "type_error.302".
TEST(MisreadSideFiles, AParameterFileSaysWhatIsWrongByKey) {
  test::TemporaryDirectory directory;
  const fs::path file = directory / "params.json";
  auto read = [&](const std::string& text) {
    test::writeBytes(file, text);
    return messageOf([&] { loadParams(file); });
  };
  EXPECT_EQ(read(R"({"robot": {"width": 0.5}})"), "read");
  EXPECT_NE(
      read(R"({"robot": {"width": 0.5, "width": 3}})").find(R"(the key "width" is given twice)"),
      std::string::npos);
  EXPECT_NE(read(R"({"robto": {"width": 0.5}})").find("unknown parameter section 'robto'"),
            std::string::npos);
  EXPECT_NE(read(R"({"robot": {"widht": "wide"}})").find("unknown parameter 'robot.widht'"),
            std::string::npos);
  EXPECT_NE(read(R"({"robot": {"name": 5}})").find("robot.name must be text, not 5"),
            std::string::npos);
}

// A pipe given as a parameter, scene or truth file was waited on until the process was killed;
// a folder said "basic_filebuf::underflow", naming no file.
TEST(MisreadSideFiles, APipeOrAFolderWhereAFileBelongsIsRefusedByName) {
  test::TemporaryDirectory directory;
  const fs::path pipe = directory / "pipe.json";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  const fs::path folder = directory / "folder.json";
  fs::create_directory(folder);
  const std::vector<std::pair<std::string, std::function<void(const fs::path&)>>> readers = {
      {"parameters", [](const fs::path& f) { loadParams(f); }},
      {"scene", [](const fs::path& f) { sim::loadScene(f); }},
      {"truth", [](const fs::path& f) { sim::loadGroundTruth(f); }},
      {"sidecar", [](const fs::path& f) { readPoseSidecar(f); }}};
  for (const auto& [name, reader] : readers) {
    const auto& read = reader;  // a structured binding: not for a lambda in clang 14
    const std::string on_pipe = messageOf([&] { read(pipe); });
    EXPECT_NE(on_pipe.find("not a regular file"), std::string::npos) << name << ": " << on_pipe;
    EXPECT_NE(on_pipe.find(pipe.string()), std::string::npos) << name << ": " << on_pipe;
    const std::string on_folder = messageOf([&] { read(folder); });
    EXPECT_NE(on_folder.find("is a directory"), std::string::npos) << name << ": " << on_folder;
  }
}

}  // namespace
}  // namespace clearway
