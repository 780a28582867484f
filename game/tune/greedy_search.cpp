#include "greedy_search.h"

#include <limits>
#include <stdexcept>

namespace penumbra::tune {

SearchResult greedy_search(const std::vector<Knob>& knobs, double budget,
                           const std::function<Evaluation(const Config&)>& evaluate,
                           const std::function<void(int)>& progress) {
  if (knobs.empty()) throw std::invalid_argument("greedy_search: no knobs");
  SearchResult out;
  out.grid = 1;
  for (const Knob& k : knobs) {
    if (k.values.empty())
      throw std::invalid_argument("greedy_search: knob " + k.name + " is empty");
    out.grid *= static_cast<int>(k.values.size());
  }
  std::map<Config, Evaluation> cache;
  auto eval = [&](const Config& c) -> const Evaluation& {
    auto it = cache.find(c);
    if (it != cache.end()) return it->second;
    const Evaluation e = evaluate(c);
    out.trace.emplace_back(c, e);
    ++out.evaluations;
    if (progress) progress(out.evaluations);
    return cache.emplace(c, e).first->second;
  };

  // Ascent.
  Config cur(knobs.size(), 0);
  Evaluation ce = eval(cur);
  while (ce.error > budget) {
    Config pick;
    Evaluation pe;
    double best_gain = -std::numeric_limits<double>::infinity();
    double lowest = std::numeric_limits<double>::infinity();
    Config lowest_cfg;
    Evaluation lowest_eval;
    for (std::size_t k = 0; k < knobs.size(); ++k) {
      if (cur[k] + 1 >= static_cast<int>(knobs[k].values.size())) continue;
      Config c = cur;
      ++c[k];
      const Evaluation e = eval(c);
      if (e.error < lowest) {
        lowest = e.error;
        lowest_cfg = c;
        lowest_eval = e;
      }
      const double drop = ce.error - e.error;
      if (drop <= 0) continue;
      const double added = e.cost - ce.cost;
      const double gain =
          added > 1e-12 * (1 + ce.cost) ? drop / added : std::numeric_limits<double>::max() * drop;
      if (gain > best_gain) {
        best_gain = gain;
        pick = c;
        pe = e;
      }
    }
    if (pick.empty()) {
      if (lowest_cfg.empty()) break;  // every knob at its last setting
      pick = lowest_cfg;
      pe = lowest_eval;
    }
    cur = pick;
    ce = pe;
  }

  // Trim: cheaper neighbours that stay within the budget.
  bool moved = ce.error <= budget;
  while (moved) {
    moved = false;
    for (std::size_t k = 0; k < knobs.size(); ++k) {
      if (cur[k] == 0) continue;
      Config c = cur;
      --c[k];
      const Evaluation e = eval(c);
      if (e.error <= budget && e.cost < ce.cost) {
        cur = c;
        ce = e;
        moved = true;
      }
    }
  }

  // The cheapest evaluated configuration within the budget, else the most accurate.
  bool found = false;
  for (const auto& [c, e] : cache) {
    if (e.error <= budget && (!found || e.cost < out.best_eval.cost)) {
      out.best = c;
      out.best_eval = e;
      found = true;
    }
  }
  out.met = found;
  if (!found)
    for (const auto& [c, e] : cache)
      if (out.best.empty() || e.error < out.best_eval.error) {
        out.best = c;
        out.best_eval = e;
      }
  return out;
}

std::string describe(const std::vector<Knob>& knobs, const Config& config) {
  std::string s;
  for (std::size_t k = 0; k < knobs.size() && k < config.size(); ++k)
    s += (s.empty() ? "" : " ") + knobs[k].name + "=" +
         knobs[k].values[static_cast<std::size_t>(config[k])];
  return s;
}

}  // namespace penumbra::tune
