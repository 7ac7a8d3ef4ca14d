#pragma once
// The mesh as the solver sees it: nodes numbered 0..n-1, volume cells (the body) and the
// boundary faces that named surface regions hold, all in Gmsh node ordering.
#include <algorithm>
#include <cctype>
#include <span>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "fem/cell_type.hpp"

namespace hencky {

/// Cells of mixed type, stored flat (struct of arrays).
struct CellSet {
  std::vector<CellType> type;
  std::vector<int> offset{0};  ///< size() + 1 entries; nodes of cell i are conn[offset[i] .. offset[i+1])
  std::vector<int> conn;
  std::vector<long> tag;       ///< Gmsh element tag, for messages

  int size() const { return static_cast<int>(type.size()); }
  std::span<const int> nodes(int i) const {
    return {conn.data() + offset[i], static_cast<std::size_t>(offset[i + 1] - offset[i])};
  }
  void add(CellType t, std::span<const int> nodes, long gmsh_tag) {
    type.push_back(t);
    conn.insert(conn.end(), nodes.begin(), nodes.end());
    offset.push_back(static_cast<int>(conn.size()));
    tag.push_back(gmsh_tag);
  }
};

/// A Gmsh physical group by name. Volume regions list cells, surface regions list faces,
/// every region lists its nodes (sorted, unique).
struct Region {
  std::string name;
  int dim = 3;
  std::vector<int> cells;  ///< indices into Mesh::cells (dim 3) or Mesh::faces (dim 2)
  std::vector<int> nodes;
};

struct Mesh {
  std::vector<Vec3> x;            ///< node coordinates
  std::vector<long> node_tag;     ///< Gmsh node tag of each node, for messages and nodal files
  CellSet cells;                  ///< the body: volume cells
  std::vector<int> cell_region;   ///< volume region (index into regions) of each cell, -1 if none
  CellSet faces;                  ///< boundary faces of the surface regions
  std::vector<Region> regions;

  int n_nodes() const { return static_cast<int>(x.size()); }
  /// The first region named `name` of a dimension in [dim_min, dim_max]; with `ignore_case`,
  /// names match without regard to case (an Abaqus deck's, input/inp_reader.hpp).
  const Region* find_region(const std::string& name, int dim_min = 0, int dim_max = 3,
                            bool ignore_case = false) const {
    for (const auto& r : regions)
      if (r.dim >= dim_min && r.dim <= dim_max && same_region_name(r.name, name, ignore_case))
        return &r;
    return nullptr;
  }

  static bool same_region_name(const std::string& a, const std::string& b, bool ignore_case) {
    if (!ignore_case) return a == b;
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
             return std::toupper(static_cast<unsigned char>(x)) ==
                    std::toupper(static_cast<unsigned char>(y));
           });
  }
};

}  // namespace hencky
