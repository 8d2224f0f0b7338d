// A simulator scene from arbitrary JSON: refused with SceneError or a JSON error, or accepted.

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "clearway/sim/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, false);
  if (json.is_discarded()) return 0;
  try {
    const clearway::sim::Scene scene = clearway::sim::sceneFromJson(json);
    (void)clearway::sim::sceneToJson(scene).dump();
  } catch (const clearway::sim::SceneError&) {
  } catch (const std::invalid_argument&) {
  } catch (const nlohmann::json::exception&) {
  }
  return 0;
}
