// Reading and validating case files (input/case_reader.hpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include "input/case_reader.hpp"

namespace hencky {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// Each test gets a fresh folder with a (dummy) mesh file part.msh in it.
class CaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("hencky-case-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(counter++) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    write("part.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  Case read(const std::string& yaml) { return read_case(write("case.yaml", yaml)); }

  /// The message of the InputError that reading `yaml` throws; fails the test when none.
  std::string error(const std::string& yaml) {
    try {
      read(yaml);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "expected an InputError for:\n" << yaml;
    return {};
  }

  /// Expects an InputError whose message contains every part.
  void expect_error(const std::string& yaml, std::initializer_list<std::string> parts) {
    const std::string m = error(yaml);
    for (const auto& p : parts) EXPECT_TRUE(has(m, p)) << "missing \"" << p << "\" in:\n" << m;
  }

  fs::path dir_;
};

// A small valid case to break in the error tests.
const std::string base = R"(mesh:
  file: part.msh
materials:
  - name: steel
    E: 2.1e11
    nu: 0.3
boundary:
  - region: bottom
    displacement: {x: 0, y: 0, z: 0}
)";

// The same with alpha (required with a temperature), on the same lines.
const std::string tbase = R"(mesh:
  file: part.msh
materials:
  - {name: steel,
     E: 2.1e11, nu: 0.3,
     alpha: 1.2e-5}
boundary:
  - region: bottom
    displacement: {x: 0, y: 0, z: 0}
)";

TEST_F(CaseTest, FullCaseIsReadCorrectly) {
  write("meshes/cyl.msh", "dummy");
  const Case c = read(R"(title: Thick cylinder, internal pressure
mesh:
  file: meshes/../meshes/cyl.msh
  order: 2
  scale: 1.0e-3
materials:
  - name: steel
    regions: [body, ring]
    E: {temperature: [20, 500], value: [2.1e11, 1.7e11]}
    nu: 0.3
    alpha: {temperature: [20, 300, 600], value: [1.2e-5, 1.3e-5, 1.4e-5]}
  - name: copper
    regions: core
    E: 1.1e11
    nu: "0.34"
    alpha: 1.7e-5
temperature:
  reference: 20
  field: "20 + 300*t*x/0.2"
boundary:
  - region: bottom
    displacement: {z: 0}
  - region: side
    displacement: {x: 0, y: "0.001*t"}
  - region: inner
    pressure: "100e6*t"
  - region: end
    traction: [0, "-1e6*t", 0]
  - region: top
    force: [0, 0, "-1000*t"]
body_force: [0, 0, "-9.81*7850"]
solver:
  scheme: initial-strain-stiffness
  curve_form: strain
  steps: 4
  end: 2.0
  max_iterations: 30
  tolerance: 1.0e-8
  relaxation: 0.8
  correction: 0
  cutback: 2
  linear: iterative
  mechanism_limit: 0.2
  predictor: none
output:
  dir: results
  every: 2
  probes:
    - name: A
      point: [0.1, 0.0, 0]
    - name: B-2
      point: [0, 0.2, 1e-3]
  reactions: [bottom, side]
)");
  EXPECT_EQ(c.file, dir_ / "case.yaml");
  EXPECT_EQ(c.title, "Thick cylinder, internal pressure");
  EXPECT_EQ(c.mesh.file, dir_ / "meshes" / "cyl.msh");
  EXPECT_EQ(c.mesh.order, 2);
  EXPECT_DOUBLE_EQ(c.mesh.scale, 1e-3);
  EXPECT_EQ(c.mesh.where.key, "mesh.file");
  EXPECT_EQ(c.mesh.where.line, 3);

  ASSERT_EQ(c.materials.size(), 2u);
  const MaterialSpec& steel = c.materials[0];
  EXPECT_EQ(steel.name, "steel");
  EXPECT_EQ(steel.regions, (std::vector<std::string>{"body", "ring"}));
  ASSERT_EQ(steel.region_where.size(), 2u);
  EXPECT_EQ(steel.region_where[1].key, "materials[0].regions[1]");
  EXPECT_EQ(steel.region_where[1].line, 8);
  EXPECT_FALSE(steel.E.is_constant());
  EXPECT_DOUBLE_EQ(steel.E(20), 2.1e11);
  EXPECT_DOUBLE_EQ(steel.E(260), 1.9e11);
  bool outside = false;
  EXPECT_DOUBLE_EQ(steel.E(600, &outside), 1.7e11);
  EXPECT_TRUE(outside);
  EXPECT_DOUBLE_EQ(steel.E(500, &outside), 1.7e11);
  EXPECT_FALSE(outside);
  EXPECT_DOUBLE_EQ(steel.E(0, &outside), 2.1e11);
  EXPECT_TRUE(outside);
  EXPECT_TRUE(steel.nu.is_constant());
  EXPECT_DOUBLE_EQ(steel.nu(1000, &outside), 0.3);
  EXPECT_FALSE(outside);
  EXPECT_NEAR(steel.alpha(450), 1.35e-5, 1e-20);
  EXPECT_EQ(steel.E.where.key, "materials[0].E");
  const MaterialSpec& copper = c.materials[1];
  EXPECT_EQ(copper.regions, (std::vector<std::string>{"core"}));
  EXPECT_DOUBLE_EQ(copper.nu(20), 0.34);
  EXPECT_DOUBLE_EQ(copper.alpha(20), 1.7e-5);

  EXPECT_TRUE(c.temperature.given);
  EXPECT_DOUBLE_EQ(c.temperature.reference, 20);
  ASSERT_TRUE(c.temperature.field);
  EXPECT_FALSE(c.temperature.file);
  EXPECT_DOUBLE_EQ((*c.temperature.field)(0.2, 0, 0, 1), 320);

  ASSERT_EQ(c.boundary.size(), 5u);
  EXPECT_EQ(c.boundary[0].kind, BoundaryKind::displacement);
  EXPECT_FALSE(c.boundary[0].components[0]);
  EXPECT_FALSE(c.boundary[0].components[1]);
  ASSERT_TRUE(c.boundary[0].components[2]);
  EXPECT_DOUBLE_EQ((*c.boundary[0].components[2])(1, 1, 1, 1), 0);
  EXPECT_EQ(c.boundary[0].where.key, "boundary[0].region");
  EXPECT_EQ(c.boundary[0].where.line, 21);
  EXPECT_EQ(c.boundary[1].region, "side");
  ASSERT_TRUE(c.boundary[1].components[1]);
  EXPECT_DOUBLE_EQ((*c.boundary[1].components[1])(0, 0, 0, 2), 0.002);
  EXPECT_FALSE(c.boundary[1].components[2]);
  EXPECT_EQ(c.boundary[2].kind, BoundaryKind::pressure);
  ASSERT_TRUE(c.boundary[2].pressure);
  EXPECT_DOUBLE_EQ((*c.boundary[2].pressure)(0, 0, 0, 0.5), 50e6);
  EXPECT_EQ(c.boundary[3].kind, BoundaryKind::traction);
  EXPECT_DOUBLE_EQ((*c.boundary[3].components[1])(0, 0, 0, 1), -1e6);
  EXPECT_EQ(c.boundary[4].kind, BoundaryKind::force);
  EXPECT_EQ(std::string(to_string(c.boundary[4].kind)), "force");
  EXPECT_DOUBLE_EQ((*c.boundary[4].components[2])(0, 0, 0, 2), -2000);
  EXPECT_EQ(c.boundary[4].components[2]->where().key, "boundary[4].force[2]");

  ASSERT_TRUE(c.body_force);
  EXPECT_DOUBLE_EQ((*c.body_force)[2](0, 0, 0, 0), -9.81 * 7850);
  EXPECT_TRUE((*c.body_force)[2].is_constant());

  EXPECT_EQ(c.solver.scheme, SchemeKind::initial_strain_stiffness);
  EXPECT_EQ(c.solver.curve_form, CurveForm::strain);
  EXPECT_EQ(c.solver.times.all(), (std::vector<double>{0.5, 1.0, 1.5, 2.0}));
  EXPECT_EQ(c.solver.max_iterations, 30);
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-8);
  EXPECT_DOUBLE_EQ(c.solver.relaxation, 0.8);
  EXPECT_DOUBLE_EQ(c.solver.mechanism_limit, 0.2);
  EXPECT_FALSE(c.solver.extrapolate);
  EXPECT_DOUBLE_EQ(c.solver.correction(0, 0, 0, 1), 0);
  EXPECT_EQ(c.solver.cutback, 2);
  EXPECT_EQ(c.solver.linear, SolverSpec::Linear::iterative);

  EXPECT_EQ(c.output.dir, dir_ / "results");
  EXPECT_EQ(c.output.every, 2);
  ASSERT_EQ(c.output.probes.size(), 2u);
  EXPECT_EQ(c.output.probes[0].name, "A");
  EXPECT_DOUBLE_EQ(c.output.probes[0].point.x(), 0.1);
  EXPECT_DOUBLE_EQ(c.output.probes[1].point.z(), 1e-3);
  EXPECT_EQ(c.output.probes[1].where.key, "output.probes[1].point");
  EXPECT_EQ(c.output.reactions, (std::vector<std::string>{"bottom", "side"}));
  EXPECT_EQ(c.output.reaction_where[1].key, "output.reactions[1]");
}

