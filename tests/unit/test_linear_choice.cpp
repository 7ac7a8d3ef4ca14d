// solver.linear: auto (solve/linear_choice.hpp): the rule chooses as documented, with its
// thresholds injected so that small models reach every branch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "solve/linear_choice.hpp"

namespace hencky {
namespace {

LinearChoiceInputs displacement(std::int64_t unknowns, double available = 0) {
  LinearChoiceInputs in;
  in.unknowns = unknowns;
  in.available_bytes = available;
  return in;
}

/// The rule with its crossover constant in n (growth 0) unless told.
LinearChoiceRule rule_from(std::int64_t analyze_from, double crossover = 4.6e6, double growth = 0) {
  LinearChoiceRule r;
  r.analyze_from = analyze_from;
  r.crossover_flops = crossover;
  r.crossover_growth = growth;
  return r;
}

TEST(LinearChoice, BelowTheAnalysisSizeTheFactorizationUnanalysed) {
  const LinearChoiceInputs in = displacement(999);
  EXPECT_FALSE(wants_factor_estimate(in, rule_from(1000)));
  EXPECT_TRUE(wants_factor_estimate(displacement(1000), rule_from(1000)));
  const LinearChoice c = choose_linear(in, rule_from(1000));
  EXPECT_EQ(c.linear, SolverSpec::Linear::direct);
  EXPECT_NE(c.reason.find("999 unknowns, fewer than the 1000"), std::string::npos) << c.reason;
}

TEST(LinearChoice, TheFactorsFlopsPerUnknownAgainstTheCrossover) {
  LinearChoiceInputs in = displacement(1000);
  in.factor_entries = 1e5;
  in.factor_flops = 1000 * 4.5e6;  // 4.5 Mflop per unknown: below 4.6
  const LinearChoice below = choose_linear(in, rule_from(1000));
  EXPECT_EQ(below.linear, SolverSpec::Linear::direct);
  EXPECT_NE(below.reason.find("4.5 Mflop per unknown, below the 4.6 from which CG + GAMG would "
                              "be faster at this size"),
            std::string::npos)
      << below.reason;
  EXPECT_DOUBLE_EQ(below.predicted_direct_bytes, 12.5 * 1e5);  // the analysed entries
  in.factor_flops = 1000 * 4.6e6;
  const LinearChoice at = choose_linear(in, rule_from(1000));
  EXPECT_EQ(at.linear, SolverSpec::Linear::petsc);
  EXPECT_NE(at.reason.find("at least the 4.6"), std::string::npos) << at.reason;
}

TEST(LinearChoice, TheCrossoverGrowsWithTheSize) {
  const LinearChoiceRule rule;  // the measured one: 3.6 Mflop per unknown × (n / 100k)^0.4
  EXPECT_DOUBLE_EQ(rule.crossover_at(1e5), 3.6e6);
  EXPECT_NEAR(rule.crossover_at(1e6), 3.6e6 * std::pow(10.0, 0.4), 1);
  // The bench's two cases at ~390k (docs/performance.md): the cantilever's 2.4 Mflop per
  // unknown stays direct, the cylinder's 6.8 goes to CG + GAMG; the 1M cantilever's 7.1 stays
  // direct on its flops (CHOLMOD 184 s, CG + GAMG 218-273 s there; memory is not given here:
  // with the 23 GB of that machine its 17.5 GB factor goes to CG + GAMG).
  LinearChoiceInputs in = displacement(384'597);
  in.factor_entries = 3.5e8;
  in.factor_flops = 2.38e6 * in.unknowns;
  EXPECT_EQ(choose_linear(in, rule).linear, SolverSpec::Linear::direct);
  in.unknowns = 386'082;
  in.factor_flops = 6.77e6 * in.unknowns;
  EXPECT_EQ(choose_linear(in, rule).linear, SolverSpec::Linear::petsc);
  in.unknowns = 1'028'922;
  in.factor_flops = 7.08e6 * in.unknowns;
  EXPECT_EQ(choose_linear(in, rule).linear, SolverSpec::Linear::direct);
}

TEST(LinearChoice, SeveralRanksAlwaysCgWithGamg) {
  LinearChoiceInputs in = displacement(300);
  in.ranks = 2;
  EXPECT_FALSE(wants_factor_estimate(in, rule_from(100)));
  const LinearChoice c = choose_linear(in, rule_from(1000));
  EXPECT_EQ(c.linear, SolverSpec::Linear::petsc);
  EXPECT_NE(c.reason.find("2 MPI ranks"), std::string::npos) << c.reason;
}

TEST(LinearChoice, AFactorThatWouldNotFitGoesIterative) {
  const LinearChoiceRule rule = rule_from(1'000'000);
  // 3000 unknowns = 1000 nodes: 12.5 B × 10 × 1000^(4/3) × 9 = 11.25 MB predicted.
  const LinearChoice fits = choose_linear(displacement(3000, 100e6), rule);
  EXPECT_NEAR(fits.predicted_direct_bytes, 12.5 * 10 * 1e4 * 9, 1);
  EXPECT_EQ(fits.linear, SolverSpec::Linear::direct);
  // 11.25 MB > 0.7 × 15 MB
  const LinearChoice tight = choose_linear(displacement(3000, 15e6), rule);
  EXPECT_EQ(tight.linear, SolverSpec::Linear::petsc);
  EXPECT_NE(tight.reason.find("more than 70 %"), std::string::npos) << tight.reason;
  // An analysed factor that would not fit, although cheap in flops.
  LinearChoiceInputs big = displacement(3000, 15e6);
  big.factor_entries = 1e6;  // 12.5 MB
  big.factor_flops = 3000;
  EXPECT_EQ(choose_linear(big, rule).linear, SolverSpec::Linear::petsc);
  // Unknown memory is not checked.
  EXPECT_EQ(choose_linear(displacement(3000, 0), rule).linear, SolverSpec::Linear::direct);
}

TEST(LinearChoice, ATemperatureSystemCountsAsTheDisplacementOnItsMesh) {
  LinearChoiceInputs heat;
  heat.per_node = 1;
  heat.unknowns = 400;  // 400 nodes: 1200 displacement unknowns
  EXPECT_TRUE(wants_factor_estimate(heat, rule_from(1000)));
  heat.unknowns = 300;
  EXPECT_FALSE(wants_factor_estimate(heat, rule_from(1000)));
  // Its factor is a ninth of the displacement's of the same mesh.
  EXPECT_NEAR(choose_linear(heat, rule_from(1000)).predicted_direct_bytes * 9,
              choose_linear(displacement(900), rule_from(1000)).predicted_direct_bytes, 1e-6);
  // Its flops per unknown count 9 times: those of the displacement system on its mesh
  // (27 times the flops over 3 times the unknowns).
  heat.factor_entries = 1e4;
  heat.factor_flops = 300 * 0.5e6;  // 0.5 Mflop per unknown, 4.5 as a displacement
  const LinearChoice c = choose_linear(heat, rule_from(100));
  EXPECT_EQ(c.linear, SolverSpec::Linear::direct);
  EXPECT_NE(c.reason.find("4.5 Mflop per unknown (as a displacement on this mesh)"),
            std::string::npos) << c.reason;
  heat.factor_flops = 300 * 0.52e6;
  EXPECT_EQ(choose_linear(heat, rule_from(100)).linear, SolverSpec::Linear::petsc);
}

TEST(LinearChoice, NonlinearModelsSayTheRuleWasMeasuredElastic) {
  LinearChoiceInputs in = displacement(10);
  in.nonlinear = true;
  EXPECT_NE(choose_linear(in, rule_from(1000)).reason.find("measured on elastic"),
            std::string::npos);
}

TEST(LinearChoice, TheEnvironmentInjectsTheThresholdAndTheMemory) {
  ::setenv("HENCKY_AUTO_ANALYZE_FROM", "123", 1);
  ::setenv("HENCKY_AUTO_CROSSOVER", "2.5e5", 1);
  ::setenv("HENCKY_AUTO_MEMORY", "4.5e6", 1);
  EXPECT_EQ(LinearChoiceRule::from_environment().analyze_from, 123);
  EXPECT_DOUBLE_EQ(LinearChoiceRule::from_environment().crossover_flops, 2.5e5);
  EXPECT_DOUBLE_EQ(available_memory_bytes(), 4.5e6);
  ::unsetenv("HENCKY_AUTO_ANALYZE_FROM");
  ::unsetenv("HENCKY_AUTO_CROSSOVER");
  ::unsetenv("HENCKY_AUTO_MEMORY");
  EXPECT_EQ(LinearChoiceRule::from_environment().analyze_from, LinearChoiceRule{}.analyze_from);
  EXPECT_GT(available_memory_bytes(), 0);  // /proc/meminfo
}

}  // namespace
}  // namespace hencky
