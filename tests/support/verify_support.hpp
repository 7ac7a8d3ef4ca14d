#pragma once
// Shared helpers of the verification tests (test_verify_*.cpp, test_patch_*.cpp): temporary case
// directories, writing meshes and case files, running a case in-process, error norms by
// quadrature with a rule finer than the solver's, observed convergence rates, and a writer of
// distorted structured cube meshes (Gmsh format 2 ASCII) for every volume cell type.
//
// Nothing here knows an answer: the analytic solutions live in the tests.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fem/geometry.hpp"
#include "fem/quadrature.hpp"
#include "fem/reference_element.hpp"
#include "input/load_case.hpp"
#include "linalg/serial_system.hpp"
#include "output/results.hpp"
#include "solve/driver.hpp"

namespace hencky::verify {

namespace fs = std::filesystem;

/// A number written so that it reads back to the same double.
inline std::string num(double v) { return fmt::format("{:.17g}", v); }

/// A fresh directory under the system temp dir, removed on destruction (kept when the
/// environment variable HENCKY_VERIFY_KEEP is set, to look at the cases).
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    static int counter = 0;
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = fs::temp_directory_path() /
            fmt::format("hencky-verify-{}-{}-{}-{}", tag, ::getpid(), counter++, stamp % 1000000);
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    if (std::getenv("HENCKY_VERIFY_KEEP")) return;
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

inline void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  out << text;
}

/// A case run in-process; keeps the log alive with the run.
struct Run {
  Log log;
  std::unique_ptr<InProcessRun> run;
  const Model& model() const { return *run->loaded.model; }
  const State& state() const { return run->states.last; }
  Vec3 u(int node) const {
    const auto& s = state().u;
    return {s[3 * node], s[3 * node + 1], s[3 * node + 2]};
  }
};

/// Writes the case file into `dir` and runs it. Throws (GoogleTest then fails the test with
/// the message) when the analysis does not converge, so that no check runs on a missing state.
inline std::unique_ptr<Run> run_case(const fs::path& dir, const std::string& yaml,
                                     const std::string& name = "case.yaml") {
  const fs::path file = dir / name;
  write_file(file, yaml);
  auto r = std::make_unique<Run>();
  r->log.quiet = true;
  r->run = run_in_process(file, r->log);
  if (r->run->result.status != AnalysisStatus::converged || r->run->states.reports.empty())
    throw std::runtime_error(fmt::format("{}: the analysis did not converge: {}", file.string(),
                                         r->run->result.failure));
  return r;
}

// ------------------------------------------------------------------------------------------
// Norms by quadrature

/// A quadrature degree well above the solver's own, for error integrals.
inline int error_degree(CellType t) {
  switch (t) {
    case CellType::tet4:
    case CellType::tet10: return 5;  // 14 points, the highest tetrahedral rule
    case CellType::hex8:
    case CellType::hex20: return 9;  // 5x5x5 Gauss
    case CellType::wedge6: return 6;
    default: return max_quadrature_degree(t);
  }
}

using VectorField = std::function<Vec3(const Vec3&)>;
using StressField = std::function<Voigt(const Vec3&)>;

struct L2Norms {
  double error = 0;   ///< ‖u_h − u‖
  double exact = 0;   ///< ‖u‖
  double volume = 0;  ///< of the mesh, by the same quadrature
  int cells = 0;
  double relative() const { return error / exact; }
  /// Mean cell size (volume / cells)^(1/3): a mesh size that also means something for
  /// unstructured meshes.
  double h() const { return std::cbrt(volume / cells); }
};

