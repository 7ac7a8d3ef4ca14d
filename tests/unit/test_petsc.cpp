// The PETSc back end in one process (the runs on several ranks are end-to-end tests:
// tests/cli/cases/40_parallel.sh): the METIS partition, and the same cases solved with the
// serial direct solver, with PETSc's MUMPS and with CG + GAMG, compared field by field. MUMPS
// must agree with CHOLMOD to round-off (1e-10 relative); CG + GAMG, whose linear solves stop at
// a relative residual of 1e-10, within the Newton iteration's own tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "input/gmsh_reader.hpp"
#include "parallel/partition.hpp"
#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {

TEST(Partition, SplitsTheCellsEvenlyAndGivesEachNodeTheLowestOwner) {
  TempDir dir("partition");
  write_file(dir / "box.geo", box_geo(2, 1, 1, 0.2));
  MeshReadOptions opt;
  opt.order = 2;
  const Mesh mesh = read_gmsh(dir / "box.geo", opt);
  const int n_cells = mesh.cells.size();
  ASSERT_GT(n_cells, 500);
  for (int parts : {1, 2, 3}) {
    std::vector<int> cells_of(parts, 0), nodes_of(parts, 0);
    const std::vector<int> owner = split_cells(mesh, parts);
    for (int rank = 0; rank < parts; ++rank) {
      const Partition p = partition_from(mesh, owner, parts, rank);
      ASSERT_EQ(static_cast<int>(p.cell_owner.size()), n_cells);
      for (int c = 0; c < n_cells; ++c) {
        ASSERT_GE(p.cell_owner[c], 0);
        ASSERT_LT(p.cell_owner[c], parts);
        EXPECT_EQ(p.owns_cell(c), p.cell_owner[c] == rank);
      }
      // The same split every time (every rank's copy of the mesh gets the same).
      EXPECT_EQ(p.cell_owner, split_cells(mesh, parts));
      for (int n = 0; n < mesh.n_nodes(); ++n) {
        int lowest = parts;
        for (int c = 0; c < n_cells; ++c) {
          const auto nodes = mesh.cells.nodes(c);
          if (std::find(nodes.begin(), nodes.end(), n) != nodes.end())
            lowest = std::min(lowest, p.cell_owner[c]);
        }
        if (n % 97 == 0) {  // a sample
          EXPECT_EQ(p.node_owner[n], lowest) << "node " << n;
        }
      }
      cells_of[rank] = p.owned_cells;
      nodes_of[rank] = p.owned_nodes;
    }
    int total_cells = 0, total_nodes = 0;
    for (int r = 0; r < parts; ++r) {
      total_cells += cells_of[r], total_nodes += nodes_of[r];
      // METIS balances cells to its default 3 % imbalance.
      EXPECT_LE(cells_of[r], 1.031 * n_cells / parts + 1) << parts << " parts";
      EXPECT_GE(cells_of[r], 0.9 * n_cells / parts) << parts << " parts";
    }
    EXPECT_EQ(total_cells, n_cells);
    EXPECT_EQ(total_nodes, mesh.n_nodes());
  }
}

/// Largest |a − b| over largest |a|.
double relative_difference(std::span<const double> a, std::span<const double> b) {
  double d = 0, s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    s = std::max(s, std::abs(a[i]));
  }
  return s > 0 ? d / s : d;
}
double relative_difference(const std::vector<Voigt>& a, const std::vector<Voigt>& b) {
  return relative_difference(std::span<const double>(a.front().data(), 6 * a.size()),
                             std::span<const double>(b.front().data(), 6 * b.size()));
}

struct Comparison {
  double u = 0, stress = 0, eps_p = 0, contact = 0;  ///< relative differences
  double eps_p_max = 0, contact_max = 0;             ///< of the direct run: not a trivial case
  int direct_iterations = 0, petsc_iterations = 0;
  std::string method;
  void report(const std::string& label) const {
    verify::report(fmt::format("{}, {}: u {:.2e}, σ {:.2e}, ε̃p {:.2e}, contact {:.2e}; {} "
                               "iterations (direct {})",
                               label, method, u, stress, eps_p, contact, petsc_iterations,
                               direct_iterations));
  }
};

/// Runs the case make_case(solver_keys) (in `dir`, its mesh already written) with the serial
/// direct solver, then with solver.linear: petsc and `options`, and compares the last states.
Comparison compare_with_direct(const TempDir& dir,
                               const std::function<std::string(const std::string&)>& make_case,
                               const std::string& options) {
  auto direct = run_case(dir.path(), make_case("linear: direct"), "direct.yaml");
  const std::string keys =
      options.empty() ? "linear: petsc"
                      : fmt::format("linear: petsc, petsc_options: \"{}\"", options);
  auto petsc = run_case(dir.path(), make_case(keys), "petsc.yaml");
  const State &a = direct->state(), &b = petsc->state();
  Comparison c;
  c.u = relative_difference(a.u, b.u);
  c.stress = relative_difference(a.stress, b.stress);
  c.eps_p = relative_difference(a.eps_p_eq, b.eps_p_eq);
  c.contact = relative_difference(a.f_contact, b.f_contact);
  c.eps_p_max = *std::max_element(a.eps_p_eq.begin(), a.eps_p_eq.end());
  for (double f : a.f_contact) c.contact_max = std::max(c.contact_max, std::abs(f));
  c.direct_iterations = direct->run->result.iterations;
  c.petsc_iterations = petsc->run->result.iterations;
  c.method = petsc->run->solver_stats.description;
  return c;
}

