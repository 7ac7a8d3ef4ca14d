#include "input/label_regions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <unordered_map>

#include "input/inp_elements.hpp"

namespace hencky {

void add_label_regions(Mesh& mesh, const std::vector<LabelRegionSpec>& regions, bool ignore_case) {
  if (regions.empty()) return;
  std::unordered_map<long, int> node_of, cell_of;
  for (int n = 0; n < mesh.n_nodes(); ++n) node_of.emplace(mesh.node_tag[n], n);
  for (int c = 0; c < mesh.cells.size(); ++c) cell_of.emplace(mesh.cells.tag[c], c);
  for (const LabelRegionSpec& g : regions) {
    if (mesh.find_region(g.name, 0, 3, ignore_case))
      throw InputError(g.where, fmt::format("the mesh already has a region '{}': name this one "
                                            "otherwise",
                                            g.name));
    Region r{g.name, 0, {}, {}};
    std::size_t k = 0;  // the label's place in item_where
    for (long label : g.nodes) {
      const auto it = node_of.find(label);
      if (it == node_of.end())
        throw InputError(g.item_where[k],
                         fmt::format("node {} is not a node of the mesh's body", label));
      r.nodes.push_back(it->second);
      ++k;
    }
    auto cell = [&](long label) {
      const auto it = cell_of.find(label);
      if (it == cell_of.end())
        throw InputError(g.item_where[k],
                         fmt::format("element {} is not a volume element of the mesh", label));
      return it->second;
    };
    if (!g.elements.empty()) {
      r.dim = 3;
      for (long label : g.elements) {
        r.cells.push_back(cell(label));
        ++k;
      }
    }
    if (!g.faces.empty()) {
      r.dim = 2;
      for (const auto& [label, side] : g.faces) {
        const int c = cell(label);
        const CellType t = mesh.cells.type[c];
        const std::span<const int> face = inp::abaqus_face(t, side);  // the deck's positions
        if (face.empty())
          throw InputError(g.item_where[k], fmt::format("element {} ({}) has no face {}", label,
                                                        cell_name(t), side));
        // The cell's nodes are in Gmsh's order: Gmsh's node j is the deck's perm[j].
        const auto perm = inp::gmsh_from_abaqus(t);
        const auto nodes = mesh.cells.nodes(c);
        int local[8];
        for (std::size_t a = 0; a < face.size(); ++a) {
          const auto j = std::find(perm.begin(), perm.end(), face[a]) - perm.begin();
          local[a] = nodes[static_cast<std::size_t>(j)];
        }
        const CellType ft = inp::face_cell_type(face.size());
        mesh.faces.add(ft, std::span<const int>(local, face.size()), label);
        r.cells.push_back(mesh.faces.size() - 1);
        ++k;
      }
    }
    for (int c : r.cells)
      for (int n : r.dim == 3 ? mesh.cells.nodes(c) : mesh.faces.nodes(c)) r.nodes.push_back(n);
    std::sort(r.nodes.begin(), r.nodes.end());
    r.nodes.erase(std::unique(r.nodes.begin(), r.nodes.end()), r.nodes.end());
    std::sort(r.cells.begin(), r.cells.end());
    r.cells.erase(std::unique(r.cells.begin(), r.cells.end()), r.cells.end());
    mesh.regions.push_back(std::move(r));
  }
}

}  // namespace hencky
