// Mesh input: every .msh flavour Gmsh writes gives the same mesh; .geo files are meshed at run
// time; order conversion; bad meshes are input errors that name the element.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include "core/error.hpp"
#include "core/log.hpp"
#include "input/case_reader.hpp"
#include "input/gmsh_reader.hpp"
#include "input/msh_reader.hpp"
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

/// Meshes the box with the Gmsh library and saves it in the given format (partitioned in one
/// file, when `partitions` > 0).
void save_box(const fs::path& file, double version, bool binary, int order = 1,
              int partitions = 0) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  const fs::path geo = file.parent_path() / "box-src.geo";
  std::ofstream(geo) << box_geo;
  gmsh::open(geo.string());
  gmsh::model::mesh::generate(3);
  if (order == 2) {
    gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 1);
    gmsh::model::mesh::setOrder(2);
  }
  if (partitions > 0) gmsh::model::mesh::partition(partitions);
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

/// The two meshes are the same to the last bit: nodes, cells, faces and regions in the same order.
void expect_same_mesh(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(a.node_tag, b.node_tag);
  ASSERT_EQ(a.x.size(), b.x.size());
  for (std::size_t i = 0; i < a.x.size(); ++i) EXPECT_EQ(a.x[i], b.x[i]) << "node " << i;
  for (auto [p, q] : {std::pair(&a.cells, &b.cells), std::pair(&a.faces, &b.faces)}) {
    EXPECT_EQ(p->type, q->type);
    EXPECT_EQ(p->offset, q->offset);
    EXPECT_EQ(p->conn, q->conn);
    EXPECT_EQ(p->tag, q->tag);
  }
  EXPECT_EQ(a.cell_region, b.cell_region);
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (std::size_t r = 0; r < a.regions.size(); ++r) {
    EXPECT_EQ(a.regions[r].name, b.regions[r].name);
    EXPECT_EQ(a.regions[r].dim, b.regions[r].dim);
    EXPECT_EQ(a.regions[r].cells, b.regions[r].cells);
    EXPECT_EQ(a.regions[r].nodes, b.regions[r].nodes);
  }
}

MeshReadOptions through_library(int order = 0) {
  MeshReadOptions o;
  o.order = order;
  o.through_gmsh_library = true;
  return o;
}

