#pragma once

// clearway-cli's usage text: the whole of it, and the lines of one command, for `--help` and for
// a command line that was wrong.

#include <string>
#include <string_view>

namespace clearway::cli {

// Every command with its options.
std::string_view usageText();

// The usage lines of `command` (several forms for acquire and serve), each ending in '\n';
// empty for a command there is no such line for.
std::string commandUsage(std::string_view command);

}  // namespace clearway::cli
