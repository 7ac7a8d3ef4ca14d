#pragma once
// Reading a case file (YAML) into the plain structs of spec/case.hpp.
#include <filesystem>
#include <string>

#include "spec/case.hpp"

namespace hencky {

/// Reads and validates a case file. Every problem is an InputError naming the file, line,
/// column and dotted key path, what was expected and what was found, with a suggestion for
/// misspelt keys and values. Paths in the result are absolute (relative ones are taken from
/// the case file's folder). Does not read the mesh. With `text`: the file's text too (for the
/// ranks' comparison of their case files, without reading the file twice).
Case read_case(const std::filesystem::path& case_file, std::string* text = nullptr);

/// read_case on a case file's text, as if it had been read from `case_file` (which need not
/// exist, and must not be empty): messages name it, and relative paths are taken from its
/// folder. For the fuzz target (fuzz/fuzz_case.cpp), which must not go through the disk.
Case read_case_text(const std::string& text, const std::filesystem::path& case_file);

}  // namespace hencky