const char* const mumps = "-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps";

// Thermo-elastic: a distorted 20-node hexahedral cube on rollers, heated non-uniformly with
// temperature-dependent E, and pulled on x1.
std::string thermal_case(const std::string& solver) {
  return fmt::format(R"Y(mesh: {{file: cube.msh}}
materials:
  - {{E: {{temperature: [0, 500], value: [2.1e11, 1.6e11]}}, nu: 0.3, alpha: 1.2e-5}}
temperature: {{reference: 20, field: "20 + 300*t*(x + 0.5*y*z)"}}
boundary:
  - {{region: x0, displacement: {{x: 0}}}}
  - {{region: y0, displacement: {{y: 0}}}}
  - {{region: z0, displacement: {{z: 0}}}}
  - {{region: x1, traction: [1e8, 0, 0]}}
solver: {{steps: 2, {}}}
)Y",
                     solver);
}

TEST(PetscSerial, ThermoElasticMatchesTheDirectSolver) {
  TempDir dir("petsc-thermal");
  write_file(dir / "cube.msh", cube_msh(3, GridCells::hex20, 0.25));
  const Comparison m = compare_with_direct(dir, thermal_case, mumps);
  m.report("thermo-elastic cube");
  EXPECT_NE(m.method.find("mumps"), std::string::npos);
  EXPECT_LT(m.u, 1e-10);
  EXPECT_LT(m.stress, 1e-10);
  const Comparison g = compare_with_direct(dir, thermal_case, "");
  g.report("thermo-elastic cube");
  EXPECT_NE(g.method.find("cg + gamg"), std::string::npos);
  EXPECT_LT(g.u, 1e-8);
  EXPECT_LT(g.stress, 1e-7);
}

// Elasto-plastic with contact: a rigid sphere pressed into the underside of a cube of linearly
// hardening steel, newton (the last state compared is the peak, with the contact forces).
std::string indentation_case(const std::string& solver) {
  return fmt::format(R"Y(mesh: {{file: cube.msh}}
materials:
  - E: 2.1e11
    nu: 0.3
    plasticity: {{linear: {{yield: 2.5e8, hardening: 2e10}}}}
boundary:
  - {{region: x0, displacement: {{x: 0}}}}
  - {{region: y0, displacement: {{y: 0}}}}
  - {{region: z1, displacement: {{z: 0}}}}
contact:
  - name: ball
    nodes: z0
    surface: {{sphere: {{center: [0, 0, -2], radius: 2}}}}
    motion: [0, 0, "4e-3*t"]
solver: {{times: [0.25, 0.5, 0.75, 1], tolerance: 1e-9, {}}}
)Y",
                     solver);
}

TEST(PetscSerial, PlasticContactMatchesTheDirectSolver) {
  TempDir dir("petsc-indentation");
  write_file(dir / "cube.msh", cube_msh(4, GridCells::hex20, 0.1));
  const Comparison m = compare_with_direct(dir, indentation_case, mumps);
  m.report("plastic indentation");
  EXPECT_GT(m.eps_p_max, 1e-4);    // it flowed
  EXPECT_GT(m.contact_max, 1e6);   // and it touched
  EXPECT_LT(m.u, 1e-9);
  EXPECT_LT(m.stress, 1e-9);
  EXPECT_LT(m.eps_p, 1e-9);
  EXPECT_LT(m.contact, 1e-9);
  EXPECT_EQ(m.petsc_iterations, m.direct_iterations);
  const Comparison g = compare_with_direct(dir, indentation_case, "");
  g.report("plastic indentation");
  EXPECT_LT(g.u, 1e-7);
  EXPECT_LT(g.stress, 1e-6);
  EXPECT_LT(g.eps_p, 1e-6);
  EXPECT_LT(g.contact, 1e-6);
}

TEST(PetscSerial, RefusedOptionsAreAnInputErrorNamingTheKey) {
  TempDir dir("petsc-options");
  write_file(dir / "cube.msh", cube_msh(1, GridCells::hex8, 0));
  write_file(dir / "case.yaml", thermal_case("linear: petsc, petsc_options: \"-pc_type nonsense\""));
  Log log;
  log.quiet = true;
  try {
    run_in_process(dir / "case.yaml", log);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'solver.petsc_options'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nonsense"), std::string::npos) << e.what();
  }
  // A misspelt option is a warning, and the run goes on with the defaults.
  auto r = run_case(dir.path(),
                    thermal_case("linear: petsc, petsc_options: \"-ksp_rtoll 1e-3\""), "typo.yaml");
  const auto& w = r->log.warnings();
  EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](const std::string& s) {
    return s.find("'-ksp_rtoll' was not used") != std::string::npos;
  }));
}

}  // namespace
