// eval on hand-made results whose right scores are known.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "clearway/eval/evaluation.h"
#include "clearway/eval/robot_fit.h"
#include "clearway/eval/segmentation_accuracy.h"
#include "clearway/io/result_manifest.h"
#include "clearway/io/scan_error.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/ground_truth_io.h"
#include "test_support.h"

namespace clearway::eval {
namespace {

using nlohmann::json;

// A map whose frame is the garage's world frame: x 4 m behind .. 12 m ahead, y -3 .. 3 m, 0.1 m
// cells.
struct HandMadeMap {
  double resolution = 0.1;
  double x0 = -4.0, y0 = -3.0;
  int width = 160, height = 60;
  std::vector<std::uint8_t> cells = std::vector<std::uint8_t>(std::size_t(width * height), 0);
  void paint(double xa, double ya, double xb, double yb, std::uint8_t label) {
    for (int r = 0; r < height; ++r)
      for (int c = 0; c < width; ++c) {
        const double x = x0 + (c + 0.5) * resolution, y = y0 + (r + 0.5) * resolution;
        if (x >= xa && x <= xb && y >= ya && y <= yb)
          cells[std::size_t(height - 1 - r) * std::size_t(width) + std::size_t(c)] = label;
      }
  }
};

class Evaluate : public ::testing::Test {
 protected:
  void SetUp() override {
    sim::SensorModel sensor;
    sensor.lines = 120;
    scene_ = *sim::builtinScene("garage");
    simulated_ = sim::simulateRosi(scene_, sensor, sim::defaultPlacement(scene_));
  }

  SegmentationResult withMap(const HandMadeMap& map, double robot_width) {
    const std::string pgm = "P5\n" + std::to_string(map.width) + " " + std::to_string(map.height) +
                            "\n255\n" + std::string(map.cells.begin(), map.cells.end());
    test::writeBytes(directory_ / "labels.pgm", pgm);
    std::vector<double> matrix;
    const Eigen::Matrix4d m = simulated_.truth.placement.worldFromScanner().matrix();
    for (int i = 0; i < 16; ++i)
      matrix.push_back(m(i / 4, i % 4));
    const json report = {
        {"ground_found", true},
        {"robot", {{"width", robot_width}, {"length", 1.2}, {"height", 1.5}, {"max_step", 0.1}}},
        {"planes", json::array()},
        {"map",
         {{"resolution", map.resolution},
          {"origin", {map.x0, map.y0}},
          {"width", map.width},
          {"height", map.height},
          {"labels", "labels.pgm"},
          {"map_from_scanner", matrix}}}};
    test::writeBytes(directory_ / "report.json", report.dump());
    return loadSegmentationResult(directory_.path());
  }

