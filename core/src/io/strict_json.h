#pragma once

// JSON read strictly: a key given twice in one object is an error, not its last value.

#include <nlohmann/json.hpp>
#include <string_view>

namespace clearway::detail {

// Parses `text`; throws std::invalid_argument naming a key given twice in one object (the parser
// keeps the last: a second "rotation_wxyz" turned a scan over, a second "width" made a robot 3 m
// wide, without a word), and nlohmann::json::parse_error for text that is no JSON.
nlohmann::json parseStrictJson(std::string_view text);

}  // namespace clearway::detail
