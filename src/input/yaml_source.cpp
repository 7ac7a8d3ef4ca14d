#include "input/yaml_source.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "core/suggest.hpp"

namespace hencky::case_input {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Text helpers

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

namespace {
/// The whole of `text` (blanks around it and a leading '+' allowed) as a number of type T.
template <class T>
bool parse_number(const std::string& text, T& v) {
  const std::string s = trim(text);
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto [p, ec] = std::from_chars(b, e, v);
  return ec == std::errc() && p == e;
}
}  // namespace

bool parse_double(const std::string& text, double& v) { return parse_number(text, v); }
bool parse_long(const std::string& text, long& v) { return parse_number(text, v); }

std::string num(double v) {
  char buf[64];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, p) : std::to_string(v);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string child_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}
std::string index_path(const std::string& parent, std::size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Scalar: {
      std::string s = n.Scalar();
      if (s.size() > 60) s = s.substr(0, 57) + "...";
      return "'" + s + "'";
    }
    default:
      return "nothing";
  }
}

std::string belongs_elsewhere(const std::string& key, const std::vector<std::string>* here,
                              std::span<const KeySection> sections) {
  std::vector<std::string> where;
  for (const auto& s : sections)
    if (s.keys != here && std::find(s.keys->begin(), s.keys->end(), key) != s.keys->end())
      where.emplace_back(s.name);
  if (where.empty()) return {};
  std::string s = "'" + key + "' is a key of ";
  for (std::size_t i = 0; i < where.size(); ++i)
    s += (i ? (i + 1 == where.size() ? " and " : ", ") : "") +
         (where[i] == "the top level" ? where[i] : "'" + where[i] + "'");
  return s;
}

// ---------------------------------------------------------------------------------------------
// Reader: typed getters

SourceLocation Reader::at(const YAML::Mark& m, const std::string& key) const {
  SourceLocation w;
  w.file = label_;
  if (m.line >= 0) w.line = m.line + 1;
  if (m.column >= 0 && m.line >= 0) w.column = m.column + 1;
  w.key = key;
  return w;
}

double Reader::number(const Val& v) const {
  if (!v.node.IsScalar()) fail(v, "expected a number, found " + describe(v.node));
  double x = 0;
  if (!parse_double(v.node.Scalar(), x)) fail(v, "expected a number, found " + describe(v.node));
  if (!std::isfinite(x)) fail(v, "expected a finite number, found " + describe(v.node));
  return x;
}

long Reader::integer(const Val& v) const {
  if (!v.node.IsScalar()) fail(v, "expected a whole number, found " + describe(v.node));
  long x = 0;
  if (!parse_long(v.node.Scalar(), x))
    fail(v, "expected a whole number, found " + describe(v.node));
  return x;
}

int Reader::integer_at_least(const Val& v, long min) const {
  const long x = integer(v);
  if (x < min)
    fail(v, "expected a whole number >= " + std::to_string(min) + ", found " + std::to_string(x));
  if (x > 1000000000L) fail(v, "expected a whole number <= 1000000000, found " + std::to_string(x));
  return static_cast<int>(x);
}

double Reader::positive(const Val& v) const {
  const double x = number(v);
  if (!(x > 0)) fail(v, "expected a number > 0, found " + num(x));
  return x;
}

std::optional<double> Reader::positive_or_auto(const Val& v, const std::string& what) const {
  if (v.node.IsScalar() && trim(v.node.Scalar()) == "auto") return std::nullopt;
  double x = 0;
  if (!v.node.IsScalar() || !parse_double(v.node.Scalar(), x) || !std::isfinite(x) || !(x > 0))
    fail(v, "expected 'auto' or " + what + ", found " + describe(v.node));
  return x;
}

double Reader::material_number(const Val& v) const {
  const double x = number(v);
  if (x != 0 && std::abs(x) < std::numeric_limits<double>::min())
    fail(v, "expected 0 or a number of magnitude >= " + num(std::numeric_limits<double>::min()) +
                ", found " + describe(v.node) +
                " (a subnormal number, too small for the stiffness and stress arithmetic)");
  return x;
}

std::string Reader::string(const Val& v, const char* what) const {
  if (!v.node.IsScalar()) fail(v, std::string("expected ") + what + ", found " + describe(v.node));
  std::string s = trim(v.node.Scalar());
  if (s.empty()) fail(v, std::string("expected ") + what + ", found an empty string");
  return s;
}