TEST_F(CaseTest, Defaults) {
  const Case c = read(base);
  EXPECT_EQ(c.title, "case");
  EXPECT_EQ(c.mesh.file, dir_ / "part.msh");
  EXPECT_EQ(c.mesh.order, 0);
  EXPECT_DOUBLE_EQ(c.mesh.scale, 1.0);
  ASSERT_EQ(c.materials.size(), 1u);
  EXPECT_TRUE(c.materials[0].regions.empty());  // the whole mesh
  EXPECT_DOUBLE_EQ(c.materials[0].alpha(100), 0.0);
  EXPECT_FALSE(c.temperature.given);
  EXPECT_FALSE(c.body_force);
  EXPECT_EQ(c.solver.scheme, SchemeKind::newton);
  EXPECT_EQ(c.solver.curve_form, CurveForm::stress);
  EXPECT_EQ(c.solver.times.all(), (std::vector<double>{1.0}));
  EXPECT_EQ(c.solver.max_iterations, 0);  // auto
  EXPECT_TRUE(c.solver.line_search);       // auto
  EXPECT_DOUBLE_EQ(c.solver.tolerance, 1e-6);
  EXPECT_DOUBLE_EQ(c.solver.relaxation, 0.0);  // auto
  EXPECT_DOUBLE_EQ(c.solver.correction(0, 0, 0, 1), 1.0);
  EXPECT_EQ(c.solver.cutback, 4);
  EXPECT_DOUBLE_EQ(c.solver.mechanism_limit, 0.05);
  EXPECT_TRUE(c.solver.extrapolate);
  EXPECT_EQ(c.solver.acceleration, SolverSpec::Acceleration::automatic);
  EXPECT_EQ(c.solver.linear, SolverSpec::Linear::automatic);
  EXPECT_EQ(c.output.dir, dir_ / "case.out");
  EXPECT_EQ(c.output.every, 1);
  EXPECT_TRUE(c.output.probes.empty());
  EXPECT_TRUE(c.output.reactions.empty());
}

TEST_F(CaseTest, StepTimes) {
  EXPECT_EQ(read(base + "solver: {times: [0.2, 0.5, 1.0]}\n").solver.times.all(),
            (std::vector<double>{0.2, 0.5, 1.0}));
  EXPECT_EQ(read(base + "solver: {steps: 4}\n").solver.times.all(),
            (std::vector<double>{0.25, 0.5, 0.75, 1.0}));
  EXPECT_EQ(read(base + "solver: {end: 3}\n").solver.times.all(), (std::vector<double>{3.0}));
  expect_error(base + "solver:\n  steps: 2\n  times: [1, 2]\n",
               {"case.yaml:11:3", "'solver.steps'", "not both"});
  expect_error(base + "solver:\n  times: [0.5, 0.5]\n",
               {"case.yaml:11:16", "'solver.times[1]'", "strictly increasing", "0.5 after 0.5"});
  expect_error(base + "solver:\n  times: [0, 1]\n", {"'solver.times[0]'", "> 0"});
  expect_error(base + "solver:\n  steps: 0\n", {"'solver.steps'", ">= 1", "found 0"});
  expect_error(base + "solver:\n  steps: 2.5\n", {"'solver.steps'", "whole number", "'2.5'"});
  expect_error(base + "solver:\n  end: -1\n", {"'solver.end'", "> 0"});
}

TEST_F(CaseTest, IterationLimitAndLineSearch) {
  EXPECT_EQ(read(base + "solver: {max_iterations: auto}\n").solver.max_iterations, 0);
  EXPECT_EQ(read(base + "solver: {max_iterations: 7}\n").solver.max_iterations, 7);
  EXPECT_FALSE(read(base + "solver: {line_search: none}\n").solver.line_search);
  EXPECT_TRUE(read(base + "solver: {line_search: auto}\n").solver.line_search);
  expect_error(base + "solver:\n  max_iterations: 0\n", {"'solver.max_iterations'", "found 0"});
  expect_error(base + "solver:\n  line_search: secant\n",
               {"case.yaml:11:16", "'solver.line_search'", "'secant'", "'auto', 'none'"});
}

TEST_F(CaseTest, StepCountIsBoundedAndEqualStepsAreARule) {
  // At most max_steps steps (solver.steps or the length of solver.times).
  expect_error(base + "solver:\n  steps: 1000000000\n",
               {"case.yaml:11:10", "'solver.steps'", "at most 1000000 steps", "found 1000000000"});
  expect_error(base + "solver:\n  steps: 1000001\n", {"'solver.steps'", "at most 1000000"});
  expect_error(base + "solver:\n  steps: 99999999999999999999\n",
               {"'solver.steps'", "whole number"});
  std::string many = base + "solver:\n  times: [";
  for (long k = 1; k <= max_steps + 1; ++k) {
    if (k > 1) many += ',';
    many += std::to_string(k);
  }
  expect_error(many + "]\n", {"'solver.times'", "at most 1000000 step end times", "1000001"});
  // The largest count is kept as its rule: no list of a million times.
  const Case c = read(base + "solver: {steps: 1000000, end: 2}\n");
  ASSERT_EQ(c.solver.times.size(), 1000000u);
  EXPECT_EQ(c.solver.times[0], 2.0 * 1 / 1000000);
  EXPECT_EQ(c.solver.times[499999], 1.0);
  EXPECT_EQ(c.solver.times.back(), 2.0);
  // The same times as the list the reader built before: end·k/n, in that order of operations.
  const Case c3 = read(base + "solver: {steps: 7, end: 0.3}\n");
  ASSERT_EQ(c3.solver.times.size(), 7u);
  for (int k = 1; k <= 7; ++k) EXPECT_EQ(c3.solver.times[k - 1], 0.3 * k / 7) << k;
}

