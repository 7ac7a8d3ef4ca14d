#pragma once
// The reader of an Abaqus/CalculiX deck (input/inp_reader.hpp) behind parse_inp: the deck
// read keyword by keyword into nodes, elements, sets and surfaces (inp_keywords.cpp), then
// turned into the Mesh and its regions (inp_reader.cpp).
#include <algorithm>
#include <array>
#include <cctype>
#include <cstddef>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "input/gmsh_reader.hpp"
#include "input/inp_deck.hpp"
#include "input/inp_elements.hpp"
#include "mesh/mesh.hpp"

namespace hencky::inp {

/// A member of a set: the labels first, first + step, .. last (one label: first = last).
struct Member {
  long first = 0, last = 0, step = 1;
  int line = 0;  ///< index into Deck::lines, for messages
  /// From a GENERATE line: a label no *NODE defines is left out (as ccx does), not an error.
  bool generated = false;
  long count() const { return (last - first) / step + 1; }
  /// Label k (from 0) of the member; first + k·step never passes `last`, so it cannot
  /// overflow as a running `label += step` could next to the largest long.
  long label(long k) const { return first + k * step; }
};

struct Set {
  std::string name;       ///< as first written
  int line = 0;           ///< where it was first defined
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

class InpReader;

/// What reads the keywords of a deck that are not mesh data, when the deck is run as a case
/// (input/inp_case.hpp): materials, conditions and steps.
class History {
 public:
  virtual ~History() = default;
  /// The keyword k of line `at`, its data lines first .. end - 1 (the reader's mesh data
  /// before it is read).
  virtual void keyword(InpReader& reader, const Keyword& k, int at, int first, int end) = 0;
  /// After the last keyword, before the Mesh is built: the sets and surfaces the history
  /// makes (InpReader::add_node_set, add_face_surface) are added here.
  virtual void finish(InpReader& reader) = 0;
};

/// A face of an element: its label and its side, from 1 (S1 .. S6, P1 .. P6).
using ElementFace = std::pair<long, int>;

/// The deck, read keyword by keyword into nodes, elements and sets; then turned into the Mesh.
class InpReader {
 public:
  InpReader(const Deck& deck, const MeshReadOptions& options, std::vector<std::string>* warnings)
      : deck_(deck), options_(options), warnings_(warnings) {}

  /// The Mesh of the deck. Throws InputError naming the file and line.
  Mesh read();

  /// The deck run as a case: the keywords that are not mesh data go to `history`, not to the
  /// warning about skipped keywords.
  void set_history(History* history) { history_ = history; }
  const Deck& deck() const { return deck_; }
  InputError fail(int line, const std::string& msg) const {
    return deck_.fail(deck_.lines[line], msg);
  }
  SourceLocation where(int line) const { return fail(line, "").where(); }
  /// The labels of the volume elements' nodes, sorted.
  std::vector<long> body_node_labels() const;
  /// Whether `labels` name every volume element of the deck (the whole body).
  bool covers_body(const std::vector<long>& labels) const;
  /// The nodes a condition's line names (of line `line`): a node label, or an NSET's labels
  /// (those of its GENERATE ranges that no *NODE defines left out).
  std::vector<long> node_targets(std::string_view target, int line) const;
  /// The faces a *DLOAD line names: with `side` >= 1 that face of an element label or of each
  /// element of an ELSET; with `side` 0, the faces of an element-based *SURFACE.
  std::vector<ElementFace> face_targets(std::string_view target, int side, int line);
  /// The elements a line names: an element label or an ELSET's labels.
  std::vector<long> element_targets(std::string_view target, int line) const;
  /// How many volume elements of each type (upper case, as written) the deck has.
  const std::map<std::string, long>& volume_types() const { return volume_types_; }
  /// Every node label of the deck's *NODE lines.
  const std::vector<long>& node_labels() const { return node_label_; }
  /// `name`, or `name` with a suffix when a set or surface of the deck already has it.
  std::string unused_name(std::string name) const {
    while (nsets_.count(upper(name)) || elsets_.count(upper(name)) ||
           surfaces_.count({upper(name), false}) || surfaces_.count({upper(name), true}))
      name += "_";
    return name;
  }
  /// A region the history makes from labels (History::finish): a node set, an element-based
  /// surface; `line` is where the labels come from, for messages.
  void add_node_set(const std::string& name, const std::vector<long>& labels, int line);
  void add_face_surface(const std::string& name, const std::vector<ElementFace>& faces, int line);

