// Contact with rigid surfaces (report section 3): the analytic surfaces, every branch of the
// node state machine, and whole analyses whose answer is known exactly: a block pressed by a
// rigid plane (uniform stress), the same block released (the Separation branch), a bar heated
// against a wall after its gap closes.
#include <gtest/gtest.h>

#include "contact/contact.hpp"
#include "contact/rigid_surface.hpp"
#include "contact/surface_type.hpp"
#include "core/invariant.hpp"
#include "input/load_case.hpp"
#include "output/results.hpp"
#include "solve/contact_step.hpp"
#include "solve/driver.hpp"
#include "verify_support.hpp"

namespace hencky {
namespace {

using verify::num;

// ------------------------------------------------------------------------------------------
// Analytic surfaces

TEST(RigidSurface, PlaneDistanceNearestAndEntry) {
  const auto s = make_plane(Vec3(0, 0, 1), Vec3(0, 0, 2));  // normal normalized
  EXPECT_DOUBLE_EQ(s->signed_distance(Vec3(3, 4, 1.5)), 0.5);
  EXPECT_EQ(s->side(Vec3(0, 0, 0.999)), -1);
  EXPECT_EQ(s->side(Vec3(0, 0, 1)), 1);  // on the surface counts as outside
  const SurfacePoint q = s->nearest(Vec3(3, 4, -1));
  EXPECT_TRUE(q.x.isApprox(Vec3(3, 4, 1)));
  EXPECT_TRUE(q.n.isApprox(Vec3(0, 0, 1)));
  const auto hit = s->intersection(Vec3(0, 0, 3), Vec3(2, 0, -1));
  ASSERT_TRUE(hit);
  EXPECT_TRUE(hit->x.isApprox(Vec3(1, 0, 1)));
  EXPECT_FALSE(s->intersection(Vec3(0, 0, 3), Vec3(0, 0, 2)));   // stays outside
  EXPECT_FALSE(s->intersection(Vec3(0, 0, 0), Vec3(0, 0, -1)));  // starts inside
  const auto at_start = s->intersection(Vec3(0, 0, 1), Vec3(0, 0, 0.5));
  ASSERT_TRUE(at_start);
  EXPECT_TRUE(at_start->x.isApprox(Vec3(0, 0, 1)));
}

TEST(RigidSurface, SphereDistanceNearestAndEntry) {
  const auto s = make_sphere(Vec3(1, 0, 0), 2);
  EXPECT_DOUBLE_EQ(s->signed_distance(Vec3(1, 0, 5)), 3);
  EXPECT_DOUBLE_EQ(s->signed_distance(Vec3(1, 1, 0)), -1);
  const SurfacePoint q = s->nearest(Vec3(1, 0, 7));
  EXPECT_TRUE(q.x.isApprox(Vec3(1, 0, 2)));
  EXPECT_TRUE(q.n.isApprox(Vec3(0, 0, 1)));
  // Along the z axis from z = 5 to z = −5: enters at z = 2.
  const auto hit = s->intersection(Vec3(1, 0, 5), Vec3(1, 0, -5));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->x.z(), 2, 1e-14);
  EXPECT_TRUE(hit->n.isApprox(Vec3(0, 0, 1)));
  EXPECT_FALSE(s->intersection(Vec3(4, 0, 5), Vec3(4, 0, -5)));  // misses (x = 4 > 1 + 2)
  EXPECT_FALSE(s->intersection(Vec3(1, 0, 5), Vec3(1, 0, 2.5)));  // stops short
  EXPECT_FALSE(s->intersection(Vec3(1, 0, 0), Vec3(1, 0, 5)));    // leaves
}

TEST(RigidSurface, CylinderDistanceNearestAndEntry) {
  const auto s = make_cylinder(Vec3(0, 0, 0), Vec3(0, 1, 0), 1);  // rod along y
  EXPECT_DOUBLE_EQ(s->signed_distance(Vec3(0, 50, 3)), 2);
  const SurfacePoint q = s->nearest(Vec3(3, 7, 4));
  EXPECT_TRUE(q.x.isApprox(Vec3(0.6, 7, 0.8)));
  EXPECT_TRUE(q.n.isApprox(Vec3(0.6, 0, 0.8)));
  const auto hit = s->intersection(Vec3(0, 2, 3), Vec3(0, 9, -3));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->x.z(), 1, 1e-14);
  EXPECT_NEAR(hit->x.y(), 2 + 7.0 * 2 / 6, 1e-14);
  EXPECT_FALSE(s->intersection(Vec3(0, 0, 3), Vec3(0, 9, 3)));  // parallel to the axis
}

