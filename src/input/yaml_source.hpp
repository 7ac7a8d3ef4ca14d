#pragma once
// The YAML layer of the case reader: nodes with their dotted key path and source location,
// typed getters that throw InputError at file:line:col, and maps whose keys are checked
// (unknown keys with a suggestion, duplicates). Knows nothing of the case's sections: the
// sections' key tables are handed in (KeySection) for the "is a key of 'solver'" hint.
#include <yaml-cpp/yaml.h>

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/expression.hpp"
#include "core/types.hpp"

namespace hencky::case_input {

// ---------------------------------------------------------------------------------------------
// Text helpers, shared with the CSV reader

std::string trim(const std::string& s);
/// The whole text (after trim, a leading '+' allowed) as a number; false when it is not one.
bool parse_double(const std::string& text, double& v);
bool parse_long(const std::string& text, long& v);
/// Shortest round-trip text of v, for messages.
std::string num(double v);
std::string lower(std::string s);

std::string child_path(const std::string& parent, const std::string& key);
std::string index_path(const std::string& parent, std::size_t i);

/// What a node is, for "found ..." in messages.
std::string describe(const YAML::Node& n);

// ---------------------------------------------------------------------------------------------
// A node with its dotted key path and the best location to report it at.

struct Val {
  YAML::Node node;
  std::string path;
  YAML::Mark mark;
};

/// The keys of one map of the case file with the name messages give it ("solver",
/// "materials[i]"): an unknown key that is valid in another section names that section.
struct KeySection {
  const char* name;
  const std::vector<std::string>* keys;
};

/// "'steps' is a key of 'solver'" when an unknown key is valid in another section.
std::string belongs_elsewhere(const std::string& key, const std::vector<std::string>* here,
                              std::span<const KeySection> sections);

class Reader {
 public:
  /// `label` is the file name in messages, `dir` the folder relative paths are taken from,
  /// `sections` every section's keys (kept by reference: it must outlive the reader).
  Reader(std::string label, std::filesystem::path dir, std::span<const KeySection> sections)
      : label_(std::move(label)), dir_(std::move(dir)), sections_(sections) {}

  const std::string& label() const { return label_; }
  const std::filesystem::path& dir() const { return dir_; }
  std::span<const KeySection> sections() const { return sections_; }

  SourceLocation at(const YAML::Mark& m, const std::string& key) const;
  SourceLocation at(const Val& v) const { return at(v.mark, v.path); }
  [[noreturn]] void fail(const Val& v, const std::string& msg) const {
    throw InputError(at(v), msg);
  }

  double number(const Val& v) const;
  long integer(const Val& v) const;
  int integer_at_least(const Val& v, long min) const;
  double positive(const Val& v) const;
  /// `auto` (nullopt) or a number > 0; `what` completes "expected 'auto' or ..." on failure.
  std::optional<double> positive_or_auto(const Val& v, const std::string& what) const;
  /// A number of a material's data (E, nu, alpha, a table's values, a curve's points):
  /// finite, and not subnormal (0 < |x| < DBL_MIN, e.g. 1e-310), which the stiffness and
  /// stress arithmetic cannot carry: it has lost precision already and its products vanish.
  double material_number(const Val& v) const;
  std::string string(const Val& v, const char* what = "a name") const;
  Expression expression(const Val& v) const;
  std::vector<Val> list(const Val& v, const std::string& what = "a list [a, b, ...]") const;
  /// A list of entries (maps, each started with '- '): as list(), and a map given where the
  /// list was expected (the '- ' forgotten) is named as such.
  std::vector<Val> entries(const Val& v, const std::string& what) const;
  std::vector<Val> list3(const Val& v, const char* what) const;
  std::array<Expression, 3> expression3(const Val& v) const;
  Vec3 vec3(const Val& v) const;
  /// A list of names, or one name (shorthand for a list of one).
  std::vector<Val> names(const Val& v) const;
  std::string choice(const Val& v, const std::vector<std::string>& options, const char* what) const;
  std::filesystem::path resolve(const std::string& p) const;

 private:
  std::string label_;
  std::filesystem::path dir_;
  std::span<const KeySection> sections_;
};

/// A YAML map whose keys were checked: no unknown keys, no duplicates.
class Map {
 public:
  /// `allowed` is compared by address with the reader's sections (the section it is not
  /// suggested from): pass the section's own table, not a copy.
  Map(const Reader& r, const Val& v, const std::vector<std::string>& allowed,
      const std::string& what = "a map of keys");

  bool has(const std::string& key) const { return entries_.count(key) != 0; }
  std::optional<Val> get(const std::string& key) const {
    auto it = entries_.find(key);
    if (it == entries_.end()) return std::nullopt;
    return it->second.val;
  }
  YAML::Mark key_mark(const std::string& key) const { return entries_.at(key).key_mark; }
  Val require(const Reader& r, const std::string& key, const std::string& hint) const;
  const Val& self() const { return self_; }

 private:
  struct Entry {
    Val val;
    YAML::Mark key_mark;
  };
  Val self_;
  std::map<std::string, Entry> entries_;
};

}  // namespace hencky::case_input
