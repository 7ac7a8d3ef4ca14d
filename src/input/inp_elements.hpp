#pragma once
// What hencky makes of the element types of an Abaqus/CalculiX deck (input/inp_reader.hpp):
// volume, face or skipped, the cell type, and the node orders of cells and faces against
// Gmsh's (fem/cell_type.hpp; CalculiX User's Manual, section 6.2).
#include <span>
#include <string>
#include <variant>

#include "fem/cell_type.hpp"

namespace hencky::inp {

/// What hencky makes of an element type.
struct ElementKind {
  enum class Kind { volume, face, skipped } kind = Kind::skipped;
  CellType type = CellType::tet4;
  int nodes = 0;  ///< nodes in the file, also of a skipped type (0: read up to the line's end)
};

/// The kind of an element type (upper case), or a message saying why hencky cannot read it.
std::variant<ElementKind, std::string> element_kind(const std::string& type);

/// Gmsh's node k of a cell is the file's node perm[k] (fem/cell_type.hpp; CalculiX manual 6.2).
std::span<const int> gmsh_from_abaqus(CellType t);

/// Face `side` (from 1) of a volume cell: its corners and then its mid-edge nodes, as
/// positions in the file's order of the cell's nodes, in Gmsh's order of the face's type.
/// Empty when the cell has no such face. Views static tables: nothing is allocated.
std::span<const int> abaqus_face(CellType t, int side);

/// The cell type of a face of `n` nodes (3, 4, 6 or 8: abaqus_face's sizes).
inline CellType face_cell_type(std::size_t n) {
  return n == 3   ? CellType::tri3
         : n == 4 ? CellType::quad4
         : n == 6 ? CellType::tri6
                  : CellType::quad8;
}

}  // namespace hencky::inp
