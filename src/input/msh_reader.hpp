#pragma once
// hencky's own reader of Gmsh .msh files (formats 2.2, 4.0 ASCII and 4.1, ASCII and binary),
// which does not go through the Gmsh library: Gmsh 4.8's reader crashes on some malformed
// files (a node tag of -1 or 2^31 in an element, a header that announces fewer entries than
// its blocks hold), and a crash cannot be caught. This reader checks every count, tag and
// reference against the file's own content and refuses what does not add up, naming the line
// (ASCII) or the byte (binary) where it found the problem.
#include <filesystem>
#include <string>
#include <string_view>

#include "input/msh_data.hpp"

namespace hencky {

/// Parses the text of a .msh file; `name` is the file named in messages. With `piece`, the file
/// must be one file of a mesh Gmsh split into files (gmsh -part N -part_split), holding one
/// partition, and is read as that part; without, such a file is refused. Throws InputError.
MshData parse_msh(std::string_view text, const std::string& name, bool piece = false);

/// Reads and parses a .msh file (`piece` as parse_msh). Throws InputError naming the file.
MshData read_msh(const std::filesystem::path& file, bool piece = false);

}  // namespace hencky