TEST_F(CaseTest, TemperatureFile) {
  write("temps.csv", "node, 0.5, 1.0\n1, 20, 100\n\n2,20,150.5\r\n7 , 21 , 1e2\n");
  const Case c = read(tbase + "temperature:\n  reference: 20\n  field: {file: temps.csv}\n");
  ASSERT_TRUE(c.temperature.file);
  EXPECT_FALSE(c.temperature.field);
  const TemperatureFile& f = *c.temperature.file;
  EXPECT_EQ(f.path, dir_ / "temps.csv");
  EXPECT_EQ(f.times, (std::vector<double>{0.5, 1.0}));
  EXPECT_EQ(f.node_tags, (std::vector<long>{1, 2, 7}));
  EXPECT_EQ(f.values, (std::vector<double>{20, 100, 20, 150.5, 21, 100}));
  EXPECT_DOUBLE_EQ(f.at(1, 0.75), 85.25);
  EXPECT_DOUBLE_EQ(f.at(1, 0.0), 20);
  EXPECT_DOUBLE_EQ(f.at(1, 2.0), 150.5);
}

TEST_F(CaseTest, TemperatureFileErrors) {
  const std::string yaml = tbase + "temperature:\n  reference: 20\n  field: {file: temps.csv}\n";
  write("temps.csv", "node,0.5,1.0\n1,20,100\n2,20,abc\n");
  expect_error(yaml,
               {"temps.csv:3:6", "'temperature.field.file'", "expected a temperature", "'abc'"});
  write("temps.csv", "node,0.5,1.0\n1,20,100\n2,20\n");
  expect_error(yaml, {"temps.csv:3", "expected 3 values", "found 2"});
  write("temps.csv", "node,1.0,0.5\n1,20,100\n");
  expect_error(yaml, {"temps.csv:1:10", "strictly increasing"});
  write("temps.csv", "id,1.0\n1,20\n");
  expect_error(yaml, {"temps.csv:1:1", "header row", "'id'"});
  write("temps.csv", "node,1.0\n1,20\n1,30\n");
  expect_error(yaml, {"temps.csv:3:1", "node 1 is listed twice (first at line 2)"});
  write("temps.csv", "node,1.0\n-4,20\n");
  expect_error(yaml, {"temps.csv:2:1", "node tag", "'-4'"});
  write("temps.csv", "node,1.0\n");
  expect_error(yaml, {"temps.csv", "no node rows"});
  write("temps.csv", "");
  expect_error(yaml, {"temps.csv", "empty"});
  fs::remove(dir_ / "temps.csv");
  expect_error(yaml, {"case.yaml:12:17", "'temperature.field.file'", "temperature file not found",
                      (dir_ / "temps.csv").string()});
}

TEST_F(CaseTest, TemperatureRules) {
  expect_error(
      tbase + "temperature:\n  field: 100\n",
      {"case.yaml:11:3", "'temperature.reference'", "missing key 'reference'", "never guessed"});
  expect_error(tbase + "temperature:\n  reference: 20\n",
               {"'temperature.field'", "missing key 'field'"});
  expect_error(tbase + "temperature:\n  reference: 20\n  field: [1, 2]\n",
               {"'temperature.field'", "found a list"});
  expect_error(tbase + "temperature:\n  reference: 20\n  field: \"20 + q\"\n",
               {"case.yaml:12:10", "'temperature.field'", "\"20 + q\"", "Unexpected token"});
  expect_error(tbase + "temperature:\n  reference: 20\n  field: {fiel: a.csv}\n",
               {"'temperature.field.fiel'", "did you mean 'file'?"});
  // alpha is required as soon as there is a temperature
  expect_error(R"(mesh: {file: part.msh}
materials:
  - {name: steel, E: 2.1e11, nu: 0.3}
temperature: {reference: 20, field: 100}
)",
               {"case.yaml:3:5", "'materials[0].alpha'", "missing key 'alpha'"});
}

TEST_F(CaseTest, UnknownKeysGetSuggestions) {
  expect_error("materails: []\n" + base, {"case.yaml:1:1", "'materails'",
                                          "unknown key 'materails'; did you mean 'materials'?",
                                          "valid keys here: 'title', 'mesh', 'materials'"});
  expect_error(base + "solver:\n  stpes: 10\n",
               {"case.yaml:11:3", "'solver.stpes'", "did you mean 'steps'?", "'cutback'"});
  expect_error(base + "steps: 10\n",
               {"case.yaml:10:1", "unknown key 'steps'", "'steps' is a key of 'solver'"});
  expect_error(R"(mesh: {file: part.msh}
materials:
  - name: steel
    e: 2.1e11
    nu: 0.3
)",
               {"case.yaml:4:5", "'materials[0].e'", "did you mean 'E'?"});
  expect_error(
      base + "  - region: top\n    displacement: {x: 0, w: 1}\n",
      {"case.yaml:11:26", "'boundary[1].displacement.w'", "unknown key 'w'", "'x', 'y', 'z'"});
  expect_error(base + "output:\n  probes:\n    - name: A\n      pont: [0, 0, 0]\n",
               {"case.yaml:13:7", "'output.probes[0].pont'", "did you mean 'point'?"});
  expect_error(base + "mesh:\n  file: part.msh\n",
               {"case.yaml:10:1", "duplicate key 'mesh'", "first given at line 1"});
}

TEST_F(CaseTest, WrongTypes) {
  expect_error(base + "solver:\n  tolerance: [1, 2]\n",
               {"case.yaml:11:14", "'solver.tolerance'", "expected a number, found a list"});
  expect_error(base + "solver:\n  tolerance: abc\n",
               {"'solver.tolerance'", "expected a number, found 'abc'"});
  expect_error(base + "solver:\n  tolerance: \"1e-3*t\"\n",  // no expressions here
               {"'solver.tolerance'", "expected a number, found '1e-3*t'"});
  expect_error(base + "solver:\n  tolerance: 2\n", {"0 < tolerance < 1", "found 2"});
  expect_error(base + "solver:\n  max_iterations: ten\n",
               {"'solver.max_iterations'", "expected a whole number, found 'ten'"});
  expect_error(base + "solver: 5\n", {"'solver'", "expected a map of keys, found '5'"});
  expect_error(base + "solver:\n", {"case.yaml:10:1", "'solver'", "found nothing"});
  expect_error(base + "body_force: [0, 0]\n", {"'body_force'", "list of 3", "found a list of 2"});
  expect_error(base + "body_force: 9.81\n", {"'body_force'", "found '9.81'"});
  expect_error(R"(mesh: {file: part.msh}
materials:
  name: steel
)",
               {"case.yaml:3:3", "'materials'", "expected a list of materials", "found a map"});
  // numbers as strings are fine where numbers are expected
  EXPECT_DOUBLE_EQ(read(base + "solver:\n  tolerance: \"1e-4\"\n").solver.tolerance, 1e-4);
}

