// The tuner's search (docs/tune.md, "The search"): per system, the cheapest configuration of a
// few discrete knobs whose error stays within a budget, without evaluating the whole grid.
//
// Each knob is a list of settings ordered from cheapest (and, as a rule, least accurate) to
// dearest. Greedy ascent: start with every knob at its first setting; while the current
// configuration's error is above the budget, evaluate each one-step move up (one knob one
// setting further) and take the one with the largest error drop per added cost,
//   gain = (error - error') / max(cost' - cost, tiny)
// (a move that adds no cost and lowers the error wins outright); when no move lowers the error
// (a non-monotone spot, e.g. 4 SH bands worse than 3 on some skies), take the move with the
// lowest error, so the ascent still reaches the accurate end. Then trim: from the configuration
// reached, try each one-step move down and take it when it stays within the budget and costs
// less, until none does. The answer is the cheapest configuration evaluated (by either phase)
// whose error is within the budget; when none is, the most accurate one evaluated (met = false).
// Evaluations are cached by configuration, so none is run twice.
// Why this search: the knobs' errors are near-monotone each (more azimuths, bands, spheres or
// probes: less error) and their costs multiply, so the cheapest feasible point lies near the
// path that buys the most error per unit of cost; each ascent step costs one evaluation per
// knob, so a search takes about (knobs) x (steps to the budget) evaluations instead of the
// product of the knobs' lengths.
// Threading: calls `evaluate` on the caller's thread, in order.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace penumbra::tune {

struct Knob {
  std::string name;
  std::vector<std::string> values;  // labels, cheapest first
};

struct Evaluation {
  double error = 0;  // relative RMS error against the reference
  double cost = 0;   // the cost model's value (any unit; only differences and order matter)
  double ms = 0;     // measured time, reported only
};

using Config = std::vector<int>;  // one index per knob

struct SearchResult {
  Config best;
  Evaluation best_eval;
  bool met = false;
  int evaluations = 0;                               // distinct configurations evaluated
  int grid = 0;                                      // product of the knobs' lengths
  std::vector<std::pair<Config, Evaluation>> trace;  // every evaluation, in order
};

// evaluate(config) -> its error and cost; progress(evaluations so far) after each evaluation.
SearchResult greedy_search(const std::vector<Knob>& knobs, double budget,
                           const std::function<Evaluation(const Config&)>& evaluate,
                           const std::function<void(int)>& progress = {});

// "azimuths=8 bands=3" for messages.
std::string describe(const std::vector<Knob>& knobs, const Config& config);

}  // namespace penumbra::tune
