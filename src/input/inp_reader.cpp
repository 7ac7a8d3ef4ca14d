#include "input/inp_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>
#include <variant>

#include "core/error.hpp"

// The keywords as the Abaqus Keywords Reference Guide and the CalculiX User's Manual (ccx 2.20,
// section 6: *NODE, *ELEMENT, *NSET, *ELSET, *SURFACE, *INCLUDE) define them. Element faces:
// CalculiX manual section 6.2 (the face numbers of each element type).

namespace hencky {
namespace {

namespace fs = std::filesystem;

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

/// A name as written, without the quotes Abaqus allows around names with spaces.
std::string unquote(std::string_view s) {
  s = trim(s);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

/// The comma-separated fields of a line, trimmed (a comma inside quotes does not separate).
std::vector<std::string_view> fields(std::string_view s) {
  std::vector<std::string_view> out;
  bool quoted = false;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= s.size(); ++i) {
    if (i < s.size() && s[i] == '"') quoted = !quoted;
    if (i == s.size() || (s[i] == ',' && !quoted)) {
      out.push_back(trim(s.substr(start, i - start)));
      start = i + 1;
    }
  }
  return out;
}

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

Keyword parse_keyword(std::string_view text) {
  Keyword k;
  const auto f = fields(text.substr(1));
  std::string name;
  for (char c : upper(f[0]))
    if (c != ' ' && c != '\t')
      name += c;
    else if (!name.empty() && name.back() != ' ')
      name += ' ';
  k.name = std::string(trim(name));
  for (std::size_t i = 1; i < f.size(); ++i) {
    if (f[i].empty()) continue;
    const auto eq = f[i].find('=');
    if (eq == std::string_view::npos)
      k.params.emplace_back(upper(trim(f[i])), "");
    else
      k.params.emplace_back(upper(trim(f[i].substr(0, eq))), unquote(f[i].substr(eq + 1)));
  }
  return k;
}

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

  void add(std::string_view text, int file, int depth) {
    int number = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string_view::npos) end = text.size();
      const Line l{file, ++number, trim(text.substr(pos, end - pos))};
      pos = end + 1;
      if (l.text.empty() || l.text.rfind("**", 0) == 0) continue;
      if (l.text.front() == '*' && parse_keyword(l.text).name == "INCLUDE") {
        include(l, depth);
        continue;
      }
      lines.push_back(l);
    }
  }

  void include(const Line& l, int depth) {
    const Keyword k = parse_keyword(l.text);
    const std::string* input = k.get("INPUT");
    if (!input || input->empty()) throw fail(l, "*INCLUDE needs INPUT=<file>");
    if (depth >= 16)
      throw fail(l, "*INCLUDE nested more than 16 deep (does a file include itself?)");
    fs::path path(*input);
    if (path.is_relative()) path = fs::path(names[l.file]).parent_path() / path;
    std::error_code ec;
    std::ifstream in;
    if (fs::is_regular_file(path, ec)) in.open(path, std::ios::binary);
    if (!in.is_open() || !in)
      throw fail(l, "*INCLUDE: cannot open " + path.string() +
                        " as a file (a relative path is taken from the including file's folder)");
    std::ostringstream ss;
    ss << in.rdbuf();
    names.push_back(path.string());
    texts.push_back(std::make_unique<std::string>(ss.str()));
    add(*texts.back(), static_cast<int>(names.size()) - 1, depth + 1);
  }
};

/// What hencky makes of an element type.
struct ElementKind {
  enum class Kind { volume, face, skipped } kind = Kind::skipped;
  CellType type = CellType::tet4;
  int nodes = 0;  ///< nodes in the file, also of a skipped type (0: read up to the line's end)
};

/// The leading digits of s (after a prefix), or -1.
int leading_number(std::string_view s) {
  int n = 0;
  std::size_t i = 0;
  for (; i < s.size() && i < 4 && std::isdigit(static_cast<unsigned char>(s[i])); ++i)
    n = 10 * n + (s[i] - '0');
  return i == 0 ? -1 : n;
}

