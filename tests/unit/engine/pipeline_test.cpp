// The pipeline's contract: validated parameters, cached re-runs for a new robot, cancellation,
// and clear answers for scans that cannot carry a result.

#include <gtest/gtest.h>

#include <limits>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>

#include "clearway/segmentation/line_segments.h"
#include "engine_fixtures.h"
#include "test_support.h"

namespace clearway {
namespace {

sim::SimulatedScan garage(int lines = 200) {
  sim::SensorModel sensor;
  sensor.lines = lines;
  const sim::Scene scene = *sim::builtinScene("garage");
  return sim::simulateRosi(scene, sensor, sim::defaultPlacement(scene));
}

// Every parallel stage cuts its work into parts by the number of threads and gathers the parts in
// order: planes, point classes, labels, reasons and reach do not depend on it (three threads cut
// the work unevenly).
void expectSameResult(const PipelineResult& result, const PipelineResult& reference,
                      const std::string& what) {
  ASSERT_EQ(result.trusted(), reference.trusted()) << what;
  EXPECT_EQ(result.analysis->planes.planes.size(), reference.analysis->planes.planes.size())
      << what;
  EXPECT_TRUE(result.point_classes == reference.point_classes) << what;
  EXPECT_TRUE(result.map.labels == reference.map.labels) << what;
  EXPECT_TRUE(result.map.reasons == reference.map.reasons) << what;
  EXPECT_TRUE(result.map.reach == reference.map.reach) << what;
}

TEST(Pipeline, GivesTheSameResultForAnyNumberOfThreads) {
  const sim::SimulatedScan straight = garage(120);
  const test::SimulatedRun tilted = test::simulateAndSegment("outdoor", 80, {}, 25.0, 12.0);
  for (const Scan* scan : {&straight.scan, &tilted.simulated.scan}) {
    const PipelineResult one = runPipeline(*scan, SegmentationParams{}, 1);
    ASSERT_TRUE(one.trusted()) << one.reason;
    for (const int threads : {2, 3})
      expectSameResult(runPipeline(*scan, SegmentationParams{}, threads), one,
                       std::to_string(threads) + " threads");
  }
}

TEST(Params, DefaultsAreValidAndRoundTripThroughJson) {
  const SegmentationParams defaults;
  EXPECT_TRUE(defaults.validate().empty());
  SegmentationParams changed;
  changed.robot.width = 1.1;
  changed.lines.method = LineMethod::kHough;
  changed.clustering.min_segments = 12;
  const SegmentationParams copy = paramsFromJson(toJson(changed));
  EXPECT_DOUBLE_EQ(copy.robot.width, 1.1);
  EXPECT_EQ(copy.lines.method, LineMethod::kHough);
  EXPECT_EQ(copy.clustering.min_segments, 12);
  for (const ParameterInfo& info : describeParameters()) {
    EXPECT_GE(info.default_value, info.minimum) << info.key;
    EXPECT_LE(info.default_value, info.maximum) << info.key;
    EXPECT_DOUBLE_EQ(parameterValue(defaults, info.key), info.default_value) << info.key;
  }
}

TEST(Params, BadValuesComeBackAsReadableReasons) {
  SegmentationParams params;
  params.robot.width = -1;
  params.map.resolution = 0.5;
  const auto reasons = params.validate();
  ASSERT_FALSE(reasons.empty());
  EXPECT_NE(reasons.front().find("robot.width"), std::string::npos);
  EXPECT_THROW(paramsFromJson(nlohmann::json{{"robot", {{"wheels", 4}}}}), std::invalid_argument);
  EXPECT_THROW(paramsFromJson(nlohmann::json{{"robot", {{"width", "wide"}}}}),
               std::invalid_argument);
  EXPECT_THROW(runPipeline(garage(20).scan, params), std::invalid_argument);
  // Too small a robot for the cells is said in the robot's terms, with the smallest that works.
  SegmentationParams tiny;
  tiny.robot.width = 0.05;
  const auto too_small = tiny.validate();
  ASSERT_EQ(too_small.size(), 1U);
  EXPECT_NE(too_small.front().find("a robot 0.05 m across is too small for cells of 0.05 m"),
            std::string::npos)
      << too_small.front();
  EXPECT_NE(too_small.front().find("at least 4 cells (0.2 m)"), std::string::npos);
}

TEST(Params, APresetWithOtherSizesIsNamedCustom) {
  for (const RobotParams& preset : robotPresets()) {
    EXPECT_EQ(presetOrCustomName(preset), preset.name);
    RobotParams changed = preset;
    changed.width += 0.05;
    EXPECT_EQ(presetOrCustomName(changed), "custom") << preset.name;
    changed = preset;
    changed.max_step = 0.05;
    EXPECT_EQ(presetOrCustomName(changed), "custom") << preset.name;
  }
  RobotParams own = robotPresets().front();
  own.name = "tracked carrier";
  own.width = 0.6;
  EXPECT_EQ(presetOrCustomName(own), "tracked carrier");
}

TEST(Params, LoadAndSaveUseFiles) {
  test::TemporaryDirectory directory;
  SegmentationParams params;
  params.robot.height = 1.9;
  saveParams(params, directory / "p.json");
  EXPECT_DOUBLE_EQ(loadParams(directory / "p.json").robot.height, 1.9);
  test::writeBytes(directory / "bad.json", "{\"map\": {\"resolution\": 7}}");
  EXPECT_THROW(loadParams(directory / "bad.json"), std::invalid_argument);
}

TEST(Pipeline, ANewRobotReusesTheAnalysisAndGivesTheSameMapAsAFullRun) {
  const auto simulated = garage();
  SegmentationParams params;
  const PipelineResult first = runPipeline(simulated.scan, params);
  params.robot.width = 1.0;
  const PipelineResult rerun = rerunForRobot(simulated.scan, first.analysis, params);
  const PipelineResult full = runPipeline(simulated.scan, params);
  EXPECT_EQ(rerun.map.labels, full.map.labels);
  EXPECT_NE(rerun.map.labels, first.map.labels);
  EXPECT_LT(rerun.map.counts[std::size_t(CellLabel::kTraversable)],
            first.map.counts[std::size_t(CellLabel::kTraversable)]);
  // The re-run shares the first run's analysis: the same object, not a copy.
  EXPECT_EQ(rerun.analysis.get(), first.analysis.get());
  EXPECT_GE(first.analysis.use_count(), 2);
  EXPECT_THROW(rerunForRobot(simulated.scan, nullptr, params), std::invalid_argument);
}

TEST(Pipeline, TheThreadsSettingReachesOpenCvForTheRunOnly) {
  // OpenCV's thread count is process-wide: a run uses the caller's, and leaves it as it was.
  const auto simulated = garage();
  const int before = cv::getNumThreads();
  const int wanted = before == 1 ? 2 : 1;
  std::vector<int> during;
  runPipeline(simulated.scan, {}, wanted, [&](double) {
    during.push_back(cv::getNumThreads());
    return true;
  });
  ASSERT_FALSE(during.empty());
  for (int threads : during)
    EXPECT_EQ(threads, wanted);
  EXPECT_EQ(cv::getNumThreads(), before);
}

TEST(Pipeline, ProgressRisesAndCancelStopsTheWork) {
  const auto simulated = garage();
  std::vector<double> fractions;
  runPipeline(simulated.scan, {}, 2, [&](double f) {
    fractions.push_back(f);
    return true;
  });
  ASSERT_GT(fractions.size(), 3u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  int calls = 0;
  EXPECT_THROW(runPipeline(simulated.scan, {}, 2, [&](double) { return ++calls < 3; }),
               OperationCancelled);
}

TEST(Pipeline, ScansTooSparseOrEmptyAreNotTrusted) {
  Scan empty;
  const PipelineResult nothing = runPipeline(empty, {});
  EXPECT_FALSE(nothing.trusted());
  EXPECT_NE(nothing.reason.find("too sparse"), std::string::npos);

  Scan nan_scan = garage(20).scan;
  for (std::size_t i = 0; i < nan_scan.size(); ++i) {
    nan_scan.points[i] = {std::numeric_limits<float>::quiet_NaN(), 0, 0};
    nan_scan.status[i] = PointStatus::kNoReturn;
  }
  const PipelineResult none = runPipeline(nan_scan, {});
  EXPECT_FALSE(none.trusted());
  EXPECT_EQ(none.map.counts[std::size_t(CellLabel::kTraversable)], 0u);
}

TEST(Pipeline, PointClassesFollowThePlanes) {
  const auto simulated = garage(300);
  const PipelineResult result = runPipeline(simulated.scan, {});
  ASSERT_EQ(result.point_classes.size(), simulated.scan.size());
  std::size_t agree = 0, ground = 0;
  for (std::size_t i = 0; i < simulated.scan.size(); ++i) {
    if (simulated.truth.classes[i] != PointClass::kGround) continue;
    ++ground;
    agree += result.point_classes[i] == PointClass::kGround;
  }
  EXPECT_GT(double(agree) / double(ground), 0.95);
}

TEST(LineSegments, SplitAndMergeAndHoughBothFindTheFloorLines) {
  // Scanner 1.5 m over an empty floor, axis down: every half line is one straight floor segment.
  sim::Scene scene;
  sim::Primitive floor;
  floor.point_class = PointClass::kGround;
  floor.center = {0, 0, -0.05};
  floor.size = {60, 60, 0.1};
  scene.primitives.push_back(floor);
  sim::SensorModel sensor;
  sensor.lines = 40;
  sensor.max_range = 8.0;
  sim::ScannerPlacement placement;
  placement.position = {0, 0, 1.5};
  placement.axis = {0, 0, -1};
  const Scan scan = sim::simulateRosi(scene, sensor, placement).scan;
  for (const LineMethod method : {LineMethod::kSplitAndMerge, LineMethod::kHough}) {
    SCOPED_TRACE(method == LineMethod::kHough ? "hough" : "split and merge");
    LineParams params;
    params.method = method;
    const auto segments = detectLineSegments(scan, params);
    std::vector<float> longest(40, 0.0F);
    for (const LineSegment& s : segments) {
      longest[s.line] = std::max(longest[s.line], s.length());
      // Every segment lies on the floor, 1.5 m along the axis (axis down: z' = -z).
      EXPECT_NEAR(s.start.z(), 1.5, 0.05);
      EXPECT_NEAR(s.end.z(), 1.5, 0.05);
    }
    // Each half line sees about 7.7 m of floor; noise may cut a little off under the scanner.
    for (float length : longest)
      EXPECT_GT(length, 6.0F);
  }
}

}  // namespace
}  // namespace clearway
