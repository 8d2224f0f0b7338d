#include "strict_json.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace clearway::detail {

nlohmann::json parseStrictJson(std::string_view text) {
  std::vector<std::vector<std::string>> keys_of_open_objects;
  std::string repeated;
  const nlohmann::json::parser_callback_t check_keys = [&](int, nlohmann::json::parse_event_t event,
                                                           nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::object_start) {
      keys_of_open_objects.emplace_back();
    } else if (event == nlohmann::json::parse_event_t::object_end &&
               !keys_of_open_objects.empty()) {
      keys_of_open_objects.pop_back();
    } else if (event == nlohmann::json::parse_event_t::key && !keys_of_open_objects.empty()) {
      std::vector<std::string>& keys = keys_of_open_objects.back();
      const std::string key = parsed.get<std::string>();
      if (std::find(keys.begin(), keys.end(), key) != keys.end() && repeated.empty())
        repeated = key;
      keys.push_back(key);
    }
    return true;
  };
  nlohmann::json json = nlohmann::json::parse(text, check_keys);
  if (!repeated.empty()) throw std::invalid_argument("the key \"" + repeated + "\" is given twice");
  return json;
}

}  // namespace clearway::detail
