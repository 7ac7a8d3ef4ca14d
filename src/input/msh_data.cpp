#include "input/msh_data.hpp"

#include <algorithm>
#include <unordered_map>

#include "core/error.hpp"

namespace hencky {
namespace {

// The MSH element types of Gmsh 4.8 with a fixed node count (its getElementProperties):
// number, nodes, dimension, name. Sorted by number.
constexpr GmshElementType element_types[] = {
    {1, 2, 1, "Line 2"},
    {2, 3, 2, "Triangle 3"},
    {3, 4, 2, "Quadrilateral 4"},
    {4, 4, 3, "Tetrahedron 4"},
    {5, 8, 3, "Hexahedron 8"},
    {6, 6, 3, "Prism 6"},
    {7, 5, 3, "Pyramid 5"},
    {8, 3, 1, "Line 3"},
    {9, 6, 2, "Triangle 6"},
    {10, 9, 2, "Quadrilateral 9"},
    {11, 10, 3, "Tetrahedron 10"},
    {12, 27, 3, "Hexahedron 27"},
    {13, 18, 3, "Prism 18"},
    {14, 14, 3, "Pyramid 14"},
    {15, 1, 0, "Point"},
    {16, 8, 2, "Quadrilateral 8"},
    {17, 20, 3, "Hexahedron 20"},
    {18, 15, 3, "Prism 15"},
    {19, 13, 3, "Pyramid 13"},
    {20, 9, 2, "Triangle 9"},
    {21, 10, 2, "Triangle 10"},
    {22, 12, 2, "Triangle 12"},
    {23, 15, 2, "Triangle 15"},
    {24, 15, 2, "Triangle 15I"},
    {25, 21, 2, "Triangle 21"},
    {26, 4, 1, "Line 4"},
    {27, 5, 1, "Line 5"},
    {28, 6, 1, "Line 6"},
    {29, 20, 3, "Tetrahedron 20"},
    {30, 35, 3, "Tetrahedron 35"},
    {31, 56, 3, "Tetrahedron 56"},
    {32, 22, 3, "Tetrahedron 22"},
    {33, 28, 3, "Tetrahedron 28"},
    {36, 16, 2, "Quadrilateral 16"},
    {37, 25, 2, "Quadrilateral 25"},
    {38, 36, 2, "Quadrilateral 36"},
    {39, 12, 2, "Quadrilateral 12"},
    {40, 16, 2, "Quadrilateral 16I"},
    {41, 20, 2, "Quadrilateral 20"},
    {42, 28, 2, "Triangle 28"},
    {43, 36, 2, "Triangle 36"},
    {44, 45, 2, "Triangle 45"},
    {45, 55, 2, "Triangle 55"},
    {46, 66, 2, "Triangle 66"},
    {47, 49, 2, "Quadrilateral 49"},
    {48, 64, 2, "Quadrilateral 64"},
    {49, 81, 2, "Quadrilateral 81"},
    {50, 100, 2, "Quadrilateral 100"},
    {51, 121, 2, "Quadrilateral 121"},
    {52, 18, 2, "Triangle 18"},
    {53, 21, 2, "Triangle 21I"},
    {54, 24, 2, "Triangle 24"},
    {55, 27, 2, "Triangle 27"},
    {56, 30, 2, "Triangle 30"},
    {57, 24, 2, "Quadrilateral 24"},
    {58, 28, 2, "Quadrilateral 28"},
    {59, 32, 2, "Quadrilateral 32"},
    {60, 36, 2, "Quadrilateral 36I"},
    {61, 40, 2, "Quadrilateral 40"},
    {62, 7, 1, "Line 7"},
    {63, 8, 1, "Line 8"},
    {64, 9, 1, "Line 9"},
    {65, 10, 1, "Line 10"},
    {66, 11, 1, "Line 11"},
    {71, 84, 3, "Tetrahedron 84"},
    {72, 120, 3, "Tetrahedron 120"},
    {73, 165, 3, "Tetrahedron 165"},
    {74, 220, 3, "Tetrahedron 220"},
    {75, 286, 3, "Tetrahedron 286"},
    {79, 34, 3, "Tetrahedron 34"},
    {80, 40, 3, "Tetrahedron 40"},
    {81, 46, 3, "Tetrahedron 46"},
    {82, 52, 3, "Tetrahedron 52"},
    {83, 58, 3, "Tetrahedron 58"},
    {84, 1, 1, "Line 1"},
    {85, 1, 2, "Triangle 1"},
    {86, 1, 2, "Quadrilateral 1"},
    {87, 1, 3, "Tetrahedron 1"},
    {88, 1, 3, "Hexahedron 1"},
    {89, 1, 3, "Prism 1"},
    {92, 64, 3, "Hexahedron 64"},
    {93, 125, 3, "Hexahedron 125"},
    {94, 216, 3, "Hexahedron 216"},
    {95, 343, 3, "Hexahedron 343"},
    {96, 512, 3, "Hexahedron 512"},
    {97, 729, 3, "Hexahedron 729"},
    {98, 1000, 3, "Hexahedron 1000"},
    {99, 32, 3, "Hexahedron 32"},
    {100, 44, 3, "Hexahedron 44"},
    {101, 56, 3, "Hexahedron 56"},
    {102, 68, 3, "Hexahedron 68"},
    {103, 80, 3, "Hexahedron 80"},
    {104, 92, 3, "Hexahedron 92"},
    {105, 104, 3, "Hexahedron 104"},
    {118, 30, 3, "Pyramid 30"},
    {119, 55, 3, "Pyramid 55"},
    {120, 91, 3, "Pyramid 91"},
    {121, 140, 3, "Pyramid 140"},
    {122, 204, 3, "Pyramid 204"},
    {123, 285, 3, "Pyramid 285"},
    {124, 385, 3, "Pyramid 385"},
    {125, 21, 3, "Pyramid 21"},
    {126, 29, 3, "Pyramid 29"},
    {127, 37, 3, "Pyramid 37"},
    {128, 45, 3, "Pyramid 45"},
    {129, 53, 3, "Pyramid 53"},
    {130, 61, 3, "Pyramid 61"},
    {131, 69, 3, "Pyramid 69"},
    {132, 1, 3, "Pyramid 1"},
    {137, 16, 3, "Tetrahedron 16"},
};

/// hencky's cell of a Gmsh element type of dimension `dim` (3: the body's cells, 2: the faces
/// of surface regions); false when hencky has none (fem/cell_type.hpp names the Gmsh types).
bool cell_type_of(int gmsh_type, int dim, CellType& t) {
  constexpr std::pair<int, CellType> cells[] = {
      {4, CellType::tet4},   {11, CellType::tet10}, {5, CellType::hex8},
      {17, CellType::hex20}, {6, CellType::wedge6}, {2, CellType::tri3},
      {9, CellType::tri6},   {3, CellType::quad4},  {16, CellType::quad8}};
  for (const auto& [type, cell] : cells)
    if (type == gmsh_type && cell_dim(cell) == dim) {
      t = cell;
      return true;
    }
  return false;
}

/// The blocks of each entity, their types in increasing order (file order within a type), as
/// the Gmsh API's getElements(dim, tag) returns an entity's elements.
std::map<std::pair<int, int>, std::vector<const MshData::Block*>> blocks_by_entity(
    const MshData& data) {
  std::map<std::pair<int, int>, std::vector<const MshData::Block*>> by;
  for (const auto& b : data.blocks) by[{b.dim, b.entity}].push_back(&b);
  for (auto& [key, list] : by)
    std::stable_sort(list.begin(), list.end(),
                     [](const auto* a, const auto* b) { return a->type < b->type; });
  return by;
}

}  // namespace

const GmshElementType* gmsh_element_type(int type) {
  const auto* end = std::end(element_types);
  const auto* it = std::lower_bound(std::begin(element_types), end, type,
                                    [](const GmshElementType& t, int n) { return t.type < n; });
  return it != end && it->type == type ? it : nullptr;
}

std::string gmsh_type_name(int type) {
  const GmshElementType* t = gmsh_element_type(type);
  if (!t) return "Gmsh element type " + std::to_string(type);
  return std::string(t->name) + " (Gmsh type " + std::to_string(type) + ")";
}

namespace {

/// to_mesh in stages, each with the state the next one needs.
class MeshBuilder {
 public:
  MeshBuilder(const MshData& data, const MeshReadOptions& options, const std::string& file)
      : data_(data), options_(options), where_{file, 0, 0, ""}, blocks_of_(blocks_by_entity(data)) {
    // Physical groups, in order of (dimension, tag), each with its entities in order of tag.
    for (const auto& e : data.entities) entities_.push_back(&e);
    std::sort(entities_.begin(), entities_.end(), [](const auto* a, const auto* b) {
      return std::pair(a->dim, a->tag) < std::pair(b->dim, b->tag);
    });
    for (const auto* e : entities_)
      for (int p : e->physicals) {
        auto& ents = groups_[{e->dim, p}];
        if (ents.empty() || ents.back() != e->tag) ents.push_back(e->tag);
      }
    file_node_.reserve(data.node_tags.size());
    for (std::size_t i = 0; i < data.node_tags.size(); ++i)
      file_node_.emplace(data.node_tags[i], i);
  }

