#include "input/msh_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "core/error.hpp"

// The MSH formats as the Gmsh reference manual describes them (section "MSH file format",
// versions 4.1 and 2.2; 4.0 from the Gmsh 4.0 manual). Only the sections hencky uses are
// parsed: $MeshFormat, $PhysicalNames, $Entities, $PartitionedEntities, $Nodes and $Elements.
// Other sections are skipped to their $End line.
//
// A partitioned mesh (gmsh -part N, MSH 4.1) classifies its nodes and elements on partitioned
// entities, each the piece of a model entity (its parent) in one or more partitions. An entity
// of its parent's dimension carries the parent's physical groups; one of lower dimension is a
// boundary between partitions, whose elements Gmsh adds to the file: they are not the model's
// and are skipped. The partitions saved in one file are read as the whole mesh; one file of a
// mesh split into several (-part_split) is refused, for it holds a part only.

namespace hencky {
namespace {

class Parser {
 public:
  Parser(std::string_view text, std::string name, bool piece)
      : s_(text), name_(std::move(name)), piece_(piece) {}

  MshData parse() {
    read_format();
    bool nodes = false, elements = false;
    for (;;) {
      skip_space();
      if (pos_ >= s_.size()) break;
      const std::size_t start = pos_;
      const std::string_view section = token();
      if (section.empty() || section[0] != '$')
        throw error(start, "expected a section ($Nodes, $Elements, ...), found '" +
                               std::string(section.substr(0, 40)) + "'");
      if (section == "$PhysicalNames") {
        read_physical_names();
      } else if (section == "$Entities" && version_ >= 4) {
        read_entities();
      } else if (section == "$PartitionedEntities") {
        read_partitioned_entities(start);
      } else if (section == "$Nodes") {
        if (nodes) throw error(start, "a second $Nodes section");
        version_ >= 4 ? read_nodes4() : read_nodes2();
        nodes = true;
      } else if (section == "$Elements") {
        if (!nodes) throw error(start, "$Elements comes before $Nodes");
        if (elements) throw error(start, "a second $Elements section");
        version_ >= 4 ? read_elements4() : read_elements2();
        elements = true;
      } else {
        skip_section(start, section);
        continue;
      }
      expect_end(section);
    }
    if (!nodes) throw error(s_.size(), "the file has no $Nodes section");
    if (!elements) throw error(s_.size(), "the file has no $Elements section");
    if (piece_ && d_.piece == 0)
      throw error(0, "not one file of a mesh split into files (gmsh -part N -part_split)");
    return std::move(d_);
  }

 private:
  // ---- errors -----------------------------------------------------------------------------
  InputError error(std::size_t at, const std::string& what) const {
    SourceLocation w{name_, 0, 0, ""};
    std::string where;
    if (binary_ && at > binary_start_) {
      where = "byte " + std::to_string(at) + ": ";
    } else {
      w.line =
          1 + static_cast<int>(std::count(s_.begin(), s_.begin() + std::min(at, s_.size()), '\n'));
    }
    return InputError(w, "not a valid Gmsh mesh file: " + where + what);
  }