// ------------------------------------------------------------------------------------------
// The registered surface types (contact/surface_type.hpp)

TEST(SurfaceTypes, RegistryNamesKeysAndDescriptions) {
  std::vector<std::string> names;
  for (const SurfaceDeclaration& d : surface_types()) {
    names.push_back(d.name);
    EXPECT_TRUE(d.make) << d.name;
    EXPECT_TRUE(d.describe) << d.name;
    EXPECT_FALSE(d.noun.empty()) << d.name;
    for (const SurfaceKey& k : d.keys) EXPECT_FALSE(k.description.empty()) << d.name << k.name;
  }
  // The case keys, in the order messages list them; summary.json's `shape` is the name.
  EXPECT_EQ(names, (std::vector<std::string>{"plane", "sphere", "cylinder", "mesh"}));
  EXPECT_EQ(surface_type("mesh").noun, "an STL body");
  EXPECT_THROW(surface_type("torus"), InternalError);

  // make and describe from the values read by key: a sphere.
  SurfaceParameters p;
  p.type = "sphere";
  p.values["center"].value = Vec3(0, 0, 2);
  p.values["radius"].value = 1.5;
  const auto s = surface_type(p.type).make(p);
  EXPECT_DOUBLE_EQ(s->signed_distance(Vec3(0, 0, -1)), 1.5);
  const SurfaceDescription d = surface_type(p.type).describe(p);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].first, "shape");
  EXPECT_EQ(std::get<std::string>(d[0].second), "sphere");
  EXPECT_EQ(d[1].first, "center");
  EXPECT_EQ(std::get<Vec3>(d[1].second), Vec3(0, 0, 2));
  EXPECT_EQ(d[2].first, "radius");
  EXPECT_EQ(std::get<double>(d[2].second), 1.5);
  // A key the type does not declare, or of another kind, is a programming error.
  EXPECT_THROW(p.number("center"), InternalError);
  EXPECT_THROW(p.vector("axis"), InternalError);
}

// ------------------------------------------------------------------------------------------
// The node state machine, branch by branch, on the plane z = 0 (rigid body below)

struct Machine {
  std::unique_ptr<RigidSurface> plane = make_plane(Vec3::Zero(), Vec3::UnitZ());
  SurfaceMotion where{plane.get(), Vec3::Zero(), Vec3::Zero()};
  ContactNode in_contact(double force) const {
    ContactNode s;
    s.contact = true;
    s.force = force * Vec3::UnitZ();
    s.point = Vec3(0.1, 0.2, 0);
    s.normal = Vec3::UnitZ();
    s.kappa = 100;
    return s;
  }
};

TEST(ContactStateMachine, ForceAndMatrixOfANodeInContact) {
  Machine m;
  ContactNode s = m.in_contact(5);
  // (3.2): force (F + κ(r* − r)·n) n, G = κ n nᵀ; a penetration of 0.01 adds κ·0.01.
  const Vec3 f = contact_force(s, Vec3(0.3, 0.2, -0.01));
  EXPECT_TRUE(f.isApprox(Vec3(0, 0, 6)));
  EXPECT_TRUE(contact_matrix(s).isApprox(Mat3(Vec3(0, 0, 100).asDiagonal())));
  s.contact = false;  // (3.3): no force, no matrix
  EXPECT_TRUE(contact_force(s, Vec3(0, 0, -1)).isZero());
  EXPECT_TRUE(contact_matrix(s).isZero());
}

