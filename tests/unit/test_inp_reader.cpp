// Abaqus/CalculiX decks (input/inp_reader.hpp): node orders mapped to Gmsh's, element faces
// S1..S6 where the Abaqus manual puts them, sets and surfaces as regions, and bad decks as input
// errors that name the line.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "core/error.hpp"
#include "input/inp_reader.hpp"

namespace fs = std::filesystem;
using namespace hencky;

namespace {

Mesh parse(const std::string& text, std::vector<std::string>* warnings = nullptr,
           const fs::path& file = "deck.inp") {
  return parse_inp(text, file, MeshReadOptions{}, warnings);
}

/// The message of the InputError that parsing `text` throws ("" when it throws none).
std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// *NODE lines of `x` (labels from 1).
std::string node_card(const std::vector<Vec3>& x) {
  std::string s = "*NODE\n";
  for (std::size_t i = 0; i < x.size(); ++i)
    s += fmt::format("{}, {}, {}, {}\n", i + 1, x[i].x(), x[i].y(), x[i].z());
  return s;
}

/// Adds the midpoints of the Abaqus edges (pairs of labels from 1) to x.
void add_midpoints(std::vector<Vec3>& x, const std::vector<std::pair<int, int>>& edges) {
  for (auto [a, b] : edges) x.push_back(0.5 * (x[a - 1] + x[b - 1]));
}

std::string element_line(int label, int n) {
  std::string s = std::to_string(label);
  for (int a = 1; a <= n; ++a) s += ", " + std::to_string(a);
  return s + "\n";
}

// The unit cube, the corner tetrahedron and the unit wedge, corners in Abaqus order.
const std::vector<Vec3> hex_corners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const std::vector<Vec3> tet_corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<Vec3> wedge_corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                         {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
// Abaqus's mid-edge nodes of C3D10 and C3D20 (Abaqus Analysis User's Guide, solid elements).
const std::vector<std::pair<int, int>> tet10_edges = {{1, 2}, {2, 3}, {3, 1},
                                                      {1, 4}, {2, 4}, {3, 4}};
const std::vector<std::pair<int, int>> hex20_edges = {
    {1, 2}, {2, 3}, {3, 4}, {4, 1}, {5, 6}, {6, 7}, {7, 8}, {8, 5}, {1, 5}, {2, 6}, {3, 7}, {4, 8}};
// Gmsh's mid-edge nodes (gmsh.info, node ordering), positions from 0.
const std::vector<std::pair<int, int>> gmsh_tet10_edges = {{0, 1}, {1, 2}, {2, 0},
                                                           {3, 0}, {3, 2}, {3, 1}};
const std::vector<std::pair<int, int>> gmsh_hex20_edges = {
    {0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3}, {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};

/// A one-element deck of `type` on `x`, with a surface of each face S1..Sn named S1..Sn.
std::string one_element_deck(const std::string& type, const std::vector<Vec3>& x, int faces) {
  std::string s = node_card(x) + "*ELEMENT, TYPE=" + type + ", ELSET=body\n" +
                  element_line(1, static_cast<int>(x.size()));
  for (int f = 1; f <= faces; ++f) s += fmt::format("*SURFACE, NAME=S{}\n1, S{}\n", f, f);
  return s;
}

/// Checks the cell's mid-edge nodes in Gmsh's order and each face S<k>: on the plane
/// `on_plane[k-1]` says, its mid-edge nodes at its edges' midpoints.
void check_element(const Mesh& m, CellType type, const std::vector<std::pair<int, int>>& gmsh_edges,
                   const std::vector<std::function<bool(const Vec3&)>>& on_plane) {
  ASSERT_EQ(m.cells.size(), 1);
  EXPECT_EQ(m.cells.type[0], type);
  const auto c = m.cells.nodes(0);
  const int corners = cell_n_corners(type);
  for (std::size_t k = 0; k < gmsh_edges.size(); ++k) {
    const auto [a, b] = gmsh_edges[k];
    EXPECT_LT((m.x[c[corners + k]] - 0.5 * (m.x[c[a]] + m.x[c[b]])).norm(), 1e-15)
        << "mid-edge node " << corners + k;
  }
  for (std::size_t f = 0; f < on_plane.size(); ++f) {
    const Region* r = m.find_region(fmt::format("S{}", f + 1), 2, 2);
    ASSERT_NE(r, nullptr);
    ASSERT_EQ(r->cells.size(), 1u);
    const auto face = m.faces.nodes(r->cells[0]);
    const CellType ft = m.faces.type[r->cells[0]];
    const int n = cell_n_corners(ft);
    for (int a : face) EXPECT_TRUE(on_plane[f](m.x[a])) << "face S" << f + 1;
    for (int k = 0; k < static_cast<int>(face.size()) - n; ++k)
      EXPECT_LT((m.x[face[n + k]] - 0.5 * (m.x[face[k]] + m.x[face[(k + 1) % n]])).norm(), 1e-15)
          << "face S" << f + 1 << " mid-edge node " << k;
  }
}

bool near(double a, double b) {
  return std::abs(a - b) < 1e-14;
}

const std::vector<std::function<bool(const Vec3&)>> hex_planes = {
    [](const Vec3& p) { return near(p.z(), 0); }, [](const Vec3& p) { return near(p.z(), 1); },
    [](const Vec3& p) { return near(p.y(), 0); }, [](const Vec3& p) { return near(p.x(), 1); },
    [](const Vec3& p) { return near(p.y(), 1); }, [](const Vec3& p) { return near(p.x(), 0); }};
const std::vector<std::function<bool(const Vec3&)>> tet_planes = {
    [](const Vec3& p) { return near(p.z(), 0); }, [](const Vec3& p) { return near(p.y(), 0); },
    [](const Vec3& p) { return near(p.x() + p.y() + p.z(), 1); },
    [](const Vec3& p) { return near(p.x(), 0); }};
const std::vector<std::function<bool(const Vec3&)>> wedge_planes = {
    [](const Vec3& p) { return near(p.z(), 0); }, [](const Vec3& p) { return near(p.z(), 1); },
    [](const Vec3& p) { return near(p.y(), 0); },
    [](const Vec3& p) { return near(p.x() + p.y(), 1); },
    [](const Vec3& p) { return near(p.x(), 0); }};

}  // namespace

TEST(InpReader, HexahedraTakeGmshsOrderAndTheirFacesAreWhereAbaqusPutsThem) {
  check_element(parse(one_element_deck("C3D8", hex_corners, 6)), CellType::hex8, {}, hex_planes);
  std::vector<Vec3> x = hex_corners;
  add_midpoints(x, hex20_edges);
  check_element(parse(one_element_deck("C3D20R", x, 6)), CellType::hex20, gmsh_hex20_edges,
                hex_planes);
}

TEST(InpReader, TetrahedraTakeGmshsOrderAndTheirFacesAreWhereAbaqusPutsThem) {
  check_element(parse(one_element_deck("C3D4", tet_corners, 4)), CellType::tet4, {}, tet_planes);
  std::vector<Vec3> x = tet_corners;
  add_midpoints(x, tet10_edges);
  check_element(parse(one_element_deck("C3D10", x, 4)), CellType::tet10, gmsh_tet10_edges,
                tet_planes);
}

TEST(InpReader, WedgeFacesAreWhereAbaqusPutsThem) {
  check_element(parse(one_element_deck("C3D6", wedge_corners, 5)), CellType::wedge6, {},
                wedge_planes);
}

TEST(InpReader, SetsBecomeRegionsOfTheirKind) {
  // Two hexahedra side by side (x in [0, 2]); an ELSET of both, one of the second; node sets
  // by list, by GENERATE, by other sets and by element sets; face elements (as Gmsh writes a
  // physical surface) and an element-based surface through an internal ELSET.
  std::string s = node_card({{0, 0, 0},
                             {1, 0, 0},
                             {1, 1, 0},
                             {0, 1, 0},
                             {0, 0, 1},
                             {1, 0, 1},
                             {1, 1, 1},
                             {0, 1, 1},
                             {2, 0, 0},
                             {2, 1, 0},
                             {2, 0, 1},
                             {2, 1, 1},
                             {5, 5, 5}});
  s += R"(** a comment
*Element, type=C3D8, elset=Left
1, 1, 2, 3, 4, 5, 6, 7, 8
*ELEMENT, TYPE=C3D8R, ELSET=right
2, 2, 9, 10, 3,
6, 11, 12, 7
*ELEMENT, TYPE=CPS4, ELSET=end_faces
3, 9, 10, 12, 11
*ELEMENT, TYPE=T3D2, ELSET=wire
4, 1, 13
*ELSET, ELSET=ALL
left, RIGHT
*NSET, NSET=base, GENERATE
1, 4, 1
*NSET, NSET=base
9, 10
*NSET, NSET=corner
1,
*NSET, NSET=Twice
corner, base, 13
*NSET, NSET=of_right, ELSET
right
*ELSET, ELSET=_top_S2, internal
1, 2
*SURFACE, NAME=Top, TYPE=ELEMENT
_top_s2, S2
*SURFACE, NAME=far, TYPE=NODE
12
*SURFACE, NAME=skin
all
*SURFACE, NAME=right_skin
right
*MATERIAL, NAME=steel
*ELASTIC
2e11, 0.3
)";
  std::vector<std::string> warnings;
  const Mesh m = parse(s, &warnings);
  EXPECT_EQ(m.n_nodes(), 12);  // node 13 is on the wire only
  EXPECT_EQ(m.cells.size(), 2);
  auto nodes_of = [&](const char* name, int dim) {
    const Region* r = m.find_region(name, dim, dim, true);
    EXPECT_NE(r, nullptr) << name;
    std::vector<long> tags;
    if (r)
      for (int n : r->nodes) tags.push_back(m.node_tag[n]);
    return tags;
  };
  EXPECT_EQ(nodes_of("BASE", 0), (std::vector<long>{1, 2, 3, 4, 9, 10}));
  EXPECT_EQ(nodes_of("twice", 0), (std::vector<long>{1, 2, 3, 4, 9, 10}));  // 13: off the body
  EXPECT_EQ(nodes_of("of_right", 0), (std::vector<long>{2, 3, 6, 7, 9, 10, 11, 12}));
  EXPECT_EQ(nodes_of("far", 0), (std::vector<long>{12}));
  EXPECT_EQ(nodes_of("top", 2), (std::vector<long>{5, 6, 7, 8, 11, 12}));
  EXPECT_EQ(nodes_of("END_FACES", 2), (std::vector<long>{9, 10, 11, 12}));
  EXPECT_EQ(m.find_region("top", 2, 2, true)->cells.size(), 2u);
  // An ELSET without a face: its elements' faces on the outside of the body.
  EXPECT_EQ(m.find_region("skin", 2, 2, true)->cells.size(), 10u);
  EXPECT_EQ(m.find_region("right_skin", 2, 2, true)->cells.size(), 5u);
  EXPECT_EQ(m.find_region("all", 3, 3, true)->cells, (std::vector<int>{0, 1}));
  EXPECT_EQ(m.find_region("right", 3, 3, true)->cells, (std::vector<int>{1}));
  EXPECT_EQ(m.find_region("wire", 0, 3, true), nullptr);  // line elements only
  EXPECT_EQ(m.find_region("_top_s2", 0, 3, true), nullptr);  // INTERNAL: the surface's only
  EXPECT_EQ(m.find_region("top", 0, 3, false), nullptr);  // as written: "Top"
  EXPECT_EQ(m.regions[m.cell_region[1]].name, "right");
  ASSERT_EQ(warnings.size(), 4u);
  EXPECT_NE(warnings[0].find("*MATERIAL, *ELASTIC"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("1 T3D2"), std::string::npos) << warnings[1];
  // The plain C3D8 is hencky's hexahedron, named for its B-bar strain (issue 48).
  EXPECT_NE(warnings[2].find("treat differently: 1 C3D8 (hencky's B-bar strain"), std::string::npos)
      << warnings[2];
  EXPECT_NE(warnings[3].find("1 C3D8R"), std::string::npos) << warnings[3];
}

TEST(InpReader, OnePartWithOneInstanceAndAnIncludedFile) {
  const fs::path dir = fs::temp_directory_path() / ("hencky-inp-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "nodes.inp") << node_card(hex_corners);
  const std::string deck = R"(*Heading
** Job name: Job-1
*Part, name=Block
*Include, input=nodes.inp
*Element, type=C3D8
1, 1, 2, 3, 4, 5, 6, 7, 8
*Nset, nset=Bottom, generate
 1,  4,  1
*End Part
*Assembly, name=Assembly
*Instance, name=Block-1, part=Block
*End Instance
*Node
 1, 0.5, 0.5, 2.0
*Nset, nset=RP
 1,
*Elset, elset=_Lid_S2, internal, instance=Block-1
 1,
*Surface, type=ELEMENT, name=Lid
_Lid_S2, S2
*End Assembly
)";
  std::vector<std::string> warnings;
  const Mesh m = parse(deck, &warnings, dir / "job.inp");
  fs::remove_all(dir);
  EXPECT_EQ(m.n_nodes(), 8);
  EXPECT_EQ(m.x[0], Vec3(0, 0, 0));  // not the reference point's coordinates
  EXPECT_NE(m.find_region("bottom", 0, 0, true), nullptr);
  EXPECT_EQ(m.find_region("rp", 0, 3, true), nullptr);  // a set of the assembly's node
  ASSERT_NE(m.find_region("LID", 2, 2, true), nullptr);
  EXPECT_EQ(m.find_region("LID", 2, 2, true)->nodes.size(), 4u);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("*NODE of the assembly"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("1 C3D8 (hencky's B-bar"), std::string::npos) << warnings[1];
}

// The keywords hencky skips are listed under the file that holds them, not the deck that
// includes it (issue 48: the warning named the including file).
TEST(InpReader, SkippedKeywordsAreNamedWithTheirOwnFile) {
  const fs::path dir = fs::temp_directory_path() / ("hencky-inp-inc-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "material.inp") << "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n";
  const std::string deck = node_card(hex_corners) +
                           "*ELEMENT, TYPE=C3D8R, ELSET=ALL\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
                           "*INCLUDE, INPUT=material.inp\n*STEP\n*STATIC\n*END STEP\n";
  std::vector<std::string> warnings;
  parse(deck, &warnings, dir / "job.inp");
  fs::remove_all(dir);
  ASSERT_GE(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].rfind("job.inp: skipped what is not mesh data", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find("*STEP, *STATIC, *END STEP"), std::string::npos) << warnings[0];
  EXPECT_EQ(warnings[0].find("*MATERIAL"), std::string::npos) << warnings[0];
  EXPECT_EQ(warnings[1].rfind("material.inp: skipped what is not mesh data", 0), 0u) << warnings[1];
  EXPECT_NE(warnings[1].find("*MATERIAL, *ELASTIC"), std::string::npos) << warnings[1];
}

TEST(InpReader, FortranExponentsAndScale) {
  MeshReadOptions o;
  o.scale = 1e-3;
  const Mesh m = parse_inp(
      "*NODE\n1, 1.0D+03, 0., 0\n2,2000,0,0\n3,0,1000\n4,0,0,1e3\n"
      "*ELEMENT,TYPE=C3D4\n1,1,2,3,4\n",
      "deck.inp", o);
  EXPECT_LT((m.x[0] - Vec3(1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((m.x[2] - Vec3(0, 1, 0)).norm(), 1e-15);  // a missing z is 0
}

// What ccx reads and an Abaqus reader might refuse (issue 48: decks of ccx's own test suite):
// a GENERATE range over numbers that are not all nodes takes the nodes there are, and an element
// line with more numbers than its type's nodes takes the first. Each with a warning.
TEST(InpReader, CcxsLeniencesAreKeptAndSaid) {
  const std::string deck = node_card(tet_corners) +  // nodes 1..4
                           "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4, 3, 2\n"
                           "*NSET, NSET=range, GENERATE\n1, 20, 1\n"
                           "*NSET, NSET=odd, GENERATE\n1, 9, 2\n";
  std::vector<std::string> warnings;
  const Mesh m = parse(deck, &warnings);
  ASSERT_EQ(m.cells.size(), 1);
  const auto nodes = m.cells.nodes(0);
  EXPECT_EQ(std::vector<int>(nodes.begin(), nodes.end()), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(m.find_region("range", 0, 0, true)->nodes.size(), 4u);
  EXPECT_EQ(m.find_region("odd", 0, 0, true)->nodes, (std::vector<int>{0, 2}));
  std::string all;
  for (const auto& w : warnings) all += w + "\n";
  EXPECT_NE(all.find("1 element line with more numbers than the type has nodes (the first on "
                     "line 7 of deck.inp): the first were taken"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("GENERATE ranges over numbers that no *NODE defines, left out as ccx leaves "
                     "them out: NSET 'odd' (3 numbers), NSET 'range' (16 numbers)"),
            std::string::npos)
      << all;
}

// A node-based and an element-based surface of one name (ccx's metalforming) are two regions
// of that name: the nodes, and the faces.
TEST(InpReader, ANodeAndAnElementSurfaceMayShareAName) {
  const std::string deck = node_card(tet_corners) + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n"
                           "*SURFACE, TYPE=NODE, NAME=top\n4\n"
                           "*SURFACE, TYPE=ELEMENT, NAME=top\n1, S2\n";
  const Mesh m = parse(deck);
  ASSERT_NE(m.find_region("top", 0, 0, true), nullptr);
  EXPECT_EQ(m.find_region("top", 0, 0, true)->nodes, (std::vector<int>{3}));
  ASSERT_NE(m.find_region("top", 2, 2, true), nullptr);
  EXPECT_EQ(m.find_region("top", 2, 2, true)->cells.size(), 1u);
}

TEST(InpReader, BadDecksNameTheLine) {
  const std::string nodes = node_card(tet_corners);  // lines 1..5
  auto expect = [&](const std::string& tail, const std::string& where, const std::string& what) {
    const std::string msg = error_of(nodes + tail);
    EXPECT_NE(msg.find(where), std::string::npos) << tail << " -> " << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  };
  expect("*ELEMENT, TYPE=C3D27\n1,1,2,3,4\n", "deck.inp:6:", "not supported");
  expect("*ELEMENT, TYPE=C3D15\n1,1,2,3,4\n", "deck.inp:6:", "not supported");
  expect("*ELEMENT, TYPE=XYZ4\n1,1,2,3,4\n", "deck.inp:6:", "unknown element type 'XYZ4'");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n*NSET, NSET=fix\n1, 2, 77\n",
         "deck.inp:9:", "NSET 'fix' names node 77, which no *NODE defines");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n*ELSET, ELSET=e\n1, 9\n",
         "deck.inp:9:", "names element 9");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n2,1,2\n", "deck.inp:8:", "cut short");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,9\n", "deck.inp:7:", "element 1 has node 9");
  expect("*NODE\n3, 0, 0, 0\n", "deck.inp:7:", "node 3 is defined twice (first on line 4)");
  expect("*NODE\n5, 0, x, 0\n", "deck.inp:7:", "found 'x'");
  expect("*NSET, NSET=a\nb\n", "deck.inp:7:", "'b' is neither a label nor an NSET");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n*SURFACE, NAME=s\n1, P3\n", "deck.inp:9:", "S1 .. S6");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n*SURFACE, NAME=s\n1, S5\n",
         "deck.inp:9:", "has no face S5");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n*SURFACE, NAME=s\nnone, S1\n",
         "deck.inp:9:", "'NONE' is neither an element label nor an ELSET");
  expect("*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n*INCLUDE, INPUT=missing.inp\n",
         "deck.inp:8:", "cannot open");
  expect("*INSTANCE, NAME=a, PART=p\n1, 0, 0\n*END INSTANCE\n", "deck.inp:7:", "is moved");
  expect("*NSET, NSET=a, GENERATE\n1, 100000000000000\n*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n",
         "deck.inp:7:", "more than");
  // The last labels a long holds: stepping past them overflowed before (UBSan). Numbers of no
  // node in a GENERATE range are left out (CcxsLeniencesAreKeptAndSaid), and the set is empty.
  std::vector<std::string> warnings;
  const Mesh m = parse(nodes + "*ELEMENT, TYPE=C3D4\n1,1,2,3,4\n*NSET, NSET=a, GENERATE\n"
                               "9223372036854775800, 9223372036854775807, 5\n",
                       &warnings);
  EXPECT_TRUE(m.find_region("a", 0, 0, true)->nodes.empty());
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.back().find("NSET 'a' (2 numbers)"), std::string::npos) << warnings.back();
  EXPECT_NE(error_of(nodes).find("no volume elements"), std::string::npos);
  EXPECT_NE(error_of("1, 2, 3\n").find("deck.inp:1:"), std::string::npos);
}