Expression Reader::expression(const Val& v) const {
  if (!v.node.IsScalar())
    fail(v, "expected a number or an expression in x, y, z, t (e.g. \"100e6*t\"), found " +
                describe(v.node));
  return Expression::parse(v.node.Scalar(), at(v));
}

std::vector<Val> Reader::list(const Val& v, const std::string& what) const {
  if (!v.node.IsSequence()) fail(v, "expected " + what + ", found " + describe(v.node));
  std::vector<Val> items;
  for (std::size_t i = 0; i < v.node.size(); ++i) {
    YAML::Node n = v.node[i];
    const YAML::Mark m = n.IsNull() || n.Mark().line < 0 ? v.mark : n.Mark();
    items.push_back({n, index_path(v.path, i), m});
  }
  return items;
}

std::vector<Val> Reader::entries(const Val& v, const std::string& what) const {
  if (v.node.IsMap()) fail(v, "expected " + what + " (start each entry with '- '), found a map");
  return list(v, what);
}

std::vector<Val> Reader::list3(const Val& v, const char* what) const {
  auto items = list(v, std::string("a list of 3 ") + what + " [x, y, z]");
  if (items.size() != 3)
    fail(v, std::string("expected a list of 3 ") + what + " [x, y, z], found a list of " +
                std::to_string(items.size()));
  return items;
}

std::array<Expression, 3> Reader::expression3(const Val& v) const {
  auto items = list3(v, "numbers or expressions");
  return {expression(items[0]), expression(items[1]), expression(items[2])};
}

Vec3 Reader::vec3(const Val& v) const {
  auto items = list3(v, "numbers");
  return {number(items[0]), number(items[1]), number(items[2])};
}

std::vector<Val> Reader::names(const Val& v) const {
  if (v.node.IsScalar()) return {v};
  auto items = list(v, "a list of names [a, b, ...]");
  if (items.empty()) fail(v, "expected a list of names [a, b, ...], found an empty list");
  return items;
}

std::string Reader::choice(const Val& v, const std::vector<std::string>& options,
                           const char* what) const {
  const std::string s = string(v, "a name");
  if (std::find(options.begin(), options.end(), s) != options.end()) return s;
  fail(v, "unknown " + std::string(what) + " '" + s + "'; " +
              suggestion(s, options, std::string(what) + "s"));
}

fs::path Reader::resolve(const std::string& p) const {
  fs::path path(p);
  if (path.is_relative()) path = dir_ / path;
  return path.lexically_normal();
}

// ---------------------------------------------------------------------------------------------
// Map: checked keys

Map::Map(const Reader& r, const Val& v, const std::vector<std::string>& allowed,
         const std::string& what)
    : self_(v) {
  if (!v.node.IsMap()) r.fail(v, "expected " + what + ", found " + describe(v.node));
  for (auto it = v.node.begin(); it != v.node.end(); ++it) {
    const YAML::Node key = it->first;
    const YAML::Mark key_mark = key.Mark();
    if (!key.IsScalar())
      throw InputError(r.at(key_mark, v.path), "expected a key name, found " + describe(key));
    const std::string name = key.Scalar();
    const std::string path = child_path(v.path, name);
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
      std::string msg = "unknown key '" + name + "'";
      const std::string hint = did_you_mean(name, allowed);
      if (!hint.empty())
        msg += "; " + hint;
      else if (auto other = belongs_elsewhere(name, &allowed, r.sections()); !other.empty())
        msg += "; " + other;
      msg += " (valid keys here: " + name_list(allowed) + ")";
      throw InputError(r.at(key_mark, path), msg);
    }
    if (auto prev = entries_.find(name); prev != entries_.end())
      throw InputError(r.at(key_mark, path), "duplicate key '" + name + "' (first given at line " +
                                                 std::to_string(prev->second.key_mark.line + 1) +
                                                 ")");
    const YAML::Node value = it->second;
    const YAML::Mark m = value.IsNull() || value.Mark().line < 0 ? key_mark : value.Mark();
    entries_.emplace(name, Entry{Val{value, path, m}, key_mark});
  }
}

Val Map::require(const Reader& r, const std::string& key, const std::string& hint) const {
  auto v = get(key);
  if (!v) {
    std::string msg = "missing key '" + key + "'";
    if (!hint.empty()) msg += " (" + hint + ")";
    throw InputError(r.at(self_.mark, child_path(self_.path, key)), msg);
  }
  return *v;
}

}  // namespace hencky::case_input
