#pragma once
// Comparing mesh parts (tests of parallel/mesh_part.hpp, on one process and on several ranks).
#include "parallel/mesh_part.hpp"

namespace hencky {

inline bool same_cells(const CellSet& a, const CellSet& b) {
  return a.type == b.type && a.offset == b.offset && a.conn == b.conn && a.tag == b.tag;
}

/// Every member of the two parts is equal.
inline bool same_part(const MeshPart& a, const MeshPart& b) {
  if (a.mesh.regions.size() != b.mesh.regions.size()) return false;
  for (std::size_t r = 0; r < a.mesh.regions.size(); ++r) {
    const Region &x = a.mesh.regions[r], &y = b.mesh.regions[r];
    if (x.name != y.name || x.dim != y.dim || x.cells != y.cells || x.nodes != y.nodes)
      return false;
  }
  return a.mesh.x == b.mesh.x && a.mesh.node_tag == b.mesh.node_tag &&
         same_cells(a.mesh.cells, b.mesh.cells) && a.mesh.cell_region == b.mesh.cell_region &&
         same_cells(a.mesh.faces, b.mesh.faces) && a.owned_nodes == b.owned_nodes &&
         a.global_node == b.global_node && a.node_owner == b.node_owner &&
         a.owner_index == b.owner_index && a.global_cell == b.global_cell &&
         a.global_point == b.global_point && a.global_face == b.global_face;
}

}  // namespace hencky
