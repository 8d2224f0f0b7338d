#include "clearway/sim/scene_io.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "clearway/io/file_util.h"
#include "clearway/io/scan_error.h"
#include "clearway/pose.h"

namespace clearway::sim {
namespace {

using nlohmann::json;

Eigen::Vector3d vector3(const json& value, const std::string& what) {
  if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
      !value[2].is_number())
    throw SceneError(what + " must be [x, y, z]");
  return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

json toJson(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}

template <typename T>
T field(const json& object, const char* key, T fallback) {
  const auto it = object.find(key);
  if (it == object.end()) return fallback;
  try {
    return it->get<T>();
  } catch (const json::exception&) {
    throw SceneError(std::string("'") + key + "' has the wrong type");
  }
}

}  // namespace

Scene sceneFromJson(const json& document) {
  if (!document.is_object()) throw SceneError("a scene is a JSON object");
  Scene scene;
  scene.name = field<std::string>(document, "name", "unnamed");
  scene.description = field<std::string>(document, "description", "");
  if (const auto scanner = document.find("scanner"); scanner != document.end()) {
    if (scanner->contains("position"))
      scene.scanner_position = vector3((*scanner)["position"], "scanner.position");
    if (scanner->contains("axis")) scene.scanner_axis = vector3((*scanner)["axis"], "scanner.axis");
    // Kept as written (the shipped scenes' [1, 0, -0.3]); the simulator makes it a unit vector.
    if (!unitDirection(scene.scanner_axis)) throw SceneError("scanner.axis must not be zero");
  }
  if (!document.contains("primitives") || !document["primitives"].is_array())
    throw SceneError("a scene needs a 'primitives' array");
  for (const json& item : document["primitives"]) {
    Primitive primitive;
    primitive.name = field<std::string>(item, "name", "");
    const std::string where = "primitive '" + primitive.name + "'";
    const std::string shape = field<std::string>(item, "shape", "box");
    if (shape == "box")
      primitive.shape = Shape::kBox;
    else if (shape == "cylinder")
      primitive.shape = Shape::kCylinder;
    else
      throw SceneError(where + ": unknown shape '" + shape + "'");
    const auto point_class = classFromName(field<std::string>(item, "class", "obstacle"));
    if (!point_class || *point_class == PointClass::kNone)
      throw SceneError(where + ": class must be ground, wall, ceiling, obstacle or stairs");
    primitive.point_class = *point_class;
    if (!item.contains("center") || !item.contains("size"))
      throw SceneError(where + " needs 'center' and 'size'");
    primitive.center = vector3(item["center"], where + ".center");
    primitive.size = vector3(item["size"], where + ".size");
    if ((primitive.size.array() < 0.0).any()) throw SceneError(where + ": negative size");
    primitive.yaw_deg = field<double>(item, "yaw_deg", 0.0);
    primitive.pitch_deg = field<double>(item, "pitch_deg", 0.0);
    primitive.roll_deg = field<double>(item, "roll_deg", 0.0);
    primitive.remission = field<double>(item, "remission", 0.5);
    primitive.transparent = field<bool>(item, "transparent", false);
    scene.primitives.push_back(primitive);
  }
  for (const json& item : document.value("places", json::array())) {
    Place place;
    place.name = field<std::string>(item, "name", "");
    place.position = vector3(item.at("position"), "place '" + place.name + "'.position");
    scene.places.push_back(place);
  }
  for (const json& item : document.value("passages", json::array())) {
    Passage passage;
    passage.name = field<std::string>(item, "name", "");
    passage.from = field<std::string>(item, "from", "");
    passage.to = field<std::string>(item, "to", "");
    passage.width = field<double>(item, "width", 0.0);
    passage.height = field<double>(item, "height", 0.0);
    passage.step = field<double>(item, "step", 0.0);
    scene.passages.push_back(passage);
  }
  return scene;
}

json sceneToJson(const Scene& scene) {
  json document;
  document["name"] = scene.name;
  document["description"] = scene.description;
  document["scanner"] = {{"position", toJson(scene.scanner_position)},
                         {"axis", toJson(scene.scanner_axis)}};
  json primitives = json::array();
  for (const Primitive& p : scene.primitives) {
    json item = {{"name", p.name},
                 {"shape", p.shape == Shape::kBox ? "box" : "cylinder"},
                 {"class", std::string(className(p.point_class))},
                 {"center", toJson(p.center)},
                 {"size", toJson(p.size)}};
    if (p.yaw_deg != 0.0) item["yaw_deg"] = p.yaw_deg;
    if (p.pitch_deg != 0.0) item["pitch_deg"] = p.pitch_deg;
    if (p.roll_deg != 0.0) item["roll_deg"] = p.roll_deg;
    if (p.remission != 0.5) item["remission"] = p.remission;
    if (p.transparent) item["transparent"] = true;
    primitives.push_back(item);
  }
  document["primitives"] = primitives;
  json places = json::array();
  for (const Place& place : scene.places)
    places.push_back({{"name", place.name}, {"position", toJson(place.position)}});
  document["places"] = places;
  json passages = json::array();
  for (const Passage& passage : scene.passages)
    passages.push_back({{"name", passage.name},
                        {"from", passage.from},
                        {"to", passage.to},
                        {"width", passage.width},
                        {"height", passage.height},
                        {"step", passage.step}});
  document["passages"] = passages;
  return document;
}

// A scene file is kilobytes; one much larger is something else.
constexpr std::uintmax_t kLargestSceneFile = 64 << 20;

Scene loadScene(const std::filesystem::path& file) {
  std::string text;
  try {
    text = readWholeFile(file, kLargestSceneFile);  // not a pipe, a folder or a device
  } catch (const ScanError& error) {
    throw SceneError(error.what());
  }
  try {
    return sceneFromJson(json::parse(text));
  } catch (const json::parse_error& error) {
    throw SceneError(file.string() + ": not valid JSON (" + error.what() + ")");
  } catch (const json::exception& error) {
    throw SceneError(file.string() + ": " + error.what());
  } catch (const SceneError& error) {
    throw SceneError(file.string() + ": " + error.what());
  }
}

void saveScene(const Scene& scene, const std::filesystem::path& file) {
  writeTextFileAtomically(file, sceneToJson(scene).dump(2) + "\n");
}

}  // namespace clearway::sim
