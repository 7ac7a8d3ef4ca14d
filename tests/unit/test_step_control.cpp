// Step control: cut-back halves a failing step at most `cutback` times and never takes a step
// of zero length; the converged steps before a failure are kept.
#include <gtest/gtest.h>

#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {
// A tolerance below round-off can never be met: every step attempt fails after max_iterations.
std::string case_text(const std::string& solver) {
  return "mesh: {file: cube.msh}\nmaterials: [{E: 2.0e11, nu: 0.3}]\nboundary:\n"
         "  - {region: x0, displacement: {x: 0, y: 0, z: 0}}\n"
         "  - {region: x1, traction: [\"1e6*t\", 0, 0]}\n"
         "solver: " + solver + "\n";
}
std::unique_ptr<InProcessRun> run(const TempDir& dir, const std::string& solver, Log& log) {
  write_file(dir / "cube.msh", cube_msh(2, GridCells::hex8, 0.0));
  write_file(dir / "case.yaml", case_text(solver));
  log.quiet = true;
  return run_in_process(dir / "case.yaml", log);
}
}  // namespace

TEST(StepControl, CutBackIsBoundedByItsDepth) {
  TempDir dir("cutback");
  Log log;
  auto r = run(dir, "{steps: 1, tolerance: 1.0e-30, max_iterations: 2, cutback: 3}", log);
  // t = 1 fails, then 0.5, 0.25 and 0.125 (depths 1..3): four attempts of two iterations.
  EXPECT_EQ(r->result.status, AnalysisStatus::not_converged);
  EXPECT_EQ(r->result.steps, 0);
  EXPECT_EQ(r->result.iterations, 8);
  EXPECT_NE(r->result.failure.find("t = 0.125"), std::string::npos) << r->result.failure;
}

TEST(StepControl, NoCutBackMeansOneAttempt) {
  TempDir dir("nocutback");
  Log log;
  auto r = run(dir, "{steps: 4, tolerance: 1.0e-30, max_iterations: 3, cutback: 0}", log);
  EXPECT_EQ(r->result.status, AnalysisStatus::not_converged);
  EXPECT_EQ(r->result.iterations, 3);
}

TEST(StepControl, ElasticStepsTakeOneIterationEach) {
  TempDir dir("onestep");
  Log log;
  auto r = run(dir, "{times: [0.1, 0.5, 1.0]}", log);
  ASSERT_EQ(r->result.status, AnalysisStatus::converged);
  ASSERT_EQ(r->states.reports.size(), 3u);
  for (const auto& rep : r->states.reports) {
    EXPECT_EQ(rep.iterations, 1);
    EXPECT_LT(rep.residual, 1e-10);
  }
  EXPECT_DOUBLE_EQ(r->states.reports.back().time, 1.0);
}

// The symbolic analysis is done once; a factorization is reused while the matrix does not
// change (E and ν constant: one for all steps, even as the temperature changes) and redone per
// step when E(T) makes the matrix change.
TEST(StepControl, FactorizationReusedWhileTheMatrixDoesNotChange) {
  for (const bool e_of_t : {false, true}) {
    TempDir dir(e_of_t ? "refactor" : "reuse");
    write_file(dir / "cube.msh", cube_msh(2, GridCells::hex8, 0.1));
    const std::string E = e_of_t ? "{temperature: [0, 500], value: [2.1e11, 1.6e11]}" : "2.0e11";
    write_file(dir / "case.yaml",
               "mesh: {file: cube.msh}\nmaterials: [{E: " + E + ", nu: 0.3, alpha: 1.2e-5}]\n"
               "temperature: {reference: 20, field: \"20 + 300*t*x\"}\nboundary:\n"
               "  - {region: x0, displacement: {x: 0, y: 0, z: 0}}\n"
               "  - {region: x1, traction: [\"1e6*t\", 0, 0]}\nsolver: {steps: 3}\n");
    Log log;
    log.quiet = true;
    auto r = run_in_process(dir / "case.yaml", log);
    ASSERT_EQ(r->result.status, AnalysisStatus::converged);
    EXPECT_EQ(r->solver_stats.n_analyses, 1);
    EXPECT_EQ(r->solver_stats.n_factorizations, e_of_t ? 3 : 1);
    EXPECT_EQ(r->solver_stats.n_solves, 3);
  }
}
