#pragma once
#include <cstdint>
#include <string_view>

namespace hencky {

/// Supported cells. Node ordering everywhere inside hencky is Gmsh's
/// (https://gmsh.info/doc/texinfo/gmsh.html#Node-ordering); writers convert to VTK's.
enum class CellType : std::uint8_t {
  tet4,    // Gmsh type 4
  tet10,   // Gmsh type 11
  hex8,    // Gmsh type 5
  hex20,   // Gmsh type 17
  wedge6,  // Gmsh type 6
  tri3,    // Gmsh type 2
  tri6,    // Gmsh type 9
  quad4,   // Gmsh type 3
  quad8,   // Gmsh type 16
};

constexpr int cell_dim(CellType t) {
  switch (t) {
    case CellType::tet4: case CellType::tet10: case CellType::hex8: case CellType::hex20:
    case CellType::wedge6: return 3;
    default: return 2;
  }
}

constexpr int cell_n_nodes(CellType t) {
  switch (t) {
    case CellType::tet4: return 4;
    case CellType::tet10: return 10;
    case CellType::hex8: return 8;
    case CellType::hex20: return 20;
    case CellType::wedge6: return 6;
    case CellType::tri3: return 3;
    case CellType::tri6: return 6;
    case CellType::quad4: return 4;
    case CellType::quad8: return 8;
  }
  return 0;
}

/// The cell made of the corner nodes only (the first nodes in Gmsh ordering).
constexpr CellType cell_linear(CellType t) {
  switch (t) {
    case CellType::tet10: return CellType::tet4;
    case CellType::hex20: return CellType::hex8;
    case CellType::tri6: return CellType::tri3;
    case CellType::quad8: return CellType::quad4;
    default: return t;
  }
}

constexpr int cell_n_corners(CellType t) { return cell_n_nodes(cell_linear(t)); }

constexpr std::string_view cell_name(CellType t) {
  switch (t) {
    case CellType::tet4: return "4-node tetrahedron";
    case CellType::tet10: return "10-node tetrahedron";
    case CellType::hex8: return "8-node hexahedron";
    case CellType::hex20: return "20-node hexahedron";
    case CellType::wedge6: return "6-node wedge";
    case CellType::tri3: return "3-node triangle";
    case CellType::tri6: return "6-node triangle";
    case CellType::quad4: return "4-node quadrilateral";
    case CellType::quad8: return "8-node quadrilateral";
  }
  return "?";
}

}  // namespace hencky