TEST_F(CaseTest, FileLevelErrors) {
  expect_error("", {"case.yaml", "empty"});
  expect_error("# just a comment\n", {"case.yaml", "empty"});
  expect_error("- a\n- b\n", {"case.yaml", "expected a map of keys", "found a list"});
  expect_error("mesh: {file: part.msh\nmaterials: []\n", {"case.yaml:", "YAML syntax error"});
  expect_error("mesh: {file: part.msh}\nmaterials: [{E: 1, nu: 0.3}]\n\tsolver: {}\n",
               {"case.yaml:3:", "YAML syntax error", "line 3 is indented with a tab"});
  const std::string m = error("mesh:\n  file: part.msh\n   order: 2\n");
  EXPECT_TRUE(has(m, "case.yaml:3:")) << m;
  EXPECT_TRUE(has(m, "YAML syntax error")) << m;
  try {
    read_case(dir_ / "nothing.yaml");
    ADD_FAILURE() << "no error for a missing case file";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), "nothing.yaml")) << e.what();
    EXPECT_TRUE(has(e.what(), "not found")) << e.what();
  }
  try {
    read_case("");
    ADD_FAILURE() << "no error for an empty case path";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), "case file not found")) << e.what();
  }
  expect_error("title: x\n", {"case.yaml", "missing key 'mesh'", "'mesh'"});
  expect_error("mesh: {file: part.msh}\n", {"missing key 'materials'"});
}

TEST_F(CaseTest, Mesh) {
  expect_error(
      "mesh:\n  file: missing.msh\nmaterials: [{E: 1, nu: 0.3}]\n",
      {"case.yaml:2:9", "'mesh.file'", "mesh file not found", (dir_ / "missing.msh").string()});
  expect_error("mesh:\n  order: 2\nmaterials: [{E: 1, nu: 0.3}]\n",
               {"case.yaml:2:3", "'mesh.file'", "missing key 'file'"});
  expect_error("mesh: {file: part.msh, order: 3}\nmaterials: [{E: 1, nu: 0.3}]\n",
               {"case.yaml:1:31", "'mesh.order'", "expected 1 or 2, found 3"});
  expect_error("mesh: {file: part.msh, scale: 0}\nmaterials: [{E: 1, nu: 0.3}]\n",
               {"'mesh.scale'", "> 0"});
  write("part.stl", "solid");
  expect_error("mesh: {file: part.stl}\nmaterials: [{E: 1, nu: 0.3}]\n",
               {"'mesh.file'", ".msh", ".geo", "'part.stl'"});
  write("sub/part.geo", "Point(1) = {0,0,0};");
  EXPECT_EQ(read("mesh: {file: sub/part.geo}\nmaterials: [{E: 1, nu: 0.3}]\n").mesh.file,
            dir_ / "sub" / "part.geo");
}

TEST_F(CaseTest, PropertyTables) {
  const std::string head = "mesh: {file: part.msh}\nmaterials:\n  - name: steel\n    nu: 0.3\n";
  expect_error(head + "    E: {temperature: [20, 300, 200, 400], value: [1, 2, 3, 4]}\n",
               {"case.yaml:5:32", "'materials[0].E.temperature[2]'", "strictly increasing",
                "200 after 300"});
  expect_error(head + "    E: {temperature: [20, 300], value: [2e11, -1e9]}\n",
               {"'materials[0].E.value[1]'", "E must be > 0", "found -1e+09"});
  expect_error(head + "    E: {temperature: [20, 300], value: [2e11]}\n",
               {"'materials[0].E.value'", "expected 2 values", "found 1"});
  expect_error(head + "    E: {temperature: [20, 300]}\n",
               {"'materials[0].E.value'", "missing key 'value'"});
  expect_error(head + "    E: {temperature: [20, 300], values: [1, 2]}\n",
               {"'materials[0].E.values'", "did you mean 'value'?"});
  expect_error(head + "    E: [1, 2]\n",
               {"'materials[0].E'", "expected a number or a table", "found a list"});
  expect_error(head + "    E: 0\n", {"case.yaml:5:8", "'materials[0].E'", "> 0", "found 0"});
  expect_error(head + "    E: steel\n", {"'materials[0].E'", "expected a number, found 'steel'"});
  const std::string head2 = "mesh: {file: part.msh}\nmaterials:\n  - name: steel\n    E: 1e9\n";
  expect_error(head2 + "    nu: 0.5\n",
               {"case.yaml:5:9", "'materials[0].nu'", "-1 < nu < 0.5", "found 0.5"});
  expect_error(head2 + "    nu: -1\n", {"'materials[0].nu'", "-1 < nu < 0.5"});
  expect_error(head2 + "    nu: {temperature: [0, 100], value: [0.3, 0.55]}\n",
               {"'materials[0].nu.value[1]'", "found 0.55"});
  expect_error(head2 + "    alpha: 1e-5\n", {"'materials[0].nu'", "missing key 'nu'"});
  expect_error(head + "    E: {temperature: [20, 300], value: [2e11, 1e11]}\n",
               {"case.yaml:5:8", "'materials[0].E'", "needs a 'temperature' section"});
  // Subnormal numbers (0 < |x| < DBL_MIN) are refused in every material value; 0 is not.
  expect_error(head + "    E: 1e-310\n",
               {"case.yaml:5:8", "'materials[0].E'", "subnormal", "found '1e-310'"});
  expect_error(head + "    E: {temperature: [20, 300], value: [2e11, 4.9e-324]}\n",
               {"'materials[0].E.value[1]'", "subnormal"});
  expect_error(head2 + "    nu: -1e-320\n", {"'materials[0].nu'", "subnormal"});
  expect_error(head2 + "    nu: 0.3\n    alpha: 2e-315\n", {"'materials[0].alpha'", "subnormal"});
  EXPECT_EQ(read(head2 + "    nu: 0\n    alpha: 0\n").materials[0].alpha(20), 0.0);
  EXPECT_EQ(read(head + "    E: 2.2250738585072014e-308\n").materials[0].E(20),
            2.2250738585072014e-308);
  // Finite E and nu whose stiffness overflows.
  expect_error(head + "    E: 1.7e308\n",
               {"case.yaml:5:8", "'materials[0].E'", "E = 1.7e+308 with nu = 0.3",
                "E/(1 - 2nu) = inf", "range of floating point"});
  expect_error(
      "mesh: {file: part.msh}\nmaterials:\n  - nu: 0.2\n    E: {temperature: [0, 100], "
      "value: [1e9, 1.7e308]}\n",
      {"'materials[0].E'", "at temperature 100", "= inf"});
  // a one-entry table is a constant
  const Case c = read(head2 + "    nu: {temperature: [100], value: [0.25]}\n");
  EXPECT_TRUE(c.materials[0].nu.is_constant());
  EXPECT_DOUBLE_EQ(c.materials[0].nu(500), 0.25);
}