  Mesh build() {
    body_cells();
    renumber_nodes();
    lower_dimensional_regions();
    for (auto& r : mesh_.regions) {
      if (r.dim == 3)
        for (int c : r.cells)
          for (int n : mesh_.cells.nodes(c)) r.nodes.push_back(n);
      std::sort(r.nodes.begin(), r.nodes.end());
      r.nodes.erase(std::unique(r.nodes.begin(), r.nodes.end()), r.nodes.end());
    }
    return std::move(mesh_);
  }

 private:
  InputError fail(const std::string& msg) const { return InputError(where_, msg); }
  std::string group_name(int dim, int tag) const {
    auto it = data_.physical_names.find({dim, tag});
    return it == data_.physical_names.end() || it->second.empty() ? std::to_string(tag)
                                                                  : it->second;
  }
  template <class F>
  void for_each_block(int dim, int entity, F&& f) const {
    auto it = blocks_of_.find({dim, entity});
    if (it != blocks_of_.end())
      for (const auto* b : it->second) f(*b);
  }

  /// The body: the cells of the physical volumes, or of every 3D entity when there are none.
  void body_cells() {
    std::vector<std::pair<int, std::vector<int>>> volume_groups;  // (region index, entities)
    for (const auto& [key, ents] : groups_) {
      if (key.first != 3) continue;
      Region r;
      r.name = group_name(key.first, key.second);
      r.dim = 3;
      mesh_.regions.push_back(r);
      volume_groups.emplace_back(static_cast<int>(mesh_.regions.size()) - 1, ents);
    }
    if (volume_groups.empty()) {
      std::vector<int> all;
      for (const auto* e : entities_)
        if (e->dim == 3) all.push_back(e->tag);
      volume_groups.emplace_back(-1, all);
    }
    // Not a structured binding: clang before 16 cannot capture one in the lambda.
    for (const auto& group : volume_groups) {
      const int region = group.first;
      for (int ent : group.second)
        for_each_block(3, ent, [&](const MshData::Block& b) { add_cells(b, region); });
    }
    if (mesh_.cells.size() == 0) {
      const bool any =
          std::any_of(data_.blocks.begin(), data_.blocks.end(),
                      [](const MshData::Block& b) { return b.dim == 3 && !b.tags.empty(); });
      throw fail(any ? "the mesh has no 3D elements in its physical volumes"
                     : "the mesh has no 3D elements (hencky needs a volume mesh)");
    }
  }