/// L2 norm of the displacement error over the cells, u_h interpolated with the cells' shape
/// functions and integrated on the cells' own (isoparametric) geometry with error_degree().
inline L2Norms l2_displacement_error(const Model& model, const State& state, const VectorField& exact) {
  const Mesh& mesh = model.mesh();
  L2Norms out;
  double e2 = 0, u2 = 0;
  Vec3 x[max_cell_nodes];
  double dNdx[3 * max_cell_nodes];
  for (int c = 0; c < mesh.cells.size(); ++c) {
    const auto nodes = mesh.cells.nodes(c);
    const int n = static_cast<int>(nodes.size());
    const CellType type = mesh.cells.type[c];
    const auto& tab = reference_table(type, error_degree(type));
    for (int a = 0; a < n; ++a) x[a] = mesh.x[nodes[a]];
    const std::span<const Vec3> xs(x, n);
    for (int q = 0; q < tab.n_points; ++q) {
      const double dv = physical_gradients(tab, q, xs, dNdx) * tab.weights[q];
      const Vec3 p = point_position(tab, q, xs);
      const double* N = &tab.N[static_cast<std::size_t>(q) * tab.n_nodes];
      Vec3 uh = Vec3::Zero();
      for (int a = 0; a < n; ++a)
        uh += N[a] * Vec3(state.u[3 * nodes[a]], state.u[3 * nodes[a] + 1], state.u[3 * nodes[a] + 2]);
      const Vec3 ue = exact(p);
      e2 += (uh - ue).squaredNorm() * dv;
      u2 += ue.squaredNorm() * dv;
      out.volume += dv;
    }
  }
  out.error = std::sqrt(e2);
  out.exact = std::sqrt(u2);
  out.cells = mesh.cells.size();
  return out;
}

/// L2 norm of the stress error sampled at the solver's own integration points (the stresses
/// the solver computed), weighted by their quadrature weights: ‖σ_h − σ‖ / ‖σ‖ (Frobenius
/// norm of the Voigt vectors with shear counted twice, i.e. of the tensor).
inline double l2_stress_error(const Model& model, const State& state, const StressField& exact) {
  const Mesh& mesh = model.mesh();
  double e2 = 0, s2 = 0;
  Vec3 x[max_cell_nodes];
  double dNdx[3 * max_cell_nodes];
  auto tensor_sq = [](const Voigt& v) {
    return v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + 2 * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
  };
  for (int c = 0; c < mesh.cells.size(); ++c) {
    const auto nodes = mesh.cells.nodes(c);
    const int n = static_cast<int>(nodes.size());
    const auto& tab = reference_table(mesh.cells.type[c]);
    for (int a = 0; a < n; ++a) x[a] = mesh.x[nodes[a]];
    const std::span<const Vec3> xs(x, n);
    for (int q = 0; q < tab.n_points; ++q) {
      const double dv = physical_gradients(tab, q, xs, dNdx) * tab.weights[q];
      const Voigt se = exact(point_position(tab, q, xs));
      e2 += tensor_sq(state.stress[model.point_offset(c) + q] - se) * dv;
      s2 += tensor_sq(se) * dv;
    }
  }
  return std::sqrt(e2 / s2);
}