/// The kind of an element type (upper case), or a message saying why hencky cannot read it.
std::variant<ElementKind, std::string> element_kind(const std::string& type) {
  using K = ElementKind::Kind;
  const std::string supported =
      "hencky reads the volume elements C3D4, C3D10, C3D8, C3D20 and C3D6 (with any suffix, "
      "e.g. C3D8R), the face elements CPS, CPE, CAX, S, M3D, R3D, SFM3D and STRI with 3, 4, 6 "
      "or 8 nodes, and skips line elements";
  for (std::string_view prefix : {"DC3D", "C3D"})
    if (type.rfind(prefix, 0) == 0) {
      const std::string_view rest = std::string_view(type).substr(prefix.size());
      const int n = leading_number(rest);
      const std::pair<int, CellType> volumes[] = {{4, CellType::tet4},
                                                  {10, CellType::tet10},
                                                  {8, CellType::hex8},
                                                  {20, CellType::hex20},
                                                  {6, CellType::wedge6}};
      for (const auto& [nodes, cell] : volumes)
        if (n == nodes) return ElementKind{K::volume, cell, nodes};
      return "element type " + type + " is not supported: " + supported;
    }
  // Face elements, by the node count after the family's prefix (STRI65: 6 nodes).
  for (std::string_view prefix : {"SFM3D", "STRI", "M3D", "R3D", "CPS", "CPE", "CAX", "S"})
    if (type.rfind(prefix, 0) == 0) {
      int n = leading_number(std::string_view(type).substr(prefix.size()));
      if (prefix == "STRI" && n == 65) n = 6;
      const std::pair<int, CellType> faces[] = {
          {3, CellType::tri3}, {4, CellType::quad4}, {6, CellType::tri6}, {8, CellType::quad8}};
      for (const auto& [nodes, cell] : faces)
        if (n == nodes) return ElementKind{K::face, cell, nodes};
      if (n > 0) return "element type " + type + " is not supported: " + supported;
      break;  // e.g. SPRING: not a face
    }
  for (std::string_view prefix :
       {"T2D",  "T3D",   "B21",   "B22",    "B23",     "B31",   "B32",     "B33",
        "PIPE", "ELBOW", "FRAME", "SPRING", "DASHPOT", "MASS",  "ROTARYI", "CONN",
        "GAP",  "DCOUP", "RB2D",  "RB3D",   "DC1D",    "JOINT", "ITS",     "DCAX"})
    if (type.rfind(prefix, 0) == 0) {
      int n = 0;
      if (prefix == "T2D" || prefix == "T3D" || prefix == "RB3D" || prefix == "RB2D")
        n = leading_number(std::string_view(type).substr(prefix.size()));
      else if (prefix == "MASS" || prefix == "ROTARYI")
        n = 1;
      return ElementKind{K::skipped, CellType::tet4, std::max(n, 0)};
    }
  return "unknown element type '" + type + "': " + supported;
}

/// Gmsh's node k of a cell is the file's node perm[k] (fem/cell_type.hpp; CalculiX manual 6.2).
std::span<const int> gmsh_from_abaqus(CellType t) {
  static constexpr int identity[20] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,
                                       10, 11, 12, 13, 14, 15, 16, 17, 18, 19};
  // Abaqus numbers the 10-node tetrahedron's edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4; Gmsh 1-2,
  // 2-3, 3-1, 4-1, 4-3, 4-2.
  static constexpr int tet10[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
  // Abaqus: edges 1-2, 2-3, 3-4, 4-1, 5-6, 6-7, 7-8, 8-5, 1-5, 2-6, 3-7, 4-8 (nodes 9..20);
  // Gmsh: 1-2, 1-4, 1-5, 2-3, 2-6, 3-4, 3-7, 4-8, 5-6, 5-8, 6-7, 7-8.
  static constexpr int hex20[20] = {0,  1, 2,  3,  4,  5,  6,  7,  8,  11,
                                    16, 9, 17, 10, 18, 19, 12, 15, 13, 14};
  if (t == CellType::tet10) return tet10;
  if (t == CellType::hex20) return hex20;
  return {identity, static_cast<std::size_t>(cell_n_nodes(t))};
}

/// Face `side` (from 1) of a volume cell: its corners and then its mid-edge nodes, as
/// positions in the file's order of the cell's nodes, in Gmsh's order of the face's type.
/// Empty when the cell has no such face. Views static tables: nothing is allocated.
std::span<const int> abaqus_face(CellType t, int side) {
  static const std::vector<std::vector<int>> tet = {
      {0, 1, 2, 4, 5, 6}, {0, 3, 1, 7, 8, 4}, {1, 3, 2, 8, 9, 5}, {2, 3, 0, 9, 7, 6}};
  static const std::vector<std::vector<int>> hex = {
      {0, 1, 2, 3, 8, 9, 10, 11},  {4, 7, 6, 5, 15, 14, 13, 12}, {0, 4, 5, 1, 16, 12, 17, 8},
      {1, 5, 6, 2, 17, 13, 18, 9}, {2, 6, 7, 3, 18, 14, 19, 10}, {3, 7, 4, 0, 19, 15, 16, 11}};
  static const std::vector<std::vector<int>> wedge = {
      {0, 1, 2}, {3, 5, 4}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}};
  const auto& table = cell_linear(t) == CellType::tet4   ? tet
                      : cell_linear(t) == CellType::hex8 ? hex
                                                         : wedge;
  if (side < 1 || side > static_cast<int>(table.size())) return {};
  const std::span<const int> f = table[side - 1];
  if (cell_linear(t) == t && t != CellType::wedge6)  // the corners: the first 3 or 4
    return f.first(t == CellType::tet4 ? 3 : 4);
  return f;
}