TEST(ContactStateMachine, InContactAndStillInsideStaysAtTheNearestPoint) {
  Machine m;
  ContactNode s = m.in_contact(5), committed = m.in_contact(5);
  const auto b = update_contact_node(s, committed, Vec3(0.1, 0.2, 0), Vec3(0.4, 0.2, -0.02),
                                     m.where);
  EXPECT_EQ(b, ContactBranch::stays_inside);
  EXPECT_TRUE(s.contact);
  EXPECT_FALSE(s.separation);
  EXPECT_NEAR(s.force.z(), 5 + 100 * 0.02, 1e-12);  // (3.4)
  EXPECT_TRUE(s.point.isApprox(Vec3(0.4, 0.2, 0)));  // nearestPoint(r)
  EXPECT_NEAR(s.gap, -0.02, 1e-15);
}

TEST(ContactStateMachine, InContactOutsideWithTensionIsReleased) {
  Machine m;
  // Committed in contact: the node separates (Separation = ⁽ᵗ⁾Contact = true).
  ContactNode s = m.in_contact(1), committed = m.in_contact(1);
  auto b = update_contact_node(s, committed, Vec3(0.1, 0.2, 0), Vec3(0.1, 0.2, 0.05), m.where);
  EXPECT_EQ(b, ContactBranch::released);
  EXPECT_FALSE(s.contact);
  EXPECT_TRUE(s.separation);
  EXPECT_TRUE(s.force.isZero());
  // Closed in this step only (committed free): released to free, no Separation.
  s = m.in_contact(1);
  b = update_contact_node(s, ContactNode{}, Vec3(0.1, 0.2, 0.01), Vec3(0.1, 0.2, 0.05), m.where);
  EXPECT_EQ(b, ContactBranch::released);
  EXPECT_FALSE(s.contact);
  EXPECT_FALSE(s.separation);
}

TEST(ContactStateMachine, InContactOutsideStillPressedIsHeld) {
  Machine m;
  ContactNode s = m.in_contact(10), committed = m.in_contact(10);
  // 0.03 above the plane: F = 10 − 100·0.03 = 7 > 0, still pressed (augmented update).
  const auto b = update_contact_node(s, committed, Vec3(0.1, 0.2, 0), Vec3(0.1, 0.2, 0.03),
                                     m.where);
  EXPECT_EQ(b, ContactBranch::held_outside);
  EXPECT_TRUE(s.contact);
  EXPECT_NEAR(s.force.z(), 7, 1e-12);
  EXPECT_TRUE(s.point.isApprox(Vec3(0.1, 0.2, 0)));
}

TEST(ContactStateMachine, SeparatingNodeThatGoesBackInIsHeldAtItsOldNearestPoint) {
  Machine m;
  ContactNode committed = m.in_contact(3), s;
  s.separation = true;
  s.kappa = 100;
  const auto b = update_contact_node(s, committed, Vec3(0.1, 0.2, 0.001), Vec3(0.5, 0.2, -0.01),
                                     m.where);
  EXPECT_EQ(b, ContactBranch::back_in);
  EXPECT_TRUE(s.contact);
  EXPECT_FALSE(s.separation);
  EXPECT_TRUE(s.point.isApprox(Vec3(0.1, 0.2, 0)));  // nearestPoint(⁽ᵗ⁾r), not of r
  EXPECT_TRUE(s.force.isZero());                     // (3.5) in the iteration it separated
}

TEST(ContactStateMachine, SeparatingNodeThatStaysOutStaysSeparated) {
  Machine m;
  ContactNode committed = m.in_contact(3), s;
  s.separation = true;
  const auto b = update_contact_node(s, committed, Vec3(0.1, 0.2, 0), Vec3(0.1, 0.2, 0.2),
                                     m.where);
  EXPECT_EQ(b, ContactBranch::stays_separated);
  EXPECT_FALSE(s.contact);
  EXPECT_TRUE(s.separation);
}

TEST(ContactStateMachine, FreeNodeWhosePathCrossesTheSurfaceCloses) {
  Machine m;
  ContactNode s;
  const auto b = update_contact_node(s, ContactNode{}, Vec3(0, 0, 0.1), Vec3(0.2, 0, -0.1),
                                     m.where);
  EXPECT_EQ(b, ContactBranch::closes);
  EXPECT_TRUE(s.contact);
  EXPECT_TRUE(s.point.isApprox(Vec3(0.1, 0, 0)));  // intersectionPoint(⁽ᵗ⁾r, r)
}

