#pragma once
// A CalculiX/Abaqus deck run as a case (`hencky run MODEL.inp`, CASE_FORMAT.md): its model data
// (mesh, materials, sections, initial temperatures, amplitudes) and its history (the steps with
// their conditions and loads) read into the Case a case file would give, with CalculiX's meaning
// of each keyword (CalculiX User's Manual, ccx 2.20, section 7). What the deck asks that hencky
// cannot do is refused before anything is solved, every such keyword listed with its file and
// line (docs/ccx-decks.md).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/mesh.hpp"
#include "spec/case.hpp"

namespace hencky {

struct DeckRead {
  Case spec;
  Mesh mesh;
  std::vector<std::string> warnings;  ///< the mesh reader's and the translation's
};

/// Reads the whole deck. Throws InputError naming the file and line (a list of every keyword
/// hencky cannot honour). With `text`: the deck's own text (not its *INCLUDEs).
DeckRead read_deck(const std::filesystem::path& file, std::string* text = nullptr);

/// read_deck on a deck's text, as if read from `file` (for the fuzz target, fuzz/fuzz_inp.cpp).
DeckRead parse_deck(std::string_view text, const std::filesystem::path& file);

}  // namespace hencky