TEST_F(CaseTest, Materials) {
  expect_error(R"(mesh: {file: part.msh}
materials:
  - {name: steel, regions: [a], E: 1, nu: 0.3}
  - {name: copper, E: 1, nu: 0.3}
)",
               {"case.yaml:4:5", "'materials[1]'", "needs 'regions'", "one material"});
  expect_error(R"(mesh: {file: part.msh}
materials:
  - {name: steel, regions: [a], E: 1, nu: 0.3}
  - {name: steel, regions: [b], E: 1, nu: 0.3}
)",
               {"'materials[1].name'", "already used by materials[0]"});
  expect_error(
      R"(mesh: {file: part.msh}
materials:
  - {name: steel, regions: [a, b], E: 1, nu: 0.3}
  - {name: copper, regions: [c, b], E: 1, nu: 0.3}
)",
      {"case.yaml:4:33", "'materials[1].regions[1]'", "already given to material 'steel'"});
  expect_error("mesh: {file: part.msh}\nmaterials: []\n", {"'materials'", "at least one material"});
  const Case c = read(
      "mesh: {file: part.msh}\nmaterials: [{regions: q, E: 1, nu: 0.3}, {regions: r, E: 2, nu: "
      "0.2}]\n");
  EXPECT_EQ(c.materials[0].name, "material0");
  EXPECT_EQ(c.materials[1].name, "material1");
  EXPECT_EQ(c.materials[1].regions, (std::vector<std::string>{"r"}));
}

TEST_F(CaseTest, ContactIsReadWithItsDefaults) {
  const Case c = read(base + R"(contact:
  - nodes: bottom
    surface: {sphere: {center: [0, 0, 1], radius: 0.5}}
  - name: punch
    nodes: top
    surface: {cylinder: {point: [0, 0, 2], axis: [0, 2, 0], radius: 0.1}}
    motion: [0, 0, "-0.01*t"]
    stiffness: 1e9
    penetration: 1e-4
)");
  ASSERT_EQ(c.contact.size(), 2u);
  EXPECT_EQ(c.contact[0].name, "contact0");
  EXPECT_EQ(c.contact[0].surface.type, "sphere");
  EXPECT_FALSE(c.contact[0].stiffness);  // auto
  EXPECT_EQ(c.contact[0].penetration, 1e-3);
  EXPECT_FALSE(c.contact[0].motion[2]);
  EXPECT_EQ(c.contact[1].surface.type, "cylinder");
  EXPECT_TRUE(c.contact[1].surface.vector("axis").isApprox(Vec3(0, 1, 0)));
  EXPECT_EQ(*c.contact[1].stiffness, 1e9);
  EXPECT_EQ(c.contact[1].penetration, 1e-4);
  EXPECT_DOUBLE_EQ((*c.contact[1].motion[2])(0, 0, 0, 2), -0.02);
}

TEST_F(CaseTest, ContactErrorsNameTheKey) {
  const std::string head = base + "contact:\n  - name: floor\n    nodes: bottom\n";
  expect_error(head, {"case.yaml:11:5", "'contact[0].surface'", "missing key 'surface'"});
  expect_error(head + "    surface: {plain: {point: [0, 0, 0], normal: [0, 0, 1]}}\n",
               {"'contact[0].surface.plain'", "unknown key 'plain'", "plane"});
  expect_error(head + "    surface: {plane: {point: [0, 0, 0], normal: [0, 0, 0]}}\n",
               {"'contact[0].surface.plane.normal'", "non-zero normal"});
  expect_error(head + "    surface: {plane: {point: [0, 0, 0], normal: [0, 0, 1]},\n"
                      "              sphere: {center: [0, 0, 0], radius: 1}}\n",
               {"'contact[0].surface.sphere'", "one surface"});
  expect_error(head + "    surface: {sphere: {center: [0, 0, 0], radius: -1}}\n",
               {"'contact[0].surface.sphere.radius'", "> 0"});
  expect_error(head + "    surface: {mesh: {file: punch.stl}}\n",
               {"'contact[0].surface.mesh.file'", "punch.stl", "not found"});
  const std::string plane = head + "    surface: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}\n";
  expect_error(plane + "    motion: [0, 0, \"0.01*x*t\"]\n",
               {"'contact[0].motion[2]'", "rigid translation", "t only"});
  expect_error(plane + "    stiffness: stiff\n",
               {"'contact[0].stiffness'", "expected 'auto' or a penalty stiffness > 0"});
  expect_error(plane + "    penetration: 2\n", {"'contact[0].penetration'", "< 1"});
  expect_error(plane + "  - name: floor\n    nodes: top\n",
               {"'contact[1].name'", "already used by contact[0]"});
  expect_error(plane + "    nodes2: x\n", {"'contact[0].nodes2'", "unknown key"});
  // Anderson mixing restarts whenever the contact set changes (docs/schemes.md).
  EXPECT_EQ(read(plane + "solver: {scheme: initial-stress, acceleration: anderson}\n")
                .solver.acceleration,
            SolverSpec::Acceleration::anderson);
}

TEST_F(CaseTest, PetscBackEnd) {
  const Case c = read(base + "solver: {linear: petsc, petsc_options: \"-pc_type hypre -ksp_rtol "
                             "1e-9 -pc_gamg_threshold -0.01\"}\n");
  EXPECT_EQ(c.solver.linear, SolverSpec::Linear::petsc);
  EXPECT_EQ(c.solver.petsc_options, "-pc_type hypre -ksp_rtol 1e-9 -pc_gamg_threshold -0.01");
  EXPECT_TRUE(read(base).solver.petsc_options.empty());
  expect_error(base + "solver: {linear: petsc, petsc_options: \"pc_type hypre\"}\n",
               {"'solver.petsc_options'", "'pc_type' is neither an option"});
  expect_error(base + "solver: {linear: petsc, petsc_options: [-ksp_monitor]}\n",
               {"'solver.petsc_options'"});
  expect_error(base + "solver: {linear: pets}\n", {"'solver.linear'", "petsc"});
}

// A material with a plasticity entry whose content starts on line 7, column 7.
const std::string phead = R"(mesh: {file: part.msh}
materials:
  - name: steel
    E: 2.1e11
    nu: 0.3
    plasticity:
)";
// The same with alpha, for cases with a temperature section (content from line 8, column 7).
const std::string pthead = R"(mesh: {file: part.msh}
materials:
  - name: steel
    E: 2.1e11
    nu: 0.3
    alpha: 1.2e-5
    plasticity:
)";
const std::string temperature_section = "temperature: {reference: 20, field: 100}\n";