  // ---- ASCII tokens -----------------------------------------------------------------------
  void skip_space() {
    while (pos_ < s_.size() &&
           (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r' || s_[pos_] == '\n'))
      ++pos_;
  }
  std::string_view token() {
    skip_space();
    const std::size_t b = pos_;
    while (pos_ < s_.size() &&
           !(s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r' || s_[pos_] == '\n'))
      ++pos_;
    return s_.substr(b, pos_ - b);
  }
  template <class T>
  T number(const char* what) {
    skip_space();
    const std::size_t at = pos_;
    const std::string_view t = token();
    if (t.empty()) throw error(at, "the file ends where " + std::string(what) + " was expected");
    T v{};
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size()) {
      std::string hint;
      if constexpr (std::is_unsigned_v<T>) hint = " (a non-negative integer)";
      throw error(
          at, std::string(what) + hint + " expected, found '" + std::string(t.substr(0, 40)) + "'");
    }
    return v;
  }
  std::size_t count(const char* what) { return number<std::size_t>(what); }
  int integer(const char* what) { return number<int>(what); }
  double real(const char* what) {
    const std::size_t at = pos_;
    const double v = number<double>(what);
    if (!std::isfinite(v)) throw error(at, std::string(what) + " is not a finite number");
    return v;
  }

  // ---- binary values ----------------------------------------------------------------------
  template <class T>
  T bin(const char* what) {
    if (s_.size() - pos_ < sizeof(T))
      throw error(pos_, "the file ends where " + std::string(what) + " was expected");
    T v;
    std::memcpy(&v, s_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  /// Checks that n values of `size` bytes remain, without overflow.
  void need(std::size_t n, std::size_t size, const char* what) {
    if (n > (s_.size() - pos_) / size)
      throw error(pos_, "the file ends inside " + std::string(what) + " (it announces " +
                            std::to_string(n) + ")");
  }
  /// In a binary file, the binary data of a section starts after the end of its header line.
  void to_binary_data() {
    if (!binary_) return;
    while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r')) ++pos_;
    if (pos_ < s_.size() && s_[pos_] == '\n') ++pos_;
  }
  // One value in the file's own encoding: text or binary.
  std::size_t tag_or_count(const char* what) {
    return binary_ ? bin<std::size_t>(what) : count(what);
  }
  int int_value(const char* what) { return binary_ ? bin<int>(what) : integer(what); }
  double real_value(const char* what) {
    const std::size_t at = pos_;
    const double v = binary_ ? bin<double>(what) : real(what);
    if (!std::isfinite(v)) throw error(at, std::string(what) + " is not a finite number");
    return v;
  }

  // ---- sections ---------------------------------------------------------------------------
  void expect(std::string_view word) {
    const std::size_t at = (skip_space(), pos_);
    const std::string_view t = token();
    if (t != word)
      throw error(at, "expected " + std::string(word) + ", found " +
                          (t.empty() ? std::string("the end of the file")
                                     : "'" + std::string(t.substr(0, 40)) + "'") +
                          " (do the counts announced in the section agree with its content?)");
  }
  void expect_end(std::string_view section) { expect("$End" + std::string(section.substr(1))); }
  void skip_section(std::size_t start, std::string_view section) {
    const std::string end = "$End" + std::string(section.substr(1));
    const std::size_t at = s_.find(end, pos_);
    if (at == std::string_view::npos)
      throw error(start, "section " + std::string(section) + " has no " + end);
    pos_ = at + end.size();
  }

  void read_format() {
    skip_space();
    const std::size_t at = pos_;
    if (token() != "$MeshFormat")
      throw error(
          at, "the file does not start with $MeshFormat (a Gmsh .msh file of format 2 or 4 does)");
    const std::size_t vat = (skip_space(), pos_);
    const std::string_view v = token();
    if (v == "2" || v == "2.0" || v == "2.1" || v == "2.2")
      version_ = 2;
    else if (v == "4" || v == "4.0")
      version_ = 4.0;
    else if (v == "4.1")
      version_ = 4.1;
    else
      throw error(vat, "MSH format version '" + std::string(v.substr(0, 20)) +
                           "' is not read (2.2, 4.0 and 4.1 are): save the mesh as 4.1");
    const int file_type = integer("the file type (0 ASCII, 1 binary)");
    const int data_size = integer("the data size");
    if (file_type != 0 && file_type != 1)
      throw error(vat, "file type must be 0 (ASCII) or 1 (binary)");
    binary_ = file_type == 1;
    if (binary_) {
      if (version_ == 4.0)
        throw error(
            vat,
            "binary MSH 4.0 is not read (Gmsh writes 4.0 in ASCII only): save the mesh as 4.1");
      if (data_size != 8)
        throw error(vat, "binary data size " + std::to_string(data_size) + " is not read (8 is)");
      while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;  // the rest of the version line
      // Not past the end when the line has no newline: pos_ > size would wrap the size checks
      // (found by fuzz/fuzz_msh.cpp, a read past the end).
      if (pos_ < s_.size()) ++pos_;
      binary_start_ = pos_;
      if (bin<int>("the endianness check") != 1)
        throw error(pos_, "the binary file was written on a machine of other endianness");
    }
    expect("$EndMeshFormat");
  }

  void read_physical_names() {
    const std::size_t n = count("the number of physical names");
    for (std::size_t i = 0; i < n; ++i) {
      skip_space();
      const std::size_t line_at = pos_;
      const int dim = integer("a physical dimension");
      const int tag = integer("a physical tag");
      skip_space();
      const std::size_t at = pos_;
      if (pos_ >= s_.size() || s_[pos_] != '"') throw error(at, "a quoted physical name expected");
      const std::size_t close = s_.find('"', pos_ + 1);
      const std::size_t eol = s_.find('\n', pos_ + 1);
      if (close == std::string_view::npos || (eol != std::string_view::npos && close > eol))
        throw error(at, "the physical name has no closing quote");
      std::string name(s_.substr(pos_ + 1, close - pos_ - 1));
      // A group of another dimension names nothing a mesh has; Gmsh's library, which converts
      // the order of a read mesh, took one of dimension 4 and crashed (shared/crashes).
      if (dim < 0 || dim > 3)
        throw error(line_at, "physical name '" + name + "' has dimension " + std::to_string(dim) +
                                 " (0 to 3)");
      d_.physical_names[{dim, tag}] = std::move(name);
      pos_ = close + 1;
    }
  }

  /// The entity (dim, tag), created when first met, and its physical groups (each once).
  /// Called per element in format 2: no allocation.
  void add_entity(int dim, int tag, std::span<const int> physicals) {
    auto [it, fresh] = entity_index_.emplace(std::pair(dim, tag), d_.entities.size());
    if (fresh) d_.entities.push_back({dim, tag, {}});
    auto& phys = d_.entities[it->second].physicals;
    for (int p : physicals)
      if (std::find(phys.begin(), phys.end(), p) == phys.end()) phys.push_back(p);
  }

  void read_entities() {
    to_binary_data();
    std::size_t n[4];
    for (auto& c : n) c = tag_or_count("an entity count");
    for (int dim = 0; dim < 4; ++dim) {
      if (!binary_) need(n[dim], 2, "$Entities");
      for (std::size_t i = 0; i < n[dim]; ++i) {
        const int tag = int_value("an entity tag");
        const int box = (dim == 0 && version_ == 4.1) ? 3 : 6;
        for (int k = 0; k < box; ++k) real_value("an entity's coordinates");
        const std::size_t n_phys = tag_or_count("a number of physical tags");
        if (binary_)
          need(n_phys, sizeof(int), "an entity's physical tags");
        else
          need(n_phys, 2, "an entity's physical tags");
        std::vector<int> phys;
        for (std::size_t k = 0; k < n_phys; ++k) phys.push_back(int_value("a physical tag"));
        if (dim > 0) {
          const std::size_t n_bound = tag_or_count("a number of bounding entities");
          if (binary_)
            need(n_bound, sizeof(int), "an entity's bounding entities");
          else
            need(n_bound, 2, "an entity's bounding entities");
          for (std::size_t k = 0; k < n_bound; ++k) int_value("a bounding entity");
        }
        add_entity(dim, tag, phys);
      }
    }
  }

  void read_partitioned_entities(std::size_t start) {
    if (version_ != 4.1) throw error(start, "partitioned meshes are read in MSH format 4.1 only");
    to_binary_data();
    const std::size_t n_parts = tag_or_count("the number of partitions");
    const std::size_t n_ghosts = tag_or_count("the number of ghost entities");
    need(n_ghosts, binary_ ? 2 * sizeof(int) : 4, "$PartitionedEntities");
    for (std::size_t k = 0; k < n_ghosts; ++k)
      int_value("a ghost entity tag"), int_value("a ghost entity's partition");
    std::size_t n[4];
    for (auto& c : n) c = tag_or_count("an entity count");
    std::set<int> volume_parts;  // the partitions of the file's volumes
    for (int dim = 0; dim < 4; ++dim) {
      need(n[dim], binary_ ? 3 * sizeof(int) : 6, "$PartitionedEntities");
      for (std::size_t i = 0; i < n[dim]; ++i) {
        const int tag = int_value("an entity tag");
        const int parent_dim = int_value("a parent entity's dimension");
        int_value("a parent entity tag");
        const std::size_t n_in = tag_or_count("a number of partitions");
        need(n_in, binary_ ? sizeof(int) : 2, "an entity's partitions");
        std::vector<int> parts;
        for (std::size_t k = 0; k < n_in; ++k) parts.push_back(int_value("a partition tag"));
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) real_value("an entity's coordinates");
        const std::size_t n_phys = tag_or_count("a number of physical tags");
        need(n_phys, binary_ ? sizeof(int) : 2, "an entity's physical tags");
        std::vector<int> phys;
        for (std::size_t k = 0; k < n_phys; ++k) phys.push_back(int_value("a physical tag"));
        if (dim > 0) {
          const std::size_t n_bound = tag_or_count("a number of bounding entities");
          need(n_bound, binary_ ? sizeof(int) : 2, "an entity's bounding entities");
          for (std::size_t k = 0; k < n_bound; ++k) int_value("a bounding entity");
        }
        if (parent_dim != dim) {  // a boundary between partitions
          between_parts_.insert({dim, tag});
          continue;
        }
        add_entity(dim, tag, phys);
        if (dim == 3) volume_parts.insert(parts.begin(), parts.end());
      }
    }
    d_.partitions = static_cast<int>(std::min<std::size_t>(n_parts, INT_MAX));
    const bool split = !volume_parts.empty() && volume_parts.size() < n_parts;
    if (split && piece_ && volume_parts.size() == 1) {
      d_.piece = *volume_parts.begin();
    } else if (split) {
      throw error(start, fmt::format("the file holds {} of the {} partitions of a mesh split into "
                                     "files (gmsh -part_split): hencky reads the whole mesh; save "
                                     "it in one file (no -part_split, or "
                                     "Mesh.PartitionSplitMeshFiles = 0)",
                                     volume_parts.size(), n_parts));
    }
  }

  void add_node(std::size_t at, std::size_t tag) {
    if (tag == 0) throw error(at, "node tag 0 (tags start at 1)");
    if (!node_index_.emplace(tag, d_.node_tags.size()).second)
      throw error(at, "node " + std::to_string(tag) + " is defined twice");
    d_.node_tags.push_back(tag);
  }

  void read_nodes2() {
    const std::size_t n = count("the number of nodes");
    to_binary_data();
    need(n, binary_ ? sizeof(int) + 3 * sizeof(double) : 8, "$Nodes");
    d_.node_tags.reserve(n);
    d_.coords.reserve(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t at = (skip_space_if_text(), pos_);
      const long long tag = binary_ ? bin<int>("a node tag") : number<long long>("a node tag");
      if (tag <= 0) throw error(at, "node tag " + std::to_string(tag) + " (tags are positive)");
      add_node(at, static_cast<std::size_t>(tag));
      for (int k = 0; k < 3; ++k) d_.coords.push_back(real_value("a node coordinate"));
    }
  }

  void read_nodes4() {
    to_binary_data();
    const std::size_t n_blocks = tag_or_count("the number of node blocks");
    const std::size_t n_nodes = tag_or_count("the number of nodes");
    if (version_ == 4.1)
      tag_or_count("the smallest node tag"), tag_or_count("the largest node tag");
    need(n_nodes, binary_ ? sizeof(std::size_t) + 3 * sizeof(double) : 8, "$Nodes");
    need(n_blocks, binary_ ? 3 * sizeof(int) + sizeof(std::size_t) : 8, "$Nodes");
    d_.node_tags.reserve(n_nodes);
    d_.coords.reserve(3 * n_nodes);
    for (std::size_t b = 0; b < n_blocks; ++b) {
      const std::size_t block_at = (skip_space_if_text(), pos_);
      int dim = 0;
      if (version_ == 4.1)
        dim = int_value("a node block's entity dimension"), int_value("a node block's entity tag");
      else
        int_value("a node block's entity tag"), dim = int_value("a node block's entity dimension");
      const int parametric = int_value("a node block's parametric flag");
      const std::size_t n = tag_or_count("a node block's size");
      if (dim < 0 || dim > 3)
        throw error(block_at, "node block of an entity of dimension " + std::to_string(dim));
      if (parametric != 0 && parametric != 1)
        throw error(block_at, "parametric flag must be 0 or 1");
      if (n > n_nodes - d_.node_tags.size())
        throw error(block_at, "the node blocks hold more nodes than the $Nodes header announces (" +
                                  std::to_string(n_nodes) + ")");
      const int values = 3 + (parametric ? dim : 0);
      const std::size_t first = d_.node_tags.size();
      if (version_ == 4.0) {
        for (std::size_t i = 0; i < n; ++i) {
          const std::size_t at = (skip_space_if_text(), pos_);
          add_node(at, count("a node tag"));
          node_values(values);
        }
        continue;
      }
      if (binary_) need(n, sizeof(std::size_t) + values * sizeof(double), "a node block");
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t at = (skip_space_if_text(), pos_);
        add_node(at, tag_or_count("a node tag"));
      }
      for (std::size_t i = first; i < first + n; ++i) node_values(values);
    }
    if (d_.node_tags.size() != n_nodes)
      throw error(pos_, "the $Nodes header announces " + std::to_string(n_nodes) +
                            " nodes, its blocks hold " + std::to_string(d_.node_tags.size()));
  }
  void node_values(int values) {
    for (int k = 0; k < values; ++k) {
      const double v = real_value("a node coordinate");
      if (k < 3) d_.coords.push_back(v);
    }
  }
  void skip_space_if_text() {
    if (!binary_) skip_space();
  }

  /// A tag in text, which must be positive: an element's tag (element == 0) or one of its
  /// node tags.
  std::size_t positive_tag(std::size_t at, const char* what, std::size_t element) {
    const long long v = number<long long>(what);
    if (v > 0) return static_cast<std::size_t>(v);
    if (element == 0) throw error(at, "element tag " + std::to_string(v) + " (tags are positive)");
    throw error(at, "element " + std::to_string(element) + " has node " + std::to_string(v) +
                        ", which $Nodes does not define");
  }

  /// Checks an element's node tags against $Nodes and stores them.
  void element_nodes(std::size_t at, std::size_t tag, const std::size_t* nodes, int nn,
                     MshData::Block& b) {
    for (int a = 0; a < nn; ++a)
      if (!node_index_.count(nodes[a]))
        throw error(at, "element " + std::to_string(tag) + " has node " + std::to_string(nodes[a]) +
                            ", which $Nodes does not define");
    b.tags.push_back(tag);
    b.nodes.insert(b.nodes.end(), nodes, nodes + nn);
  }

  const GmshElementType& known_type(std::size_t at, int type) {
    const GmshElementType* t = gmsh_element_type(type);
    if (!t) throw error(at, "unknown element type " + std::to_string(type));
    return *t;
  }

  void read_elements4() {
    to_binary_data();
    const std::size_t n_blocks = tag_or_count("the number of element blocks");
    const std::size_t n_elements = tag_or_count("the number of elements");
    if (version_ == 4.1)
      tag_or_count("the smallest element tag"), tag_or_count("the largest element tag");
    need(n_blocks, binary_ ? 3 * sizeof(int) + sizeof(std::size_t) : 8, "$Elements");
    std::size_t seen = 0;
    std::vector<std::size_t> values;
    for (std::size_t b = 0; b < n_blocks; ++b) {
      const std::size_t block_at = (skip_space_if_text(), pos_);
      int dim = 0, entity = 0;
      if (version_ == 4.1)
        dim = int_value("an element block's entity dimension"),
        entity = int_value("an element block's entity tag");
      else
        entity = int_value("an element block's entity tag"),
        dim = int_value("an element block's entity dimension");
      const int type = int_value("an element type");
      const std::size_t n = tag_or_count("an element block's size");
      const GmshElementType& t = known_type(block_at, type);
      if (t.dim != dim)
        throw error(block_at, std::string(t.name) + " elements (dimension " +
                                  std::to_string(t.dim) +
                                  ") in a block of an entity of dimension " + std::to_string(dim));
      if (n > n_elements - seen)
        throw error(block_at,
                    "the element blocks hold more elements than the $Elements header announces (" +
                        std::to_string(n_elements) + ")");
      seen += n;
      const std::size_t per = 1 + static_cast<std::size_t>(t.nodes);
      need(n, binary_ ? per * sizeof(std::size_t) : 2 * per, "an element block");
      const bool skip = between_parts_.count({dim, entity}) > 0;  // not the model's elements
      if (!skip) add_entity(dim, entity, {});
      MshData::Block block{dim, entity, type, {}, {}};
      block.tags.reserve(n);
      block.nodes.reserve(n * t.nodes);
      values.resize(per);
      for (std::size_t e = 0; e < n; ++e) {
        const std::size_t at = (skip_space_if_text(), pos_);
        if (binary_) {
          std::memcpy(values.data(), s_.data() + pos_, per * sizeof(std::size_t));
          pos_ += per * sizeof(std::size_t);
        } else {
          values[0] = positive_tag(at, "an element tag", 0);
          for (std::size_t k = 1; k < per; ++k)
            values[k] = positive_tag(at, "a node tag", values[0]);
        }
        element_nodes(at, values[0], values.data() + 1, t.nodes, block);
      }
      if (!skip) d_.blocks.push_back(std::move(block));
    }
    if (seen != n_elements)
      throw error(pos_, "the $Elements header announces " + std::to_string(n_elements) +
                            " elements, its blocks hold " + std::to_string(seen));
  }

  /// Format 2: each element names its type, physical group and elementary entity. Elements of
  /// one entity and type are gathered into one block, in file order. An element repeated with
  /// the same tag (Gmsh writes one line per physical group of the entity) adds its physical
  /// group only.
  void read_elements2() {
    const std::size_t n = count("the number of elements");
    to_binary_data();
    need(n, binary_ ? 4 * sizeof(int) : 8, "$Elements");
    binary_ ? elements2_binary(n) : elements2_text(n);
  }

  /// One element of format 2: its entity gets the physical group; an element met before adds
  /// only that.
  void add_element2(std::size_t at, long long tag, int type, int physical, int elementary,
                    const std::vector<std::size_t>& nodes) {
    const GmshElementType& t = known_type(at, type);
    if (tag <= 0) throw error(at, "element tag " + std::to_string(tag) + " (tags are positive)");
    add_entity(t.dim, elementary, std::span<const int>(&physical, physical != 0 ? 1 : 0));
    if (!seen_tags2_.insert(static_cast<std::size_t>(tag)).second) return;
    auto [it, fresh] = block_of2_.emplace(std::tuple(t.dim, elementary, type), d_.blocks.size());
    if (fresh) d_.blocks.push_back({t.dim, elementary, type, {}, {}});
    element_nodes(at, static_cast<std::size_t>(tag), nodes.data(), t.nodes, d_.blocks[it->second]);
  }

  void elements2_text(std::size_t n) {
    std::vector<std::size_t> nodes;
    for (std::size_t done = 0; done < n; ++done) {
      const std::size_t at = (skip_space(), pos_);
      const long long tag = number<long long>("an element tag");
      const int type = integer("an element type");
      const GmshElementType& t = known_type(at, type);
      const int n_tags = integer("a number of element tags");
      if (n_tags < 0 || n_tags > 64)
        throw error(at,
                    "element " + std::to_string(tag) + " has " + std::to_string(n_tags) + " tags");
      int physical = 0, elementary = 0;
      for (int k = 0; k < n_tags; ++k) {
        const int v = integer("an element tag");
        if (k == 0) physical = v;
        if (k == 1) elementary = v;
      }
      nodes.resize(t.nodes);
      for (auto& v : nodes) v = positive_tag(at, "a node tag", static_cast<std::size_t>(tag));
      add_element2(at, tag, type, physical, elementary, nodes);
    }
  }

  void elements2_binary(std::size_t n) {
    std::vector<std::size_t> nodes;
    for (std::size_t done = 0; done < n;) {
      const std::size_t at = pos_;
      const int type = bin<int>("an element type");
      const int count_ = bin<int>("an element count");
      const int n_tags = bin<int>("a number of element tags");
      const GmshElementType& t = known_type(at, type);
      if (count_ <= 0 || static_cast<std::size_t>(count_) > n - done)
        throw error(at, "an element block of " + std::to_string(count_) + " elements where " +
                            std::to_string(n - done) + " remain of the $Elements header's count");
      if (n_tags < 0 || n_tags > 64)
        throw error(at, "elements with " + std::to_string(n_tags) + " tags");
      need(count_, (1 + n_tags + t.nodes) * sizeof(int), "an element block");
      for (int e = 0; e < count_; ++e, ++done) {
        const std::size_t eat = pos_;
        const int tag = bin<int>("an element tag");
        int physical = 0, elementary = 0;
        for (int k = 0; k < n_tags; ++k) {
          const int v = bin<int>("an element tag");
          if (k == 0) physical = v;
          if (k == 1) elementary = v;
        }
        nodes.resize(t.nodes);
        for (auto& v : nodes) {
          const int node = bin<int>("a node tag");
          if (node <= 0)
            throw error(eat, "element " + std::to_string(tag) + " has node " +
                                 std::to_string(node) + ", which $Nodes does not define");
          v = static_cast<std::size_t>(node);
        }
        add_element2(eat, tag, type, physical, elementary, nodes);
      }
    }
  }

  std::string_view s_;
  std::string name_;
  bool piece_ = false;  ///< read one file of a split mesh as its part
  std::size_t pos_ = 0;
  double version_ = 0;
  bool binary_ = false;
  std::size_t binary_start_ = 0;
  MshData d_;
  std::map<std::pair<int, int>, std::size_t> entity_index_;
  std::unordered_map<std::size_t, std::size_t> node_index_;
  std::set<std::pair<int, int>> between_parts_;  ///< (dim, tag) of partition boundaries
  // Format 2: (dim, entity, type) -> block, and the element tags met.
  std::map<std::tuple<int, int, int>, std::size_t> block_of2_;
  std::unordered_set<std::size_t> seen_tags2_;
};

}  // namespace

MshData parse_msh(std::string_view text, const std::string& name, bool piece) {
  return Parser(text, name, piece).parse();
}

MshData read_msh(const std::filesystem::path& file, bool piece) {
  const SourceLocation where{file.string(), 0, 0, ""};
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (!in || ec) throw InputError(where, "cannot open the mesh file");
  std::string text(size, '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size)))
    throw InputError(where, "cannot read the mesh file");
  return parse_msh(text, file.string(), piece);
}

}  // namespace hencky
