#include "penumbra/jobs/schedule.h"

#include <algorithm>
#include <cstdint>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace penumbra::jobs {
namespace {

// A fixed-size bitset over node indices, sized at run time.
struct Bits {
  std::vector<std::uint64_t> w;
  explicit Bits(std::size_t n = 0) : w((n + 63) / 64, 0) {}
  void set(std::size_t i) { w[i / 64] |= std::uint64_t{1} << (i % 64); }
  bool test(std::size_t i) const { return (w[i / 64] >> (i % 64)) & 1u; }
  void merge(const Bits& o) {
    for (std::size_t k = 0; k < w.size(); ++k) w[k] |= o.w[k];
  }
};

std::vector<std::string> sorted_names(const ecs::TypeSet& set) {
  std::vector<std::string> names;
  for (std::size_t t = 0; t < ecs::kMaxTypes; ++t) {
    if (set.test(t)) names.emplace_back(ecs::type_info(static_cast<ecs::TypeId>(t)).name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace

System& Schedule::push(std::string name, System::Kind kind) {
  auto s = std::make_unique<System>();
  s->name = std::move(name);
  s->kind = kind;
  if (kind == System::Kind::kSync) s->access.exclusive = true;
  systems_.push_back(std::move(s));
  built_ = false;
  return *systems_.back();
}

void Schedule::add_sync_point(std::string name) {
  push(std::move(name), System::Kind::kSync);
}

namespace {

using EdgeMatrix = std::vector<std::vector<char>>;

// 1. The node list in registration order, with a sync point wherever deferred commands must be
//    applied before a later system can see their effect (the sync systems go to `owned`).
std::vector<System*> with_sync_points(const std::vector<std::unique_ptr<System>>& systems,
                                      std::vector<std::unique_ptr<System>>& owned) {
  owned.clear();
  std::vector<System*> list;
  ecs::TypeSet pending;
  bool pending_spawn = false;
  auto add_sync = [&](std::string name) {
    auto s = std::make_unique<System>();
    s->name = std::move(name);
    s->kind = System::Kind::kSync;
    s->access.exclusive = true;
    list.push_back(s.get());
    owned.push_back(std::move(s));
    pending.reset();
    pending_spawn = false;
  };
  for (const auto& sp : systems) {
    System& s = *sp;
    if (s.kind == System::Kind::kSync) {
      list.push_back(&s);
      pending.reset();
      pending_spawn = false;
      continue;
    }
    const bool sees_pending = s.access.touches(pending) || (pending & s.exclude).any() ||
                              (pending_spawn && s.kind == System::Kind::kChunks);
    if (sees_pending) add_sync("sync before " + s.name);
    list.push_back(&s);
    pending |= s.access.structural;
    pending_spawn = pending_spawn || s.access.spawns;
  }
  if (pending.any() || pending_spawn) add_sync("sync: end of frame");
  std::unordered_map<std::string, std::uint32_t> index;
  for (std::uint32_t i = 0; i < list.size(); ++i)
    if (!index.emplace(list[i]->name, i).second)
      throw std::invalid_argument("Schedule: two systems are named '" + list[i]->name + "'");
  return list;
}

// 2. Direct edges: sync points against everything, conflicts (by registration, unless ordering
//    is explicit), and the explicit after / before constraints.
EdgeMatrix direct_edges(const std::vector<System*>& list, Schedule::Ordering ordering) {
  const std::size_t n = list.size();
  std::unordered_map<std::string, std::uint32_t> index;
  for (std::uint32_t i = 0; i < n; ++i) index.emplace(list[i]->name, i);
  EdgeMatrix edge(n, std::vector<char>(n, 0));
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = i + 1; j < n; ++j) {
      const bool sync =
          list[i]->kind == System::Kind::kSync || list[j]->kind == System::Kind::kSync;
      if (sync || (ordering == Schedule::Ordering::kRegistration &&
                   list[i]->access.conflicts_with(list[j]->access))) {
        edge[i][j] = 1;
      }
    }
  }
  auto lookup = [&](const std::string& owner, const std::string& name) {
    auto it = index.find(name);
    if (it == index.end()) {
      throw std::invalid_argument("Schedule: system '" + owner +
                                  "' is ordered against unknown system '" + name + "'");
    }
    return it->second;
  };
  for (std::uint32_t i = 0; i < n; ++i) {
    for (const auto& a : list[i]->after) edge[lookup(list[i]->name, a)][i] = 1;
    for (const auto& b : list[i]->before) edge[i][lookup(list[i]->name, b)] = 1;
  }
  return edge;
}

// 3. Topological order (Kahn, ties broken by registration position: deterministic); throws on a
//    cycle, naming its systems.
std::vector<std::uint32_t> topological_order(const EdgeMatrix& edge,
                                             const std::vector<System*>& list) {
  const std::size_t n = list.size();
  std::vector<std::uint32_t> indeg(n, 0), order;
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = 0; j < n; ++j) indeg[j] += edge[i][j];
  }
  std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, std::greater<>> ready;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (indeg[i] == 0) ready.push(i);
  }
  while (!ready.empty()) {
    const std::uint32_t u = ready.top();
    ready.pop();
    order.push_back(u);
    for (std::uint32_t v = 0; v < n; ++v) {
      if (edge[u][v] && --indeg[v] == 0) ready.push(v);
    }
  }
  if (order.size() != n) {
    std::string cycle;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (indeg[i] > 0) cycle += (cycle.empty() ? "" : ", ") + list[i]->name;
    }
    throw std::invalid_argument("Schedule: ordering constraints form a cycle among: " + cycle);
  }
  return order;
}