TEST(ContactStateMachine, FreeNodeThatDoesNotReachTheSurfaceStaysFree) {
  Machine m;
  ContactNode s;
  const auto b = update_contact_node(s, ContactNode{}, Vec3(0, 0, 0.1), Vec3(0, 0, 0.05),
                                     m.where);
  EXPECT_EQ(b, ContactBranch::stays_free);
  EXPECT_FALSE(s.contact);
  EXPECT_FALSE(s.separation);
  EXPECT_NEAR(s.gap, 0.05, 1e-15);
}

TEST(ContactStateMachine, AMovingSurfaceThatRunsIntoAStillNodeCatchesIt) {
  // The plane rises from z = 0 to z = 0.2 while the node stays at z = 0.1: in the surface's
  // frame the node crosses it, so it closes; the contact point is on the moved plane.
  Machine m;
  m.where.m1 = Vec3(0, 0, 0.2);
  ContactNode s;
  const auto b = update_contact_node(s, ContactNode{}, Vec3(0, 0, 0.1), Vec3(0, 0, 0.1), m.where);
  EXPECT_EQ(b, ContactBranch::closes);
  EXPECT_TRUE(s.point.isApprox(Vec3(0, 0, 0.2)));
  EXPECT_NEAR(s.gap, -0.1, 1e-15);
}

// ------------------------------------------------------------------------------------------
// Whole analyses with exact answers

constexpr double E = 200e9, nu = 0.3;

/// The unit cube of cube_msh() on the plane z = 0 (it touches it), held by rollers on x0 and
/// y0 and with its top face z1 held at z; the plane moves up by `motion`.
std::string pressed_block_case(const std::string& motion, const std::string& times,
                               const std::string& extra = "") {
  return verify::block_on_plane_case("{file: cube.msh}", 0, motion, times, E, nu, extra);
}

/// A contact step on the one-hexahedron cube of pressed_block_case(): the model, and the
/// committed state at t = 0 with a trial state for a step to t = 1 begun from it.
struct CubeContactStep {
  verify::TempDir dir{"contact-step"};
  Log log;
  LoadedCase loaded;
  std::unique_ptr<ContactStep> contact;
  State c, trial;
  explicit CubeContactStep(const std::string& yaml) {
    log.quiet = true;
    verify::write_file(dir.path() / "cube.msh", verify::cube_msh(1, verify::GridCells::hex8, 0));
    verify::write_file(dir.path() / "case.yaml", yaml);
    loaded = load_case(dir.path() / "case.yaml", log);
    contact = std::make_unique<ContactStep>(model());
    c.u.assign(model().dofs().n_dofs(), 0.0);
    contact->initial(c);
    trial = c;
    trial.time = 1;
    contact->begin(c, trial);
  }
  const Model& model() const { return *loaded.model; }
  /// Puts every contact node at height z.
  void move_face_to(double z) {
    for (const ContactPoint& p : model().contacts()[0].points) trial.u[3 * p.node + 2] = z;
  }
};

class PressedBlock : public ::testing::TestWithParam<verify::GridCells> {};

