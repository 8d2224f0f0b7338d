// The built-in scenes (docs/SCENES.md). Floors are at z = 0, x points "forward" from the scanner.

#include "clearway/sim/builtin_scenes.h"

#include <cmath>
#include <functional>
#include <map>
#include <numbers>

namespace clearway::sim {
namespace {

using Eigen::Vector3d;

// Adds an axis-aligned box given by two opposite corners.
Primitive& addBox(Scene& scene, const std::string& name, PointClass point_class,
                  const Vector3d& low, const Vector3d& high) {
  Primitive box;
  box.name = name;
  box.point_class = point_class;
  box.center = (low + high) / 2.0;
  box.size = (high - low).cwiseAbs();
  scene.primitives.push_back(box);
  return scene.primitives.back();
}

void addPlace(Scene& scene, const std::string& name, const Vector3d& position) {
  scene.places.push_back({name, position});
}

void addPassage(Scene& scene, const std::string& name, const std::string& from,
                const std::string& to, double width, double height, double step = 0.0) {
  scene.passages.push_back({name, from, to, width, height, step});
}

// A wall along y at x = `x` from y0 to y1, with a door of `width` x `height` centred at door_y.
void addWallWithDoor(Scene& scene, const std::string& name, double x, double y0, double y1,
                     double wall_height, double door_y, double width, double height) {
  constexpr double kThickness = 0.2;
  const double x0 = x, x1 = x + kThickness;
  addBox(scene, name + "_left", PointClass::kWall, {x0, y0, 0.0},
         {x1, door_y - width / 2, wall_height});
  addBox(scene, name + "_right", PointClass::kWall, {x0, door_y + width / 2, 0.0},
         {x1, y1, wall_height});
  if (height < wall_height)
    addBox(scene, name + "_lintel", PointClass::kWall, {x0, door_y - width / 2, height},
           {x1, door_y + width / 2, wall_height});
}

// Solid steps rising along +x from (x0, y0..y1) starting at height z0.
void addStairs(Scene& scene, const std::string& name, double x0, double y0, double y1, double z0,
               int steps, double rise, double tread) {
  for (int k = 0; k < steps; ++k) {
    const double top = z0 + rise * (k + 1);
    addBox(scene, name + "_" + std::to_string(k + 1), PointClass::kStairs,
           {x0 + tread * k, y0, 0.0}, {x0 + tread * (k + 1), y1, top});
  }
}

Scene garage(const SceneParameters& p) {
  Scene scene;
  scene.name = "garage";
  scene.description =
      "Closed garage (8 x 6 m, 2.6 m high) with a truck, crates and a pallet; a door in the front "
      "wall (x = 4 m) leads to an open yard.";
  addBox(scene, "floor", PointClass::kGround, {-4.0, -3.0, -0.1}, {4.0, 3.0, 0.0});
  addBox(scene, "yard", PointClass::kGround, {4.0, -6.0, -0.1}, {12.0, 6.0, 0.0});
  addBox(scene, "ceiling", PointClass::kCeiling, {-4.2, -3.2, 2.6}, {4.2, 3.2, 2.7});
  addBox(scene, "back_wall", PointClass::kWall, {-4.2, -3.2, 0.0}, {-4.0, 3.2, 2.6});
  addBox(scene, "left_wall", PointClass::kWall, {-4.0, 3.0, 0.0}, {4.0, 3.2, 2.6});
  addBox(scene, "right_wall", PointClass::kWall, {-4.0, -3.2, 0.0}, {4.0, -3.0, 2.6});
  addWallWithDoor(scene, "front_wall", 4.0, -3.2, 3.2, 2.6, -1.0, p.door_width, p.door_height);
  addBox(scene, "truck", PointClass::kObstacle, {-3.5, 0.6, 0.0}, {1.5, 2.6, 2.2}).remission = 0.8;
  addBox(scene, "crate", PointClass::kObstacle, {2.6, 1.6, 0.0}, {3.4, 2.6, 0.8});
  addBox(scene, "pallet", PointClass::kObstacle, {-0.5, -2.4, 0.0}, {0.7, -1.6, 0.12});
  addBox(scene, "yard_fence", PointClass::kWall, {11.8, -6.0, 0.0}, {12.0, 6.0, 1.8});
  scene.scanner_position = {0.5, -0.5, 1.2};
  scene.scanner_axis = {1.0, 0.0, -0.35};
  addPlace(scene, "inside", {2.0, -1.0, 0.0});
  addPlace(scene, "outside", {7.0, -1.0, 0.0});
  addPassage(scene, "door", "inside", "outside", p.door_width, p.door_height);
  return scene;
}

Scene hallway(const SceneParameters& p) {
  Scene scene;
  scene.name = "hallway";
  scene.description =
      "A 3 m wide corridor; from x = 3 m a ramp (left lane) and stairs (right lane), separated by "
      "a "
      "wall, climb to an upper level.";
  const int steps = 4;
  const double level = steps * p.stair_rise;
  const double slope = p.ramp_slope_deg * std::numbers::pi / 180.0;
  const double ramp_run = level / std::tan(slope);
  const double stairs_run = steps * p.stair_tread;
  const double end = 3.0 + std::max(ramp_run, stairs_run) + 4.0;
  addBox(scene, "lower_floor", PointClass::kGround, {-2.0, -1.5, -0.1}, {3.0, 1.5, 0.0});
  // The ramp: a slab pitched about y, its top face rising from (3, 0) to (3 + run, level).
  Primitive ramp;
  ramp.name = "ramp";
  ramp.point_class = PointClass::kGround;
  const double ramp_length = std::hypot(ramp_run, level);
  ramp.size = {ramp_length, 1.45, 0.1};
  ramp.pitch_deg = -p.ramp_slope_deg;
  ramp.center =
      Vector3d(3.0 + ramp_run / 2, 0.775, level / 2) + ramp.rotation() * Vector3d(0.0, 0.0, -0.05);
  scene.primitives.push_back(ramp);
  addBox(scene, "upper_floor", PointClass::kGround, {3.0 + ramp_run, 0.05, 0.0}, {end, 1.5, level});
  addStairs(scene, "stairs", 3.0, -1.5, -0.05, 0.0, steps, p.stair_rise, p.stair_tread);
  addBox(scene, "upper_landing", PointClass::kGround, {3.0 + stairs_run, -1.5, 0.0},
         {end, -0.05, level});
  addBox(scene, "divider", PointClass::kWall, {3.0, -0.05, 0.0}, {end, 0.05, level + 1.0});
  addBox(scene, "left_wall", PointClass::kWall, {-2.0, 1.5, 0.0}, {end, 1.7, 3.5});
  addBox(scene, "right_wall", PointClass::kWall, {-2.0, -1.7, 0.0}, {end, -1.5, 3.5});
  addBox(scene, "end_wall", PointClass::kWall, {end, -1.7, 0.0}, {end + 0.2, 1.7, 3.5});
  scene.scanner_position = {0.0, 0.0, 1.2};
  scene.scanner_axis = {1.0, 0.0, -0.2};
  addPlace(scene, "lower", {1.5, 0.0, 0.0});
  addPlace(scene, "upper_ramp", {3.0 + ramp_run + 0.8, 0.8, level});
  addPlace(scene, "upper_stairs", {3.0 + stairs_run + 1.0, -0.8, level});
  addPassage(scene, "ramp", "lower", "upper_ramp", 1.45, 0.0);
  addPassage(scene, "stairs", "lower", "upper_stairs", 1.45, 0.0, p.stair_rise);
  return scene;
}

Scene outdoor(const SceneParameters&) {
  Scene scene;
  scene.name = "outdoor";
  scene.description =
      "Uneven paved ground (slabs tilted up to 3 deg), a 0.15 m kerb, rubble boxes and a pipe "
      "bridge 1.3 m above the ground.";
  for (int i = 0; i < 4; ++i) {
    auto& slab = addBox(scene, "slab_" + std::to_string(i), PointClass::kGround,
                        {-2.0 + 3.0 * i, -6.0, -0.2}, {1.0 + 3.0 * i, 6.0, 0.0});
    slab.pitch_deg = (i % 2 == 0 ? 1.5 : -1.0);
    slab.roll_deg = (i == 2 ? 2.0 : 0.0);
  }
  addBox(scene, "far_ground", PointClass::kGround, {10.0, -6.0, -0.2}, {16.0, 6.0, 0.15});
  addBox(scene, "kerb", PointClass::kObstacle, {9.8, -6.0, 0.0}, {10.0, 6.0, 0.15});
  const double rubble[][6] = {{3.0, 1.5, 0.0, 3.6, 2.1, 0.3},
                              {4.5, -2.5, 0.0, 5.3, -1.9, 0.5},
                              {6.0, 2.5, 0.0, 6.4, 2.9, 0.12},
                              {2.0, -4.0, 0.0, 3.0, -3.2, 0.8},
                              {7.5, -0.2, 0.0, 7.8, 0.3, 0.08}};
  int index = 0;
  for (const auto& r : rubble)
    addBox(scene, "rubble_" + std::to_string(index++), PointClass::kObstacle, {r[0], r[1], r[2]},
           {r[3], r[4], r[5]});
  Primitive pipe;
  pipe.name = "pipe";
  pipe.shape = Shape::kCylinder;
  pipe.point_class = PointClass::kObstacle;
  pipe.center = {5.5, 0.0, 1.45};
  pipe.size = {0.3, 0.3, 12.0};
  pipe.roll_deg = 90.0;  // axis along y
  scene.primitives.push_back(pipe);
  addBox(scene, "pipe_support_left", PointClass::kWall, {5.35, 5.0, 0.0}, {5.65, 5.3, 1.6});
  addBox(scene, "pipe_support_right", PointClass::kWall, {5.35, -5.3, 0.0}, {5.65, -5.0, 1.6});
  scene.scanner_position = {0.0, 0.0, 1.2};
  scene.scanner_axis = {1.0, 0.0, -0.3};
  addPlace(scene, "start", {1.5, 0.0, 0.0});
  addPlace(scene, "beyond_pipe", {8.5, 0.0, 0.0});
  addPlace(scene, "beyond_kerb", {12.0, 0.0, 0.15});
  addPassage(scene, "under_pipe", "start", "beyond_pipe", 10.0, 1.3);
  addPassage(scene, "kerb", "beyond_pipe", "beyond_kerb", 0.0, 0.0, 0.15);
  return scene;
}

Scene stairwell(const SceneParameters& p) {
  Scene scene;
  scene.name = "stairwell";
  scene.description =
      "A stairwell (the paper's Fig. 1): a 1.4 m wide flight of 12 steps between walls, "
      "a landing at the top.";
  const int steps = 12;
  const double top = steps * p.stair_rise;
  addBox(scene, "floor", PointClass::kGround, {-2.0, -1.5, -0.1}, {2.0, 1.5, 0.0});
  addStairs(scene, "stairs", 2.0, -0.7, 0.7, 0.0, steps, p.stair_rise, p.stair_tread);
  const double landing_x = 2.0 + steps * p.stair_tread;
  addBox(scene, "landing", PointClass::kGround, {landing_x, -1.5, 0.0},
         {landing_x + 2.0, 1.5, top});
  addBox(scene, "left_wall", PointClass::kWall, {-2.0, 0.7, 0.0},
         {landing_x + 2.0, 0.9, top + 2.5});
  addBox(scene, "right_wall", PointClass::kWall, {-2.0, -0.9, 0.0},
         {landing_x + 2.0, -0.7, top + 2.5});
  addBox(scene, "end_wall", PointClass::kWall, {landing_x + 2.0, -1.5, 0.0},
         {landing_x + 2.2, 1.5, top + 2.5});
  addBox(scene, "back_wall", PointClass::kWall, {-2.2, -1.5, 0.0}, {-2.0, 1.5, 3.0});
  scene.scanner_position = {0.0, 0.0, 1.0};
  scene.scanner_axis = {1.0, 0.0, 0.0};
  addPlace(scene, "bottom", {0.5, 0.0, 0.0});
  addPlace(scene, "top", {landing_x + 1.0, 0.0, top});
  addPassage(scene, "flight", "bottom", "top", 1.4, 0.0, p.stair_rise);
  return scene;
}

Scene doorways(const SceneParameters&) {
  Scene scene;
  scene.name = "doorways";
  scene.description =
      "A wall 4 m ahead with five doors into five rooms: widths 0.7 .. 1.3 m, "
      "heights 2.0 m except a 1.4 m low door.";
  const double widths[] = {0.7, 0.85, 0.95, 1.1, 1.3};
  const double heights[] = {2.0, 2.0, 2.0, 1.4, 2.0};
  const double room_width = 2.2;
  const double y_start = -2.5 * room_width;
  addBox(scene, "corridor_floor", PointClass::kGround, {-2.0, y_start, -0.1}, {4.0, -y_start, 0.0});
  addBox(scene, "rooms_floor", PointClass::kGround, {4.0, y_start, -0.1}, {8.0, -y_start, 0.0});
  addBox(scene, "back_wall", PointClass::kWall, {-2.2, y_start, 0.0}, {-2.0, -y_start, 2.5});
  addPlace(scene, "corridor", {1.0, 0.0, 0.0});
  for (int k = 0; k < 5; ++k) {
    const double y0 = y_start + k * room_width, y1 = y0 + room_width;
    const std::string room = "room_" + std::to_string(k + 1);
    addWallWithDoor(scene, "wall_" + std::to_string(k + 1), 4.0, y0, y1, 2.5, (y0 + y1) / 2,
                    widths[k], heights[k]);
    addBox(scene, room + "_back", PointClass::kWall, {8.0, y0, 0.0}, {8.2, y1, 2.5});
    if (k > 0)
      addBox(scene, room + "_side", PointClass::kWall, {4.2, y0 - 0.1, 0.0}, {8.0, y0 + 0.1, 2.5});
    addPlace(scene, room, {6.0, (y0 + y1) / 2, 0.0});
    addPassage(scene, "door_" + std::to_string(k + 1), "corridor", room, widths[k], heights[k]);
  }
  addBox(scene, "left_end", PointClass::kWall, {-2.0, -y_start, 0.0}, {8.2, -y_start + 0.2, 2.5});
  addBox(scene, "right_end", PointClass::kWall, {-2.0, y_start - 0.2, 0.0}, {8.2, y_start, 2.5});
  scene.scanner_position = {0.0, 0.0, 1.2};
  scene.scanner_axis = {1.0, 0.0, -0.25};
  return scene;
}

Scene glass(const SceneParameters&) {
  Scene scene;
  scene.name = "glass";
  scene.description =
      "A room whose front wall (x = 4 m) is glass: the laser gets no return from it.";
  addBox(scene, "floor", PointClass::kGround, {-3.0, -3.0, -0.1}, {4.0, 3.0, 0.0});
  addBox(scene, "outside_floor", PointClass::kGround, {4.1, -6.0, -0.1}, {10.0, 6.0, 0.0});
  auto& pane = addBox(scene, "glass_wall", PointClass::kWall, {4.0, -3.0, 0.0}, {4.05, 3.0, 2.5});
  pane.transparent = true;
  addBox(scene, "left_wall", PointClass::kWall, {-3.0, 3.0, 0.0}, {4.0, 3.2, 2.5});
  addBox(scene, "right_wall", PointClass::kWall, {-3.0, -3.2, 0.0}, {4.0, -3.0, 2.5});
  addBox(scene, "back_wall", PointClass::kWall, {-3.2, -3.2, 0.0}, {-3.0, 3.2, 2.5});
  scene.scanner_position = {0.0, 0.0, 1.2};
  scene.scanner_axis = {1.0, 0.0, -0.3};
  addPlace(scene, "inside", {2.0, 0.0, 0.0});
  addPlace(scene, "beyond_glass", {6.0, 0.0, 0.0});
  return scene;
}

Scene noGround(const SceneParameters&) {
  Scene scene;
  scene.name = "no-ground";
  scene.description =
      "A hall scanned with the turntable axis pointing up: only walls above the "
      "scanner and the ceiling are seen, never the floor.";
  addBox(scene, "floor", PointClass::kGround, {-5.0, -5.0, -0.1}, {5.0, 5.0, 0.0});
  addBox(scene, "ceiling", PointClass::kCeiling, {-5.0, -5.0, 3.0}, {5.0, 5.0, 3.1});
  addBox(scene, "north_wall", PointClass::kWall, {5.0, -5.0, 0.0}, {5.2, 5.0, 3.0});
  addBox(scene, "south_wall", PointClass::kWall, {-5.2, -5.0, 0.0}, {-5.0, 5.0, 3.0});
  addBox(scene, "east_wall", PointClass::kWall, {-5.0, 5.0, 0.0}, {5.0, 5.2, 3.0});
  addBox(scene, "west_wall", PointClass::kWall, {-5.0, -5.2, 0.0}, {5.0, -5.0, 3.0});
  scene.scanner_position = {0.0, 0.0, 1.2};
  scene.scanner_axis = {0.0, 0.0, 1.0};
  addPlace(scene, "centre", {0.0, 0.0, 0.0});
  return scene;
}

using Builder = std::function<Scene(const SceneParameters&)>;
const std::map<std::string, Builder>& builders() {
  static const std::map<std::string, Builder> kBuilders = {
      {"garage", garage},       {"hallway", hallway},   {"outdoor", outdoor},
      {"stairwell", stairwell}, {"doorways", doorways}, {"glass", glass},
      {"no-ground", noGround}};
  return kBuilders;
}

}  // namespace

std::vector<std::string> builtinSceneNames() {
  std::vector<std::string> names;
  for (const auto& [name, builder] : builders())
    names.push_back(name);
  return names;
}

std::optional<Scene> builtinScene(const std::string& name, const SceneParameters& parameters) {
  const auto it = builders().find(name);
  if (it == builders().end()) return std::nullopt;
  return it->second(parameters);
}

}  // namespace clearway::sim
