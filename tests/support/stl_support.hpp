#pragma once
// STL files for tests: any triangle list written as ASCII or binary STL, and a closed,
// outward-oriented icosphere (test_stl_surface.cpp; solver tests with a rigid STL body).
//
// ASCII coordinates are written with 17 significant digits, so they read back as the same
// doubles; binary STL stores float32, so binary coordinates are the floats nearest to them.
#include <fmt/format.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace hencky {

/// Three corners, counter-clockwise seen from outside the body (right-hand rule).
using StlTriangle = std::array<Vec3, 3>;

/// Writes `triangles` as an ASCII STL ("solid <header>") or a binary one (`header` at the start
/// of the 80-byte header, so a binary file may well begin with "solid").
inline void write_stl(const std::filesystem::path& file, const std::vector<StlTriangle>& triangles,
                      bool binary, const std::string& header = "hencky test") {
  auto normal = [](const StlTriangle& t) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    return n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
  };
  if (!binary) {
    std::ofstream out(file);
    out << "solid " << header << '\n';
    for (const StlTriangle& t : triangles) {
      const Vec3 n = normal(t);
      out << fmt::format("  facet normal {:.17g} {:.17g} {:.17g}\n    outer loop\n", n[0], n[1],
                         n[2]);
      for (const Vec3& x : t)
        out << fmt::format("      vertex {:.17g} {:.17g} {:.17g}\n", x[0], x[1], x[2]);
      out << "    endloop\n  endfacet\n";
    }
    out << "endsolid " << header << '\n';
    if (!out) throw std::runtime_error("cannot write " + file.string());
    return;
  }
  std::string bytes(80, ' ');
  bytes.replace(0, std::min<std::size_t>(header.size(), 80), header.substr(0, 80));
  auto put_u32 = [&bytes](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  };
  auto put_vec = [&](const Vec3& x) {
    for (int j = 0; j < 3; ++j) put_u32(std::bit_cast<std::uint32_t>(static_cast<float>(x[j])));
  };
  put_u32(static_cast<std::uint32_t>(triangles.size()));
  for (const StlTriangle& t : triangles) {
    put_vec(normal(t));
    for (const Vec3& x : t) put_vec(x);
    bytes.append(2, '\0');  // attribute byte count
  }
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

/// Triangles of an icosphere: the icosahedron with each triangle split into four
/// `subdivisions` times, every vertex projected on the sphere. 20 * 4^subdivisions triangles,
/// outward oriented.
inline std::vector<StlTriangle> icosphere_triangles(const Vec3& center, double radius,
                                                    int subdivisions) {
  // Icosahedron vertices (0, ±1, ±φ) and cyclic permutations; its faces are the triples of
  // mutually adjacent vertices (edge length 2), each oriented away from the centre.
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> x;
  for (int s1 : {-1, 1})
    for (int s2 : {-1, 1}) {
      x.emplace_back(0, s1, s2 * phi);
      x.emplace_back(s1, s2 * phi, 0);
      x.emplace_back(s2 * phi, 0, s1);
    }
  std::vector<std::array<int, 3>> faces;
  auto adjacent = [&](int i, int j) { return std::abs((x[i] - x[j]).norm() - 2) < 1e-9; };
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k)
        if (adjacent(i, j) && adjacent(j, k) && adjacent(i, k)) {
          const bool outward = (x[j] - x[i]).cross(x[k] - x[i]).dot(x[i]) > 0;
          faces.push_back(outward ? std::array{i, j, k} : std::array{i, k, j});
        }
  for (Vec3& v : x) v.normalize();

  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;  // shared by the two faces of an edge
    auto mid = [&](int i, int j) {
      const auto [it, inserted] =
          midpoint.try_emplace(std::minmax(i, j), static_cast<int>(x.size()));
      if (inserted) x.push_back((x[i] + x[j]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(4 * faces.size());
    for (const auto& [a, b, c] : faces) {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  std::vector<StlTriangle> triangles;
  triangles.reserve(faces.size());
  for (const auto& f : faces)
    triangles.push_back(
        {center + radius * x[f[0]], center + radius * x[f[1]], center + radius * x[f[2]]});
  return triangles;
}

/// Writes a closed, outward-oriented icosphere (vertices on the sphere) as ASCII or binary STL.
inline void write_icosphere_stl(const std::filesystem::path& file, const Vec3& center,
                                double radius, int subdivisions, bool binary) {
  write_stl(file, icosphere_triangles(center, radius, subdivisions), binary, "icosphere");
}

}  // namespace hencky
