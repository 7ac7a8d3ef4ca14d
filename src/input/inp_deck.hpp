#pragma once
// The text of an Abaqus/CalculiX deck (input/inp_reader.hpp) as lines and keywords: comments
// and blank lines dropped, *INCLUDE files read in place, keyword lines split into their name
// and parameters. Abaqus Keywords Reference Guide; CalculiX User's Manual (ccx 2.20), section 6.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace hencky::inp {

/// s in upper case (ASCII).
std::string upper(std::string_view s);
/// s without the blanks (spaces, tabs, line ends) around it.
std::string_view trim(std::string_view s);
/// A name as written, without the quotes Abaqus allows around names with spaces.
std::string unquote(std::string_view s);
/// The whole text of a deck's file; an InputError naming it ("cannot open the `what`") when it
/// cannot be read.
std::string read_text(const std::filesystem::path& file, const char* what);
/// The comma-separated fields of a line, trimmed (a comma inside quotes does not separate).
std::vector<std::string_view> fields(std::string_view s);

/// One line of the deck, with its file (index into Deck::names) and number (from 1).
struct Line {
  int file = 0;
  int number = 0;
  std::string_view text;
};

/// A keyword line: its name in upper case (inner blanks single), and its parameters, names in
/// upper case and values as written.
struct Keyword {
  std::string name;
  std::vector<std::pair<std::string, std::string>> params;

  const std::string* get(std::string_view p) const {
    for (const auto& [k, v] : params)
      if (k == p) return &v;
    return nullptr;
  }
  bool has(std::string_view p) const { return get(p) != nullptr; }
};

/// The keyword line `text` (from its '*').
Keyword parse_keyword(std::string_view text);

/// The files of the deck (the one named and those *INCLUDE reads), their text, and their lines
/// in the order they are read, without comments and blank lines; *INCLUDE lines are replaced
/// by the lines of the file they name.
struct Deck {
  std::vector<std::string> names;
  std::vector<std::unique_ptr<std::string>> texts;  // the lines view these
  std::vector<Line> lines;

  InputError fail(const Line& l, const std::string& msg) const {
    return InputError(SourceLocation{names[l.file], l.number, 0, ""}, msg);
  }

  /// Appends the lines of `text`, file `file` (an index into names), read at *INCLUDE depth
  /// `depth`. Throws InputError.
  void add(std::string_view text, int file, int depth);
  /// Reads the file an *INCLUDE line names and adds its lines. Throws InputError.
  void include(const Line& l, int depth);
};

}  // namespace hencky::inp