  void add_cells(const MshData::Block& b, int region) {
    CellType ct;
    if (!cell_type_of(b.type, 3, ct))
      throw fail("unsupported volume element " + gmsh_type_name(b.type) +
                 "; hencky supports 4/10-node tetrahedra, 8/20-node hexahedra and 6-node "
                 "wedges " +
                 (options_.piece ? "(the files of a split mesh are read as they are: mesh with "
                                   "gmsh -order 2 -string \"Mesh.SecondOrderIncomplete=1;\" "
                                   "for serendipity quadratic elements before splitting)"
                                 : "(use mesh.order: 2 for serendipity quadratic elements)"));
    const int nn = cell_n_nodes(ct);
    for (std::size_t e = 0; e < b.tags.size(); ++e) {
      auto [it, fresh] = cell_of_tag_.emplace(b.tags[e], mesh_.cells.size());
      if (!fresh) continue;  // element in two physical volumes: first one wins
      int local[max_cell_nodes];
      for (int a = 0; a < nn; ++a) {
        const std::size_t gt = b.nodes[e * nn + a];
        if (!file_node_.count(gt))
          throw fail("element " + std::to_string(b.tags[e]) + " has node " + std::to_string(gt) +
                     ", which is not among the file's nodes");
        auto [nit, nfresh] = node_index_.emplace(gt, static_cast<int>(body_node_tags_.size()));
        if (nfresh) body_node_tags_.push_back(gt);
        local[a] = nit->second;
      }
      mesh_.cells.add(ct, std::span<const int>(local, nn), static_cast<long>(b.tags[e]));
      mesh_.cell_region.push_back(region);
      if (region >= 0) mesh_.regions[region].cells.push_back(mesh_.cells.size() - 1);
    }
  }