TEST_F(CaseTest, PlasticityCurveTables) {
  Case c = read(phead + R"(      curve:
        kind: uniaxial
        table:
          - temperature: 20
            strain: [0.00114286, 0.01, 0.05]
            stress: [240e6, 260e6, 300e6]
)");
  ASSERT_TRUE(c.materials[0].plasticity);
  const PlasticitySpec& p = *c.materials[0].plasticity;
  EXPECT_EQ(p.unloading, PlasticitySpec::Unloading::elastic);  // the default
  EXPECT_EQ(p.where.line, 7);
  EXPECT_EQ(p.curve.kind, CurveSpec::Kind::table);
  EXPECT_EQ(p.curve.form, CurveSpec::Form::uniaxial);
  EXPECT_EQ(p.curve.where.key, "materials[0].plasticity.curve");
  ASSERT_EQ(p.curve.tables.size(), 1u);
  const CurveSpec::Table& t = p.curve.tables[0];
  EXPECT_DOUBLE_EQ(t.temperature, 20);
  EXPECT_EQ(t.strain, (std::vector<double>{0.00114286, 0.01, 0.05}));
  EXPECT_EQ(t.stress, (std::vector<double>{240e6, 260e6, 300e6}));
  EXPECT_EQ(t.where.key, "materials[0].plasticity.curve.table[0]");
  ASSERT_EQ(t.point_where.size(), 3u);
  EXPECT_EQ(t.point_where[1].line, 11);
  EXPECT_EQ(t.point_where[1].column, 34);
  EXPECT_EQ(t.point_where[1].key, "materials[0].plasticity.curve.table[0].strain[1]");

  // one table: the temperature may be left out; several: each has one, increasing
  c = read(phead +
           "      curve: {kind: plastic, table: [{strain: [0, 0.1], stress: [2e8, 3e8]}]}\n"
           "      unloading: curve\n");
  EXPECT_EQ(c.materials[0].plasticity->curve.form, CurveSpec::Form::plastic);
  EXPECT_EQ(c.materials[0].plasticity->unloading, PlasticitySpec::Unloading::curve);
  EXPECT_EQ(c.materials[0].plasticity->curve.tables[0].strain.size(), 2u);
  c = read(pthead + R"(      curve:
        kind: intensity
        table:
          - {temperature: 20, strain: [0.001], stress: [242307692.3]}
          - {temperature: 500, strain: [0.000619048, 0.02], stress: [1.5e8, 1.8e8]}
)" + temperature_section);
  const CurveSpec& curve = c.materials[0].plasticity->curve;
  EXPECT_EQ(curve.form, CurveSpec::Form::intensity);
  ASSERT_EQ(curve.tables.size(), 2u);
  EXPECT_DOUBLE_EQ(curve.tables[1].temperature, 500);
  EXPECT_EQ(curve.tables[1].stress, (std::vector<double>{1.5e8, 1.8e8}));
}

TEST_F(CaseTest, PlasticityValuesMayNotBeSubnormal) {
  expect_error(phead +
                   "      curve: {kind: plastic, table: [{strain: [0, 0.1], stress: [2e8, "
                   "1e-310]}]}\n",
               {"'materials[0].plasticity.curve.table[0].stress[1]'", "subnormal"});
  expect_error(phead +
                   "      curve: {kind: plastic, table: [{strain: [0, 3e-320], stress: [2e8, "
                   "3e8]}]}\n",
               {"'materials[0].plasticity.curve.table[0].strain[1]'", "subnormal"});
  expect_error(phead + "      perfect: {yield: 1e-310}\n",
               {"'materials[0].plasticity.perfect.yield'", "subnormal"});
  expect_error(phead + "      ramberg_osgood: {E: 2e11, yield: 2e8, alpha: 1e-309, n: 5}\n",
               {"'materials[0].plasticity.ramberg_osgood.alpha'", "subnormal"});
}

// A scheme on the strain form F = ε(σ) of the curve stops at once, naming the schemes that can,
// where the curve is flat from its yield point on (issue 16): F does not exist above it.
TEST_F(CaseTest, StrainFormSchemesRefuseCurvesFlatFromYield) {
  const std::vector<std::string> flat = {
      "      perfect: {yield: 240e6}\n",
      "      linear: {yield: 240e6, hardening: 0}\n",
      "      curve: {kind: plastic, table: [{strain: [0], stress: [240e6]}]}\n",
      "      curve: {kind: plastic, table: [{strain: [0, 0.1], stress: [240e6, 240e6]}]}\n"};
  for (const std::string& curve : flat) {
    for (const char* solver : {"{scheme: initial-strain}", "{scheme: initial-strain-stiffness}",
                               "{scheme: variable-stiffness, curve_form: strain}"})
      expect_error(phead + curve + "solver: " + solver + "\n",
                   {"'materials[0].plasticity", "strain form", "newton, initial-stress",
                    "curve_form: stress"});
    for (const char* solver : {"{scheme: newton}", "{scheme: initial-stress}",
                               "{scheme: variable-stiffness}"})
      EXPECT_NO_THROW(read(phead + curve + "solver: " + solver + "\n")) << curve << solver;
  }
  EXPECT_NO_THROW(read(phead + "      linear: {yield: 240e6, hardening: 2e9}\n" +
                       "solver: {scheme: initial-strain}\n"));
}

TEST_F(CaseTest, PlasticityAnalyticCurves) {
  Case c = read(phead + "      perfect: {yield: 240e6}\n");
  const CurveSpec* curve = &c.materials[0].plasticity->curve;
  EXPECT_EQ(curve->kind, CurveSpec::Kind::perfect);
  EXPECT_DOUBLE_EQ(curve->yield(20), 240e6);
  EXPECT_EQ(curve->yield.where.key, "materials[0].plasticity.perfect.yield");

  c = read(pthead +
           "      linear: {yield: {temperature: [20, 500], value: [240e6, 150e6]}, "
           "hardening: -1e9}\n" +
           temperature_section);
  curve = &c.materials[0].plasticity->curve;
  EXPECT_EQ(curve->kind, CurveSpec::Kind::linear);
  EXPECT_DOUBLE_EQ(curve->yield(260), 195e6);
  EXPECT_DOUBLE_EQ(curve->hardening(20), -1e9);  // softening is allowed (> -3G)

  c = read(phead + "      ramberg_osgood: {E: 2e11, yield: 240e6, alpha: 0.002, n: 10}\n");
  curve = &c.materials[0].plasticity->curve;
  EXPECT_EQ(curve->kind, CurveSpec::Kind::ramberg_osgood);
  EXPECT_DOUBLE_EQ(curve->ro_E, 2e11);
  EXPECT_DOUBLE_EQ(curve->yield(20), 240e6);
  EXPECT_DOUBLE_EQ(curve->ro_alpha, 0.002);
  EXPECT_DOUBLE_EQ(curve->ro_n, 10);
}