/// Least-squares slope of log(error) against log(h): the observed order of convergence.
inline double observed_rate(const std::vector<double>& h, const std::vector<double>& e) {
  const std::size_t n = h.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double lx = std::log(h[i]), ly = std::log(e[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// Prints a line the reader of the test log (and docs/verification.md) can find.
inline void report(const std::string& what) { std::cout << "[verify] " << what << std::endl; }

// ------------------------------------------------------------------------------------------
// Linear fields

/// Voigt strain (engineering shears) of the displacement gradient G (G(i, j) = du_i/dx_j).
inline Voigt strain_of_gradient(const Mat3& G) {
  Voigt e;
  e << G(0, 0), G(1, 1), G(2, 2), G(1, 2) + G(2, 1), G(2, 0) + G(0, 2), G(0, 1) + G(1, 0);
  return e;
}

/// muparser expression of component i of u = c + G x.
inline std::string linear_expression(const Mat3& G, const Vec3& c, int i) {
  return fmt::format("{} + {}*x + {}*y + {}*z", num(c[i]), num(G(i, 0)), num(G(i, 1)), num(G(i, 2)));
}

// ------------------------------------------------------------------------------------------
// Distorted structured cube meshes written by hand (Gmsh MSH 2.2 ASCII)

enum class GridCells { hex8, hex20, wedge6, mixed };

inline const char* to_string(GridCells k) {
  switch (k) {
    case GridCells::hex8: return "hex8";
    case GridCells::hex20: return "hex20";
    case GridCells::wedge6: return "wedge6";
    case GridCells::mixed: return "mixed hex8+wedge6";
  }
  return "?";
}

/// Nodes and elements of a Gmsh 2.2 mesh written by the tests (cube_msh, and the bar of
/// test_verify_plastic_thermal.cpp). Node tags are positions in x plus one; mid-edge nodes are
/// created once per edge; every element's elementary entity is its physical tag.
struct MshBuilder {
  struct Element {
    int type, physical;
    std::vector<int> nodes;
  };
  std::vector<Vec3> x;
  std::vector<Element> elements;
  std::map<std::pair<int, int>, int> mid;

  /// The node at the middle of the edge a-b (node tags), created the first time it is asked for.
  int midnode(int a, int b) {
    const auto key = std::minmax(a, b);
    if (auto it = mid.find(key); it != mid.end()) return it->second;
    x.push_back(0.5 * (x[a - 1] + x[b - 1]));
    const int tag = static_cast<int>(x.size());
    mid.emplace(key, tag);
    return tag;
  }
  /// A hexahedron with corners c (Gmsh's order): 8 nodes, or 20 with its mid-edge nodes.
  void hex(const std::array<int, 8>& c, bool quadratic, int physical) {
    // clang-format off
    constexpr std::array<std::array<int, 2>, 12> edges{{{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5},
                                                        {2, 3}, {2, 6}, {3, 7}, {4, 5}, {4, 7},
                                                        {5, 6}, {6, 7}}};  // Gmsh's order
    // clang-format on
    Element e{quadratic ? 17 : 5, physical, {c.begin(), c.end()}};
    if (quadratic)
      for (auto [a, b] : edges) e.nodes.push_back(midnode(c[a], c[b]));
    elements.push_back(e);
  }
  /// A quadrilateral face a b c d (node tags, in order around it): 4 nodes, or 8.
  void quad(int a, int b, int c, int d, bool quadratic, int physical) {
    Element f{quadratic ? 16 : 3, physical, {a, b, c, d}};
    if (quadratic)
      for (auto [p, q] : std::array<std::array<int, 2>, 4>{{{a, b}, {b, c}, {c, d}, {d, a}}})
        f.nodes.push_back(midnode(p, q));
    elements.push_back(f);
  }
  /// The .msh text, with the physical names given as {dimension, tag, name}.
  std::string text(const std::vector<std::tuple<int, int, std::string>>& names) const {
    std::string s = fmt::format("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n{}\n",
                                names.size());
    for (const auto& [dim, tag, name] : names) s += fmt::format("{} {} \"{}\"\n", dim, tag, name);
    s += fmt::format("$EndPhysicalNames\n$Nodes\n{}\n", x.size());
    for (std::size_t a = 0; a < x.size(); ++a)
      s += fmt::format("{} {} {} {}\n", a + 1, num(x[a].x()), num(x[a].y()), num(x[a].z()));
    s += fmt::format("$EndNodes\n$Elements\n{}\n", elements.size());
    for (std::size_t e = 0; e < elements.size(); ++e) {
      s += fmt::format("{} {} 2 {} {}", e + 1, elements[e].type, elements[e].physical,
                       elements[e].physical);
      for (int v : elements[e].nodes) s += fmt::format(" {}", v);
      s += "\n";
    }
    return s + "$EndElements\n";
  }
};

/// The regions of cube_msh() and of the thermal bar: the body and the six faces of a box.
inline std::vector<std::tuple<int, int, std::string>> box_region_names() {
  std::vector<std::tuple<int, int, std::string>> names{{3, 1, "body"}};
  const char* faces[] = {"x0", "x1", "y0", "y1", "z0", "z1"};
  for (int f = 0; f < 6; ++f) names.emplace_back(2, 11 + f, faces[f]);
  return names;
}

/// The boundary block of a case on quarter_ring_geo()'s ring in plane strain: symmetry rollers
/// on xsym and ysym, both end faces held axially, and the internal pressure `pressure` (a
/// number, or an expression in quotes) on the bore.
inline std::string ring_plane_strain_boundary(const std::string& pressure) {
  return "boundary:\n"
         "  - {region: xsym, displacement: {x: 0}}\n"
         "  - {region: ysym, displacement: {y: 0}}\n"
         "  - {region: bottom, displacement: {z: 0}}\n"
         "  - {region: top, displacement: {z: 0}}\n"
         "  - {region: inner, pressure: " +
         pressure + "}\n";
}

/// The cube [0, L]^3 cut into n^3 hexahedra (or each hexahedron into two wedges, or a mix: the
/// wedge columns are those with i + j even), with every interior node moved by up to
/// `distortion` times the grid step in each direction (deterministic pseudo-random). Quadratic
/// hexahedra get their mid-edge nodes at the midpoints of the (moved) corners, so that their
/// geometry stays trilinear.
///
/// Regions: volume "body"; surfaces x0 x1 y0 y1 z0 z1 (the faces of the cube); points p000,
/// p100, p010, p001 (corners of the cube).
inline std::string cube_msh(int n, GridCells kind, double distortion, double L = 1.0,
                            std::uint32_t seed = 12345) {
  std::mt19937 rng(seed);
  auto rnd = [&] { return 2.0 * (static_cast<double>(rng()) / 4294967295.0) - 1.0; };
  const int m = n + 1;
  const double step = L / n;
  MshBuilder b;
  auto id = [&](int i, int j, int k) { return 1 + i + m * (j + m * k); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Vec3 p(i * step, j * step, k * step);
        if (i > 0 && i < n && j > 0 && j < n && k > 0 && k < n)
          for (int d = 0; d < 3; ++d) p[d] += distortion * step * rnd();
        b.x.push_back(p);
      }
  const bool quadratic = kind == GridCells::hex20;
  auto is_wedge_column = [&](int i, int j) {
    return kind == GridCells::wedge6 || (kind == GridCells::mixed && (i + j) % 2 == 0);
  };

  // Physical tags: 1 body; 11..16 faces; 21..24 points.
  const std::array<std::pair<int, int>, 4> points{{{21, id(0, 0, 0)}, {22, id(n, 0, 0)},
                                                   {23, id(0, n, 0)}, {24, id(0, 0, n)}}};
  for (auto [tag, node] : points) b.elements.push_back({15, tag, {node}});

  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::array<int, 8> c{id(i, j, k),         id(i + 1, j, k),     id(i + 1, j + 1, k),
                                   id(i, j + 1, k),     id(i, j, k + 1),     id(i + 1, j, k + 1),
                                   id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        if (is_wedge_column(i, j)) {
          b.elements.push_back({6, 1, {c[0], c[1], c[2], c[4], c[5], c[6]}});
          b.elements.push_back({6, 1, {c[0], c[2], c[3], c[4], c[6], c[7]}});
        } else {
          b.hex(c, quadratic, 1);
        }
        // Boundary faces of this cell.
        auto quad = [&](int tag, int a, int bb, int cc, int d) {
          b.quad(c[a], c[bb], c[cc], c[d], quadratic, tag);
        };
        if (i == 0) quad(11, 0, 3, 7, 4);
        if (i == n - 1) quad(12, 1, 2, 6, 5);
        if (j == 0) quad(13, 0, 1, 5, 4);
        if (j == n - 1) quad(14, 3, 2, 6, 7);
        for (int side = 0; side < 2; ++side) {
          if (k != (side == 0 ? 0 : n - 1)) continue;
          const int tag = side == 0 ? 15 : 16, o = side == 0 ? 0 : 4;
          if (is_wedge_column(i, j)) {
            b.elements.push_back({2, tag, {c[o], c[o + 1], c[o + 2]}});
            b.elements.push_back({2, tag, {c[o], c[o + 2], c[o + 3]}});
          } else {
            quad(tag, o, o + 1, o + 2, o + 3);
          }
        }
      }

  auto names = box_region_names();
  const char* corners[] = {"p000", "p100", "p010", "p001"};
  for (int p = 0; p < 4; ++p) names.emplace_back(0, 21 + p, corners[p]);
  return b.text(names);
}

/// The Gmsh entities of the box lo..hi (point size h): points 1-4 at z = lo.z and 5-8 at
/// z = hi.z (counter-clockwise from (lo.x, lo.y)), surfaces 1 (z = lo.z), 2 (z = hi.z),
/// 3 (y = lo.y), 4 (x = hi.x), 5 (y = hi.y), 6 (x = lo.x), volume 1; no physical groups.
inline std::string box_entities_geo(const Vec3& lo, const Vec3& hi, double h) {
  return fmt::format(R"(x0 = {}; y0 = {}; z0 = {}; x1 = {}; y1 = {}; z1 = {}; h = {};
Point(1) = {{x0, y0, z0, h}}; Point(2) = {{x1, y0, z0, h}}; Point(3) = {{x1, y1, z0, h}}; Point(4) = {{x0, y1, z0, h}};
Point(5) = {{x0, y0, z1, h}}; Point(6) = {{x1, y0, z1, h}}; Point(7) = {{x1, y1, z1, h}}; Point(8) = {{x0, y1, z1, h}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Line(5) = {{5, 6}}; Line(6) = {{6, 7}}; Line(7) = {{7, 8}}; Line(8) = {{8, 5}};
Line(9) = {{1, 5}}; Line(10) = {{2, 6}}; Line(11) = {{3, 7}}; Line(12) = {{4, 8}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Curve Loop(2) = {{5, 6, 7, 8}}; Plane Surface(2) = {{2}};
Curve Loop(3) = {{1, 10, -5, -9}}; Plane Surface(3) = {{3}};
Curve Loop(4) = {{2, 11, -6, -10}}; Plane Surface(4) = {{4}};
Curve Loop(5) = {{3, 12, -7, -11}}; Plane Surface(5) = {{5}};
Curve Loop(6) = {{4, 9, -8, -12}}; Plane Surface(6) = {{6}};
Surface Loop(1) = {{1, 2, 3, 4, 5, 6}}; Volume(1) = {{1}};
)",
                     num(lo.x()), num(lo.y()), num(lo.z()), num(hi.x()), num(hi.y()),
                     num(hi.z()), num(h));
}

/// A box [0,Lx] x [0,Ly] x [0,Lz] for Gmsh's built-in kernel, meshed into unstructured
/// tetrahedra of size h at run time. Regions as cube_msh(): body; x0 x1 y0 y1 z0 z1;
/// p000 p100 p010 p001.
inline std::string box_geo(double Lx, double Ly, double Lz, double h) {
  return fmt::format("Mesh.CharacteristicLengthMax = {};\n", num(h)) +
         box_entities_geo(Vec3::Zero(), Vec3(Lx, Ly, Lz), h) + R"(Physical Volume("body") = {1};
Physical Surface("x0") = {6}; Physical Surface("x1") = {4};
Physical Surface("y0") = {3}; Physical Surface("y1") = {5};
Physical Surface("z0") = {1}; Physical Surface("z1") = {2};
Physical Point("p000") = {1}; Physical Point("p100") = {2};
Physical Point("p010") = {4}; Physical Point("p001") = {5};
)";
}

/// A quarter of the ring a <= r <= b (x, y >= 0) of thickness t along z, structured: nr
/// divisions radially, nt around, one layer through the thickness. `cells`: "tet" (each prism
/// split into tetrahedra), "wedge" (triangles extruded into prisms), "hex" (recombined).
/// Regions: body; inner outer (the arcs); xsym (x = 0) ysym (y = 0); bottom (z = 0) top (z = t).
inline std::string quarter_ring_geo(double a, double b, double t, int nr, int nt, const std::string& cells) {
  const bool hex = cells == "hex", wedge = cells == "wedge";
  return fmt::format(R"(a = {}; b = {}; t = {};
Point(1) = {{0, 0, 0}}; Point(2) = {{a, 0, 0}}; Point(3) = {{b, 0, 0}}; Point(4) = {{0, b, 0}}; Point(5) = {{0, a, 0}};
Line(1) = {{2, 3}}; Circle(2) = {{3, 1, 4}}; Line(3) = {{4, 5}}; Circle(4) = {{5, 1, 2}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Transfinite Curve{{1, 3}} = {}; Transfinite Curve{{2, 4}} = {}; Transfinite Surface{{1}};
{}
out[] = Extrude {{0, 0, t}} {{ Surface{{1}}; Layers{{1}}; {} }};
Physical Volume("body") = {{out[1]}};
Physical Surface("bottom") = {{1}};
Physical Surface("top") = {{out[0]}};
Physical Surface("ysym") = {{out[2]}};
Physical Surface("outer") = {{out[3]}};
Physical Surface("xsym") = {{out[4]}};
Physical Surface("inner") = {{out[5]}};
)",
                     num(a), num(b), num(t), nr + 1, nt + 1, hex ? "Recombine Surface{1};" : "",
                     hex || wedge ? "Recombine;" : "");
}


// ------------------------------------------------------------------------------------------
// Runs that keep every converged state (small meshes only), whatever the final status

/// Keeps the report and the state of every converged step.
struct EveryStep final : StepObserver {
  std::vector<StepReport> reports;
  std::vector<State> states;
  void step_done(const StepReport& r, const State& s, const RecoveredFields&) override {
    reports.push_back(r);
    states.push_back(s);
  }
};

/// A case run in-process with the direct solver, keeping every converged state. Unlike
/// run_case() it does not throw when the analysis stops: `result` says how it ended.
struct SteppedRun {
  Log log;
  LoadedCase loaded;
  EveryStep all;
  AnalysisResult result;
  double seconds = 0;  ///< wall time of the analysis (loading excluded)
  const Model& model() const { return *loaded.model; }
};

inline std::unique_ptr<SteppedRun> run_stepped(const fs::path& dir, const std::string& yaml,
                                               const std::string& name = "case.yaml") {
  write_file(dir / name, yaml);
  auto r = std::make_unique<SteppedRun>();
  r->log.quiet = true;
  r->loaded = load_case(dir / name, r->log);
  auto solver = make_serial_system(r->loaded.model->assembler(), r->loaded.model->dofs(),
                                   LinearSolverKind::direct);
  Timings timings;
  const auto t0 = std::chrono::steady_clock::now();
  r->result = run_analysis(*r->loaded.model, *solver, r->log, timings, r->all);
  r->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

/// Integration-point positions of the mesh, in the order of the state's point arrays.
inline std::vector<Vec3> point_positions(const Model& model) {
  const Mesh& mesh = model.mesh();
  std::vector<Vec3> out(static_cast<std::size_t>(model.n_points()));
  Vec3 x[max_cell_nodes];
  for (int c = 0; c < mesh.cells.size(); ++c) {
    const auto nodes = mesh.cells.nodes(c);
    const auto& tab = reference_table(mesh.cells.type[c]);
    for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh.x[nodes[a]];
    for (int q = 0; q < tab.n_points; ++q)
      out[static_cast<std::size_t>(model.point_offset(c) + q)] =
          point_position(tab, q, std::span<const Vec3>(x, nodes.size()));
  }
  return out;
}

/// A block (the regions of cube_msh() and box_geo()) on the rigid plane z = `plane_z` (normal
/// +z), held by rollers on x0 and y0 and at z on its top face z1, its bottom face z0 the
/// contact's nodes; the plane moves along z by `motion` (an expression in t). Elastic E, ν;
/// `extra` is inserted before the solver line, which gives `times` and tolerance 1e-12
/// (penetration 1e-12 too: the block's answers are exact); the reaction of z1 is reported.
inline std::string block_on_plane_case(const std::string& mesh, double plane_z,
                                       const std::string& motion, const std::string& times,
                                       double E, double nu, const std::string& extra = "") {
  return fmt::format(R"(mesh: {}
materials:
  - {{E: {}, nu: {}}}
boundary:
  - {{region: x0, displacement: {{x: 0}}}}
  - {{region: y0, displacement: {{y: 0}}}}
  - {{region: z1, displacement: {{z: 0}}}}
contact:
  - name: floor
    nodes: z0
    surface: {{plane: {{point: [0, 0, {}], normal: [0, 0, 1]}}}}
    motion: [0, 0, "{}"]
    penetration: 1e-12
{}solver: {{times: [{}], tolerance: 1e-12}}
output: {{reactions: [z1]}}
)",
                     mesh, num(E), num(nu), num(plane_z), motion, extra, times);
}

}  // namespace hencky::verify
