// clearway-cli: the headless face of Clearway. main() only dispatches and maps failures to exit
// codes: 0 success, 1 the work failed, 2 the command line was wrong.

#include <algorithm>
#include <exception>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "arguments.h"
#include "clearway/io/scan_error.h"
#include "clearway/memory_tuning.h"
#include "clearway/progress.h"
#include "clearway/sim/scene_io.h"
#include "commands.h"
#include "usage.h"

namespace {

bool asksForHelp(const std::string& word) {
  return word == "--help" || word == "-h";
}

}  // namespace

int main(int argc, char** argv) {
  clearway::keepFreedMemoryForReuse();
  using Command = std::function<int(const std::vector<std::string>&)>;
  const std::map<std::string, Command> commands = {
      {"info", clearway::cli::runInfo},       {"simulate", clearway::cli::runSimulate},
      {"scene", clearway::cli::runScene},     {"eval", clearway::cli::runEval},
      {"segment", clearway::cli::runSegment}, {"emulate", clearway::cli::runEmulate},
      {"acquire", clearway::cli::runAcquire}, {"bench", clearway::cli::runBench},
      {"serve", clearway::cli::runServe},
  };
  using clearway::cli::commandUsage;
  using clearway::cli::usageText;
  const std::vector<std::string> words(argv + 1, argv + argc);
  if (words.empty()) {
    std::cerr << usageText();
    return 2;
  }
  const std::string& name = words.front();
  if (asksForHelp(name)) {
    std::cout << usageText();
    return 0;
  }
  if (name == "--version") {
    std::cout << "clearway-cli " << CLEARWAY_VERSION << '\n';
    return 0;
  }
  // `help`, `help COMMAND` and `COMMAND --help`: a new user's first tries.
  if (name == "help") {
    if (words.size() == 1) {
      std::cout << usageText();
      return 0;
    }
    if (!commands.count(words[1])) {
      std::cerr << "clearway-cli: unknown command '" << words[1] << "'\n" << usageText();
      return 2;
    }
    std::cout << "usage:\n" << commandUsage(words[1]);
    return 0;
  }
  const auto command = commands.find(name);
  if (command == commands.end()) {
    std::cerr << "clearway-cli: unknown command '" << name << "'\n" << usageText();
    return 2;
  }
  const std::vector<std::string> options(words.begin() + 1, words.end());
  if (std::any_of(options.begin(), options.end(), asksForHelp)) {
    std::cout << "usage:\n" << commandUsage(name);
    return 0;
  }
  try {
    return command->second(options);
  } catch (const clearway::cli::UsageError& error) {
    std::cerr << "clearway-cli " << name << ": " << error.what() << "\nusage:\n"
              << commandUsage(name);
    return 2;
  } catch (const clearway::ScanError& error) {
    std::cerr << "clearway-cli: " << error.what() << '\n';
    return 1;
  } catch (const clearway::sim::SceneError& error) {
    std::cerr << "clearway-cli: " << error.what() << '\n';
    return 1;
  } catch (const clearway::OperationCancelled&) {
    std::cerr << "clearway-cli: cancelled\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "clearway-cli: out of memory\n";
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "clearway-cli: " << error.what() << '\n';
    return 1;
  }
}
