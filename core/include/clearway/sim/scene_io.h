#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "clearway/sim/scene.h"

namespace clearway::sim {

// Throws SceneError (a std::runtime_error) with a readable reason for a malformed scene.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Scene sceneFromJson(const nlohmann::json& json);
nlohmann::json sceneToJson(const Scene& scene);
Scene loadScene(const std::filesystem::path& file);
void saveScene(const Scene& scene, const std::filesystem::path& file);

}  // namespace clearway::sim
