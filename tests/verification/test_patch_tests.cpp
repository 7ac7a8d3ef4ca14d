// Patch tests for every volume cell type on distorted meshes of the unit cube: a linear
// displacement field must be reproduced exactly (to round-off) and its stress must be D·ε at
// every integration point, whether the field is imposed on the whole boundary or results from
// uniform loads (traction, pressure, force) with minimal supports. Nothing here can be tuned:
// an element that fails these is inconsistent (wrong shape functions, wrong quadrature, wrong
// B matrix or D, wrong load integration).
#include <gtest/gtest.h>

#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {

constexpr double E = 2.1e11, nu = 0.3;

struct PatchMesh {
  std::string label;  ///< also the test name suffix
  std::string file;   ///< file name of the mesh in the case dir
  std::string text;   ///< its contents
  int order;          ///< mesh.order (0: as written)
  CellType expect;    ///< a cell type the mesh must contain
};

std::ostream& operator<<(std::ostream& o, const PatchMesh& m) { return o << m.label; }

std::vector<PatchMesh> patch_meshes() {
  // Unstructured Gmsh tetrahedra (every interior node is "distorted" by construction) and
  // hand-written structured meshes whose interior nodes are moved by up to 25% of the step.
  return {
      {"tet4", "box.geo", box_geo(1, 1, 1, 0.3), 1, CellType::tet4},
      {"tet10", "box.geo", box_geo(1, 1, 1, 0.45), 2, CellType::tet10},
      {"hex8", "cube.msh", cube_msh(4, GridCells::hex8, 0.25), 0, CellType::hex8},
      {"hex20", "cube.msh", cube_msh(3, GridCells::hex20, 0.25), 0, CellType::hex20},
      {"wedge6", "cube.msh", cube_msh(4, GridCells::wedge6, 0.25), 0, CellType::wedge6},
      {"mixed_hex8_wedge6", "cube.msh", cube_msh(4, GridCells::mixed, 0.25), 0, CellType::wedge6},
  };
}

std::string case_head(const PatchMesh& m) {
  std::string s = "title: patch test " + m.label + "\nmesh:\n  file: " + m.file + "\n";
  if (m.order > 0) s += fmt::format("  order: {}\n", m.order);
  s += "materials:\n  - name: m\n    E: " + num(E) + "\n    nu: " + num(nu) + "\n";
  return s;
}

const char* const faces[] = {"x0", "x1", "y0", "y1", "z0", "z1"};

/// Largest |u_h − (c + G x)| over all nodes, relative to the largest |c + G x|, and the number
/// of nodes not on the boundary.
struct NodalCheck {
  double rel_error = 0;
  int interior = 0;
};
NodalCheck check_nodes(const Run& r, const Mat3& G, const Vec3& c) {
  const Mesh& mesh = r.model().mesh();
  std::vector<bool> on_boundary(mesh.n_nodes(), false);
  for (const auto& reg : mesh.regions)
    if (reg.dim == 2)
      for (int n : reg.nodes) on_boundary[n] = true;
  double err = 0, ref = 0;
  NodalCheck out;
  for (int n = 0; n < mesh.n_nodes(); ++n) {
    const Vec3 ue = c + G * mesh.x[n];
    err = std::max(err, (r.u(n) - ue).lpNorm<Eigen::Infinity>());
    ref = std::max(ref, ue.lpNorm<Eigen::Infinity>());
    if (!on_boundary[n]) ++out.interior;
  }
  out.rel_error = err / ref;
  return out;
}

/// Largest |σ_q − σ| over all integration points, relative to |σ|∞.
double check_points(const Run& r, const Voigt& sigma) {
  double err = 0;
  for (const Voigt& s : r.state().stress) err = std::max(err, (s - sigma).lpNorm<Eigen::Infinity>());
  return err / sigma.lpNorm<Eigen::Infinity>();
}

bool has_type(const Mesh& mesh, CellType t) {
  return std::find(mesh.cells.type.begin(), mesh.cells.type.end(), t) != mesh.cells.type.end();
}

class PatchTest : public ::testing::TestWithParam<PatchMesh> {};

// u = c + G x prescribed on every boundary node: the interior nodes must take the same linear
// field and every integration point must carry σ = D ε(G).
TEST_P(PatchTest, LinearDisplacementOnWholeBoundary) {
  const PatchMesh& m = GetParam();
  TempDir dir("patch-u-" + m.label);
  write_file(dir / m.file, m.text);
  Mat3 G;
  G << 1.0e-3, 2.0e-4, -3.0e-4,  //
      -5.0e-4, 5.0e-4, 4.0e-4,   //
      6.0e-4, -1.0e-4, 7.0e-4;
  const Vec3 c(1e-4, -2e-4, 3e-4);
  std::string y = case_head(m) + "boundary:\n";
  for (const char* f : faces)
    y += fmt::format("  - region: {}\n    displacement: {{x: \"{}\", y: \"{}\", z: \"{}\"}}\n", f,
                     linear_expression(G, c, 0), linear_expression(G, c, 1),
                     linear_expression(G, c, 2));
  auto r = run_case(dir.path(), y);
  ASSERT_TRUE(has_type(r->model().mesh(), m.expect));

  const NodalCheck nodes = check_nodes(*r, G, c);
  const Voigt sigma = ElasticConstants{E, nu, 0}.stiffness() * strain_of_gradient(G);
  const double stress_err = check_points(*r, sigma);
  report(fmt::format("patch u-prescribed {:<18} cells {:5d} interior nodes {:4d}  max|du|/|u| {:.2e}  "
                     "max|dsigma|/|sigma| {:.2e}",
                     m.label, r->model().mesh().cells.size(), nodes.interior, nodes.rel_error,
                     stress_err));
  RecordProperty("u_rel_error", fmt::format("{:.3e}", nodes.rel_error));
  RecordProperty("stress_rel_error", fmt::format("{:.3e}", stress_err));
  EXPECT_GT(nodes.interior, 0);
  EXPECT_LT(nodes.rel_error, 1e-10);
  EXPECT_LT(stress_err, 1e-8);
}

