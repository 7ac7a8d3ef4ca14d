#pragma once
// mesh.regions of a case (spec/case.hpp, LabelRegionSpec): regions named by the mesh's node and
// element labels, added to the Mesh after it is read.
#include <vector>

#include "mesh/mesh.hpp"
#include "spec/case.hpp"

namespace hencky {

/// Adds each region to `mesh`: its nodes (dimension 0), volume cells (3) or faces (2, appended to
/// mesh.faces). Faces are numbered as the Abaqus and CalculiX manuals number them (S1 .. S6).
/// Throws InputError at the label that names no node, cell or face of the mesh, or at a region
/// whose name the mesh already has (`ignore_case`: names match without regard to case).
void add_label_regions(Mesh& mesh, const std::vector<LabelRegionSpec>& regions, bool ignore_case);

}  // namespace hencky