TEST_P(PressedBlock, UniformStressExactly) {
  verify::TempDir dir("contact-block");
  verify::write_file(dir.path() / "cube.msh", verify::cube_msh(2, GetParam(), 0.15));
  const double d = 1e-3;  // the plane rises by d: ε_zz = −d
  const auto run = verify::run_stepped(dir.path(), pressed_block_case(num(d) + "*t", "0.5, 1"));
  ASSERT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
  const State& s = run->all.states.back();
  const double szz = -E * d;
  double worst = 0;
  for (const Voigt& sig : s.stress) {
    worst = std::max(worst, std::abs(sig[2] - szz));
    for (int k : {0, 1, 3, 4, 5}) worst = std::max(worst, std::abs(sig[k]));
  }
  verify::report(fmt::format("block on a rigid plane ({}): largest stress error {:.2e} of σ_zz",
                             verify::to_string(GetParam()), worst / std::abs(szz)));
  EXPECT_LT(worst, 1e-9 * std::abs(szz));
  // Conservation: the support's force balances the reaction at the top, and equals σ·A.
  const auto totals = contact_totals(run->model(), s);
  ASSERT_EQ(totals.size(), 1u);
  EXPECT_NEAR(totals[0].force, -szz, 1e-9 * std::abs(szz));
  EXPECT_NEAR(totals[0].resultant.z(), -szz, 1e-9 * std::abs(szz));
  EXPECT_EQ(totals[0].nodes, static_cast<int>(run->model().contacts()[0].points.size()));
  const auto reactions = region_reactions(run->model(), s);
  EXPECT_NEAR(reactions[0].z() + totals[0].resultant.z(), 0, 1e-9 * std::abs(szz));
  // The contact pressure is −σ_zz at every node, corners of quadratic faces included.
  const NodalContact nc = nodal_contact(run->model(), s);
  for (const ContactPoint& p : run->model().contacts()[0].points)
    EXPECT_NEAR(nc.pressure[p.node], -szz, 1e-8 * std::abs(szz)) << "node " << p.node;
}

INSTANTIATE_TEST_SUITE_P(Cells, PressedBlock,
                         ::testing::Values(verify::GridCells::hex8, verify::GridCells::hex20,
                                           verify::GridCells::wedge6),
                         [](const auto& info) {
                           std::string s = verify::to_string(info.param);
                           for (char& c : s)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return s;
                         });

TEST(ContactStep, AnOscillatingContactSetFailsTheStepInsteadOfLooping) {
  // Iterates that put the block's face alternately 1e-3 below and above the plane make every
  // node flip between contact and separation; after max_flips() changes the step fails (and the
  // step loop cuts it back) instead of iterating on to max_iterations.
  CubeContactStep cs(pressed_block_case("0", "1"));
  ASSERT_EQ(contact_totals(cs.model(), cs.c)[0].nodes, 4);  // touching at t = 0
  int updates = 0;
  EXPECT_THROW(
      {
        for (; updates < 100; ++updates) {
          cs.move_face_to(updates % 2 == 0 ? 1e-3 : -1e-3);
          cs.contact->update(cs.c, cs.trial);
        }
      },
      SolveError);
  EXPECT_EQ(updates, cs.contact->max_flips());  // the (max_flips + 1)-th change throws
}

TEST(ContactStep, AConvergedNodeThatTheSurfacePullsOnIsReleased) {
  // The face of the cube on the plane, every node in contact: one pulled with 1e3 N, one with
  // 1e-3 N (under the limit of 1 N: round-off of the step's tolerance), the others pushed.
  CubeContactStep cs(pressed_block_case("0", "1"));
  auto& nodes = cs.trial.contact[0];
  ASSERT_EQ(nodes.size(), 4u);
  for (ContactNode& n : nodes) {
    ASSERT_TRUE(n.contact);
    n.force = 1e3 * n.normal;
  }
  nodes[0].force = -1e3 * nodes[0].normal;
  nodes[1].force = -1e-3 * nodes[1].normal;
  EXPECT_EQ(cs.contact->release_pulling(cs.c, cs.trial, 1.0), 1);
  EXPECT_FALSE(nodes[0].contact);
  EXPECT_TRUE(nodes[0].separation);  // in contact at t: it separates, (3.5)
  EXPECT_TRUE(nodes[0].force.isZero());
  for (int i : {1, 2, 3}) EXPECT_TRUE(nodes[i].contact) << "node " << i;
  EXPECT_TRUE(cs.contact->progress().set_changed);  // the step cannot end on this iterate
  EXPECT_EQ(cs.contact->progress().in_contact, 3);
  // Nothing pulls any more: nothing to release, and the forces pushing stay.
  EXPECT_EQ(cs.contact->release_pulling(cs.c, cs.trial, 1.0), 0);
  EXPECT_NEAR(nodes[2].force.dot(nodes[2].normal), 1e3, 1e-9);
}