// A general uniform stress (all six components) produced by the tractions σ·n on the six
// faces, the body held by three points only (3-2-1: no reaction, the loads are
// self-equilibrated). The displacement is the linear field ε x plus the rigid rotation that
// the point supports select.
TEST_P(PatchTest, UniformStressFromTractionsWithPointSupports) {
  const PatchMesh& m = GetParam();
  TempDir dir("patch-t-" + m.label);
  write_file(dir / m.file, m.text);
  Voigt sigma;
  sigma << 30e6, -20e6, 10e6, 5e6, -8e6, 12e6;  // {11, 22, 33, 23, 31, 12}
  Mat3 S;
  S << sigma[0], sigma[5], sigma[4], sigma[5], sigma[1], sigma[3], sigma[4], sigma[3], sigma[2];
  // u = G x with G upper triangular: the symmetric part is ε, the skew part is the rotation
  // that keeps u_y = u_z = 0 at p100 and u_z = 0 at p010.
  const Voigt eps = ElasticConstants{E, nu, 0}.compliance() * sigma;
  Mat3 G;
  G << eps[0], eps[5], eps[4], 0, eps[1], eps[3], 0, 0, eps[2];

  std::string y = case_head(m) + "boundary:\n";
  for (int f = 0; f < 6; ++f) {
    Vec3 n = Vec3::Zero();
    n[f / 2] = f % 2 ? 1.0 : -1.0;
    const Vec3 t = S * n;
    y += fmt::format("  - region: {}\n    traction: [{}, {}, {}]\n", faces[f], num(t[0]), num(t[1]),
                     num(t[2]));
  }
  y += "  - region: p000\n    displacement: {x: 0, y: 0, z: 0}\n"
       "  - region: p100\n    displacement: {y: 0, z: 0}\n"
       "  - region: p010\n    displacement: {z: 0}\n";
  y += "output:\n  reactions: [p000, p100, p010]\n";
  auto r = run_case(dir.path(), y);
  ASSERT_TRUE(has_type(r->model().mesh(), m.expect));

  const NodalCheck nodes = check_nodes(*r, G, Vec3::Zero());
  const double stress_err = check_points(*r, sigma);
  double reaction = 0;
  for (const Vec3& f : region_reactions(r->model(), r->state())) reaction = std::max(reaction, f.norm());
  reaction /= sigma.lpNorm<Eigen::Infinity>();  // per unit face area of the unit cube
  report(fmt::format("patch traction    {:<18} max|du|/|u| {:.2e}  max|dsigma|/|sigma| {:.2e}  "
                     "|reactions|/|sigma A| {:.2e}",
                     m.label, nodes.rel_error, stress_err, reaction));
  RecordProperty("u_rel_error", fmt::format("{:.3e}", nodes.rel_error));
  RecordProperty("stress_rel_error", fmt::format("{:.3e}", stress_err));
  EXPECT_LT(nodes.rel_error, 1e-10);
  EXPECT_LT(stress_err, 1e-8);
  EXPECT_LT(reaction, 1e-8);
}

// Uniform triaxial stress diag(s_x, −p, F/A) from a traction, a pressure and a total force on
// three faces, with rollers (normal displacement 0) on the three opposite faces.
TEST_P(PatchTest, UniformStressFromTractionPressureForceWithRollers) {
  const PatchMesh& m = GetParam();
  TempDir dir("patch-p-" + m.label);
  write_file(dir / m.file, m.text);
  const double sx = 40e6, p = 15e6, F = 25e6;  // unit cube: the z1 face has area 1
  Voigt sigma;
  sigma << sx, -p, F, 0, 0, 0;
  const Voigt eps = ElasticConstants{E, nu, 0}.compliance() * sigma;
  const Mat3 G = Vec3(eps[0], eps[1], eps[2]).asDiagonal();
  std::string y = case_head(m) + "boundary:\n";
  y += "  - region: x0\n    displacement: {x: 0}\n"
       "  - region: y0\n    displacement: {y: 0}\n"
       "  - region: z0\n    displacement: {z: 0}\n";
  y += fmt::format("  - region: x1\n    traction: [{}, 0, 0]\n", num(sx));
  y += fmt::format("  - region: y1\n    pressure: {}\n", num(p));
  y += fmt::format("  - region: z1\n    force: [0, 0, {}]\n", num(F));
  auto r = run_case(dir.path(), y);
  ASSERT_TRUE(has_type(r->model().mesh(), m.expect));

  const NodalCheck nodes = check_nodes(*r, G, Vec3::Zero());
  const double stress_err = check_points(*r, sigma);
  report(fmt::format("patch rollers     {:<18} max|du|/|u| {:.2e}  max|dsigma|/|sigma| {:.2e}",
                     m.label, nodes.rel_error, stress_err));
  RecordProperty("u_rel_error", fmt::format("{:.3e}", nodes.rel_error));
  RecordProperty("stress_rel_error", fmt::format("{:.3e}", stress_err));
  EXPECT_LT(nodes.rel_error, 1e-10);
  EXPECT_LT(stress_err, 1e-8);
}

INSTANTIATE_TEST_SUITE_P(PatchCells, PatchTest, ::testing::ValuesIn(patch_meshes()),
                         [](const ::testing::TestParamInfo<PatchMesh>& info) { return info.param.label; });

}  // namespace
