#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <tuple>

#include "clearway/sim/builtin_scenes.h"
#include "clearway/sim/ground_truth_io.h"
#include "clearway/sim/scene_io.h"
#include "test_support.h"

namespace clearway::sim {
namespace {

TEST(Scenes, ShippedSceneFilesAreTheBuiltInsDefaults) {
  for (const std::string& name : builtinSceneNames()) {
    SCOPED_TRACE(name);
    const auto file =
        std::filesystem::path(CLEARWAY_SOURCE_DIR) / "resources/scenes" / (name + ".json");
    ASSERT_TRUE(std::filesystem::exists(file))
        << "regenerate with: clearway-cli scene " << name << " -o " << file;
    EXPECT_EQ(sceneToJson(loadScene(file)), sceneToJson(*builtinScene(name)))
        << "resources/scenes is stale: clearway-cli scene " << name << " -o " << file;
  }
}

TEST(Scenes, JsonRoundTripKeepsEverything) {
  const Scene scene = *builtinScene("outdoor");
  const Scene copy = sceneFromJson(sceneToJson(scene));
  ASSERT_EQ(copy.primitives.size(), scene.primitives.size());
  const auto pipe_it = std::find_if(copy.primitives.begin(), copy.primitives.end(),
                                    [](const Primitive& p) { return p.name == "pipe"; });
  ASSERT_NE(pipe_it, copy.primitives.end());
  const Primitive& pipe = *pipe_it;
  EXPECT_EQ(pipe.shape, Shape::kCylinder);
  EXPECT_DOUBLE_EQ(pipe.roll_deg, 90.0);
  EXPECT_EQ(copy.passages.size(), scene.passages.size());
  EXPECT_EQ(copy.scanner_axis, scene.scanner_axis);
}

TEST(Scenes, MalformedScenesAreRefusedWithAReason) {
  using nlohmann::json;
  EXPECT_THROW(sceneFromJson(json::array()), SceneError);
  EXPECT_THROW(sceneFromJson(json{{"name", "x"}}), SceneError);
  const json bad_class = {
      {"primitives", {{{"class", "lava"}, {"center", {0, 0, 0}}, {"size", {1, 1, 1}}}}}};
  EXPECT_THROW(sceneFromJson(bad_class), SceneError);
  const json bad_vector = {{"primitives", {{{"center", {0, 0}}, {"size", {1, 1, 1}}}}}};
  EXPECT_THROW(sceneFromJson(bad_vector), SceneError);
  const json negative = {{"primitives", {{{"center", {0, 0, 0}}, {"size", {1, -1, 1}}}}}};
  EXPECT_THROW(sceneFromJson(negative), SceneError);
  test::TemporaryDirectory directory;
  test::writeBytes(directory / "broken.json", "{ not json");
  EXPECT_THROW(loadScene(directory / "broken.json"), SceneError);
  EXPECT_THROW(loadScene(directory / "missing.json"), SceneError);
}

// The SceneError reading `document` gives; fails the test when it reads.
std::string sceneErrorOf(const nlohmann::json& document) {
  try {
    sceneFromJson(document);
    ADD_FAILURE() << "read " << document.dump().substr(0, 200);
  } catch (const SceneError& error) {
    return error.what();
  }
  return {};
}

// Each value was read as given: a passage to a place the scene lacks joined nothing, a width of -1
// was "no limit", a negative remission a negative intensity, a scanner at 1e308 saw nothing. Each
// is refused naming its key and value.
TEST(Scenes, ValuesNoSceneHoldsAreRefusedNamingKeyAndValue) {
  using nlohmann::json;
  const json garage = sceneToJson(*builtinScene("garage"));
  const auto with = [&](const std::string& key, const json& value) {
    json changed = garage;
    changed[json::json_pointer(key)] = value;
    return changed;
  };
  std::size_t truck = 0;  // remission 0.8, size [5, 2, 2.2]
  while (truck < garage["primitives"].size() && garage["primitives"][truck]["name"] != "truck")
    ++truck;
  ASSERT_LT(truck, garage["primitives"].size());
  const auto primitive = [&](const std::string& key) {
    return "/primitives/" + std::to_string(truck) + "/" + key;
  };
  ASSERT_EQ(garage["passages"][0]["name"], "door");
  for (const auto& [document, expected] : std::vector<std::pair<json, std::string>>{
           {with("/passages/0/to", "outsid"),
            "passage 'door'.to = 'outsid' names no place of the scene (places: 'inside', "
            "'outside')"},
           {with("/passages/0/from", "hall"), "passage 'door'.from = 'hall'"},
           {with("/passages/0/width", -1),
            "passage 'door'.width = -1 is outside 0 .. 20000 m (0: no limit)"},
           {with("/passages/0/height", -2), "passage 'door'.height = -2 is outside"},
           {with("/passages/0/step", -0.1), "passage 'door'.step = -0.1 is outside"},
           {with("/passages/0/width", true), "passage 'door'.width = true is not a finite number"},
           {with(primitive("remission"), -0.2),
            "primitive 'truck'.remission = -0.2 is outside 0 .. 1"},
           {with(primitive("remission"), 3), "primitive 'truck'.remission = 3 is outside 0 .. 1"},
           {with(primitive("yaw_deg"), 1e9), "primitive 'truck'.yaw_deg = 1e+09 is outside"},
           {with(primitive("size"), {5, -1, 2.2}),
            "primitive 'truck'.size = [5, -1, 2.2]: every edge must be more than 0"},
           {with(primitive("size"), {5, 0, 2.2}), "primitive 'truck'.size = [5, 0, 2.2]"},
           {with(primitive("center"), {0, 0, 1e308}),
            "primitive 'truck'.center = [0, 0, 1e+308] lies more than 10 km from the origin"},
           {with(primitive("shape"), "cylinder"),
            "primitive 'truck'.size = [5, 2, 2.2]: a cylinder's size is [diameter, diameter, "
            "length]"},
           {with("/scanner/position", {0.5, -0.5, 1e308}),
            "scanner.position = [0.5, -0.5, 1e+308] lies more than 10 km from the origin"},
           {with("/scanner/axis", {0, 0, 0}), "scanner.axis = [0, 0, 0] is no direction"},
           {with("/places/0/position", {2e4, 0, 0}),
            "place 'inside'.position = [20000, 0, 0] lies more than 10 km from the origin"},
           {with("/places/1/name", "inside"), "two places are named 'inside'"},
       }) {
    const std::string message = sceneErrorOf(document);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  }
  // A width of 0 is no limit, and stays so.
  EXPECT_EQ(sceneFromJson(with("/passages/0/width", 0)).passages[0].width, 0.0);
}

TEST(Scenes, GarageDoorDecidesWhoGetsOut) {
  SceneParameters parameters;
  parameters.door_width = 0.9;
  parameters.door_height = 2.0;
  const Scene garage = *builtinScene("garage", parameters);
  const auto presets = robotPresets();
  auto reaches = [&](const RobotBox& robot) { return !reachablePlaces(garage, robot).empty(); };
  EXPECT_TRUE(reaches(presets[0].second)) << "0.85 m robot, 0.9 m door";
  EXPECT_FALSE(reaches(presets[1].second)) << "1.0 m robot";
  EXPECT_FALSE(reaches(presets[2].second)) << "2.1 m tall robot, 2.0 m door";
}

TEST(Scenes, HallwayRampIsReachableStairsAreNot) {
  const Scene hallway = *builtinScene("hallway");
  const auto pairs = reachablePlaces(hallway, RobotBox{});
  EXPECT_NE(std::find(pairs.begin(), pairs.end(),
                      std::make_pair(std::string("lower"), std::string("upper_ramp"))),
            pairs.end());
  for (const auto& [a, b] : pairs)
    EXPECT_TRUE(a != "upper_stairs" && b != "upper_stairs");
}

TEST(Scenes, DoorwaysLetThroughOnlyTheDoorsThatFit) {
  const auto pairs = reachablePlaces(*builtinScene("doorways"), RobotBox{0.85, 1.2, 1.5, 0.1});
  // Doors: 0.7, 0.85 (not strictly wider), 0.95, 1.1 but 1.4 m high, 1.3.
  std::set<std::string> rooms;
  for (const auto& [a, b] : pairs)
    if (a == "corridor") rooms.insert(b);
  EXPECT_EQ(rooms, (std::set<std::string>{"room_3", "room_5"}));
}

// The stairwell simulated at `lines` lines, its truth saved as s.truth.json in `directory`.
SimulatedScan stairwellTruthIn(const std::filesystem::path& directory, int lines) {
  const Scene scene = *builtinScene("stairwell");
  SensorModel sensor;
  sensor.lines = lines;
  SimulatedScan simulated = simulateRosi(scene, sensor, defaultPlacement(scene));
  saveGroundTruth(simulated.truth, directory / "s.truth.json", "s.pcd");
  return simulated;
}

TEST(GroundTruthFile, RoundTrips) {
  test::TemporaryDirectory directory;
  const SimulatedScan simulated = stairwellTruthIn(directory.path(), 30);
  const GroundTruth read = loadGroundTruth(directory / "s.truth.json");
  EXPECT_EQ(read.classes, simulated.truth.classes);
  EXPECT_EQ(read.surfaces, simulated.truth.surfaces);
  ASSERT_EQ(read.seen_surfaces.size(), simulated.truth.seen_surfaces.size());
  EXPECT_NEAR(read.seen_surfaces[0].offset, simulated.truth.seen_surfaces[0].offset, 1e-9);
  EXPECT_EQ(read.sensor.lines, 30);
  EXPECT_TRUE(
      read.placement.worldFromScanner().isApprox(simulated.truth.placement.worldFromScanner()));
}

TEST(GroundTruthFile, BadFilesAreRefused) {
  test::TemporaryDirectory directory;
  test::writeBytes(directory / "a.truth.json", R"({"format": "something else"})");
  EXPECT_THROW(loadGroundTruth(directory / "a.truth.json"), SceneError);
  test::writeBytes(directory / "b.truth.json", R"({"format": "clearway-truth"})");
  EXPECT_THROW(loadGroundTruth(directory / "b.truth.json"), SceneError);
  EXPECT_THROW(loadGroundTruth(directory / "none.truth.json"), SceneError);
}

// The scanner's placement places the map for eval: a position of 1e308, a zero axis or a roll of
// 1e9 deg were read as given and scored the map against a scene it was nowhere near.
TEST(GroundTruthFile, ScannerPlacementNoScannerHasIsRefused) {
  using nlohmann::json;
  test::TemporaryDirectory directory;
  stairwellTruthIn(directory.path(), 4);
  const json truth = json::parse(test::readBytes(directory / "s.truth.json"));
  for (const auto& [key, value, expected] : std::vector<std::tuple<std::string, json, std::string>>{
           {"position",
            {0, 0, 1e308},
            "scanner.position = [0, 0, 1e+308] lies more than 10 km from the origin"},
           {"position", {-2e4, 0, 1}, "scanner.position = [-20000, 0, 1] lies more than 10 km"},
           {"position", {0, 0}, "scanner.position = [0,0] must be [x, y, z]"},
           {"position", {0, "up", 1}, "scanner.position = [0,\"up\",1] must be [x, y, z]"},
           {"axis", {0, 0, 0}, "scanner.axis = [0, 0, 0] is no direction"},
           {"axis", {1, 0, 0, 5}, "scanner.axis = [1,0,0,5] must be [x, y, z]"},
           {"axis_roll_deg", 1e9, "scanner.axis_roll_deg = 1e+09 is outside -360 .. 360"},
           {"axis_roll_deg", "90", "scanner.axis_roll_deg = \"90\" is not a number"},
       }) {
    SCOPED_TRACE(key + " " + value.dump());
    json changed = truth;
    changed["scanner"][key] = value;
    test::writeBytes(directory / "bad.truth.json", changed.dump());
    try {
      loadGroundTruth(directory / "bad.truth.json");
      ADD_FAILURE() << "read";
    } catch (const SceneError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("bad.truth.json: " + expected), std::string::npos) << message;
    }
  }
  // Nor does the simulator write such a placement into a truth file.
  const Scene scene = *builtinScene("stairwell");
  ScannerPlacement far = defaultPlacement(scene);
  far.position.z() = 1e308;
  EXPECT_THROW(simulateRosi(scene, SensorModel{}, far), std::invalid_argument);
}

}  // namespace
}  // namespace clearway::sim
