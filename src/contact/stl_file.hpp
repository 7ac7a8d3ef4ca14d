#pragma once
// The STL file format, binary and ASCII, read into a soup of triangles (contact/stl_surface.hpp
// welds, checks and indexes it). Every failure is an InputError naming the file, and the line
// of an ASCII file.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"

namespace hencky::stl {

/// Triangles as read: three corners each, and for an ASCII file each facet's line.
struct Soup {
  std::vector<Vec3> corners;
  std::vector<int> line;
};

/// "(x, y, z)" to 9 digits, for messages.
std::string point_str(const Vec3& x);

/// Throws InputError at `where` unless `scale` is a positive finite number.
void check_scale(const SourceLocation& where, double scale);

/// The bytes of an STL file; `scale` is checked first, as the constructor would.
std::string read_stl_file(const std::filesystem::path& file, double scale);

/// The triangles of the bytes of an STL file, coordinates multiplied by `scale`: binary when
/// the size is that of a binary STL (84 + 50 n bytes), ASCII when the text starts with
/// "solid"; InputError for anything else, and for a malformed or non-finite triangle.
Soup parse_stl(std::string_view bytes, const SourceLocation& where, double scale);

}  // namespace hencky::stl