  sim::Scene scene_;
  sim::SimulatedScan simulated_;
  test::TemporaryDirectory directory_;
};

TEST_F(Evaluate, PerfectPointClassesScoreOne) {
  SegmentationResult result;
  result.point_classes = simulated_.truth.classes;
  const Evaluation e = evaluate(simulated_.truth, result);
  for (PointClass c : {PointClass::kGround, PointClass::kWall, PointClass::kObstacle}) {
    EXPECT_DOUBLE_EQ(e.classes[std::size_t(c)].precision, 1.0);
    EXPECT_DOUBLE_EQ(e.classes[std::size_t(c)].iou, 1.0);
  }
}

TEST_F(Evaluate, CallingEverythingGroundGivesTheGroundShareAsPrecision) {
  SegmentationResult result;
  result.point_classes.assign(simulated_.truth.classes.size(), PointClass::kGround);
  const Evaluation e = evaluate(simulated_.truth, result);
  std::size_t ground = 0, returns = 0;
  for (PointClass c : simulated_.truth.classes) {
    ground += c == PointClass::kGround;
    returns += c != PointClass::kNone;
  }
  const ClassScore& g = e.classes[std::size_t(PointClass::kGround)];
  EXPECT_DOUBLE_EQ(g.recall, 1.0);
  EXPECT_DOUBLE_EQ(g.precision, double(ground) / double(returns));
  EXPECT_DOUBLE_EQ(e.classes[std::size_t(PointClass::kWall)].recall, 0.0);
}

TEST_F(Evaluate, PointCountMismatchIsAnError) {
  SegmentationResult result;
  result.point_classes.assign(10, PointClass::kGround);
  EXPECT_THROW(evaluate(simulated_.truth, result), std::runtime_error);
}

TEST_F(Evaluate, TruthPlanesAreRecalledAndTiltedOnesMeasured) {
  SegmentationResult exact, tilted;
  for (const sim::SurfaceTruth& s : simulated_.truth.seen_surfaces) {
    if (!s.planar || s.points < 200) continue;
    exact.planes.push_back({s.normal, s.offset, ""});
    // Tilt by 5 degrees about an axis perpendicular to the normal, flip half of them.
    const Eigen::Vector3d axis = s.normal.unitOrthogonal();
    const Eigen::Vector3d n = Eigen::AngleAxisd(5.0 * M_PI / 180.0, axis) * s.normal;
    const double sign = tilted.planes.size() % 2 ? -1.0 : 1.0;
    tilted.planes.push_back({sign * n, sign * s.offset, ""});
  }
  const Evaluation e = evaluate(simulated_.truth, exact);
  EXPECT_DOUBLE_EQ(e.planes.recall, 1.0);
  EXPECT_DOUBLE_EQ(e.planes.precision, 1.0);
  EXPECT_NEAR(e.planes.mean_normal_error_deg, 0.0, 1e-6);
  const Evaluation t = evaluate(simulated_.truth, tilted);
  EXPECT_DOUBLE_EQ(t.planes.recall, 1.0);
  EXPECT_NEAR(t.planes.mean_normal_error_deg, 5.0, 1e-6);
  EXPECT_NEAR(t.planes.mean_offset_error_m, 0.0, 1e-9);
}

TEST_F(Evaluate, GreenInsideTheTruckIsFalseTraversable) {
  HandMadeMap map;
  map.paint(1.8, -1.2, 2.2, -0.8, 1);  // open floor by the door: true
  map.paint(-1.2, 1.4, -0.8, 1.8, 1);  // inside the truck: false
  const Evaluation e = evaluate(simulated_.truth, withMap(map, 0.85));
  const std::size_t cells_per_patch = 16;
  EXPECT_EQ(e.map.traversable_cells, 2 * cells_per_patch);
  EXPECT_EQ(e.map.false_traversable_cells, cells_per_patch);
  EXPECT_DOUBLE_EQ(e.map.false_traversable_rate, 0.5);
}

TEST_F(Evaluate, APathThroughTheDoorIsRightForTheSmallRobotAndUnsafeForTheWide) {
  HandMadeMap map;
  map.paint(1.5, -1.1, 8.0, -0.9, 2);  // a line of careful cells through the 0.9 m door's middle
  const Evaluation small = evaluate(simulated_.truth, withMap(map, 0.85));
  ASSERT_EQ(small.map.places.size(), 1u);
  EXPECT_TRUE(small.map.places[0].expected);
  EXPECT_TRUE(small.map.places[0].found);
  EXPECT_EQ(small.map.false_traversable_cells, 0u);

  const Evaluation wide = evaluate(simulated_.truth, withMap(map, 1.0));
  EXPECT_FALSE(wide.map.places[0].expected);
  EXPECT_TRUE(wide.map.places[0].found);
  EXPECT_GT(wide.map.false_traversable_cells, 0u) << "the door cells cannot hold a 1.0 m robot";
}

TEST_F(Evaluate, BrokenResultFoldersAreRefused) {
  EXPECT_THROW(loadSegmentationResult(directory_ / "absent"), std::runtime_error);
  test::writeBytes(directory_ / "report.json", R"({"map": {"resolution": 0.1}})");
  EXPECT_THROW(loadSegmentationResult(directory_.path()), std::runtime_error);
  HandMadeMap map;
  withMap(map, 0.85);
  test::writeBytes(directory_ / "labels.pgm", "P5\n160 60\n255\nshort");
  EXPECT_THROW(loadSegmentationResult(directory_.path()), std::runtime_error);
}

// Values no writer of Clearway's gives (a hand edit, a writer bug) were scored: a cell of 0 m,
// a map frame of zeros ("false traversable at (-nan, -nan, -nan)"), a label of 200, an empty
// origin ("vector::_M_range_check", naming neither file nor key). Each is refused by its key.
TEST_F(Evaluate, ResultValuesOutOfRangeAreRefusedByName) {
  HandMadeMap map;
  withMap(map, 0.85);  // a good folder, edited below
  const json good = json::parse(test::readBytes(directory_ / "report.json"));
  auto refusal = [&](const std::function<void(json&)>& edit) {
    json report = good;
    edit(report);
    test::writeBytes(directory_ / "report.json", report.dump());
    try {
      loadSegmentationResult(directory_.path());
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
    return std::string("loaded");
  };
  EXPECT_NE(refusal([](json& r) { r["map"]["resolution"] = 0.0; }).find("map.resolution"),
            std::string::npos);
  EXPECT_NE(refusal([](json& r) { r["map"]["resolution"] = -0.05; }).find("map.resolution"),
            std::string::npos);
  EXPECT_NE(refusal([](json& r) { r["map"]["origin"] = json::array(); }).find("map.origin"),
            std::string::npos);
  EXPECT_NE(refusal([](json& r) {
              r["map"]["origin"] = {1e300, 0.0};
            }).find("map.origin"),
            std::string::npos);
  EXPECT_NE(refusal([](json& r) {
              r["map"]["map_from_scanner"] = std::vector<double>(16, 0.0);
            }).find("map.map_from_scanner is not a rotation"),
            std::string::npos);
  EXPECT_NE(refusal([](json& r) { r["robot"]["width"] = -1.0; }).find("robot.width"),
            std::string::npos);
  EXPECT_EQ(refusal([](json& r) { r["robot"]["max_step"] = 0.0; }), "loaded");  // climbs nothing
  EXPECT_NE(refusal([](json& r) {
              r["map"]["map_from_scanner"][3] = 1e300;
            }).find("moves the scanner more than 1000 km"),
            std::string::npos);
  EXPECT_NE(refusal([](json& r) {
              r["map"]["labels"] = "../elsewhere.pgm";
            }).find("is not a file name in the result folder"),
            std::string::npos);
  EXPECT_EQ(refusal([](json&) {}), "loaded");
  HandMadeMap odd;
  odd.paint(0.0, -1.0, 1.0, 1.0, 200);
  const std::string pgm = "P5\n" + std::to_string(odd.width) + " " + std::to_string(odd.height) +
                          "\n255\n" + std::string(odd.cells.begin(), odd.cells.end());
  test::writeBytes(directory_ / "labels.pgm", pgm);
  EXPECT_NE(refusal([](json&) {}).find("label 200 is none of the map's labels"), std::string::npos);
}

// A manifest of no files vouched for a folder of any files.
TEST_F(Evaluate, AManifestMustVouchForTheReport) {
  HandMadeMap map;
  withMap(map, 0.85);
  for (const char* files : {R"({})", R"([])"}) {
    test::writeBytes(directory_ / kResultManifestName,
                     std::string(R"({"run_id": "x", "files": )") + files + "}");
    try {
      verifyResultFolder(directory_.path());
      ADD_FAILURE() << files << " vouched for the folder";
    } catch (const ScanError& error) {
      EXPECT_NE(std::string(error.what()).find("does not list report.json"), std::string::npos)
          << error.what();
    }
  }
}

// A class of 1.5 was read as class 1, a truth file of a later layout as this one.
TEST_F(Evaluate, TruthValuesOutOfTheirLayoutAreRefused) {
  const auto file = directory_ / "scan.truth.json";
  sim::saveGroundTruth(simulated_.truth, file, "scan.pcd");
  const json good = json::parse(test::readBytes(file));
  auto refusal = [&](const std::function<void(json&)>& edit) {
    json truth = good;
    edit(truth);
    test::writeBytes(file, truth.dump());
    try {
      sim::loadGroundTruth(file);
    } catch (const std::exception& error) {
      return std::string(error.what());
    }
    return std::string("loaded");
  };
  EXPECT_EQ(refusal([](json&) {}), "loaded");
  EXPECT_EQ(sim::loadGroundTruth(file).scan, "scan.pcd");
  EXPECT_NE(refusal([](json& t) { t["classes"][0] = 1.5; }).find("class 1.5 is not a whole number"),
            std::string::npos);
  EXPECT_NE(refusal([](json& t) { t["version"] = 99; }).find("truth file version 99"),
            std::string::npos);
}

// Every planar truth surface as its own plane, its points assigned to it: the perfect segmentation.
PointPlanes truthSegmentation(const sim::GroundTruth& truth) {
  PointPlanes result;
  result.point_plane.assign(truth.surfaces.size(), -1);
  std::map<int, std::int32_t> plane_of_surface;
  for (const sim::SurfaceTruth& surface : truth.seen_surfaces) {
    if (!surface.planar) continue;
    plane_of_surface[surface.id] = std::int32_t(result.planes.size());
    result.planes.push_back({surface.normal, surface.offset, "other"});
  }
  for (std::size_t i = 0; i < truth.surfaces.size(); ++i) {
    const auto plane = plane_of_surface.find(truth.surfaces[i]);
    if (plane != plane_of_surface.end()) result.point_plane[i] = plane->second;
  }
  return result;
}

TEST_F(Evaluate, TheTruthItselfIsAPerfectSegmentation) {
  const SegmentationAccuracy accuracy =
      scoreSegmentation(simulated_.truth, truthSegmentation(simulated_.truth));
  EXPECT_DOUBLE_EQ(accuracy.planes.recall, 1.0);
  EXPECT_DOUBLE_EQ(accuracy.point_purity, 1.0);
  EXPECT_DOUBLE_EQ(accuracy.coverage, 1.0);
  EXPECT_GT(accuracy.assigned_points, simulated_.scan.validCount() / 2);
}

TEST_F(Evaluate, OnePlaneForEveryPointIsImpureAndRecallsOnlyItself) {
  PointPlanes one = truthSegmentation(simulated_.truth);
  // The plane of the truth surface with the most points takes every point.
  const auto largest =
      std::max_element(simulated_.truth.seen_surfaces.begin(), simulated_.truth.seen_surfaces.end(),
                       [](const auto& a, const auto& b) { return a.points < b.points; });
  one.planes = {{largest->normal, largest->offset, "ground"}};
  std::size_t with_surface = 0;
  for (std::size_t i = 0; i < one.point_plane.size(); ++i) {
    one.point_plane[i] = simulated_.truth.surfaces[i] >= 0 ? 0 : -1;
    with_surface += simulated_.truth.surfaces[i] >= 0;
  }
  const SegmentationAccuracy accuracy = scoreSegmentation(simulated_.truth, one);
  EXPECT_EQ(accuracy.assigned_points, with_surface);
  // Pure are the largest surface's points and those of coplanar surfaces: far from all.
  EXPECT_GE(accuracy.point_purity, double(largest->points) / double(with_surface) - 1e-9);
  EXPECT_LT(accuracy.point_purity, 0.8);
  EXPECT_LT(accuracy.planes.recall, 0.5);
  EXPECT_DOUBLE_EQ(accuracy.planes.precision, 1.0);
}

TEST_F(Evaluate, SegmentationOfAnotherScanIsRefused) {
  PointPlanes wrong = truthSegmentation(simulated_.truth);
  wrong.point_plane.pop_back();
  EXPECT_THROW(scoreSegmentation(simulated_.truth, wrong), std::invalid_argument);
  PointPlanes dangling = truthSegmentation(simulated_.truth);
  const auto first_point =
      std::find_if(simulated_.truth.surfaces.begin(), simulated_.truth.surfaces.end(),
                   [](std::int32_t surface) { return surface >= 0; });
  dangling.point_plane[std::size_t(first_point - simulated_.truth.surfaces.begin())] = 999;
  EXPECT_THROW(scoreSegmentation(simulated_.truth, dangling), std::invalid_argument);
}

TEST(RobotFit, StepsAndLowObstaclesStopTheRobot) {
  // RobotFit keeps a reference to its scene: the scene must outlive it (ASan found the temporary
  // this test used to pass: stack-use-after-scope).
  const sim::Scene scene = *sim::builtinScene("hallway");
  const RobotFit hallway(scene);
  const sim::RobotBox robot{0.85, 1.2, 1.5, 0.1};
  EXPECT_TRUE(hallway.fits(robot, {1.0, 0.0, 0.0}, 0.0));
  EXPECT_TRUE(hallway.fits(robot, {5.0, 0.8, 0.4}, 0.0)) << "on the ramp";
  EXPECT_FALSE(hallway.fits(robot, {3.6, -0.8, 0.3}, 0.0)) << "on the stairs";
  EXPECT_FALSE(hallway.fits(robot, {5.0, 0.0, 0.4}, 0.0)) << "astride the divider";
  const auto ground = hallway.groundHeight(5.0, 0.8, 3.0);
  ASSERT_TRUE(ground);
  EXPECT_GT(*ground, 0.1);
}

TEST(RobotFit, APipeStopsTheRobotWhereItHangsLowerThanTheRobotsTopNotWhereItsBoxDoes) {
  // A pipe along y, its underside 1 m above the floor; the robot's top at 1.02 m meets it within
  // 7.5 cm of its lowest line. The pipe's box reaches down to 1 m across its whole 0.3 m width.
  sim::Scene scene;
  sim::Primitive floor;
  floor.point_class = PointClass::kGround;
  floor.center = {0.0, 0.0, -0.05};
  floor.size = {10.0, 10.0, 0.1};
  sim::Primitive pipe;
  pipe.shape = sim::Shape::kCylinder;
  pipe.center = {0.0, 0.0, 1.15};
  pipe.size = {0.3, 0.3, 10.0};
  pipe.roll_deg = 90.0;
  scene.primitives = {floor, pipe};
  const RobotFit fit(scene);
  const sim::RobotBox robot{0.6, 1.0, 1.02, 0.1};
  // Length along x: the box's front edge 10 cm short of the pipe's axis, where the pipe's surface
  // is 1.8 cm above the robot's top; then 5 cm short, where it is 1.1 cm below it.
  EXPECT_TRUE(fit.fits(robot, {-0.60, 0.0, 0.0}, 0.0));
  EXPECT_FALSE(fit.fits(robot, {-0.55, 0.0, 0.0}, 0.0));
  // Under the pipe across its axis, and clear of it beside it.
  EXPECT_FALSE(fit.fits(robot, {0.0, 0.0, 0.0}, 0.0));
  EXPECT_TRUE(fit.fits(robot, {-0.8, 0.0, 0.0}, 0.0));
}

// Flat ground at height 0 for x < 0, and for x > 0 a slab pitched `pitch_deg` (negative: rising
// with x) whose top is at `height_at_edge` where the flat ground ends. The slab runs on under the
// flat ground, which hides it there.
sim::Scene flatThenPitched(double pitch_deg, double height_at_edge) {
  sim::Primitive flat;
  flat.point_class = PointClass::kGround;
  flat.center = {-1.0, 0.0, -0.1};
  flat.size = {2.0, 4.0, 0.2};
  sim::Primitive pitched = flat;
  pitched.pitch_deg = pitch_deg;
  pitched.size = {4.0, 4.0, 0.2};
  // A turned box's top, over its centre, lies half its thickness / cos(pitch) above the centre.
  const double half_thickness_up = 0.1 / std::cos(pitch_deg * std::numbers::pi / 180.0);
  pitched.center = {0.0, 0.0, height_at_edge - half_thickness_up};
  sim::Scene scene;
  scene.primitives = {flat, pitched};
  return scene;
}

TEST(RobotFit, AStepIsWhereTwoSurfacesMeetNotWhatTheGroundRisesBetweenSamples) {
  // Samples 0.15 m apart along a 0.6 m robot centred at x = 0.075: one pair straddles x = 0.
  const Eigen::Vector3d straddling{0.075, 0.0, 0.0};
  const sim::RobotBox robot{0.6, 0.6, 1.0, 0.05};
  {
    // A 25 deg ramp from the floor: its samples rise 7 cm apart, and it has no step.
    const sim::Scene ramp = flatThenPitched(-25.0, 0.0);
    const RobotFit fit(ramp);
    EXPECT_TRUE(fit.fits(robot, straddling, 0.0));
    EXPECT_TRUE(fit.fits(robot, {0.5, 0.0, 0.2}, 0.0)) << "on the ramp";
  }
  {
    // A 6 cm step down to a slab rising 10 deg away from it: the samples either side are 4.7 cm
    // apart, the step 6 cm.
    const sim::Scene slabs = flatThenPitched(-10.0, -0.06);
    const RobotFit fit(slabs);
    EXPECT_FALSE(fit.fits(robot, straddling, 0.0));
    EXPECT_TRUE(fit.fits({0.6, 0.6, 1.0, 0.07}, straddling, 0.0)) << "a robot taking 7 cm steps";
    EXPECT_TRUE(fit.fits(robot, {0.5, 0.0, 0.0}, 0.0)) << "on the slab alone";
  }
}

}  // namespace
}  // namespace clearway::eval