/// The message of the InputError that reading `file` throws ("" when none is thrown).
std::string read_error(const fs::path& file) {
  try {
    read_gmsh(file, {});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(GmshReader, EveryMshFlavourGivesTheSameMesh) {
  const fs::path dir = fresh_dir("flavours");
  std::vector<Mesh> meshes;
  for (double version : {2.2, 4.0, 4.1})
    for (bool binary : {false, true}) {
      if (version == 4.0 && binary) continue;  // Gmsh writes 4.0 in ASCII only
      const fs::path f = dir / ("box-v" + std::to_string(version) + (binary ? "b" : "a") + ".msh");
      save_box(f, version, binary);
      meshes.push_back(read_gmsh(f, {}));
      // hencky's reader gives what the Gmsh library reads from the same file, bit for bit.
      SCOPED_TRACE(f.filename().string());
      expect_same_mesh(meshes.back(), read_gmsh(f, through_library()));
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

// Several element types on one entity, in blocks out of type order, an element in two
// physical volumes, an unnamed physical group and a point group: hencky's reader orders them
// as the Gmsh library does (entities by tag, an entity's elements type by type).
TEST(GmshReader, MixedBlocksAreOrderedAsGmshOrdersThem) {
  const fs::path dir = fresh_dir("mixed");
  const std::string nodes = R"($Nodes
1 12 1 12
3 1 0 12
1
2
3
4
5
6
7
8
9
10
11
12
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
2 0 0
2 1 0
2 0 1
2 1 1
$EndNodes
)";
  std::ofstream(dir / "mixed.msh") << R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
3 5 "hexa"
2 9 "face"
$EndPhysicalNames
$Entities
1 0 1 2
7 0 0 0 1 4
3 0 0 0 2 1 1 1 9 0
1 0 0 0 1 1 1 2 5 6 0
2 1 0 0 2 1 1 1 6 0
$EndEntities
)" << nodes << R"($Elements
6 7 10 60
3 2 4 1
20 2 9 10 7
3 1 6 1
30 2 9 10 6 11 12
3 1 5 1
10 1 2 3 4 5 6 7 8
3 1 4 2
40 1 2 4 5
41 2 3 4 7
2 3 2 1
50 2 9 6
0 7 15 1
60 1
$EndElements
)";
  const Mesh mine = read_gmsh(dir / "mixed.msh", {});
  expect_same_mesh(mine, read_gmsh(dir / "mixed.msh", through_library()));
  ASSERT_EQ(mine.cells.size(), 5);  // volume 1 is in groups 5 and 6: its elements come once
  EXPECT_EQ(mine.cells.tag, (std::vector<long>{40, 41, 10, 30, 20}));
  ASSERT_NE(mine.find_region("hexa"), nullptr);
  ASSERT_NE(mine.find_region("6"), nullptr);  // unnamed: by number
  EXPECT_EQ(mine.find_region("4")->nodes.size(), 1u);
  fs::remove_all(dir);
}

// An order conversion goes through the Gmsh library, as it always did, but only once
// hencky's reader has accepted the file: a malformed file never reaches Gmsh's reader.
TEST(GmshReader, OrderConversionGoesThroughGmshAfterTheFileIsChecked) {
  const fs::path dir = fresh_dir("order");
  save_box(dir / "linear.msh", 4.1, false, 1);
  MeshReadOptions two;
  two.order = 2;
  const Mesh converted = read_gmsh(dir / "linear.msh", two);
  for (auto t : converted.cells.type) EXPECT_EQ(t, CellType::tet10);
  expect_same_mesh(converted, read_gmsh(dir / "linear.msh", through_library(2)));
  std::ofstream(dir / "bad.msh") << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 4\n"
                                    "3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n";
  try {
    read_gmsh(dir / "bad.msh", two);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.msh:6: not a valid Gmsh mesh file"), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

// A geometry Gmsh cannot mesh: Gmsh reports it from inside its meshing threads, which aborted
// the process before; now it is an input error with Gmsh's own message.
TEST(GmshReader, GeometryGmshCannotMeshIsAnInputError) {
  const fs::path dir = fresh_dir("unmeshable");
  std::ofstream(dir / "t.geo") << "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {0, 1, 0};\n"
                                  "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};\n"
                                  "Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};\n"
                                  "Transfinite Curve{1} = 3; Transfinite Surface{1};\n";
  const std::string e = read_error(dir / "t.geo");
  EXPECT_NE(e.find("t.geo: Gmsh cannot mesh this geometry: Surface 1 cannot be meshed using the "
                   "transfinite algo"),
            std::string::npos)
      << e;
  // The library is usable afterwards (its state was reset).
  std::ofstream(dir / "box.geo") << box_geo;
  EXPECT_GT(read_gmsh(dir / "box.geo", {}).cells.size(), 10);
  fs::remove_all(dir);
}

namespace {
const char* one_tet = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 4 1 4
3 1 0 4
1
2
3
4
0 0 0
1 0 0
0 1 0
0 0 1
$EndNodes
$Elements
1 1 1 1
3 1 4 1
1 1 2 3 4
$EndElements
)";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}
}  // namespace

// Malformed files that crashed Gmsh 4.8's reader (shared/crashes/msh4-*) and others: each is an
// input error naming the file, the line and what is wrong.
TEST(GmshReader, MalformedMshFilesAreInputErrorsNamingTheLine) {
  const fs::path dir = fresh_dir("malformed");
  std::ofstream(dir / "good.msh") << one_tet;
  ASSERT_EQ(read_error(dir / "good.msh"), "");
  const std::string two_tets_nodes = replaced(
      replaced(one_tet, "1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n", "1 5 1 5\n3 1 0 5\n1\n2\n3\n4\n5\n"),
      "0 0 1\n$EndNodes", "0 0 1\n1 1 1\n$EndNodes");
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"node-minus-one", replaced(one_tet, "1 1 2 3 4\n", "1 -1 2 3 4\n"),
       ":19: not a valid Gmsh mesh file: element 1 has node -1, which $Nodes does not define"},
      {"node-2-31", replaced(one_tet, "1 1 2 3 4\n", "1 2147483648 2 3 4\n"),
       ":19: not a valid Gmsh mesh file: element 1 has node 2147483648, which $Nodes does not "
       "define"},
      {"nodes-count-small", replaced(one_tet, "1 4 1 4\n", "1 1 1 4\n"),
       ":6: not a valid Gmsh mesh file: the node blocks hold more nodes than the $Nodes header "
       "announces (1)"},
      {"nodes-count-large", replaced(one_tet, "1 4 1 4\n", "1 5 1 4\n"),
       "the $Nodes header announces 5 nodes, its blocks hold 4"},
      {"elements-count-small",
       replaced(replaced(two_tets_nodes, "1 1 1 1\n3 1 4 1\n", "1 0 1 2\n3 1 4 2\n"), "1 1 2 3 4\n",
                "1 1 2 3 4\n2 2 3 4 5\n"),
       ":20: not a valid Gmsh mesh file: the element blocks hold more elements than the $Elements "
       "header announces (0)"},
      {"v2-body-under-4.0",
       "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n$Nodes\n1 6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
       "5 1 1 0\n6 1 0 1\n$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n",
       ":6: not a valid Gmsh mesh file: the $Nodes header announces 6 nodes, its blocks hold 0"},
      {"blocks-count-small", replaced(one_tet, "1 4 1 4\n3 1 0 4\n", "0 4 1 4\n3 1 0 4\n"),
       ":5: not a valid Gmsh mesh file: the $Nodes header announces 4 nodes, its blocks hold 0"},
      {"duplicate-node", replaced(one_tet, "1\n2\n3\n4\n", "1\n2\n3\n3\n"),
       ":10: not a valid Gmsh mesh file: node 3 is defined twice"},
      {"unknown-type", replaced(one_tet, "3 1 4 1\n", "3 1 999 1\n"),
       ":18: not a valid Gmsh mesh file: unknown element type 999"},
      {"type-of-other-dimension", replaced(one_tet, "3 1 4 1\n", "2 1 4 1\n"),
       "Tetrahedron 4 elements (dimension 3) in a block of an entity of dimension 2"},
      {"nan-coordinate", replaced(one_tet, "0 1 0\n", "0 nan 0\n"),
       ":13: not a valid Gmsh mesh file: a node coordinate is not a finite number"},
      {"text-for-number", replaced(one_tet, "0 1 0\n", "0 one 0\n"),
       ":13: not a valid Gmsh mesh file: a node coordinate expected, found 'one'"},
      {"truncated", std::string(one_tet).substr(0, std::string(one_tet).find("0 0 1\n")),
       ":14: not a valid Gmsh mesh file: the file ends where a node coordinate was expected"},
      {"no-elements", std::string(one_tet).substr(0, std::string(one_tet).find("$Elements")),
       "the file has no $Elements section"},
      {"unclosed-section", replaced(one_tet, "$EndMeshFormat\n", "$EndMeshFormat\n$Comments\nhi\n"),
       "section $Comments has no $EndComments"},
      {"version-3", replaced(one_tet, "4.1 0 8", "3.0 0 8"),
       ":2: not a valid Gmsh mesh file: MSH format version '3.0' is not read (2.2, 4.0 and 4.1 "
       "are)"},
      {"binary-data-size-4", replaced(one_tet, "4.1 0 8", "4.1 1 4"),
       "binary data size 4 is not read"},
      // Found by fuzz/fuzz_msh.cpp: a binary file whose version line has no newline was read past
      // its end (fuzz/corpus/msh/regress-binary-version-line-unended.msh).
      {"binary-version-line-unended", "$MeshFormat\n4.1 1 8 \"x\"",
       "the file ends where the endianness check was expected"},
      {"partitioned-empty",
       replaced(one_tet, "$EndMeshFormat\n", "$EndMeshFormat\n$PartitionedEntities\n"),
       "the number of partitions (a non-negative integer) expected, found '$Nodes'"},
      {"partitioned-4.0",
       replaced(replaced(one_tet, "4.1 0 8", "4.0 0 8"), "$EndMeshFormat\n",
                "$EndMeshFormat\n$PartitionedEntities\n"),
       "partitioned meshes are read in MSH format 4.1 only"},
      {"not-a-mesh", "solid cube\nendsolid\n",
       ":1: not a valid Gmsh mesh file: the file does not start with $MeshFormat"},
      {"msh2-node-zero",
       "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n0 0 0 "
       "0\n$EndNodes\n$Elements\n0\n$EndElements\n",
       ":6: not a valid Gmsh mesh file: node tag 0 (tags are positive)"},
      {"msh2-unknown-node",
       "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n1\n"
       "1 15 2 0 1 2\n$EndElements\n",
       ":10: not a valid Gmsh mesh file: element 1 has node 2, which $Nodes does not define"},
  };
  for (const auto& [name, text, expected] : cases) {
    const fs::path f = dir / (name + ".msh");
    std::ofstream(f) << text << std::flush;
    const std::string e = read_error(f);
    EXPECT_NE(e.find(f.string() + ":"), std::string::npos) << name << ": " << e;
    EXPECT_NE(e.find(expected), std::string::npos) << name << ": " << e;
  }
  fs::remove_all(dir);
}

namespace {

/// The same mesh as a set: node coordinates by node tag, cells and faces by element tag with
/// their nodes' tags, regions by name with their cells' and nodes' tags (a partitioned file
/// orders nodes and cells by partition).
void expect_same_mesh_by_tags(const Mesh& a, const Mesh& b) {
  auto nodes = [](const Mesh& m) {
    std::map<long long, Vec3> out;
    for (int n = 0; n < m.n_nodes(); ++n) out[m.node_tag[n]] = m.x[n];
    return out;
  };
  auto cells = [](const Mesh& m, const CellSet& c) {
    std::map<long long, std::vector<long long>> out;
    for (int e = 0; e < c.size(); ++e)
      for (int n : c.nodes(e)) out[c.tag[e]].push_back(m.node_tag[n]);
    return out;
  };
  auto regions = [](const Mesh& m) {
    std::map<std::string, std::pair<std::set<long long>, std::set<long long>>> out;
    for (const Region& r : m.regions) {
      auto& [c, n] = out[r.name + "/" + std::to_string(r.dim)];
      for (int e : r.cells) c.insert(r.dim == 3 ? m.cells.tag[e] : m.faces.tag[e]);
      for (int v : r.nodes) n.insert(m.node_tag[v]);
    }
    return out;
  };
  EXPECT_EQ(nodes(a), nodes(b));
  EXPECT_EQ(cells(a, a.cells), cells(b, b.cells));
  EXPECT_EQ(cells(a, a.faces), cells(b, b.faces));
  EXPECT_EQ(regions(a), regions(b));
}

}  // namespace

// A mesh that Gmsh partitioned (gmsh -part N) and saved in one file is the whole mesh: the
// partitioned entities carry their parents' regions, and the boundaries between partitions,
// whose elements Gmsh adds, are left out. One file of a mesh split into files (-part_split)
// holds a part only: refused, saying so.
TEST(GmshReader, PartitionsInOneFileAreTheWholeMeshAndASplitFileIsRefused) {
  const fs::path dir = fresh_dir("partitioned");
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  std::ofstream(dir / "box-src.geo") << box_geo;
  gmsh::open((dir / "box-src.geo").string());
  gmsh::model::mesh::generate(3);
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  for (int binary : {0, 1}) {  // ASCII and binary coordinates differ in the last bit
    gmsh::option::setNumber("Mesh.Binary", binary);
    gmsh::write((dir / ("plain" + std::to_string(binary) + ".msh")).string());
  }
  gmsh::model::mesh::partition(3);
  for (int binary : {0, 1}) {
    gmsh::option::setNumber("Mesh.Binary", binary);
    gmsh::write((dir / ("parts" + std::to_string(binary) + ".msh")).string());
  }
  gmsh::option::setNumber("Mesh.Binary", 0);
  gmsh::option::setNumber("Mesh.PartitionSplitMeshFiles", 1);
  gmsh::write((dir / "split.msh").string());
  gmsh::finalize();

  for (const std::string binary : {"0", "1"}) {
    const std::string name = "parts" + binary + ".msh";
    SCOPED_TRACE(name);
    const Mesh plain = read_gmsh(dir / ("plain" + binary + ".msh"), {});
    ASSERT_GT(plain.cells.size(), 10);
    const Mesh parts = read_gmsh(dir / name, {});
    EXPECT_EQ(parts.regions.size(), plain.regions.size());
    expect_same_mesh_by_tags(plain, parts);
    // The Gmsh library's reading (the way to an order conversion) gives the same.
    expect_same_mesh_by_tags(plain, read_gmsh(dir / name, through_library()));
  }
  for (int k = 1; k <= 3; ++k) {
    const fs::path piece = dir / ("split_" + std::to_string(k) + ".msh");
    ASSERT_TRUE(fs::exists(piece));
    const std::string e = read_error(piece);
    EXPECT_NE(e.find(piece.string() + ":"), std::string::npos) << e;
    EXPECT_NE(e.find("holds 1 of the 3 partitions of a mesh split into files"), std::string::npos)
        << e;
  }
  // Read as a piece (each rank its own file, parallel/mesh_part.hpp's part_of_piece), a file
  // of the split mesh gives its part; a whole mesh is not a piece.
  MeshReadOptions as_piece;
  as_piece.piece = true;
  long long cells = 0;
  for (int k = 1; k <= 3; ++k)
    cells += read_gmsh(dir / ("split_" + std::to_string(k) + ".msh"), as_piece).cells.size();
  EXPECT_EQ(cells, read_gmsh(dir / "plain0.msh", {}).cells.size());
  EXPECT_THROW(read_gmsh(dir / "parts0.msh", as_piece), InputError);
  fs::remove_all(dir);
}

// Every prefix of a binary and of an ASCII file, and a few thousand random byte changes: each
// is read or refused as an input error, never a crash (the test runs under the sanitizers
// too).
TEST(GmshReader, TruncatedAndMutatedFilesNeverCrash) {
  const fs::path dir = fresh_dir("mutated");
  save_box(dir / "b.msh", 4.1, true);
  save_box(dir / "b2.msh", 2.2, true);
  save_box(dir / "bp.msh", 4.1, true, 1, 3);  // partitioned
  for (const char* name : {"b.msh", "b2.msh", "bp.msh"}) {
    std::ifstream in(dir / name, std::ios::binary);
    const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(whole.size(), 1000u);
    int refused = 0, read = 0;
    auto attempt = [&](const std::string& text) {
      try {
        parse_msh(text, name);
        ++read;
      } catch (const InputError&) {
        ++refused;
      }
    };
    for (std::size_t n = 0; n < whole.size(); n += 7) attempt(whole.substr(0, n));
    std::mt19937 rng(5);
    for (int k = 0; k < 3000; ++k) {
      std::string text = whole;
      for (int flips = 0; flips < 3; ++flips)
        text[rng() % text.size()] = static_cast<char>(rng() % 256);
      attempt(text);
    }
    EXPECT_GT(refused, 0);
    EXPECT_EQ(read + refused, static_cast<int>((whole.size() + 6) / 7) + 3000);
  }
  fs::remove_all(dir);
}