  /// The fields of data line `line`, the empty ones (a trailing comma) dropped.
  std::vector<std::string_view> data(int line) const {
    auto f = fields(text(line));
    f.erase(std::remove_if(f.begin(), f.end(), [](std::string_view s) { return s.empty(); }),
            f.end());
    return f;
  }
  /// The fields of data line `line` with the empty ones inside kept (`node, 1, , value`: the
  /// last degree of freedom not given), the trailing ones dropped.
  std::vector<std::string_view> data_in_place(int line) const {
    auto f = fields(text(line));
    while (!f.empty() && f.back().empty()) f.pop_back();
    return f;
  }
  static bool is_label(std::string_view s) {
    return !s.empty() && (std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '+');
  }
  long label(std::string_view s, int line, const char* what) const;
  /// A number of line `line` (Fortran's 1.0D+03 too); `what` names it in the message.
  double real(std::string_view s, int line, const char* what = "coordinate") const;

 private:
  static constexpr std::size_t max_members = 200'000'000;

  std::string_view text(int line) const { return deck_.lines[line].text; }

  /// Calls f(label, line) for each label of the set's members.
  template <class F>
  void each_label(const Set& s, F&& f) const {
    for (const Member& m : s.members)
      for (long k = 0, n = m.count(); k < n; ++k) f(m.label(k), m.line);
  }

  // The keywords (inp_keywords.cpp).
  /// The keyword k of line `at`, its data lines first .. end - 1.
  void keyword(const Keyword& k, int at, int first, int end);
  /// A keyword hencky does not read, listed in warn() under the file of line `at`.
  void skip(const std::string& what, int at);
  void part(const Keyword& k, int at);
  void instance(const Keyword& k, int at, int first, int end);
  void nodes(const Keyword& k, int at, int first, int end);
  void elements(const Keyword& k, int at, int first, int end);
  void add_element(const std::string& type, const ElementKind& ek, const std::vector<long>& labels,
                   int line);
  Set& open_set(std::map<std::string, Set>& sets, const std::string& name, int at);
  void add_member(Set& s, const Member& m);
  void set(const Keyword& k, int at, int first, int end, bool of_nodes);
  const Set& find_set(const std::map<std::string, Set>& sets, std::string_view name, int line,
                      const char* kind) const;
  void surface(const Keyword& k, int at, int first, int end);

  // The Mesh (inp_reader.cpp).
  Mesh build();
  /// The labels of a node set that *NODE defines: a label of no node is an error, but for those
  /// of GENERATE ranges, left out (as ccx leaves them out) and counted in `gaps` when given.
  std::vector<long> set_nodes(const Set& s, long* gaps = nullptr) const;
  /// The nodes of a node set's labels that are on the body.
  void add_nodes(const Set& s, Region& r);
  void node_regions(Mesh& mesh);
  /// The element of a label that a set names (it must be an element of the deck); nullptr for
  /// a skipped (line) element.
  const Element* element(long label, int line, const std::string& set) const;
  void face_regions(Mesh& mesh);
  /// A face's corner labels, sorted: the same for the two cells that share the face.
  std::array<long, 4> face_key(const Element& e, std::span<const int> face) const;
  /// How many volume elements have each face (built when first asked).
  const std::map<std::array<long, 4>, int>& face_count();
  void volume_regions(Mesh& mesh);
  void warn() const;

  const Deck& deck_;
  const MeshReadOptions& options_;
  std::vector<std::string>* warnings_;
  History* history_ = nullptr;

  std::vector<long> node_label_;
  std::vector<int> node_line_;
  std::vector<double> xyz_;
  std::unordered_map<long, int> node_of_label_;
  std::vector<Element> elements_;
  std::vector<long> conn_;
  std::unordered_map<long, int> element_of_label_;
  std::unordered_map<long, int> skipped_elements_;  // label -> line
  std::map<std::string, int> skipped_types_, renamed_types_, convention_types_;
  std::map<std::string, long> volume_types_;
  std::map<std::string, Set> nsets_, elsets_;  // by upper-case name
  std::vector<std::string> nset_order_, elset_order_;
  /// By upper-case name and whether node-based: ccx keeps a node-based and an element-based
  /// surface of one name apart (metalforming of its test suite defines both).
  using SurfaceKey = std::pair<std::string, bool>;
  std::map<SurfaceKey, Surface> surfaces_;
  std::vector<SurfaceKey> surface_order_;
  std::size_t total_members_ = 0;
  std::vector<std::pair<int, std::string>> skipped_;  // (file, keyword), in order met
  std::map<std::string, long> generate_gaps_;         // NSET -> GENERATE labels of no node
  std::pair<long, int> extra_numbers_{0, -1};  // element lines with numbers past the nodes, first
  std::string part_name_;
  int instances_ = 0;
  bool in_assembly_ = false, in_instance_ = false;

  std::map<std::array<long, 4>, int> face_count_;  // see face_count()
  std::unordered_map<long, int> body_node_;        // node label -> hencky node
  std::unordered_map<long, int> cell_of_element_;  // element label -> cell
};

}  // namespace hencky::inp
