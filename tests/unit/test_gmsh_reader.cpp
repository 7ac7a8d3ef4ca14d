// Mesh input: every .msh flavour Gmsh writes gives the same mesh; .geo files are meshed at run
// time; order conversion; bad meshes are input errors that name the element.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/case.hpp"
#include "io/gmsh_reader.hpp"
#include "io/log.hpp"
#include "solve/model.hpp"

namespace fs = std::filesystem;
using namespace hencky;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() /
                     ("hencky-gmsh-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const char* box_geo = R"(SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Mesh.MeshSizeMax = 0.5;
Physical Volume("body") = {1};
Physical Surface("left") = {1};
Physical Surface("right") = {2};
Physical Curve("edge") = {1};
)";

/// Meshes the box with the Gmsh library and saves it in the given format.
void save_box(const fs::path& file, double version, bool binary) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  const fs::path geo = file.parent_path() / "box-src.geo";
  std::ofstream(geo) << box_geo;
  gmsh::open(geo.string());
  gmsh::model::mesh::generate(3);
  gmsh::option::setNumber("Mesh.MshFileVersion", version);
  gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
  gmsh::write(file.string());
  gmsh::finalize();
}

double volume(const Mesh& m) {
  // Sum of tetrahedron volumes from corner nodes (straight-sided meshes).
  double v = 0;
  for (int e = 0; e < m.cells.size(); ++e) {
    const auto n = m.cells.nodes(e);
    v += (m.x[n[1]] - m.x[n[0]]).cross(m.x[n[2]] - m.x[n[0]]).dot(m.x[n[3]] - m.x[n[0]]) / 6;
  }
  return v;
}

}  // namespace

TEST(GmshReader, EveryMshFlavourGivesTheSameMesh) {
  const fs::path dir = fresh_dir("flavours");
  std::vector<Mesh> meshes;
  for (double version : {2.2, 4.1})
    for (bool binary : {false, true}) {
      const fs::path f = dir / ("box-v" + std::to_string(int(version)) + (binary ? "b" : "a") + ".msh");
      save_box(f, version, binary);
      meshes.push_back(read_gmsh(f, {}));
    }
  const Mesh& ref = meshes.front();
  ASSERT_GT(ref.cells.size(), 10);
  EXPECT_NEAR(volume(ref), 2.0, 1e-12);
  for (const Mesh& m : meshes) {
    EXPECT_EQ(m.n_nodes(), ref.n_nodes());
    EXPECT_EQ(m.cells.conn, ref.cells.conn);
    EXPECT_EQ(m.faces.conn, ref.faces.conn);
    ASSERT_EQ(m.regions.size(), ref.regions.size());
    for (std::size_t r = 0; r < m.regions.size(); ++r) {
      EXPECT_EQ(m.regions[r].name, ref.regions[r].name);
      EXPECT_EQ(m.regions[r].nodes, ref.regions[r].nodes);
    }
    // ASCII files carry 16 significant digits, binary ones the exact double: one ulp apart.
    for (int i = 0; i < m.n_nodes(); ++i) EXPECT_LE((m.x[i] - ref.x[i]).norm(), 1e-15);
  }
  // Regions: a volume, two surfaces with faces, a curve with nodes only.
  const Region* left = ref.find_region("left");
  ASSERT_NE(left, nullptr);
  EXPECT_EQ(left->dim, 2);
  EXPECT_FALSE(left->cells.empty());
  for (int n : left->nodes) EXPECT_NEAR(ref.x[n].x(), 0.0, 1e-12);
  const Region* edge = ref.find_region("edge");
  ASSERT_NE(edge, nullptr);
  EXPECT_EQ(edge->dim, 1);
  EXPECT_GE(edge->nodes.size(), 2u);
  fs::remove_all(dir);
}

TEST(GmshReader, GeoIsMeshedAndOrderTwoConverts) {
  const fs::path dir = fresh_dir("geo");
  std::ofstream(dir / "box.geo") << box_geo;
  const Mesh linear = read_gmsh(dir / "box.geo", {});
  MeshReadOptions two;
  two.order = 2;
  two.scale = 1e-3;  // mm -> m
  const Mesh quad = read_gmsh(dir / "box.geo", two);
  for (auto t : linear.cells.type) EXPECT_EQ(t, CellType::tet4);
  for (auto t : quad.cells.type) EXPECT_EQ(t, CellType::tet10);
  for (auto t : quad.faces.type) EXPECT_EQ(t, CellType::tri6);
  EXPECT_EQ(quad.cells.size(), linear.cells.size());
  EXPECT_GT(quad.n_nodes(), linear.n_nodes());
  EXPECT_NEAR(volume(quad), 2e-9, 1e-20);  // corner nodes scaled
  // Mid-edge nodes sit at the midpoints of straight edges: Gmsh's edge (0,1) is node 4.
  const auto n = quad.cells.nodes(0);
  EXPECT_LT((quad.x[n[4]] - 0.5 * (quad.x[n[0]] + quad.x[n[1]])).norm(), 1e-15);
  fs::remove_all(dir);
}

TEST(GmshReader, BadFilesAreInputErrorsNamingTheFile) {
  const fs::path dir = fresh_dir("bad");
  std::ofstream(dir / "garbage.msh") << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\nnonsense\n";
  try {
    read_gmsh(dir / "garbage.msh", {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("garbage.msh"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "syntax.geo") << "Point(1) = {0, 0, 0;\n";
  try {
    read_gmsh(dir / "syntax.geo", {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("syntax"), std::string::npos) << e.what();
  }
  // Only a surface mesh: no body.
  std::ofstream(dir / "flat.geo") << "Point(1)={0,0,0,1};Point(2)={1,0,0,1};Point(3)={0,1,0,1};\n"
                                     "Line(1)={1,2};Line(2)={2,3};Line(3)={3,1};\n"
                                     "Curve Loop(1)={1,2,3};Plane Surface(1)={1};\n";
  try {
    read_gmsh(dir / "flat.geo", {});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("3D"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(GmshReader, InvertedElementIsNamed) {
  const fs::path dir = fresh_dir("inverted");
  // Two tetrahedra; element 7 has its nodes in the wrong order (negative volume).
  std::ofstream(dir / "two.msh") << R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "base"
3 2 "body"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 0 0 -1
$EndNodes
$Elements
3
6 4 2 2 1 1 2 3 4
7 4 2 2 1 1 2 3 5
8 2 2 1 1 1 2 3
$EndElements
)";
  std::ofstream(dir / "case.yaml") << "mesh: {file: two.msh}\nmaterials: [{E: 1.0e9, nu: 0.3}]\n"
                                      "boundary:\n  - {region: base, displacement: {x: 0, y: 0, z: 0}}\n";
  const Case c = read_case(dir / "case.yaml");
  Log log;
  log.quiet = true;
  try {
    Model m(c, read_gmsh(c.mesh.file, {}), log);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("element 7"), std::string::npos) << w;
    EXPECT_NE(w.find("inverted"), std::string::npos) << w;
  }
  fs::remove_all(dir);
}
