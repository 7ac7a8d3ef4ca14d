#pragma once
// CalculiX's result file (.frd, ASCII), for CalculiX GraphiX (cgx) and the tools that read what
// ccx writes. The layout follows the cgx manual's "Result Format" chapter (the model header,
// user header, nodal point coordinate, element definition and nodal results blocks, in their
// "long" ASCII variant) and, where the manual leaves a choice, what ccx 2.20 itself writes
// (ccx's frd.c, frdheader.c, frdvector.c and frdselect.c): a file of this writer and ccx's .frd
// of the same nodes, elements and values differ only in the header's text lines (date, program).
//
// What is written:
//   header    "    1C", then "    1U..." lines (date, time, program, version) and one
//             "    1UMAT" line per volume region that holds cells (its number and name; the
//             volume regions, those of dimension 3, are numbered from 1 in Mesh::regions);
//   nodes     "    2C" with the node count, one " -1" line per node (label, x, y, z), " -3";
//   elements  "    3C" with the cell count, per cell a " -1" line (label, ccx's element type,
//             group 0, material: the number of the cell's volume region, 0 without one)
//             and " -2" lines of at most 10 node labels in ccx's .frd order, " -3";
//   per step  for each field a "    1PSTEP" line, a "  100CL" line (set number, time, node
//             count, static analysis), " -4" and " -5" lines naming the field and its
//             components, one " -1" line per node (label and up to 6 values; a " -2" line for
//             each 6 more), " -3";
//   end       " 9999".
// Nodes (in the coordinate block and in every result block) and cells are written in ascending
// order of their labels: frdselect.c sorts the nodes of a result block, the format wants it.
// Numbers are written as ccx does, single precision in fixed 12-column fields (%12.5E).
//
// hencky keeps cells in Gmsh's node order (fem/cell_type.hpp); the writer permutes them into
// the order ccx writes (frd_from_gmsh below). That is the Abaqus/CalculiX order of the deck
// (input/inp_elements.hpp, gmsh_from_abaqus) except for the 20-node hexahedron, whose .frd
// record lists the mid-edge nodes of the bottom face, then of the four vertical edges, then of
// the top face (the deck: bottom, top, vertical).
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace hencky {

/// One nodal result block: its name as ccx writes it (DISP, STRESS, TOSTRAIN, FORC, PE, NDTEMP),
/// its components' names (D1 D2 D3; SXX SYY SZZ SXY SYZ SZX; ...), and per node of the mesh (in
/// the Mesh's node order) the components' values: values[node * components.size() + k].
///
/// Names have at most 8 characters (the format's columns). The number of components sets the
/// kind ccx gives such a block: 3 a vector (and cgx's computed magnitude "ALL" is declared after
/// them, as for ccx's DISP and FORC), 6 a symmetric tensor in ccx's order XX YY ZZ XY YZ ZX
/// (STRESS, TOSTRAIN), any other number scalars (PE, NDTEMP).
struct FrdField {
  std::string name;
  std::vector<std::string> components;
  std::vector<double> values;
};

/// ccx's element type number in a .frd: he8 1, pe6 2, te4 3, he20 4, te10 6 (pe15 5 is not a
/// hencky cell); 0 for the face types, which the writer does not write.
int frd_element_type(CellType t);

/// The node order of a cell's record in a .frd: its node j is Gmsh's node frd_from_gmsh(t)[j].
/// Empty for the face types.
std::span<const int> frd_from_gmsh(CellType t);

class FrdWriter {
 public:
  /// Opens `file` and writes the header and the mesh: nodes by their labels (mesh.node_tag),
  /// cells by their labels (mesh.cells.tag) in ccx's node order. Throws InputError
  /// (core/error.hpp) if the file cannot be written, std::invalid_argument if the mesh cannot
  /// be written as a .frd (labels not positive, repeated or wider than 10 digits; a face cell
  /// among the cells). Empty node_tag or cells.tag: labels 1..n.
  FrdWriter(const std::filesystem::path& file, const Mesh& mesh);
  /// The cells' materials as ccx numbers and names them in the header and the element records:
  /// cell c's number of_cell[c] (from 1; 0: none) and number k's name names[k - 1].
  struct Materials {
    std::vector<int> of_cell;
    std::vector<std::string> names;
  };
  /// The same, each cell with its material's number instead of its volume region's.
  FrdWriter(const std::filesystem::path& file, const Mesh& mesh, const Materials& materials);
  /// One result step (`step` from 1, its time): every field as a block. The blocks of the k-th
  /// call are result set k ("100CL  10k", as ccx counts the sets it writes); `step` is written as
  /// the increment of the "1PSTEP" line (ccx's step number there is 1). Throws
  /// std::invalid_argument on a field of the wrong size or a name too long for its columns,
  /// OutputError if the file cannot be written.
  void step(int step, double time, const std::vector<FrdField>& fields);
  /// A restart: the result sets of the .frd `old` (written by this writer for the same mesh)
  /// up to time `up_to`, copied as they are, the counts continued from them. Returns the number
  /// of sets copied; a file that cannot be read copies none.
  int adopt(const std::filesystem::path& old, double up_to);
  /// The closing line (9999); also done by the destructor if not called. Throws OutputError if
  /// the file cannot be written (the destructor does not throw).
  void close();
  ~FrdWriter();

  FrdWriter(const FrdWriter&) = delete;
  FrdWriter& operator=(const FrdWriter&) = delete;

 private:
  FrdWriter(const std::filesystem::path& file, const Mesh& mesh, const Materials* materials);
  /// The header, the nodes and the elements (the constructor's part).
  void write_mesh(const Mesh& mesh, const std::vector<int>& cell_order, const Materials* materials);
  /// Writes `text` and empties it; OutputError if the file cannot be written.
  void flush(std::string& text);
  std::filesystem::path file_;
  std::ofstream out_;
  std::vector<int> node_order_;  ///< node indices in ascending order of their labels
  std::vector<long> node_label_;
  int sets_ = 0;    ///< result sets written (calls of step)
  int blocks_ = 0;  ///< result blocks written (the "1PSTEP" counter)
  bool closed_ = false;
};

}  // namespace hencky