TEST(ContactStep, AutoKappaIsRaisedWhereAGapDoesNotHalve) {
  // Two updates at the same iterate, 1e-3 inside the plane: the gap of every node stays above
  // the allowed one and does not shrink, so auto raises each κ tenfold (a given κ stays).
  for (const bool given : {false, true}) {
    std::string yaml = pressed_block_case("0", "1");
    if (given) yaml.replace(yaml.find("penetration:"), 0, "stiffness: 1e9\n    ");
    CubeContactStep cs(yaml);
    const Model& m = cs.model();
    ContactStep& contact = *cs.contact;
    State &c = cs.c, &trial = cs.trial;
    cs.move_face_to(-1e-3);
    const ContactProgress first = contact.update(c, trial);
    EXPECT_FALSE(first.kappa_raised);  // no earlier gap to compare with
    EXPECT_GT(first.worst_gap, 1);
    std::vector<double> values(m.assembler().pattern().nnz(), 0.0);
    contact.add_matrix(trial, values);
    EXPECT_FALSE(contact.matrix_stale(trial));
    const ContactProgress second = contact.update(c, trial);
    EXPECT_EQ(second.kappa_raised, !given);
    for (std::size_t i = 0; i < m.contacts()[0].points.size(); ++i)
      EXPECT_DOUBLE_EQ(trial.contact[0][i].kappa,
                       (given ? 1 : 10) * m.contacts()[0].initial_kappa(static_cast<int>(i)));
    EXPECT_EQ(contact.matrix_stale(trial), !given);  // a raised κ needs a new factorization
  }
}

class PressedPlasticBlock : public ::testing::TestWithParam<const char*> {};

TEST_P(PressedPlasticBlock, EverySchemeFollowsTheUniaxialCurve) {
  // Linear hardening, plastic modulus Hp: pressed to ε_zz = −d beyond yield the block is in
  // uniaxial stress |σ| = (d + σy/Hp) / (1/E + 1/Hp), uniform: every scheme must land on it.
  verify::TempDir dir("contact-plastic-block");
  verify::write_file(dir.path() / "cube.msh", verify::cube_msh(2, verify::GridCells::hex8, 0.1));
  const double sy = 250e6, Hp = 20e9, d = 4e-3;
  const std::string mat = fmt::format(
      "E: {}, nu: {}, plasticity: {{linear: {{yield: {}, hardening: {}}}}}", num(E), num(nu),
      num(sy), num(Hp));
  std::string yaml = pressed_block_case(num(d) + "*t", "0.25, 0.5, 0.75, 1");
  yaml.replace(yaml.find("E: "), fmt::format("E: {}, nu: {}", num(E), num(nu)).size(), mat);
  yaml.replace(yaml.find("tolerance: 1e-12"), 16,
               fmt::format("tolerance: 1e-9, scheme: {}, relaxation: 0.1, max_iterations: 400",
                           GetParam()));
  const auto run = verify::run_stepped(dir.path(), yaml);
  ASSERT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
  const State& s = run->all.states.back();
  const double szz = -(d + sy / Hp) / (1 / E + 1 / Hp);
  double worst = 0;
  for (const Voigt& sig : s.stress) worst = std::max(worst, std::abs(sig[2] - szz));
  verify::report(fmt::format("plastic block on a rigid plane, {}: σ_zz error {:.2e} of {:.4g}, "
                             "{} iterations",
                             GetParam(), worst / std::abs(szz), szz, run->result.iterations));
  EXPECT_LT(worst, 1e-6 * std::abs(szz));
  EXPECT_NEAR(contact_totals(run->model(), s)[0].force, -szz, 1e-6 * std::abs(szz));
}

