#pragma once
// hencky's reader of the mesh in an Abaqus/CalculiX input deck (.inp), as CalculiX's cgx,
// FreeCAD's FEM workbench, PrePoMax, Gmsh (-format inp) and Abaqus/CAE write it.
//
// Read: *NODE; *ELEMENT of the volume types C3D4, C3D10, C3D8, C3D20 and C3D6 (any suffix, e.g.
// C3D8R or C3D10M, and the heat-transfer DC3D types: hencky integrates them its own way), and
// of the face types (CPS, CPE, CAX, S, M3D, R3D, SFM3D and STRI, with 3, 4, 6 or 8 nodes);
// *NSET and *ELSET, with GENERATE and with other sets among their members; *SURFACE,
// TYPE=ELEMENT (element and face label pairs, S1..S6) or TYPE=NODE; *INCLUDE; one *PART with at
// most one *INSTANCE that does not move it. Node orders are mapped to Gmsh's (fem/cell_type.hpp):
// the 10-node tetrahedron's last two mid-edge nodes swap, the 20-node hexahedron's mid-edge
// nodes are reordered. Line elements (trusses, beams, springs, masses) are skipped, and so are
// the keywords that are not mesh data (materials, sections, steps): each kind is named once in
// a warning.
//
// Regions: every NSET (and node-based surface) is a region of nodes (dimension 0); every
// element-based surface, and every ELSET of face elements, a region of faces (dimension 2);
// every ELSET of volume elements a region of cells (dimension 3). Names are matched without
// regard to case, as Abaqus does (Model::find_region). When sets of different kinds share a
// name, a condition takes the one of its kind: a displacement the NSET, a pressure the surface
// (before an ELSET of faces), a material the ELSET of volumes.
//
// The body is every volume element. Its nodes are numbered 0..n-1 in the order of their labels
// and its cells kept in the order of the file, so that a deck Gmsh exported from a mesh gives
// the same numbering as the .msh (msh_data.hpp).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "input/gmsh_reader.hpp"
#include "mesh/mesh.hpp"

namespace hencky {

/// Parses the text of a deck; `file` names it in messages, and *INCLUDE paths are taken from
/// its folder. Warnings (skipped keywords and elements) are appended to `warnings` when given.
/// Only `options.scale` applies. Throws InputError naming the file and line.
Mesh parse_inp(std::string_view text, const std::filesystem::path& file,
               const MeshReadOptions& options, std::vector<std::string>* warnings = nullptr);

/// Reads and parses a deck (parse_inp). Throws InputError naming the file.
Mesh read_inp(const std::filesystem::path& file, const MeshReadOptions& options,
              std::vector<std::string>* warnings = nullptr);

/// True when `file` is read as an Abaqus/CalculiX deck (extension .inp, any case).
bool is_inp_file(const std::filesystem::path& file);

}  // namespace hencky