TEST_F(CaseTest, PlasticityKeyErrors) {
  expect_error(phead + "      {}\n",
               {"case.yaml:7:7", "'materials[0].plasticity'", "needs a hardening curve",
                "'curve', 'perfect', 'linear', 'ramberg_osgood'"});
  expect_error(phead + "      perfect: {yield: 1e8}\n      linear: {yield: 1e8, hardening: 1e9}\n",
               {"case.yaml:8:7", "'materials[0].plasticity.linear'",
                "give one hardening curve, found both 'perfect' and 'linear'"});
  expect_error(phead + "      kind: uniaxial\n",
               {"case.yaml:7:7", "'materials[0].plasticity.kind'", "unknown key 'kind'",
                "'kind' is a key of 'materials[i].plasticity.curve'"});
  expect_error(
      phead + "      perfect: {yeild: 1e8}\n",
      {"case.yaml:7:17", "'materials[0].plasticity.perfect.yeild'", "did you mean 'yield'?"});
  expect_error(phead + "      perfect: {}\n",
               {"'materials[0].plasticity.perfect.yield'", "missing key 'yield'"});
  expect_error(phead + "      curve: {kind: uniaxal, table: []}\n",
               {"case.yaml:7:21", "'materials[0].plasticity.curve.kind'",
                "unknown curve kind 'uniaxal'; did you mean 'uniaxial'?"});
  expect_error(phead + "      curve: {table: [{strain: [0], stress: [1e8]}]}\n",
               {"'materials[0].plasticity.curve.kind'", "missing key 'kind'", "uniaxial", "plastic",
                "intensity"});
  expect_error(
      phead + "      curve: {kind: plastic, table: {strain: [0], stress: [1e8]}}\n",
      {"'materials[0].plasticity.curve.table'", "expected a list of tables", "found a map"});
  expect_error(phead + "      curve: {kind: plastic, table: []}\n",
               {"'materials[0].plasticity.curve.table'", "at least one table"});
  expect_error(phead + "      curve: {kind: plastic, table: [{strain: [], stress: []}]}\n",
               {"'materials[0].plasticity.curve.table[0].strain'", "at least one point"});
  expect_error(phead + "      curve: {kind: plastic, table: [{strain: [0, 0.1], stress: [1e8]}]}\n",
               {"'materials[0].plasticity.curve.table[0].stress'",
                "expected 2 stresses (one per strain), found 1"});
  expect_error(phead +
                   "      curve: {kind: plastic, table: [{strain: [0, 0.1, 0.1], "
                   "stress: [1e8, 2e8, 3e8]}]}\n",
               {"case.yaml:7:56", "'materials[0].plasticity.curve.table[0].strain[2]'",
                "strains must be strictly increasing, found 0.1 after 0.1"});
  expect_error(phead + "      curve: {kind: plastic, table: [{strain: [0], stres: [1e8]}]}\n",
               {"'materials[0].plasticity.curve.table[0].stres'", "did you mean 'stress'?"});
  expect_error(
      phead + "      perfect: {yield: 1e8}\n      unloading: elastik\n",
      {"case.yaml:8:18", "'materials[0].plasticity.unloading'", "did you mean 'elastic'?"});
  expect_error(
      phead + "      perfect: {yield: 0}\n",
      {"case.yaml:7:24", "'materials[0].plasticity.perfect.yield'", "yield must be > 0, found 0"});
  expect_error(phead + "      linear: {yield: 1e8, hardening: 1e9, n: 3}\n",
               {"'materials[0].plasticity.linear.n'", "unknown key 'n'",
                "'n' is a key of 'materials[i].plasticity.ramberg_osgood'"});
  expect_error(
      phead + "      ramberg_osgood: {E: 2e11, yield: 240e6, alpha: 0.002, n: 1}\n",
      {"'materials[0].plasticity.ramberg_osgood.n'", "expected an exponent n > 1", "found 1"});
  expect_error(phead + "      ramberg_osgood: {E: 2e11, yield: 240e6, alpha: 0, n: 5}\n",
               {"'materials[0].plasticity.ramberg_osgood.alpha'", "> 0", "found 0"});
  expect_error(phead + "      ramberg_osgood: {yield: 240e6, alpha: 0.002, n: 5}\n",
               {"'materials[0].plasticity.ramberg_osgood.E'", "missing key 'E'"});
}

TEST_F(CaseTest, PlasticityTemperatureRules) {
  const std::string two = R"(      curve:
        kind: plastic
        table:
          - {temperature: 500, strain: [0, 0.1], stress: [1.5e8, 2e8]}
          - {temperature: 20, strain: [0, 0.1], stress: [2.4e8, 3e8]}
)";
  expect_error(pthead + two + temperature_section,
               {"case.yaml:12:27", "'materials[0].plasticity.curve.table[1].temperature'",
                "strictly increasing, found 20 after 500"});
  expect_error(pthead + R"(      curve:
        kind: plastic
        table:
          - {temperature: 20, strain: [0, 0.1], stress: [2.4e8, 3e8]}
          - {strain: [0, 0.1], stress: [1.5e8, 2e8]}
)" + temperature_section,
               {"case.yaml:12:13", "'materials[0].plasticity.curve.table[1].temperature'",
                "missing key 'temperature'", "only when there is one table"});
  // one table converted with an E that depends on temperature: at which temperature?
  expect_error(R"(mesh: {file: part.msh}
materials:
  - name: steel
    E: {temperature: [20, 500], value: [2.1e11, 1.7e11]}
    nu: 0.3
    alpha: 1.2e-5
    plasticity:
      curve: {kind: uniaxial, table: [{strain: [0.00114286, 0.01], stress: [240e6, 260e6]}]}
)" + temperature_section,
               {"case.yaml:8:39", "'materials[0].plasticity.curve.table[0].temperature'",
                "missing key 'temperature'", "E or nu depends on temperature"});
  // several tables, or a yield or hardening table, need a temperature section
  expect_error(phead + R"(      curve:
        kind: plastic
        table:
          - {temperature: 20, strain: [0, 0.1], stress: [2.4e8, 3e8]}
          - {temperature: 500, strain: [0, 0.1], stress: [1.5e8, 2e8]}
)",
               {"case.yaml:11:13", "'materials[0].plasticity.curve.table[1]'",
                "need a 'temperature' section"});
  expect_error(phead + "      perfect: {yield: {temperature: [20, 500], value: [2.4e8, 1.5e8]}}\n",
               {"case.yaml:7:24", "'materials[0].plasticity.perfect.yield'",
                "needs a 'temperature' section"});
  expect_error(
      phead + "      linear: {yield: 2e8, hardening: {temperature: [20, 500], value: [1e9, 0]}}\n",
      {"'materials[0].plasticity.linear.hardening'", "needs a 'temperature' section"});
}

// Conversion errors come from Hardening (needs E and nu) and carry the point's location.
TEST_F(CaseTest, PlasticityCurveIsCheckedWithEAndNu) {
  expect_error(phead + R"(      curve:
        kind: uniaxial
        table:
          - temperature: 20
            strain: [0.00114286, 0.002, 0.003]
            stress: [240e6, 260e6, 500e6]
)",
               {"case.yaml:11:41", "'materials[0].plasticity.curve.table[0]'",
                "point 2 (strain 0.003, stress 5e+08)", "does not increase"});
  expect_error(
      phead +
          "      curve: {kind: uniaxial, table: [{strain: [0.002, 0.01], "
          "stress: [240e6, 260e6]}]}\n",
      {"case.yaml:7:49", "'materials[0].plasticity.curve.table[0]'", "point 0",
       "the first point must be the yield point on the elastic line", "i.e. strain 0.00114286"});
  expect_error(phead +
                   "      curve: {kind: plastic, table: [{strain: [0.001, 0.01], "
                   "stress: [240e6, 260e6]}]}\n",
               {"'materials[0].plasticity.curve.table[0]'", "point 0", "its strain must be 0"});
  expect_error(phead + "      linear: {yield: 240e6, hardening: -3e11}\n",
               {"case.yaml:7:41", "'materials[0].plasticity.linear.hardening'",
                "must be > -3G = -2.42308e+11"});
}