INSTANTIATE_TEST_SUITE_P(Schemes, PressedPlasticBlock,
                         ::testing::Values("newton", "variable-stiffness", "initial-strain",
                                           "initial-strain-stiffness", "initial-stress",
                                           "initial-stress-stiffness"),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (char& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

TEST(ContactRelease, TheBlockSeparatesAndReturnsToZeroStress) {
  verify::TempDir dir("contact-release");
  verify::write_file(dir.path() / "cube.msh", verify::cube_msh(2, verify::GridCells::hex8, 0.1));
  // Up by 1e-3 until t = 1, back down to 0 at t = 2 and on to −0.5e-3 at t = 3.
  const auto run = verify::run_stepped(
      dir.path(), pressed_block_case("1e-3*(t <= 1 ? t : 2 - t)", "0.5, 1, 1.5, 2.25, 2.5, 3"));
  ASSERT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
  const auto& states = run->all.states;
  ASSERT_EQ(states.size(), 6u);
  const int n_points = static_cast<int>(run->model().contacts()[0].points.size());
  EXPECT_EQ(contact_totals(run->model(), states[1])[0].nodes, n_points);
  // t = 2.25: the plane is below where the block's face rests; every node has just separated.
  for (int k : {3, 4, 5}) {
    const State& s = states[k];
    const auto totals = contact_totals(run->model(), s);
    EXPECT_EQ(totals[0].nodes, 0) << "t = " << s.time;
    EXPECT_EQ(totals[0].force, 0);
    for (double f : s.f_contact) EXPECT_EQ(f, 0);
    double worst = 0;
    for (const Voigt& sig : s.stress) worst = std::max(worst, sig.cwiseAbs().maxCoeff());
    EXPECT_LT(worst, 1e-9 * E * 1e-3) << "t = " << s.time;
  }
  // The step in which they leave marks them separating (contact_state 2), the next one free.
  const NodalContact leaving = nodal_contact(run->model(), states[3]);
  const NodalContact later = nodal_contact(run->model(), states[4]);
  for (const ContactPoint& p : run->model().contacts()[0].points) {
    EXPECT_EQ(leaving.state[p.node], 2) << "node " << p.node;
    EXPECT_EQ(later.state[p.node], 0) << "node " << p.node;
    EXPECT_NEAR(later.gap[p.node], 0.5e-3, 1e-12);
  }
}

TEST(ContactThermal, ABarHeatedAgainstAWallAfterItsGapCloses) {
  // Bar 1 x 1 x 1 on rollers, z0 held; a rigid wall at z = 1 + g faces it from above. Heated
  // by ΔT(t) = 200 t: free expansion α ΔT until α ΔT·L = g (t = 0.5), then σ_zz = −E(αΔT − g/L).
  verify::TempDir dir("contact-thermal");
  verify::write_file(dir.path() / "cube.msh", verify::cube_msh(2, verify::GridCells::hex20, 0.1));
  const double alpha = 1.2e-5, g = 1.2e-3;
  const std::string yaml = fmt::format(R"(mesh: {{file: cube.msh}}
materials:
  - {{E: {}, nu: {}, alpha: {}}}
temperature: {{reference: 20, field: "20 + 200*t"}}
boundary:
  - {{region: x0, displacement: {{x: 0}}}}
  - {{region: y0, displacement: {{y: 0}}}}
  - {{region: z0, displacement: {{z: 0}}}}
contact:
  - name: wall
    nodes: z1
    surface: {{plane: {{point: [0, 0, {}], normal: [0, 0, -1]}}}}
    penetration: 1e-12
solver: {{times: [0.25, 0.5, 0.75, 1], tolerance: 1e-10}}
)",
                                       num(E), num(nu), num(alpha), num(1 + g));
  const auto run = verify::run_stepped(dir.path(), yaml);
  ASSERT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
  const auto& states = run->all.states;
  ASSERT_EQ(states.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const double dT = 200 * states[k].time;
    const double szz = -E * std::max(0.0, alpha * dT - g);
    double worst = 0;
    for (const Voigt& sig : states[k].stress) {
      worst = std::max(worst, std::abs(sig[2] - szz));
      for (int c : {0, 1, 3, 4, 5}) worst = std::max(worst, std::abs(sig[c]));
    }
    verify::report(fmt::format("heated bar against a wall, t = {:g}: σ_zz = {:.6g} expected, "
                               "largest error {:.2e}",
                               states[k].time, szz, worst));
    EXPECT_LT(worst, 1e-9 * E * alpha * 200) << "t = " << states[k].time;
  }
}

}  // namespace
}  // namespace hencky