  /// Renumbers the body's nodes by Gmsh tag, so that the numbering does not depend on the
  /// order the cells were met in.
  void renumber_nodes() {
    std::vector<int> order(body_node_tags_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return body_node_tags_[a] < body_node_tags_[b]; });
    std::vector<int> new_of_old(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) new_of_old[order[i]] = static_cast<int>(i);
    for (auto& n : mesh_.cells.conn) n = new_of_old[n];
    mesh_.x.resize(order.size());
    mesh_.node_tag.resize(order.size());
    const auto& xyz = data_.coords;
    for (std::size_t i = 0; i < order.size(); ++i) {
      const std::size_t gt = body_node_tags_[order[i]];
      const std::size_t ci = file_node_.at(gt);
      mesh_.x[i] = Vec3(xyz[3 * ci], xyz[3 * ci + 1], xyz[3 * ci + 2]) * options_.scale;
      mesh_.node_tag[i] = static_cast<long>(gt);
      node_index_[gt] = static_cast<int>(i);
    }
  }

  /// Lower-dimensional regions: faces for surfaces, node sets for all.
  void lower_dimensional_regions() {
    for (const auto& [key, ents] : groups_) {
      if (key.first == 3) continue;
      Region r;
      r.name = group_name(key.first, key.second);
      r.dim = key.first;
      for (int ent : ents)
        for_each_block(r.dim, ent, [&](const MshData::Block& b) { add_region_elements(b, r); });
      mesh_.regions.push_back(std::move(r));
    }
  }

  void add_region_elements(const MshData::Block& b, Region& r) {
    const GmshElementType* t = gmsh_element_type(b.type);
    CellType ct{};
    const bool is_face = r.dim == 2 && cell_type_of(b.type, 2, ct);
    if (r.dim == 2 && !is_face)
      throw fail("region '" + r.name + "': unsupported surface element " + gmsh_type_name(b.type));
    const int nn = t ? t->nodes : 0;
    for (std::size_t e = 0; e < b.tags.size(); ++e) {
      int local[max_cell_nodes];
      for (int a = 0; a < nn; ++a) {
        const std::size_t gt = b.nodes[e * nn + a];
        auto it = node_index_.find(gt);
        if (it == node_index_.end())
          throw fail("region '" + r.name + "': element " + std::to_string(b.tags[e]) +
                     " has node " + std::to_string(gt) +
                     " which is not a node of the volume mesh (the surface is not on the body)");
        if (a < max_cell_nodes) local[a] = it->second;
        r.nodes.push_back(it->second);
      }
      if (is_face) {
        mesh_.faces.add(ct, std::span<const int>(local, nn), static_cast<long>(b.tags[e]));
        r.cells.push_back(mesh_.faces.size() - 1);
      }
    }
  }

  const MshData& data_;
  const MeshReadOptions& options_;
  SourceLocation where_;
  std::map<std::pair<int, int>, std::vector<const MshData::Block*>> blocks_of_;
  std::vector<const MshData::Entity*> entities_;
  std::map<std::pair<int, int>, std::vector<int>> groups_;  // (dim, tag) -> entity tags
  std::unordered_map<std::size_t, std::size_t> file_node_;  // Gmsh tag -> position in coords
  std::unordered_map<std::size_t, int> node_index_;         // Gmsh tag -> hencky node
  std::vector<std::size_t> body_node_tags_;
  std::unordered_map<std::size_t, int> cell_of_tag_;  // Gmsh element tag -> cell
  Mesh mesh_;
};

}  // namespace

Mesh to_mesh(const MshData& data, const MeshReadOptions& options, const std::string& file) {
  return MeshBuilder(data, options, file).build();
}

}  // namespace hencky
