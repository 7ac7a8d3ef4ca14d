#include "input/inp_elements.hpp"

#include <algorithm>
#include <cctype>
#include <string_view>
#include <utility>
#include <vector>

namespace hencky::inp {
namespace {

/// The leading digits of s (after a prefix), or -1.
int leading_number(std::string_view s) {
  int n = 0;
  std::size_t i = 0;
  for (; i < s.size() && i < 4 && std::isdigit(static_cast<unsigned char>(s[i])); ++i)
    n = 10 * n + (s[i] - '0');
  return i == 0 ? -1 : n;
}

}  // namespace

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

}  // namespace hencky::inp