/// A member of a set: the labels first, first + step, .. last (one label: first = last).
struct Member {
  long first = 0, last = 0, step = 1;
  int line = 0;  ///< index into Deck::lines, for messages
  long count() const { return (last - first) / step + 1; }
  /// Label k (from 0) of the member; first + k·step never passes `last`, so it cannot
  /// overflow as a running `label += step` could next to the largest long.
  long label(long k) const { return first + k * step; }
};

struct Set {
  std::string name;  ///< as first written
  int line = 0;      ///< where it was first defined
  bool internal = false;  ///< INTERNAL (Abaqus/CAE's sets behind a surface): not a region
  std::vector<Member> members;
  std::size_t count = 0;  ///< labels over all members (with repeats)
};

struct SurfaceItem {
  std::string set;  ///< an ELSET (NSET) name, or empty for a label
  long label = 0;
  int side = 0;  ///< face number from 1 (element-based surfaces)
  int line = 0;
};

struct Surface {
  std::string name;
  bool nodes = false;
  int line = 0;
  std::vector<SurfaceItem> items;
};

struct Element {
  long label = 0;
  ElementKind kind;
  std::string type;  ///< as the file names it, upper case
  int offset = 0;    ///< its node labels: conn[offset .. offset + kind.nodes), the file's order
  int line = 0;
};

/// The deck, read keyword by keyword into nodes, elements and sets; then turned into the Mesh.
class InpReader {
 public:
  InpReader(const Deck& deck, const MeshReadOptions& options, std::vector<std::string>* warnings)
      : deck_(deck), options_(options), warnings_(warnings) {}

  Mesh read() {
    const auto& lines = deck_.lines;
    std::size_t i = 0;
    while (i < lines.size()) {
      if (lines[i].text.front() != '*')
        throw fail(static_cast<int>(i), "a data line before any keyword");
      const int at = static_cast<int>(i);
      const Keyword k = parse_keyword(lines[i].text);
      std::size_t end = i + 1;
      while (end < lines.size() && lines[end].text.front() != '*') ++end;
      keyword(k, at, static_cast<int>(i + 1), static_cast<int>(end));
      i = end;
    }
    return build();
  }

 private:
  static constexpr std::size_t max_members = 200'000'000;

  InputError fail(int line, const std::string& msg) const {
    return deck_.fail(deck_.lines[line], msg);
  }
  std::string_view text(int line) const { return deck_.lines[line].text; }

  /// The fields of data line `line`, the empty ones (a trailing comma) dropped.
  std::vector<std::string_view> data(int line) const {
    auto f = fields(text(line));
    f.erase(std::remove_if(f.begin(), f.end(), [](std::string_view s) { return s.empty(); }),
            f.end());
    return f;
  }

