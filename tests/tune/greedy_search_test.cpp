// The tuner's greedy search (game/tune/greedy_search.h) on synthetic knobs whose errors and
// costs are known, so the answer can be checked against the whole grid.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "tune/greedy_search.h"

namespace penumbra::tune {
namespace {

// Error falls geometrically along each knob, cost multiplies: the usual shape.
Evaluation separable(const Config& c) {
  Evaluation e;
  e.error = 0.2 * std::pow(0.5, c[0]) + 0.1 * std::pow(0.6, c[1]);
  e.cost = (1 + c[0]) * (1.0 + 2.0 * c[1]);
  return e;
}

const std::vector<Knob> kKnobs = {{"a", {"0", "1", "2", "3", "4", "5"}},
                                  {"b", {"0", "1", "2", "3", "4", "5"}}};

// The cheapest grid point within the budget (brute force).
double cheapest_feasible(double budget) {
  double best = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) {
      const Evaluation e = separable({a, b});
      if (e.error <= budget) best = std::min(best, e.cost);
    }
  return best;
}

TEST(GreedySearch, FindsAFeasibleCheapConfigurationWithFewEvaluations) {
  for (double budget : {0.2, 0.1, 0.05, 0.03, 0.02}) {
    int calls = 0;
    const SearchResult r = greedy_search(kKnobs, budget, [&](const Config& c) {
      ++calls;
      return separable(c);
    });
    EXPECT_TRUE(r.met) << budget;
    EXPECT_LE(r.best_eval.error, budget);
    EXPECT_EQ(r.evaluations, calls);  // nothing evaluated twice
    EXPECT_EQ(r.grid, 36);
    EXPECT_LT(r.evaluations, r.grid / 2) << budget;
    // Greedy, not exhaustive: within 2x of the true optimum's cost on this shape.
    EXPECT_LE(r.best_eval.cost, 2 * cheapest_feasible(budget)) << budget;
  }
}

TEST(GreedySearch, StartsAtTheCheapestCornerAndStopsThereWhenItSuffices) {
  const SearchResult r = greedy_search(kKnobs, 0.5, separable);
  EXPECT_EQ(r.best, (Config{0, 0}));
  EXPECT_EQ(r.evaluations, 1);
}

TEST(GreedySearch, UnreachableBudgetGivesTheMostAccurateEvaluated) {
  const SearchResult r = greedy_search(kKnobs, 1e-6, separable);
  EXPECT_FALSE(r.met);
  EXPECT_EQ(r.best, (Config{5, 5}));  // the ascent reaches the accurate corner
}

TEST(GreedySearch, CrossesANonMonotoneStep) {
  // Knob 0's second setting is worse than its first (4 bands worse than 3); only its third
  // reaches the budget: the ascent must step through it.
  const std::vector<Knob> knobs = {{"bands", {"3", "4", "5"}}};
  const double errors[] = {0.05, 0.06, 0.01};
  const SearchResult r = greedy_search(knobs, 0.02, [&](const Config& c) {
    return Evaluation{errors[c[0]], 1.0 + c[0], 0};
  });
  EXPECT_TRUE(r.met);
  EXPECT_EQ(r.best, (Config{2}));
}

TEST(GreedySearch, RejectsEmptyKnobs) {
  EXPECT_THROW(greedy_search({}, 0.1, separable), std::invalid_argument);
  EXPECT_THROW(greedy_search({{"a", {}}}, 0.1, separable), std::invalid_argument);
}

TEST(GreedySearch, Describe) {
  EXPECT_EQ(describe(kKnobs, {2, 3}), "a=2 b=3");
}

}  // namespace
}  // namespace penumbra::tune