// Which nodes each node reaches, given a topological order.
std::vector<Bits> reachability(const EdgeMatrix& edge, const std::vector<std::uint32_t>& order) {
  const std::size_t n = edge.size();
  std::vector<Bits> reach(n, Bits(n));
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    for (std::uint32_t v = 0; v < n; ++v) {
      if (edge[*it][v]) {
        reach[*it].set(v);
        reach[*it].merge(reach[v]);
      }
    }
  }
  return reach;
}

// 4. Conflicting pairs that no path orders (explicit ordering): returned, and serialised in
//    registration order so the frame stays race-free.
std::vector<Conflict> serialise_unordered_conflicts(const std::vector<System*>& list,
                                                    const std::vector<Bits>& reach,
                                                    EdgeMatrix& edge) {
  std::vector<Conflict> conflicts;
  for (std::uint32_t i = 0; i < list.size(); ++i) {
    for (std::uint32_t j = i + 1; j < list.size(); ++j) {
      if (list[i]->access.conflicts_with(list[j]->access) && !reach[i].test(j) &&
          !reach[j].test(i)) {
        conflicts.push_back({list[i]->name, list[j]->name});
        edge[i][j] = 1;
      }
    }
  }
  return conflicts;
}

// 5. The transitively reduced graph as nodes in topological order.
std::vector<Schedule::Node> reduced_nodes(const std::vector<System*>& list, const EdgeMatrix& edge,
                                          const std::vector<std::uint32_t>& order,
                                          const std::vector<Bits>& reach) {
  const std::size_t n = list.size();
  std::vector<std::uint32_t> position(n);
  for (std::uint32_t p = 0; p < n; ++p) position[order[p]] = p;
  std::vector<Schedule::Node> nodes(n, Schedule::Node{});
  for (std::uint32_t p = 0; p < n; ++p) nodes[p].system = list[order[p]];
  for (std::uint32_t u = 0; u < n; ++u) {
    for (std::uint32_t v = 0; v < n; ++v) {
      if (!edge[u][v]) continue;
      bool implied = false;
      for (std::uint32_t w = 0; w < n && !implied; ++w) {
        implied = w != v && edge[u][w] && reach[w].test(v);
      }
      if (implied) continue;
      nodes[position[u]].successors.push_back(position[v]);
      nodes[position[v]].predecessors.push_back(position[u]);
    }
  }
  for (Schedule::Node& node : nodes) {
    std::sort(node.successors.begin(), node.successors.end());
    std::sort(node.predecessors.begin(), node.predecessors.end());
  }
  return nodes;
}

}  // namespace

bool Schedule::set_paused(std::string_view name, bool paused) {
  for (const auto& s : systems_)
    if (s->name == name && s->kind != System::Kind::kSync) {
      s->paused = paused;
      return true;
    }
  return false;
}

bool Schedule::paused(std::string_view name) const {
  for (const auto& s : systems_)
    if (s->name == name) return s->paused;
  return false;
}

void Schedule::build() {
  const std::vector<System*> list = with_sync_points(systems_, auto_syncs_);
  EdgeMatrix edge = direct_edges(list, ordering_);
  std::vector<std::uint32_t> order = topological_order(edge, list);
  std::vector<Bits> reach = reachability(edge, order);
  conflicts_ = serialise_unordered_conflicts(list, reach, edge);
  if (!conflicts_.empty()) {
    order = topological_order(edge, list);
    reach = reachability(edge, order);
  }
  nodes_ = reduced_nodes(list, edge, order, reach);
  built_ = true;
}

std::string Schedule::to_dot() const {
  std::ostringstream out;
  out << "digraph schedule {\n  rankdir=LR;\n  node [shape=box, fontname=\"monospace\"];\n";
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const System& s = *nodes_[i].system;
    out << "  n" << i << " [label=\"" << s.name;
    if (s.kind == System::Kind::kSync) {
      out << "\", shape=diamond];\n";
      continue;
    }
    const auto reads = sorted_names(s.access.reads & ~s.access.writes);
    const auto writes = sorted_names(s.access.writes);
    if (!reads.empty()) out << "\\nR: " << join(reads);
    if (!writes.empty()) out << "\\nW: " << join(writes);
    if (s.access.spawns) out << "\\n+ spawns";
    if (s.access.structural.any())
      out << "\\n+ adds/removes: " << join(sorted_names(s.access.structural));
    out << "\"];\n";
  }
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    for (std::uint32_t s : nodes_[i].successors) out << "  n" << i << " -> n" << s << ";\n";
  }
  out << "}\n";
  return out.str();
}

}  // namespace penumbra::jobs