TEST_F(CaseTest, Boundary) {
  const std::string head = "mesh: {file: part.msh}\nmaterials: [{E: 1, nu: 0.3}]\nboundary:\n";
  expect_error(head + "  - region: a\n    pressure: 1\n    traction: [0, 0, 1]\n",
               {"case.yaml:6:5", "'boundary[0].traction'", "found both 'pressure' and 'traction'"});
  expect_error(head + "  - region: a\n", {"case.yaml:4:5", "'boundary[0]'", "no condition",
                                          "'displacement', 'pressure', 'traction', 'force'"});
  expect_error(head + "  - pressure: 1\n", {"'boundary[0].region'", "missing key 'region'"});
  expect_error(head + "  - region: [a, b]\n    pressure: 1\n",
               {"'boundary[0].region'", "one region name", "one entry per region"});
  expect_error(head + "  - region: a\n    traction: [0, 1]\n",
               {"'boundary[0].traction'", "list of 3", "found a list of 2"});
  expect_error(head + "  - region: a\n    force: [0, 1, \"2*tt\"]\n",
               {"case.yaml:5:19", "'boundary[0].force[2]'", "\"2*tt\"", "did you mean 't'?"});
  expect_error(head + "  - region: a\n    displacement: {}\n",
               {"'boundary[0].displacement'", "at least one of x, y, z"});
  expect_error(head + "  - region: a\n    displacement: 0\n",
               {"'boundary[0].displacement'", "found '0'"});
  expect_error(head + "  - region: a\n    pressure: [1]\n",
               {"'boundary[0].pressure'", "expected a number or an expression", "found a list"});
  expect_error(
      head +
          "  - region: a\n    displacement: {x: 0}\n  - region: a\n    displacement: {y: 0, x: "
          "1}\n",
      {"case.yaml:7:29", "'boundary[1].displacement.x'", "already prescribed by boundary[0]"});
  expect_error(head + "  region: a\n  pressure: 1\n",
               {"'boundary'", "expected a list of conditions", "'- '"});
  expect_error(head + "  - region: a\n    presure: 1\n",
               {"'boundary[0].presure'", "did you mean 'pressure'?"});
}

TEST_F(CaseTest, SolverChoices) {
  for (const char* s : {"newton", "variable-stiffness", "initial-strain",
                        "initial-strain-stiffness", "initial-stress", "initial-stress-stiffness"})
    EXPECT_STREQ(scheme_name(read(base + "solver: {scheme: " + s + "}\n").solver.scheme), s);
  expect_error(base + "solver:\n  scheme: newtn\n",
               {"case.yaml:11:11", "'solver.scheme'", "unknown scheme 'newtn'",
                "did you mean 'newton'?", "'initial-stress-stiffness'"});
  expect_error(base + "solver:\n  curve_form: stres\n", {"did you mean 'stress'?"});
  expect_error(base + "solver:\n  linear: drect\n", {"'solver.linear'", "did you mean 'direct'?"});
  expect_error(base + "solver:\n  correction: -0.5\n", {"'solver.correction'", ">= 0"});
  // γ per step (the report chooses it "for each time step"): an expression of t, checked at
  // every planned step's end time.
  const auto g = read(base + "solver: {times: [0.5, 1], correction: \"t < 0.75 ? 0 : 1\"}\n");
  EXPECT_DOUBLE_EQ(g.solver.correction(0, 0, 0, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(g.solver.correction(0, 0, 0, 1.0), 1.0);
  expect_error(base + "solver:\n  steps: 4\n  correction: \"1 - t\"\n  end: 2\n",
               {"'solver.correction'", ">= 0", "found -0.5 at t = 1.5"});
  expect_error(base + "solver:\n  correction: \"x\"\n",
               {"'solver.correction'", "depend on t only", "found 'x'"});
  expect_error(base + "solver:\n  relaxation: 0\n", {"'solver.relaxation'", "expected 'auto' or", "> 0"});
  EXPECT_DOUBLE_EQ(read(base + "solver: {relaxation: auto}\n").solver.relaxation, 0.0);
  expect_error(base + "solver:\n  cutback: -1\n", {"'solver.cutback'", ">= 0"});
  expect_error(base + "solver:\n  mechanism_limit: 0\n", {"'solver.mechanism_limit'", "> 0"});
  expect_error(base + "solver:\n  predictor: extrapolated\n",
               {"'solver.predictor'", "did you mean 'extrapolate'?"});
  expect_error(base + "solver:\n  acceleration: andersen\n",
               {"'solver.acceleration'", "did you mean 'anderson'?"});
  expect_error(base + "solver:\n  acceleration: anderson\n",
               {"'solver.acceleration'", "initial-stress-stiffness", "not to 'newton'"});
  EXPECT_EQ(read(base + "solver: {acceleration: auto}\n").solver.acceleration,
            SolverSpec::Acceleration::automatic);
  EXPECT_EQ(read(base + "solver: {scheme: initial-stress, acceleration: none}\n").solver.acceleration,
            SolverSpec::Acceleration::none);
}

// A map where a list of entries belongs (the '- ' forgotten) is named as such, in every list of
// entries of the case (Reader::entries).
TEST_F(CaseTest, AMapWhereAListOfEntriesBelongs) {
  const std::string hint = "(start each entry with '- '), found a map";
  expect_error("mesh: {file: part.msh}\nmaterials:\n  name: steel\n  E: 2e11\n  nu: 0.3\n",
               {"'materials'", "a list of materials " + hint});
  expect_error("mesh: {file: part.msh}\nmaterials:\n  - {E: 2e11, nu: 0.3}\nboundary:\n"
               "  region: bottom\n  displacement: {x: 0}\n",
               {"'boundary'", "a list of conditions " + hint});
  expect_error(base + "contact:\n  name: floor\n  nodes: bottom\n",
               {"'contact'", "a list of contacts " + hint});
  expect_error(base + "output:\n  probes:\n    name: A\n    point: [0, 0, 0]\n",
               {"'output.probes'", "a list of probes " + hint});
  expect_error(phead + "      curve: {kind: plastic, table: {strain: [0], stress: [1e8]}}\n",
               {"'materials[0].plasticity.curve.table'", hint});
}

TEST_F(CaseTest, Output) {
  expect_error(base +
                   "output:\n  probes:\n    - {name: A, point: [0, 0, 0]}\n    - {name: A, point: "
                   "[1, 0, 0]}\n",
               {"case.yaml:13:14", "'output.probes[1].name'", "already used by output.probes[0]"});
  expect_error(base + "output:\n  probes:\n    - {name: A, point: [0, 0]}\n",
               {"'output.probes[0].point'", "list of 3 numbers", "found a list of 2"});
  expect_error(base + "output:\n  probes:\n    - {name: A, point: [0, 0, x]}\n",
               {"'output.probes[0].point[2]'", "expected a number, found 'x'"});
  expect_error(base + "output:\n  probes:\n    - {name: \"A.1\", point: [0, 0, 0]}\n",
               {"'output.probes[0].name'", "letters, digits"});
  expect_error(base + "output:\n  reactions: [botom]\n",
               {"case.yaml:11:15", "'output.reactions[0]'", "no displacement condition",
                "did you mean 'bottom'?"});
  expect_error(base + "output:\n  reactions: [bottom, bottom]\n", {"listed twice"});
  expect_error(base + "output:\n  every: 0\n", {"'output.every'", ">= 1"});
  EXPECT_EQ(read(base + "output: {dir: /tmp/x/../y}\n").output.dir, fs::path("/tmp/y"));
  EXPECT_EQ(read(base + "output: {reactions: bottom}\n").output.reactions,
            (std::vector<std::string>{"bottom"}));
}

TEST_F(CaseTest, ExpressionErrorsInTheCase) {
  expect_error(base + "  - region: inner\n    pressure: \"100e6*t +\"\n",
               {"case.yaml:11:15", "'boundary[1].pressure'", "\"100e6*t +\"",
                "Unexpected end of expression"});
  expect_error(base + "body_force: [0, 0, \"-9.81*rho\"]\n",
               {"case.yaml:10:20", "'body_force[2]'", "Unexpected token \"rho\""});
}

}  // namespace
}  // namespace hencky
