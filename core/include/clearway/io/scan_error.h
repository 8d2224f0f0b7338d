#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace clearway {

// `text` fit for an operator's terminal or a label: control characters (a terminal's escape
// sequences among them: ESC, and CSI as the single code point U+009B) and bytes that are not
// UTF-8 each become '?'. Error messages quote pieces of the files they refuse, and a file's bytes
// must not clear or recolour the screen the message is read on.
std::string printableText(std::string_view text);

// A file that cannot be read as a scan. what() is one line: "FILE: problem", the problem printable
// (printableText) whatever bytes of the file it quotes. The file's name stays as given: it is the
// operator's to recognise (a Latin-1 name as its bytes), and not the file's content.
class ScanError : public std::runtime_error {
 public:
  ScanError(const std::filesystem::path& file, const std::string& problem)
      : std::runtime_error(file.string() + ": " + printableText(problem)),
        problem_(printableText(problem)) {}
  const std::string& problem() const { return problem_; }

 private:
  std::string problem_;
};

}  // namespace clearway