  long label(std::string_view s, int line, const char* what) const {
    long v = 0;
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') ++b;
    const auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e || v <= 0)
      throw fail(line, fmt::format("expected a {} (a positive whole number), found '{}'", what, s));
    return v;
  }
  static bool is_label(std::string_view s) {
    return !s.empty() && (std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '+');
  }

  double real(std::string_view s, int line) const {
    std::string t;  // only for Fortran's 1.0D+03: the usual number is parsed where it is
    if (s.find_first_of("dD") != std::string_view::npos) {
      t = s;
      for (char& c : t)
        if (c == 'd' || c == 'D') c = 'e';
    }
    const char* b = t.empty() ? s.data() : t.data();
    const char* e = b + (t.empty() ? s.size() : t.size());
    if (b != e && *b == '+') ++b;
    double v = 0;
    const auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || p != e || !std::isfinite(v))
      throw fail(line, fmt::format("expected a coordinate (a finite number), found '{}'", s));
    return v;
  }

  void keyword(const Keyword& k, int at, int first, int end) {
    if (k.name.empty()) throw fail(at, "a keyword line without a keyword ('*' alone)");
    if (k.name == "HEADING") return;
    if (k.name == "PART") return part(k, at);
    if (k.name == "END PART" || k.name == "END INSTANCE") {
      in_instance_ = false;
      return;
    }
    if (k.name == "ASSEMBLY") {
      in_assembly_ = true;
      return;
    }
    if (k.name == "END ASSEMBLY") {
      in_assembly_ = false;
      return;
    }
    if (k.name == "INSTANCE") return instance(k, at, first, end);
    // Nodes, elements and sets of the assembly itself (outside its instance) are reference
    // points and their sets, not the body.
    const bool of_assembly = in_assembly_ && !in_instance_ && !k.has("INSTANCE");
    if (k.name == "NODE" || k.name == "ELEMENT" || k.name == "NSET" || k.name == "ELSET") {
      if (k.has("INPUT"))
        throw fail(at, "*" + k.name +
                           ", INPUT=... is not read; write *INCLUDE, INPUT=... "
                           "around the data lines instead");
      if (of_assembly) {
        skip("*" + k.name + " of the assembly (reference points)");
        return;
      }
    }
    if (k.name == "NODE") return nodes(k, at, first, end);
    if (k.name == "ELEMENT") return elements(k, at, first, end);
    if (k.name == "NSET") return set(k, at, first, end, true);
    if (k.name == "ELSET") return set(k, at, first, end, false);
    if (k.name == "SURFACE") return surface(k, at, first, end);
    skip("*" + k.name);
  }

  void skip(const std::string& what) {
    if (std::find(skipped_.begin(), skipped_.end(), what) == skipped_.end())
      skipped_.push_back(what);
  }

  void part(const Keyword& k, int at) {
    const std::string* name = k.get("NAME");
    const std::string n = name ? *name : "";
    if (!part_name_.empty())
      throw fail(at, fmt::format("a second *PART ('{}' after '{}'): hencky reads a deck of one "
                                 "part (write the model as one part, or without parts)",
                                 n, part_name_));
    part_name_ = n.empty() ? "(unnamed)" : n;
  }

  void instance(const Keyword& k, int at, int first, int end) {
    const std::string* name = k.get("NAME");
    if (++instances_ > 1)
      throw fail(at, fmt::format("a second *INSTANCE ('{}'): hencky reads a deck of one part "
                                 "with at most one instance of it",
                                 name ? *name : ""));
    if (first < end)
      throw fail(first,
                 "the instance is moved (translation or rotation lines): hencky reads the "
                 "part where its nodes are; write the deck without the move");
    in_instance_ = true;
  }

  void nodes(const Keyword& k, int at, int first, int end) {
    if (const std::string* sys = k.get("SYSTEM"); sys && upper(*sys) != "R")
      throw fail(
          at, "*NODE, SYSTEM=" + *sys + ": hencky reads rectangular coordinates only (SYSTEM=R)");
    const std::string* nset = k.get("NSET");
    Set* s = nset ? &open_set(nsets_, *nset, at) : nullptr;
    for (int l = first; l < end; ++l) {
      const auto f = data(l);
      if (f.empty()) continue;
      if (f.size() > 4)
        throw fail(l, fmt::format("a node line is 'label, x, y, z'; found {} fields", f.size()));
      const long n = label(f[0], l, "node label");
      double x[3] = {0, 0, 0};
      for (std::size_t d = 1; d < f.size(); ++d) x[d - 1] = real(f[d], l);
      const auto [it, fresh] = node_of_label_.emplace(n, static_cast<int>(node_label_.size()));
      if (!fresh)
        throw fail(l, fmt::format("node {} is defined twice (first on line {})", n,
                                  deck_.lines[node_line_[it->second]].number));
      node_label_.push_back(n);
      node_line_.push_back(l);
      xyz_.insert(xyz_.end(), x, x + 3);
      if (s) add_member(*s, {n, n, 1, l});
    }
  }

  void elements(const Keyword& k, int at, int first, int end) {
    const std::string* t = k.get("TYPE");
    if (!t || t->empty()) throw fail(at, "*ELEMENT needs TYPE=<element type>, e.g. TYPE=C3D10");
    const std::string type = upper(*t);
    const auto kind = element_kind(type);
    if (const auto* why = std::get_if<std::string>(&kind)) throw fail(at, *why);
    const ElementKind ek = std::get<ElementKind>(kind);
    const std::string* elset = k.get("ELSET");
    Set* s = elset ? &open_set(elsets_, *elset, at) : nullptr;
    // An element's labels may go on over several lines (Abaqus: a line ends with a comma;
    // CalculiX reads on until the type's node count, comma or not): read until the count.
    const std::size_t want = ek.nodes > 0 ? static_cast<std::size_t>(ek.nodes) + 1 : 0;
    std::vector<long> labels;
    int start = first;
    for (int l = first; l < end; ++l) {
      if (labels.empty()) start = l;
      for (auto v : data(l)) labels.push_back(label(v, l, "label"));
      if (labels.empty()) continue;
      if (want == 0 ? text(l).back() == ',' : labels.size() < want) {
        if (l + 1 < end) continue;
        throw fail(l, fmt::format("element {} has {} nodes, and {} has {}: the element's "
                                  "line ends the data (is the file cut short?)",
                                  labels[0], labels.size() - 1, type, ek.nodes));
      }
      if (want > 0 && labels.size() > want)
        throw fail(l, fmt::format("element {} has {} nodes, and {} has {}", labels[0],
                                  labels.size() - 1, type, ek.nodes));
      add_element(type, ek, labels, start);
      if (s) add_member(*s, {labels[0], labels[0], 1, start});
      labels.clear();
    }
  }

  void add_element(const std::string& type, const ElementKind& ek, const std::vector<long>& labels,
                   int line) {
    const long e = labels[0];
    if (element_of_label_.count(e) || skipped_elements_.count(e)) {
      const int before = element_of_label_.count(e) ? elements_[element_of_label_.at(e)].line
                                                    : skipped_elements_.at(e);
      throw fail(line, fmt::format("element {} is defined twice (first on line {})", e,
                                   deck_.lines[before].number));
    }
    if (ek.kind == ElementKind::Kind::skipped) {
      skipped_elements_.emplace(e, line);
      ++skipped_types_[type];
      return;
    }
    if (type != "C3D4" && type != "C3D10" && type != "C3D8" && type != "C3D20" && type != "C3D6" &&
        ek.kind == ElementKind::Kind::volume)
      ++renamed_types_[type];
    element_of_label_.emplace(e, static_cast<int>(elements_.size()));
    elements_.push_back({e, ek, type, static_cast<int>(conn_.size()), line});
    conn_.insert(conn_.end(), labels.begin() + 1, labels.end());
  }

  Set& open_set(std::map<std::string, Set>& sets, const std::string& name, int at) {
    if (name.empty()) throw fail(at, "a set without a name");
    auto [it, fresh] = sets.try_emplace(upper(name));
    if (fresh) {
      it->second.name = name;
      it->second.line = at;
      (&sets == &nsets_ ? nset_order_ : elset_order_).push_back(it->first);
    }
    return it->second;
  }

  void add_member(Set& s, const Member& m) {
    const std::size_t n = static_cast<std::size_t>(m.count());
    s.count += n;
    total_members_ += n;
    if (total_members_ > max_members)
      throw fail(m.line, fmt::format("the sets hold more than {} labels", max_members));
    s.members.push_back(m);
  }

  void set(const Keyword& k, int at, int first, int end, bool of_nodes) {
    const char* kind = of_nodes ? "NSET" : "ELSET";
    const std::string* name = k.get(kind);
    if (!name) throw fail(at, fmt::format("*{} needs {}=<name>", kind, kind));
    auto& sets = of_nodes ? nsets_ : elsets_;
    Set& s = open_set(sets, *name, at);
    s.internal = s.internal || k.has("INTERNAL");
    const bool generate = k.has("GENERATE");
    const bool of_elsets = of_nodes && k.has("ELSET");  // *NSET, ELSET: nodes of element sets
    for (int l = first; l < end; ++l) {
      const auto f = data(l);
      if (generate) {
        if (f.size() < 2 || f.size() > 3)
          throw fail(l, "a GENERATE line is 'first, last' or 'first, last, step'");
        Member m{label(f[0], l, "label"), label(f[1], l, "label"),
                 f.size() == 3 ? label(f[2], l, "step") : 1, l};
        if (m.last < m.first)
          throw fail(l, fmt::format("GENERATE from {} down to {}", m.first, m.last));
        add_member(s, m);
        continue;
      }
      for (auto v : f) {
        if (of_elsets) {
          each_label(find_set(elsets_, v, l, "ELSET"), [&](long el, int) {
            auto it = element_of_label_.find(el);
            if (it == element_of_label_.end()) return;  // checked where the ELSET is used
            const Element& x = elements_[it->second];
            for (int a = 0; a < x.kind.nodes; ++a) {
              const long n = conn_[x.offset + a];
              add_member(s, {n, n, 1, l});
            }
          });
        } else if (is_label(v)) {
          const long n = label(v, l, of_nodes ? "node label" : "element label");
          add_member(s, {n, n, 1, l});
        } else {
          const Set& other = find_set(sets, v, l, kind);
          // A copy, as the set is when named: a later addition to it does not count here.
          const std::vector<Member> copy = other.members;
          for (const Member& m : copy) add_member(s, m);
        }
      }
    }
  }

  const Set& find_set(const std::map<std::string, Set>& sets, std::string_view name, int line,
                      const char* kind) const {
    const auto it = sets.find(upper(unquote(name)));
    if (it == sets.end())
      throw fail(line, fmt::format("'{}' is neither a label nor an {} defined before this line",
                                   name, kind));
    return it->second;
  }

  void surface(const Keyword& k, int at, int first, int end) {
    const std::string* name = k.get("NAME");
    if (!name || name->empty()) throw fail(at, "*SURFACE needs NAME=<name>");
    const std::string* type = k.get("TYPE");
    const std::string t = type ? upper(*type) : "ELEMENT";
    if (t != "ELEMENT" && t != "NODE")
      throw fail(at, "*SURFACE, TYPE=" + *type +
                         ": hencky reads element-based (TYPE=ELEMENT) and node-based (TYPE=NODE) "
                         "surfaces");
    auto [it, fresh] = surfaces_.try_emplace(upper(*name));
    Surface& s = it->second;
    if (fresh) {
      s.name = *name;
      s.nodes = t == "NODE";
      s.line = at;
      surface_order_.push_back(it->first);
    } else if (s.nodes != (t == "NODE")) {
      throw fail(at, "surface '" + *name + "' was defined before with another TYPE");
    }
    for (int l = first; l < end; ++l) {
      const auto f = data(l);
      if (f.empty()) continue;
      SurfaceItem item;
      item.line = l;
      if (is_label(f[0]))
        item.label = label(f[0], l, s.nodes ? "node label" : "element label");
      else
        item.set = upper(unquote(f[0]));
      if (!s.nodes && !(f.size() == 1 && !item.set.empty())) {  // an ELSET alone: its exterior
        const std::string face = f.size() > 1 ? upper(f[1]) : "";
        if (face.size() != 2 || face[0] != 'S' || face[1] < '1' || face[1] > '6')
          throw fail(l, fmt::format("an element-based surface line is 'element or ELSET, face' "
                                    "with the face S1 .. S6; found '{}'",
                                    text(l)));
        item.side = face[1] - '0';
      }
      s.items.push_back(std::move(item));
    }
  }

  // ---------------------------------------------------------------------------------------
  // The Mesh

  /// Calls f(label, line) for each label of the set's members.
  template <class F>
  void each_label(const Set& s, F&& f) const {
    for (const Member& m : s.members)
      for (long k = 0, n = m.count(); k < n; ++k) f(m.label(k), m.line);
  }

  Mesh build() {
    Mesh mesh;
    // The body: every volume element, in the file's order; its nodes by label.
    std::vector<long> body_labels;
    for (const Element& e : elements_)
      if (e.kind.kind == ElementKind::Kind::volume)
        for (int a = 0; a < e.kind.nodes; ++a) {
          const long n = conn_[e.offset + a];
          if (!node_of_label_.count(n))
            throw fail(e.line,
                       fmt::format("element {} has node {}, which no *NODE defines", e.label, n));
          body_labels.push_back(n);
        }
    if (body_labels.empty())
      throw InputError(SourceLocation{deck_.names[0], 0, 0, ""},
                       "the deck has no volume elements (hencky needs C3D4, C3D10, C3D8, C3D20 "
                       "or C3D6 elements)");
    std::sort(body_labels.begin(), body_labels.end());
    body_labels.erase(std::unique(body_labels.begin(), body_labels.end()), body_labels.end());
    for (std::size_t i = 0; i < body_labels.size(); ++i) {
      const int file_node = node_of_label_.at(body_labels[i]);
      body_node_.emplace(body_labels[i], static_cast<int>(i));
      mesh.x.emplace_back(xyz_[3 * file_node], xyz_[3 * file_node + 1], xyz_[3 * file_node + 2]);
      mesh.x.back() *= options_.scale;
      mesh.node_tag.push_back(body_labels[i]);
    }
    for (const Element& e : elements_)
      if (e.kind.kind == ElementKind::Kind::volume) {
        const auto perm = gmsh_from_abaqus(e.kind.type);
        int local[max_cell_nodes];
        for (int a = 0; a < e.kind.nodes; ++a) local[a] = body_node_.at(conn_[e.offset + perm[a]]);
        cell_of_element_.emplace(e.label, mesh.cells.size());
        mesh.cells.add(e.kind.type, std::span<const int>(local, e.kind.nodes), e.label);
      }
    mesh.cell_region.assign(mesh.cells.size(), -1);
    node_regions(mesh);
    face_regions(mesh);
    volume_regions(mesh);
    for (auto& r : mesh.regions) {
      if (r.dim == 3)
        for (int c : r.cells)
          for (int n : mesh.cells.nodes(c)) r.nodes.push_back(n);
      if (r.dim == 2)
        for (int f : r.cells)
          for (int n : mesh.faces.nodes(f)) r.nodes.push_back(n);
      std::sort(r.nodes.begin(), r.nodes.end());
      r.nodes.erase(std::unique(r.nodes.begin(), r.nodes.end()), r.nodes.end());
    }
    warn();
    return mesh;
  }

  /// The nodes of a node set's labels that are on the body (each label must be a node).
  void add_nodes(const Set& s, Region& r) const {
    each_label(s, [&](long n, int line) {
      if (!node_of_label_.count(n))
        throw fail(line, fmt::format("NSET '{}' names node {}, which no *NODE defines", s.name, n));
      auto it = body_node_.find(n);
      if (it != body_node_.end()) r.nodes.push_back(it->second);
    });
  }

  void node_regions(Mesh& mesh) const {
    for (const auto& key : nset_order_) {
      if (nsets_.at(key).internal) continue;
      Region r{nsets_.at(key).name, 0, {}, {}};
      add_nodes(nsets_.at(key), r);
      mesh.regions.push_back(std::move(r));
    }
    for (const auto& key : surface_order_) {
      const Surface& s = surfaces_.at(key);
      if (!s.nodes) continue;
      Region r{s.name, 0, {}, {}};
      for (const SurfaceItem& item : s.items) {
        if (!item.set.empty()) {
          const auto it = nsets_.find(item.set);
          if (it == nsets_.end())
            throw fail(item.line, fmt::format("surface '{}': '{}' is neither a node label nor "
                                              "an NSET",
                                              s.name, item.set));
          add_nodes(it->second, r);
        } else {
          Set one;
          one.name = s.name;
          one.members.push_back({item.label, item.label, 1, item.line});
          add_nodes(one, r);
        }
      }
      mesh.regions.push_back(std::move(r));
    }
  }

  /// The element of a label that a set names (it must be an element of the deck); nullptr for
  /// a skipped (line) element.
  const Element* element(long label, int line, const std::string& set) const {
    auto it = element_of_label_.find(label);
    if (it != element_of_label_.end()) return &elements_[it->second];
    if (skipped_elements_.count(label)) return nullptr;
    throw fail(line, fmt::format("'{}' names element {}, which no *ELEMENT defines", set, label));
  }

  void face_regions(Mesh& mesh) {
    for (const auto& key : surface_order_) {
      const Surface& s = surfaces_.at(key);
      if (s.nodes) continue;
      Region r{s.name, 2, {}, {}};
      std::set<std::pair<long, int>> seen;  // (element, side): each face once
      auto add = [&](long label, int side, int line) {
        const Element* e = element(label, line, "surface '" + s.name + "'");
        if (!e || e->kind.kind != ElementKind::Kind::volume)
          throw fail(line, fmt::format("surface '{}': element {} is not a volume element, and "
                                       "only a volume element's faces S1 .. S6 are read",
                                       s.name, label));
        const std::span<const int> face = abaqus_face(e->kind.type, side);
        if (face.empty())
          throw fail(line, fmt::format("surface '{}': element {} ({}) has no face S{}", s.name,
                                       label, e->type, side));
        if (!seen.emplace(label, side).second) return;
        int local[8];
        for (std::size_t a = 0; a < face.size(); ++a)
          local[a] = body_node_.at(conn_[e->offset + face[a]]);
        const CellType ft = face.size() == 3   ? CellType::tri3
                            : face.size() == 4 ? CellType::quad4
                            : face.size() == 6 ? CellType::tri6
                                               : CellType::quad8;
        mesh.faces.add(ft, std::span<const int>(local, face.size()), label);
        r.cells.push_back(mesh.faces.size() - 1);
      };
      for (const SurfaceItem& item : s.items) {
        if (item.set.empty()) {
          add(item.label, item.side, item.line);
          continue;
        }
        const auto it = elsets_.find(item.set);
        if (it == elsets_.end())
          throw fail(item.line, fmt::format("surface '{}': '{}' is neither an element label "
                                            "nor an ELSET",
                                            s.name, item.set));
        each_label(it->second, [&](long e, int line) {
          (void)line;
          if (item.side > 0) {
            add(e, item.side, item.line);
            return;
          }
          // No face named: the set's elements' faces on the outside of the body (Abaqus:
          // the exterior faces of the element set).
          const Element* el = element(e, item.line, "surface '" + s.name + "'");
          if (!el || el->kind.kind != ElementKind::Kind::volume) return;
          for (int side = 1;; ++side) {
            const std::span<const int> face = abaqus_face(el->kind.type, side);
            if (face.empty()) break;
            if (face_count().at(face_key(*el, face)) == 1) add(e, side, item.line);
          }
        });
      }
      mesh.regions.push_back(std::move(r));
    }
    // ELSETs of face elements (Gmsh's and cgx's export of surfaces).
    for (const auto& key : elset_order_) {
      const Set& s = elsets_.at(key);
      if (s.internal) continue;
      Region r{s.name, 2, {}, {}};
      std::set<long> seen;
      each_label(s, [&](long label, int line) {
        const Element* e = element(label, line, "ELSET '" + s.name + "'");
        if (!e || e->kind.kind != ElementKind::Kind::face || !seen.insert(label).second) return;
        int local[8];
        for (int a = 0; a < e->kind.nodes; ++a) {
          const long n = conn_[e->offset + a];
          auto it = body_node_.find(n);
          if (it == body_node_.end())
            throw fail(e->line, fmt::format("ELSET '{}': element {} has node {}, which is not a "
                                            "node of the volume elements (the face is not on "
                                            "the body)",
                                            s.name, label, n));
          local[a] = it->second;
        }
        mesh.faces.add(e->kind.type, std::span<const int>(local, e->kind.nodes), label);
        r.cells.push_back(mesh.faces.size() - 1);
      });
      if (!r.cells.empty()) mesh.regions.push_back(std::move(r));
    }
  }

  /// A face's corner labels, sorted: the same for the two cells that share the face.
  std::array<long, 4> face_key(const Element& e, std::span<const int> face) const {
    std::array<long, 4> key{0, 0, 0, 0};  // a triangle's 4th stays 0 (labels are positive)
    const std::size_t corners = face.size() == 3 || face.size() == 6 ? 3 : 4;
    for (std::size_t a = 0; a < corners; ++a) key[a] = conn_[e.offset + face[a]];
    std::sort(key.begin(), key.end());
    return key;
  }

  /// How many volume elements have each face (built when first asked).
  const std::map<std::array<long, 4>, int>& face_count() {
    if (face_count_.empty())
      for (const Element& e : elements_)
        if (e.kind.kind == ElementKind::Kind::volume)
          for (int side = 1;; ++side) {
            const std::span<const int> face = abaqus_face(e.kind.type, side);
            if (face.empty()) break;
            ++face_count_[face_key(e, face)];
          }
    return face_count_;
  }

  void volume_regions(Mesh& mesh) {
    for (const auto& key : elset_order_) {
      const Set& s = elsets_.at(key);
      if (s.internal) continue;
      Region r{s.name, 3, {}, {}};
      bool faces_only = s.count > 0;
      each_label(s, [&](long label, int line) {
        const Element* e = element(label, line, "ELSET '" + s.name + "'");
        if (e && e->kind.kind == ElementKind::Kind::volume) {
          r.cells.push_back(cell_of_element_.at(label));
          faces_only = false;
        }
      });
      std::sort(r.cells.begin(), r.cells.end());
      r.cells.erase(std::unique(r.cells.begin(), r.cells.end()), r.cells.end());
      if (r.cells.empty() && faces_only) continue;  // a region of faces (face_regions)
      const int index = static_cast<int>(mesh.regions.size());
      for (int c : r.cells)
        if (mesh.cell_region[c] < 0) mesh.cell_region[c] = index;
      mesh.regions.push_back(std::move(r));
    }
  }

  void warn() const {
    if (!warnings_) return;
    const std::string file = fs::path(deck_.names[0]).filename().string();
    if (!skipped_.empty()) {
      std::string list;
      for (const auto& k : skipped_) list += (list.empty() ? "" : ", ") + k;
      warnings_->push_back(file +
                           ": skipped what is not mesh data (hencky takes materials, "
                           "conditions and steps from the case file): " +
                           list);
    }
    if (!skipped_types_.empty()) {
      std::string list;
      for (const auto& [type, n] : skipped_types_)
        list += fmt::format("{}{} {}", list.empty() ? "" : ", ", n, type);
      warnings_->push_back(file +
                           ": skipped the elements that are neither volumes nor faces: " + list);
    }
    if (!renamed_types_.empty()) {
      std::string list;
      for (const auto& [type, n] : renamed_types_)
        list += fmt::format("{}{} {}", list.empty() ? "" : ", ", n, type);
      warnings_->push_back(file +
                           ": read as hencky's elements of the same nodes, integrated as "
                           "hencky integrates them: " +
                           list);
    }
  }

  const Deck& deck_;
  const MeshReadOptions& options_;
  std::vector<std::string>* warnings_;

  std::vector<long> node_label_;
  std::vector<int> node_line_;
  std::vector<double> xyz_;
  std::unordered_map<long, int> node_of_label_;
  std::vector<Element> elements_;
  std::vector<long> conn_;
  std::unordered_map<long, int> element_of_label_;
  std::unordered_map<long, int> skipped_elements_;  // label -> line
  std::map<std::string, int> skipped_types_, renamed_types_;
  std::map<std::string, Set> nsets_, elsets_;  // by upper-case name
  std::vector<std::string> nset_order_, elset_order_;
  std::map<std::string, Surface> surfaces_;
  std::vector<std::string> surface_order_;
  std::size_t total_members_ = 0;
  std::vector<std::string> skipped_;
  std::string part_name_;
  int instances_ = 0;
  bool in_assembly_ = false, in_instance_ = false;

  std::map<std::array<long, 4>, int> face_count_;  // see face_count()
  std::unordered_map<long, int> body_node_;        // node label -> hencky node
  std::unordered_map<long, int> cell_of_element_;  // element label -> cell
};

}  // namespace

Mesh parse_inp(std::string_view text, const fs::path& file, const MeshReadOptions& options,
               std::vector<std::string>* warnings) {
  Deck deck;
  deck.names.push_back(file.string());
  deck.add(text, 0, 0);
  return InpReader(deck, options, warnings).read();
}

Mesh read_inp(const fs::path& file, const MeshReadOptions& options,
              std::vector<std::string>* warnings) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(SourceLocation{file.string(), 0, 0, ""}, "cannot open the mesh file");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  return parse_inp(text, file, options, warnings);
}

bool is_inp_file(const fs::path& file) {
  return upper(file.extension().string()) == ".INP";
}

}  // namespace hencky
