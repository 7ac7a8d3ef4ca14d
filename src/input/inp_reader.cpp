#include "input/inp_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "input/inp_parser.hpp"

// The deck's nodes, elements, sets and surfaces (inp_keywords.cpp) turned into the Mesh and its
// regions. Element faces: CalculiX manual section 6.2 (the face numbers of each element type).

namespace hencky {

namespace fs = std::filesystem;

namespace inp {

Mesh InpReader::build() {
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

void InpReader::add_nodes(const Set& s, Region& r) {
  long gaps = 0;  // a GENERATE range over numbers that are not all nodes: ccx's way
  for (long n : set_nodes(s, &gaps)) {
    auto it = body_node_.find(n);
    if (it != body_node_.end()) r.nodes.push_back(it->second);
  }
  if (gaps > 0) generate_gaps_[s.name] += gaps;
}

void InpReader::node_regions(Mesh& mesh) {
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

const Element* InpReader::element(long label, int line, const std::string& set) const {
  auto it = element_of_label_.find(label);
  if (it != element_of_label_.end()) return &elements_[it->second];
  if (skipped_elements_.count(label)) return nullptr;
  throw fail(line, fmt::format("'{}' names element {}, which no *ELEMENT defines", set, label));
}

void InpReader::face_regions(Mesh& mesh) {
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
        throw fail(line, fmt::format("surface '{}': element {} ({}) has no face S{}", s.name, label,
                                     e->type, side));
      if (!seen.emplace(label, side).second) return;
      int local[8];
      for (std::size_t a = 0; a < face.size(); ++a)
        local[a] = body_node_.at(conn_[e->offset + face[a]]);
      const CellType ft = face_cell_type(face.size());
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

std::array<long, 4> InpReader::face_key(const Element& e, std::span<const int> face) const {
  std::array<long, 4> key{0, 0, 0, 0};  // a triangle's 4th stays 0 (labels are positive)
  const std::size_t corners = face.size() == 3 || face.size() == 6 ? 3 : 4;
  for (std::size_t a = 0; a < corners; ++a) key[a] = conn_[e.offset + face[a]];
  std::sort(key.begin(), key.end());
  return key;
}

const std::map<std::array<long, 4>, int>& InpReader::face_count() {
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

void InpReader::volume_regions(Mesh& mesh) {
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

void InpReader::warn() const {
  if (!warnings_) return;
  const std::string file = fs::path(deck_.names[0]).filename().string();
  // Each file of the deck (the main one and its *INCLUDEs) with the keywords it holds.
  for (std::size_t f = 0; f < deck_.names.size(); ++f) {
    std::string list;
    for (const auto& [in, k] : skipped_)
      if (in == static_cast<int>(f)) list += (list.empty() ? "" : ", ") + k;
    if (!list.empty())
      warnings_->push_back(fs::path(deck_.names[f]).filename().string() +
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
  if (extra_numbers_.first > 0) {
    const Line& l = deck_.lines[extra_numbers_.second];
    warnings_->push_back(fmt::format(
        "{}: {} element line{} with more numbers than the type has nodes (the first on line {} "
        "of {}): the first were taken as the nodes, as ccx takes them",
        file, extra_numbers_.first, extra_numbers_.first > 1 ? "s" : "", l.number,
        fs::path(deck_.names[l.file]).filename().string()));
  }
  if (!generate_gaps_.empty()) {
    std::string list;
    for (const auto& [name, n] : generate_gaps_)
      list += fmt::format("{}NSET '{}' ({} number{})", list.empty() ? "" : ", ", name, n,
                          n > 1 ? "s" : "");
    warnings_->push_back(file +
                         ": GENERATE ranges over numbers that no *NODE defines, left out "
                         "as ccx leaves them out: " +
                         list);
  }
  if (!convention_types_.empty()) {
    // The unsuffixed types whose integration or interpolation is not ccx's (docs/case-reference.md,
    // "Abaqus and CalculiX decks").
    std::string list;
    for (const auto& [type, n] : convention_types_) {
      const bool bbar = type == "C3D8" || type == "C3D6";
      list += fmt::format("{}{} {} ({})", list.empty() ? "" : "; ", n, type,
                          bbar ? "hencky's B-bar strain, the volumetric strain the element's mean; "
                                 "ccx integrates them fully without it, stiffer in bending"
                               : "temperatures interpolated with the element's quadratic "
                                 "functions; ccx projects them onto trilinear ones, as "
                                 "temperature.interpolation: linear does");
    }
    warnings_->push_back(file + ": elements that hencky and ccx treat differently: " + list);
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

}  // namespace inp

Mesh parse_inp(std::string_view text, const fs::path& file, const MeshReadOptions& options,
               std::vector<std::string>* warnings) {
  inp::Deck deck;
  deck.names.push_back(file.string());
  deck.add(text, 0, 0);
  return inp::InpReader(deck, options, warnings).read();
}

Mesh read_inp(const fs::path& file, const MeshReadOptions& options,
              std::vector<std::string>* warnings) {
  return parse_inp(inp::read_text(file, "mesh file"), file, options, warnings);
}

bool is_inp_file(const fs::path& file) {
  return inp::upper(file.extension().string()) == ".INP";
}

}  // namespace hencky
