#pragma once

// The built-in scenes of docs/SCENES.md, each a function of its parameters.

#include <optional>
#include <string>
#include <vector>

#include "clearway/sim/scene.h"

namespace clearway::sim {

struct SceneParameters {
  double door_width = 0.9;   // garage door, the paper's benchmark [m]
  double door_height = 2.0;  // [m]
  double ramp_slope_deg = 12.0;
  double stair_rise = 0.17;
  double stair_tread = 0.29;
};

std::vector<std::string> builtinSceneNames();
// nullopt for an unknown name.
std::optional<Scene> builtinScene(const std::string& name, const SceneParameters& parameters = {});

}  // namespace clearway::sim
