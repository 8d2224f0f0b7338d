// Segmentation parameters from arbitrary JSON: refused with std::invalid_argument or a JSON error,
// or accepted and then checked by validate(); never a crash or undefined behaviour (int casts).

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "clearway/segmentation/params.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, false);
  if (json.is_discarded()) return 0;
  try {
    const clearway::SegmentationParams params = clearway::paramsFromJson(json);
    (void)params.validate();
    (void)clearway::toJson(params).dump();
  } catch (const std::invalid_argument&) {
  } catch (const nlohmann::json::exception&) {
  }
  return 0;
}
