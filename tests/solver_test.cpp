// Tests of restitch/solver: BkMaxFlow and PushRelabelMaxFlow against an Edmonds-Karp oracle,
// alpha-expansion against exhaustive search and its guarantees, check_metric,
// and the MRF file format.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "restitch/solver/alpha_expansion.hpp"
#include "restitch/solver/max_flow_bk.hpp"
#include "restitch/solver/max_flow_push_relabel.hpp"
#include "restitch/solver/mrf.hpp"
#include "restitch/solver/mrf_io.hpp"

using restitch::AlphaExpansion;
using restitch::BkMaxFlow;
using restitch::PushRelabelMaxFlow;
using restitch::SolveReport;
using restitch::StatusCode;
using restitch::TableMrf;

namespace {

// Numbers straight from the engine's raw output (std distributions differ
// across standard libraries).
struct Rng {
  std::mt19937_64 engine;
  explicit Rng(std::uint64_t seed) : engine(seed) {}
  int uniform_int(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(engine() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  double uniform01() { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }
  bool chance(double p) { return uniform01() < p; }
};

// ---------------------------------------------------------------------------
// Max-flow oracle: Edmonds-Karp (BFS augmenting paths) on a dense matrix.
// Node n is the source, n + 1 the sink.
template <class Cap>
struct EdmondsKarp {
  int n;
  std::vector<Cap> cap;  // (n+2)^2 residual capacities
  explicit EdmondsKarp(int nodes) : n(nodes), cap(static_cast<std::size_t>((nodes + 2) * (nodes + 2)), Cap(0)) {}
  Cap& at(int i, int j) { return cap[static_cast<std::size_t>(i * (n + 2) + j)]; }
  void add_tweights(int i, Cap s, Cap t) {
    at(n, i) += s;
    at(i, n + 1) += t;
  }
  void add_edge(int i, int j, Cap c, Cap r) {
    at(i, j) += c;
    at(j, i) += r;
  }
  // Nodes reachable from the source in the residual graph.
  std::vector<char> reachable() {
    std::vector<char> seen(static_cast<std::size_t>(n + 2), 0);
    std::vector<int> queue{n};
    seen[static_cast<std::size_t>(n)] = 1;
    for (std::size_t k = 0; k < queue.size(); ++k)
      for (int v = 0; v < n + 2; ++v)
        if (!seen[static_cast<std::size_t>(v)] && at(queue[k], v) > 0) {
          seen[static_cast<std::size_t>(v)] = 1;
          queue.push_back(v);
        }
    return seen;
  }
  // Nodes that reach the sink in the residual graph.
  std::vector<char> reaches_sink() {
    std::vector<char> seen(static_cast<std::size_t>(n + 2), 0);
    std::vector<int> queue{n + 1};
    seen[static_cast<std::size_t>(n + 1)] = 1;
    for (std::size_t k = 0; k < queue.size(); ++k)
      for (int v = 0; v < n + 2; ++v)
        if (!seen[static_cast<std::size_t>(v)] && at(v, queue[k]) > 0) {
          seen[static_cast<std::size_t>(v)] = 1;
          queue.push_back(v);
        }
    return seen;
  }
  Cap max_flow() {
    Cap flow = 0;
    for (;;) {
      std::vector<int> prev(static_cast<std::size_t>(n + 2), -1);
      std::vector<int> queue{n};
      prev[static_cast<std::size_t>(n)] = n;
      for (std::size_t k = 0; k < queue.size() && prev[static_cast<std::size_t>(n + 1)] < 0; ++k)
        for (int v = 0; v < n + 2; ++v)
          if (prev[static_cast<std::size_t>(v)] < 0 && at(queue[k], v) > 0) {
            prev[static_cast<std::size_t>(v)] = queue[k];
            queue.push_back(v);
          }
      if (prev[static_cast<std::size_t>(n + 1)] < 0) return flow;
      Cap f = std::numeric_limits<Cap>::max();
      for (int v = n + 1; v != n; v = prev[static_cast<std::size_t>(v)])
        f = std::min(f, at(prev[static_cast<std::size_t>(v)], v));
      for (int v = n + 1; v != n; v = prev[static_cast<std::size_t>(v)]) {
        at(prev[static_cast<std::size_t>(v)], v) -= f;
        at(v, prev[static_cast<std::size_t>(v)]) += f;
      }
      flow += f;
    }
  }
};

struct GraphSpec {
  int n = 0;
  struct T {
    int i;
    double s, t;
  };
  struct E {
    int i, j;
    double c, r;
  };
  std::vector<T> tw;
  std::vector<E> edges;
};

double random_capacity(Rng& rng, bool integral) {
  if (rng.chance(0.25)) return 0;
  return integral ? rng.uniform_int(1, 12) : 0.01 + 10 * rng.uniform01();
}

GraphSpec random_graph(Rng& rng, bool integral) {
  GraphSpec g;
  g.n = rng.uniform_int(2, 30);
  const int tw = rng.uniform_int(1, 2 * g.n);
  for (int k = 0; k < tw; ++k)
    g.tw.push_back({rng.uniform_int(0, g.n - 1), random_capacity(rng, integral), random_capacity(rng, integral)});
  const int edges = rng.uniform_int(0, 4 * g.n);
  for (int k = 0; k < edges; ++k) {
    const int i = rng.uniform_int(0, g.n - 1);
    int j = rng.uniform_int(0, g.n - 2);
    if (j >= i) ++j;
    g.edges.push_back({i, j, random_capacity(rng, integral), random_capacity(rng, integral)});
  }
  return g;
}

// Original capacity of the cut (S = in_source_segment) of graph g.
template <class Cap, class MaxFlow>
Cap cut_capacity(const GraphSpec& g, const MaxFlow& mf) {
  Cap c = 0;
  for (const auto& t : g.tw) c += mf.in_source_segment(t.i) ? Cap(t.t) : Cap(t.s);
  for (const auto& e : g.edges) {
    const bool si = mf.in_source_segment(e.i), sj = mf.in_source_segment(e.j);
    if (si && !sj) c += Cap(e.c);
    if (sj && !si) c += Cap(e.r);
  }
  return c;
}

template <class Cap, template <class> class MaxFlow = BkMaxFlow>
void check_against_oracle(std::uint64_t seed, int graphs) {
  Rng rng(seed);
  MaxFlow<Cap> mf;  // one object, reused through reset()
  for (int k = 0; k < graphs; ++k) {
    const GraphSpec g = random_graph(rng, true);
    mf.reset(g.n, static_cast<int>(g.edges.size()));
    CHECK(mf.add_node(g.n) == 0);
    EdmondsKarp<Cap> ek(g.n);
    for (const auto& t : g.tw) {
      mf.add_tweights(t.i, Cap(t.s), Cap(t.t));
      ek.add_tweights(t.i, Cap(t.s), Cap(t.t));
    }
    for (const auto& e : g.edges) {
      mf.add_edge(e.i, e.j, Cap(e.c), Cap(e.r));
      ek.add_edge(e.i, e.j, Cap(e.c), Cap(e.r));
    }
    const Cap flow = mf.max_flow();
    const Cap expected = ek.max_flow();
    INFO("graph " << k << " nodes " << g.n);
    REQUIRE(flow == expected);
    CHECK(cut_capacity<Cap>(g, mf) == flow);
    // The contract fixes the cut: exactly the nodes reachable from the source.
    const std::vector<char> reach = ek.reachable();
    for (int i = 0; i < g.n; ++i) REQUIRE(mf.in_source_segment(i) == (reach[static_cast<std::size_t>(i)] != 0));
    // And the sink side: exactly the nodes that reach the sink (the rest could go either way).
    const std::vector<char> to_sink = ek.reaches_sink();
    for (int i = 0; i < g.n; ++i) REQUIRE(mf.in_sink_segment(i) == (to_sink[static_cast<std::size_t>(i)] != 0));
  }
}

}  // namespace

TEST_CASE("solver: contracts are detected", "[solver]") {
  STATIC_REQUIRE(restitch::is_max_flow_v<BkMaxFlow<double>>);
  STATIC_REQUIRE(restitch::is_max_flow_v<BkMaxFlow<std::int64_t>>);
  STATIC_REQUIRE(restitch::is_max_flow_v<PushRelabelMaxFlow<double>>);
  STATIC_REQUIRE(restitch::is_max_flow_v<PushRelabelMaxFlow<std::int64_t>>);
  STATIC_REQUIRE(restitch::has_sink_segment_v<PushRelabelMaxFlow<double>>);
  STATIC_REQUIRE_FALSE(restitch::is_max_flow_v<int>);
  STATIC_REQUIRE_FALSE(restitch::is_max_flow_v<TableMrf>);
  STATIC_REQUIRE(restitch::is_labelling_problem_v<TableMrf>);
  STATIC_REQUIRE_FALSE(restitch::is_labelling_problem_v<BkMaxFlow<double>>);
  STATIC_REQUIRE(restitch::is_graph_solver_v<AlphaExpansion<>>);
  STATIC_REQUIRE_FALSE(restitch::is_graph_solver_v<TableMrf>);
}

namespace {

// Cormen et al.'s example network and a node with both terminal capacities, on back end MF.
template <template <class> class MF>
void check_known_network() {
  // Cormen et al.'s example network: maximum flow 23.
  // s -> 0 (16), s -> 1 (13), 0 -> 2 (12), 1 -> 0 (4), 1 -> 3 (14),
  // 2 -> 1 (9), 3 -> 2 (7), 2 -> t (20), 3 -> t (4).
  MF<std::int64_t> mf;
  mf.reset(4, 5);
  mf.add_node(4);
  mf.add_tweights(0, 16, 0);
  mf.add_tweights(1, 13, 0);
  mf.add_tweights(2, 0, 20);
  mf.add_tweights(3, 0, 4);
  mf.add_edge(0, 2, 12, 0);
  mf.add_edge(1, 0, 4, 0);
  mf.add_edge(1, 3, 14, 0);
  mf.add_edge(2, 1, 9, 0);
  mf.add_edge(3, 2, 7, 0);
  CHECK(mf.max_flow() == 23);
  // Minimum cut with the smallest source side: {s, 0, 1, 3}.
  CHECK(mf.in_source_segment(0));
  CHECK(mf.in_source_segment(1));
  CHECK_FALSE(mf.in_source_segment(2));
  CHECK(mf.in_source_segment(3));

  // A node with both terminal capacities passes min(s, t) directly; a node
  // no path reaches is on the sink side.
  MF<double> g;
  g.add_node(3);
  g.add_tweights(0, 5, 3);
  g.add_tweights(0, 1, 4);  // adds: s 6, t 7
  g.add_edge(1, 2, 2, 2);
  CHECK(g.max_flow() == 6.0);
  CHECK_FALSE(g.in_source_segment(0));
  CHECK_FALSE(g.in_source_segment(1));
  CHECK_FALSE(g.in_source_segment(2));
}

template <template <class> class MF>
void check_fractional(std::uint64_t seed) {
  Rng rng(seed);
  MF<double> mf;
  for (int k = 0; k < 300; ++k) {
    const GraphSpec g = random_graph(rng, false);
    mf.reset();
    mf.add_node(g.n);
    EdmondsKarp<double> ek(g.n);
    double total = 1;
    for (const auto& t : g.tw) {
      mf.add_tweights(t.i, t.s, t.t);
      ek.add_tweights(t.i, t.s, t.t);
      total += t.s + t.t;
    }
    for (const auto& e : g.edges) {
      mf.add_edge(e.i, e.j, e.c, e.r);
      ek.add_edge(e.i, e.j, e.c, e.r);
    }
    const double flow = mf.max_flow();
    INFO("graph " << k);
    REQUIRE(flow == Approx(ek.max_flow()).margin(1e-12 * total));
    CHECK(cut_capacity<double>(g, mf) == Approx(flow).margin(1e-12 * total));
  }
}

// max_flow(), more edges and terminal capacities, max_flow() again: the flow of the whole graph.
template <template <class> class MF>
void check_continues(std::uint64_t seed) {
  Rng rng(seed);
  for (int k = 0; k < 100; ++k) {
    const GraphSpec g = random_graph(rng, true);
    MF<std::int64_t> mf;
    EdmondsKarp<std::int64_t> ek(g.n);
    mf.add_node(g.n);
    const std::size_t half = g.edges.size() / 2;
    for (const auto& t : g.tw) {
      mf.add_tweights(t.i, std::int64_t(t.s), std::int64_t(t.t));
      ek.add_tweights(t.i, std::int64_t(t.s), std::int64_t(t.t));
    }
    for (std::size_t e = 0; e < half; ++e)
      mf.add_edge(g.edges[e].i, g.edges[e].j, int(g.edges[e].c), int(g.edges[e].r));
    mf.max_flow();
    for (std::size_t e = half; e < g.edges.size(); ++e)
      mf.add_edge(g.edges[e].i, g.edges[e].j, int(g.edges[e].c), int(g.edges[e].r));
    mf.add_tweights(0, 3, 2);
    ek.add_tweights(0, 3, 2);
    for (const auto& e : g.edges) ek.add_edge(e.i, e.j, std::int64_t(e.c), std::int64_t(e.r));
    REQUIRE(mf.max_flow() == ek.max_flow());
    const std::vector<char> reach = ek.reachable(), to_sink = ek.reaches_sink();
    for (int i = 0; i < g.n; ++i) {
      REQUIRE(mf.in_source_segment(i) == (reach[static_cast<std::size_t>(i)] != 0));
      REQUIRE(mf.in_sink_segment(i) == (to_sink[static_cast<std::size_t>(i)] != 0));
    }
  }
}

// A chain of 200 000 nodes: one long augmenting path (deep search trees; long label ranges).
template <template <class> class MF>
void check_long_chain() {
  const int n = 200000;
  MF<std::int64_t> mf(n, n);
  mf.add_node(n);
  mf.add_tweights(0, 7, 0);
  mf.add_tweights(n - 1, 0, 9);
  for (int i = 0; i + 1 < n; ++i) mf.add_edge(i, i + 1, i == n / 2 ? 5 : 100, 0);
  CHECK(mf.max_flow() == 5);
  CHECK(mf.in_source_segment(n / 2));
  CHECK_FALSE(mf.in_source_segment(n / 2 + 1));
  CHECK(mf.in_sink_segment(n / 2 + 1));
  CHECK_FALSE(mf.in_sink_segment(n / 2));
}

}  // namespace

TEST_CASE("solver: max-flow back ends on a known network", "[solver]") {
  SECTION("BkMaxFlow") { check_known_network<BkMaxFlow>(); }
  SECTION("PushRelabelMaxFlow") { check_known_network<PushRelabelMaxFlow>(); }
}

TEST_CASE("solver: BkMaxFlow equals Edmonds-Karp on random graphs (int64)", "[solver]") {
  check_against_oracle<std::int64_t>(0x5eed0001, 400);
}

TEST_CASE("solver: BkMaxFlow equals Edmonds-Karp on random graphs (double)", "[solver]") {
  // Integer-valued doubles: every sum is exact, so flow and cut must match exactly.
  check_against_oracle<double>(0x5eed0002, 400);
}

TEST_CASE("solver: PushRelabelMaxFlow equals Edmonds-Karp on random graphs", "[solver]") {
  // The same flow and the same two segments (both fixed by the contract), exactly.
  check_against_oracle<std::int64_t, PushRelabelMaxFlow>(0x5eed0011, 400);
  check_against_oracle<double, PushRelabelMaxFlow>(0x5eed0012, 400);
}

TEST_CASE("solver: PushRelabelMaxFlow equals BkMaxFlow on 26-neighbourhood grids", "[solver]") {
  // Graphs the size of expansion moves, where global relabelling also runs in the middle of a discharge
  // (21 times over these 12 grids, counted once with a scratch counter; the small random graphs above, 394
  // times in 800): the same flow and the same segments as BkMaxFlow (itself checked against Edmonds-Karp
  // above), exactly (integer capacities).
  Rng rng(0x5eed0015);
  PushRelabelMaxFlow<std::int64_t> pr;
  BkMaxFlow<std::int64_t> bk;
  int both_sides = 0;  // grids where both segments are non-empty
  for (int k = 0; k < 12; ++k) {
    const int side = 4 + k % 5, n = side * side * side;
    pr.reset(n, 13 * n);
    bk.reset(n, 13 * n);
    pr.add_node(n);
    bk.add_node(n);
    for (int i = 0; i < n; ++i) {
      const std::int64_t s = rng.chance(0.5) ? rng.uniform_int(0, 40) : 0, t = rng.chance(0.5) ? rng.uniform_int(0, 40) : 0;
      pr.add_tweights(i, s, t);
      bk.add_tweights(i, s, t);
    }
    auto id = [side](int x, int y, int z) { return x + side * (y + side * z); };
    for (int z = 0; z < side; ++z)
      for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
          for (int d = 1; d < 27; ++d) {
            const int dx = d % 3 - 1, dy = d / 3 % 3 - 1, dz = d / 9 - 1;
            if (!(dz > 0 || (dz == 0 && (dy > 0 || (dy == 0 && dx > 0))))) continue;
            const int X = x + dx, Y = y + dy, Z = z + dz;
            if (X < 0 || X >= side || Y < 0 || Y >= side || Z < 0 || Z >= side) continue;
            const std::int64_t c = rng.uniform_int(0, 9), r = rng.chance(0.5) ? 0 : rng.uniform_int(0, 9);
            pr.add_edge(id(x, y, z), id(X, Y, Z), c, r);
            bk.add_edge(id(x, y, z), id(X, Y, Z), c, r);
          }
    INFO("grid " << k << " side " << side);
    REQUIRE(pr.max_flow() == bk.max_flow());
    int source_side = 0, sink_side = 0;
    for (int i = 0; i < n; ++i) {
      REQUIRE(pr.in_source_segment(i) == bk.in_source_segment(i));
      REQUIRE(pr.in_sink_segment(i) == bk.in_sink_segment(i));
      source_side += pr.in_source_segment(i);
      sink_side += pr.in_sink_segment(i);
    }
    both_sides += source_side > 0 && sink_side > 0;
  }
  CHECK(both_sides >= 8);  // the comparisons are not about trivial cuts
}

TEST_CASE("solver: max-flow back ends with fractional capacities give a minimum cut", "[solver]") {
  SECTION("BkMaxFlow") { check_fractional<BkMaxFlow>(0x5eed0003); }
  SECTION("PushRelabelMaxFlow") { check_fractional<PushRelabelMaxFlow>(0x5eed0013); }
}

TEST_CASE("solver: max-flow back ends solve again after more edges are added", "[solver]") {
  SECTION("BkMaxFlow") { check_continues<BkMaxFlow>(0x5eed0004); }
  SECTION("PushRelabelMaxFlow") { check_continues<PushRelabelMaxFlow>(0x5eed0014); }
}

TEST_CASE("solver: max-flow back ends handle long paths without recursion", "[solver]") {
  SECTION("BkMaxFlow") { check_long_chain<BkMaxFlow>(); }
  SECTION("PushRelabelMaxFlow") { check_long_chain<PushRelabelMaxFlow>(); }
}

// ---------------------------------------------------------------------------
// Labelling problems.

namespace {

// Exhaustive minimum over all M^N labellings.
double exhaustive_minimum(const TableMrf& p, std::vector<int>* best_labels = nullptr) {
  const int n = p.node_count(), m = p.label_count();
  std::vector<int> l(static_cast<std::size_t>(n), 0);
  double best = std::numeric_limits<double>::infinity();
  for (;;) {
    const double e = restitch::energy(p, l);
    if (e < best) {
      best = e;
      if (best_labels) *best_labels = l;
    }
    int k = 0;
    while (k < n && ++l[static_cast<std::size_t>(k)] == m) l[static_cast<std::size_t>(k++)] = 0;
    if (k == n) return best;
  }
}

// The lowest energy any single expansion move from `labels` can reach.
double best_expansion_move(const TableMrf& p, const std::vector<int>& labels) {
  const int n = p.node_count();
  double best = restitch::energy(p, labels);
  for (int alpha = 0; alpha < p.label_count(); ++alpha)
    for (int mask = 0; mask < (1 << n); ++mask) {
      std::vector<int> l = labels;
      for (int i = 0; i < n; ++i)
        if (mask & (1 << i)) l[static_cast<std::size_t>(i)] = alpha;
      best = std::min(best, restitch::energy(p, l));
    }
  return best;
}

enum class Pairwise { potts, truncated_linear, submodular_random, arbitrary };

// A random connected-ish graph with integer terms (energies are exact).
TableMrf random_problem(Rng& rng, int n, int m, Pairwise kind, int truncation = 2, double forbidden_chance = 0) {
  TableMrf p(n, m);
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < m; ++a) p.set_unary(i, a, rng.chance(forbidden_chance) ? 1e9 : rng.uniform_int(0, 9));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (j != i + 1 && !rng.chance(0.35)) continue;
      const int e = rng.uniform_int(0, 1) ? p.add_edge(i, j) : p.add_edge(j, i);
      const double w = rng.uniform_int(1, 5);
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) {
          double v = 0;
          switch (kind) {
            case Pairwise::potts:
              v = a == b ? 0 : w;
              break;
            case Pairwise::truncated_linear:
              v = w * std::min(std::abs(a - b), truncation);
              break;
            case Pairwise::submodular_random:
            case Pairwise::arbitrary:
              v = rng.uniform_int(0, 9);
              break;
          }
          p.set_pairwise(e, a, b, v);
        }
      if (kind == Pairwise::submodular_random) {  // 2 labels: make A + D <= B + C
        const double a00 = std::min(p.pairwise(e, 0, 0), p.pairwise(e, 0, 1) + p.pairwise(e, 1, 0));
        const double s = p.pairwise(e, 0, 1) + p.pairwise(e, 1, 0);
        p.set_pairwise(e, 0, 0, a00);
        p.set_pairwise(e, 1, 1, std::min(p.pairwise(e, 1, 1), s - a00));
      }
    }
  return p;
}

std::vector<int> random_labels(Rng& rng, int n, int m) {
  std::vector<int> l(static_cast<std::size_t>(n));
  for (int& x : l) x = rng.uniform_int(0, m - 1);
  return l;
}

// A problem defined by formulas, not tables (the contract is generic).
struct ChainProblem {
  std::vector<double> u;  // n x m
  int n, m;
  double weight;
  int node_count() const { return n; }
  int label_count() const { return m; }
  double unary(int i, int a) const { return u[static_cast<std::size_t>(i * m + a)]; }
  int edge_count() const { return n - 1; }
  std::pair<int, int> edge(int e) const { return {e, e + 1}; }
  double pairwise(int, int a, int b) const { return weight * std::abs(a - b); }
};

}  // namespace

TEST_CASE("solver: two labels, submodular: alpha-expansion finds the exhaustive optimum", "[solver]") {
  Rng rng(0x5eed0101);
  AlphaExpansion<> solver;
  for (int k = 0; k < 200; ++k) {
    const int n = rng.uniform_int(4, 7);
    const TableMrf p = random_problem(rng, n, 2, Pairwise::submodular_random);
    REQUIRE(restitch::check_metric(p).ok);
    std::vector<int> labels = random_labels(rng, n, 2);
    SolveReport report;
    REQUIRE(solver.solve(p, labels, report, restitch::Progress()).ok());
    INFO("problem " << k);
    CHECK(report.energy == exhaustive_minimum(p));
    CHECK(report.energy == restitch::energy(p, labels));
    CHECK(report.converged);
    CHECK_FALSE(report.non_metric_detected);
  }
}

TEST_CASE("solver: metric terms: within 2c of the optimum and a local minimum of every expansion", "[solver]") {
  Rng rng(0x5eed0102);
  AlphaExpansion<> solver;
  for (int k = 0; k < 120; ++k) {
    const int n = rng.uniform_int(4, 7), m = rng.uniform_int(3, 4);
    const bool potts = k % 2 == 0;
    const int truncation = 2;
    const TableMrf p = random_problem(rng, n, m, potts ? Pairwise::potts : Pairwise::truncated_linear, truncation);
    REQUIRE(restitch::check_metric(p).ok);
    std::vector<int> labels = random_labels(rng, n, m);
    SolveReport report;
    REQUIRE(solver.solve(p, labels, report, restitch::Progress()).ok());
    const double optimum = exhaustive_minimum(p);
    const double c = potts ? 1 : truncation;  // max / min non-zero pairwise value per edge
    INFO("problem " << k << (potts ? " potts" : " truncated linear"));
    CHECK(report.energy >= optimum);
    CHECK(report.energy <= 2 * c * optimum);
    // Every expansion move is solved exactly, so none can improve the result.
    CHECK(best_expansion_move(p, labels) == report.energy);
    CHECK_FALSE(report.non_metric_detected);
  }
}

TEST_CASE("solver: alpha-expansion never raises the energy", "[solver]") {
  Rng rng(0x5eed0103);
  for (int k = 0; k < 40; ++k) {
    const bool metric = k % 2 == 0;
    const int n = rng.uniform_int(20, 60), m = rng.uniform_int(3, 6);
    const TableMrf p = random_problem(rng, n, m, metric ? Pairwise::truncated_linear : Pairwise::arbitrary, 3, 0.05);
    std::vector<int> labels = random_labels(rng, n, m);
    const double initial = restitch::energy(p, labels);
    std::vector<double> seen{initial};
    AlphaExpansion<> solver;
    solver.on_move = [&](const std::vector<int>& l, double tracked) {
      const double e = restitch::energy(p, l);  // recomputed independently
      CHECK(e == tracked);                      // integer terms: exact
      seen.push_back(e);
    };
    SolveReport report;
    REQUIRE(solver.solve(p, labels, report, restitch::Progress()).ok());
    INFO("problem " << k << (metric ? " metric" : " non-metric"));
    for (std::size_t s = 1; s < seen.size(); ++s) REQUIRE(seen[s] < seen[s - 1]);
    CHECK(report.moves_accepted == static_cast<int>(seen.size()) - 1);
    CHECK(report.initial_energy == initial);
    CHECK(report.energy == seen.back());
    CHECK(report.energy == restitch::energy(p, labels));
    for (std::size_t c = 1; c < report.cycle_energies.size(); ++c)
      CHECK(report.cycle_energies[c] <= report.cycle_energies[c - 1]);
    CHECK(report.converged);
    if (metric) CHECK_FALSE(report.non_metric_detected);
  }
}

TEST_CASE("solver: forbidden constants do not swamp small terms", "[solver]") {
  // Unary terms of 1e9 ("forbidden") next to terms of 1e-3: with two labels
  // and Potts terms the result must still be the exact optimum.
  Rng rng(0x5eed0104);
  AlphaExpansion<> solver;
  for (int k = 0; k < 100; ++k) {
    const int n = rng.uniform_int(4, 7);
    TableMrf p(n, 2);
    for (int i = 0; i < n; ++i)
      for (int a = 0; a < 2; ++a) p.set_unary(i, a, rng.chance(0.2) ? 1e9 : 1e-3 * rng.uniform_int(0, 9));
    for (int i = 0; i + 1 < n; ++i) {
      const int e = p.add_edge(i, i + 1);
      const double w = 1e-3 * rng.uniform_int(1, 4);
      p.set_pairwise(e, 0, 1, w);
      p.set_pairwise(e, 1, 0, w);
    }
    std::vector<int> labels = random_labels(rng, n, 2);
    SolveReport report;
    REQUIRE(solver.solve(p, labels, report, restitch::Progress()).ok());
    const double optimum = exhaustive_minimum(p);
    INFO("problem " << k);
    CHECK(report.energy == Approx(optimum).epsilon(1e-12).margin(1e-12));
  }
}

TEST_CASE("solver: non-metric terms are detected", "[solver]") {
  // 2 nodes, 3 labels: E(0,2) = 10 > E(0,1) + E(1,2) = 2 breaks the triangle inequality.
  TableMrf p(2, 3);
  const int e = p.add_edge(0, 1);
  const double table[3][3] = {{0, 1, 10}, {1, 0, 1}, {10, 1, 0}};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) p.set_pairwise(e, a, b, table[a][b]);
  const restitch::MetricCheck mc = restitch::check_metric(p);
  CHECK_FALSE(mc.ok);
  CHECK(mc.edge == 0);
  CHECK(mc.alpha == 1);
  CHECK(mc.beta == 0);
  CHECK(mc.gamma == 2);
  CHECK(mc.excess == 8);
  CHECK(mc.message.find("edge 0") != std::string::npos);

  // Unary terms keep node 0 off label 2 and node 1 off label 0, so from (0, 2)
  // the first useful move is expanding label 1, which meets
  // A + D = E(0,2) + E(1,1) = 10 > B + C = E(0,1) + E(1,2) = 2.
  const double u[2][3] = {{0, 2, 20}, {20, 2, 0}};
  for (int i = 0; i < 2; ++i)
    for (int a = 0; a < 3; ++a) p.set_unary(i, a, u[i][a]);
  std::vector<int> labels{0, 2};
  SolveReport report;
  AlphaExpansion<> solver;
  std::vector<std::vector<int>> moves;
  solver.on_move = [&](const std::vector<int>& l, double) { moves.push_back(l); };
  REQUIRE(solver.solve(p, labels, report, restitch::Progress()).ok());
  CHECK(report.non_metric_detected);
  // The documented truncation lowers E(1,1) to B + C - A = -8, so the cut
  // proposes (1, 1) (true energy 4 < 10, accepted); then label 2 gives (1, 2).
  REQUIRE(moves.size() == 2);
  CHECK(moves[0] == std::vector<int>{1, 1});
  CHECK(moves[1] == std::vector<int>{1, 2});
  CHECK(report.initial_energy == 10);
  CHECK(report.energy == 3);  // the optimum, (0, 1) or (1, 2)

  // A metric version passes; the second edge is the first violation otherwise.
  TableMrf q(3, 3);
  for (int k = 0; k < 2; ++k) {
    const int f = q.add_edge(k, k + 1);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) q.set_pairwise(f, a, b, k == 0 ? std::abs(a - b) : table[a][b]);
  }
  const restitch::MetricCheck mq = restitch::check_metric(q);
  CHECK_FALSE(mq.ok);
  CHECK(mq.edge == 1);
  // Non-zero diagonal: E(a,a) = 5 breaks E(a,a) + E(b,g) <= E(b,a) + E(a,g) for b = g.
  TableMrf d(2, 2);
  const int f = d.add_edge(0, 1);
  d.set_pairwise(f, 0, 0, 5);
  CHECK_FALSE(restitch::check_metric(d).ok);
  d.set_pairwise(f, 0, 0, 0);
  CHECK(restitch::check_metric(d).ok);
}

TEST_CASE("solver: alpha-expansion is deterministic and generic", "[solver]") {
  Rng rng(0x5eed0105);
  ChainProblem chain{{}, 300, 7, 0.37};
  for (int k = 0; k < chain.n * chain.m; ++k) chain.u.push_back(rng.uniform01());
  std::vector<int> first(static_cast<std::size_t>(chain.n), 0), second = first;
  SolveReport r1, r2;
  AlphaExpansion<> solver;
  REQUIRE(solver.solve(chain, first, r1, restitch::Progress()).ok());
  REQUIRE(solver.solve(chain, second, r2, restitch::Progress()).ok());
  CHECK(first == second);
  CHECK(std::memcmp(&r1.energy, &r2.energy, sizeof(double)) == 0);
  CHECK(r1.energy < r1.initial_energy);
  CHECK(r1.nodes == 300);
  CHECK(r1.labels == 7);
  CHECK(r1.edges == 299);
  CHECK(r1.cycles >= 1);
  CHECK(r1.expansions >= 7);
  CHECK(r1.energy == restitch::energy(chain, first));
}

namespace {

// The max-flow contract's back end made of the Edmonds-Karp oracle: the graph
// is recorded, solved densely in max_flow().
struct EdmondsKarpBackEnd {
  using capacity_type = double;
  int n = 0;
  std::vector<GraphSpec::T> tw;
  std::vector<GraphSpec::E> edges;
  std::vector<char> reach;
  void reset(int, int) {
    n = 0;
    tw.clear();
    edges.clear();
  }
  int add_node(int k = 1) {
    n += k;
    return n - k;
  }
  void add_tweights(int i, double s, double t) { tw.push_back({i, s, t}); }
  void add_edge(int i, int j, double c, double r) { edges.push_back({i, j, c, r}); }
  double max_flow() {
    EdmondsKarp<double> ek(n);
    for (const auto& t : tw) ek.add_tweights(t.i, t.s, t.t);
    for (const auto& e : edges) ek.add_edge(e.i, e.j, e.c, e.r);
    const double f = ek.max_flow();
    reach = ek.reachable();
    return f;
  }
  bool in_source_segment(int i) const { return reach[static_cast<std::size_t>(i)] != 0; }
};

// A 4 x 4 x 4 grid with the 26-neighbourhood (the graphs restitch builds),
// integer unary terms and truncated linear pairwise terms.
struct Grid26Problem {
  int side = 4, m = 6;
  std::vector<double> u;
  std::vector<std::pair<int, int>> edges;
  Grid26Problem(Rng& rng, int labels) : m(labels) {
    for (int k = 0; k < side * side * side * m; ++k) u.push_back(rng.uniform_int(0, 20));
    for (int z = 0; z < side; ++z)
      for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                if (!(dz > 0 || (dz == 0 && (dy > 0 || (dy == 0 && dx > 0))))) continue;
                const int X = x + dx, Y = y + dy, Z = z + dz;
                if (X < 0 || X >= side || Y < 0 || Y >= side || Z < 0 || Z >= side) continue;
                edges.emplace_back(x + side * (y + side * z), X + side * (Y + side * Z));
              }
  }
  int node_count() const { return side * side * side; }
  int label_count() const { return m; }
  double unary(int i, int l) const { return u[static_cast<std::size_t>(i * m + l)]; }
  int edge_count() const { return static_cast<int>(edges.size()); }
  std::pair<int, int> edge(int e) const { return edges[static_cast<std::size_t>(e)]; }
  double pairwise(int e, int a, int b) const { return (1 + e % 3) * std::min(std::abs(a - b), 3); }
};

}  // namespace

TEST_CASE("solver: alpha-expansion moves do not depend on the max-flow back end", "[solver]") {
  // The back-end contract fixes the cut (the smallest source side), so with
  // exact (integer) terms BkMaxFlow, PushRelabelMaxFlow and the Edmonds-Karp oracle must give the
  // same moves, the same labels and the same energy.
  Rng rng(0x5eed0107);
  for (int k = 0; k < 4; ++k) {
    const Grid26Problem p(rng, 4 + k);
    REQUIRE(p.edge_count() == 3 * 3 * 16 + 2 * 3 * 3 * 3 * 4 + 4 * 27);  // faces + edge and corner diagonals
    std::vector<int> initial(64);
    for (int& l : initial) l = rng.uniform_int(0, p.m - 1);
    std::vector<int> bk = initial, ek = initial, pr = initial;
    SolveReport rb, re, rp;
    REQUIRE(AlphaExpansion<BkMaxFlow<double>>().solve(p, bk, rb, restitch::Progress()).ok());
    REQUIRE(AlphaExpansion<EdmondsKarpBackEnd>().solve(p, ek, re, restitch::Progress()).ok());
    REQUIRE(AlphaExpansion<PushRelabelMaxFlow<double>>().solve(p, pr, rp, restitch::Progress()).ok());
    INFO("problem " << k);
    CHECK(bk == ek);
    CHECK(pr == ek);
    CHECK(rb.energy == re.energy);
    CHECK(rp.energy == re.energy);
    CHECK(rb.expansions == re.expansions);
    CHECK(rp.expansions == re.expansions);
    CHECK(rb.moves_accepted == re.moves_accepted);
    CHECK(rp.moves_accepted == re.moves_accepted);
    CHECK(rb.moves_accepted > 0);
    CHECK(rb.energy < rb.initial_energy);
  }
}

TEST_CASE("solver: the tie rule: a node that could go either way keeps its label, or takes alpha on request",
          "[solver]") {
  STATIC_REQUIRE(restitch::has_sink_segment_v<BkMaxFlow<double>>);
  // Two nodes, two labels, every term 0 but a cost of 1 for node 1 at label 0: expanding label 1 moves
  // node 1 (it pays less there); node 0 costs the same either way, so it is a tie.
  TableMrf p(2, 2);
  p.set_unary(0, 0, 0.0);
  p.set_unary(0, 1, 0.0);
  p.set_unary(1, 0, 1.0);
  p.set_unary(1, 1, 0.0);
  p.add_edge(0, 1, {0.0, 0.0, 0.0, 0.0});
  SolveReport keep_report, move_report;
  std::vector<int> keep{0, 0}, move{0, 0};
  AlphaExpansion<> keeps;
  REQUIRE(keeps.solve(p, keep, keep_report).ok());
  AlphaExpansion<> moves;
  moves.ties_to_alpha = true;
  REQUIRE(moves.solve(p, move, move_report).ok());
  CHECK(keep == std::vector<int>{0, 1});
  CHECK(move == std::vector<int>{1, 1});
  CHECK(keep_report.energy == 0.0);
  CHECK(move_report.energy == 0.0);
  // A back end that cannot report the sink side refuses the option rather than ignore it.
  STATIC_REQUIRE_FALSE(restitch::has_sink_segment_v<EdmondsKarpBackEnd>);
  AlphaExpansion<EdmondsKarpBackEnd> oracle;
  oracle.ties_to_alpha = true;
  std::vector<int> labels{0, 0};
  SolveReport report;
  CHECK(oracle.solve(p, labels, report).code() == restitch::StatusCode::invalid_argument);
}

TEST_CASE("solver: alpha-expansion input errors and edge cases", "[solver]") {
  TableMrf p(3, 2);
  p.add_edge(0, 1);
  AlphaExpansion<> solver;
  SolveReport report;
  std::vector<int> labels{0, 1};
  CHECK(solver.solve(p, labels, report, restitch::Progress()).code() == StatusCode::invalid_argument);
  labels = {0, 2, 1};
  const restitch::Status bad = solver.solve(p, labels, report, restitch::Progress());
  CHECK(bad.code() == StatusCode::invalid_argument);
  CHECK(bad.message().find("node 1") != std::string::npos);

  labels.clear();  // empty: starts from all zeros
  REQUIRE(solver.solve(p, labels, report, restitch::Progress()).ok());
  CHECK(labels.size() == 3);

  p.set_unary(2, 1, std::numeric_limits<double>::quiet_NaN());
  labels = {0, 0, 0};
  const restitch::Status nan = solver.solve(p, labels, report, restitch::Progress());
  CHECK(nan.code() == StatusCode::invalid_argument);
  CHECK(nan.message().find("not finite") != std::string::npos);

  struct SelfLoop : ChainProblem {
    std::pair<int, int> edge(int e) const { return {e, e}; }
  } loop;
  loop.n = 3;
  loop.m = 2;
  loop.weight = 1;
  loop.u.assign(6, 0.0);
  labels = {0, 0, 0};
  CHECK(solver.solve(loop, labels, report, restitch::Progress()).code() == StatusCode::invalid_argument);

  TableMrf empty;
  labels.clear();
  REQUIRE(solver.solve(empty, labels, report, restitch::Progress()).ok());
  CHECK(report.energy == 0);
  CHECK(labels.empty());
}

TEST_CASE("solver: alpha-expansion can be cancelled", "[solver]") {
  Rng rng(0x5eed0106);
  const TableMrf p = random_problem(rng, 40, 5, Pairwise::truncated_linear);
  std::vector<int> labels = random_labels(rng, 40, 5);
  const double initial = restitch::energy(p, labels);
  int calls = 0;
  double last_fraction = -1;
  bool monotone = true;
  const restitch::Progress stop_after_two([&](std::string_view stage, double fraction) {
    monotone = monotone && stage == "alpha-expansion" && fraction > last_fraction && fraction <= 1;
    last_fraction = fraction;
    return ++calls < 2;
  });
  SolveReport report;
  CHECK(AlphaExpansion<>().solve(p, labels, report, stop_after_two).code() == StatusCode::cancelled);
  CHECK(calls == 2);
  CHECK(monotone);
  CHECK(report.expansions == 2);
  CHECK(restitch::energy(p, labels) <= initial);
  CHECK(report.energy == restitch::energy(p, labels));
}

namespace {

// Everything a solve reports, for comparing runs bit for bit.
struct SolveTrace {
  std::vector<int> labels;
  std::vector<std::vector<int>> moves;  // the labelling after each accepted move (on_move)
  std::vector<double> move_energies;
  SolveReport report;
  restitch::StatusCode code = StatusCode::ok;
};

template <class Problem>
SolveTrace traced_solve(const Problem& p, std::vector<int> start, int threads, bool ties_to_alpha = false,
                        int stop_after = -1) {
  SolveTrace t;
  AlphaExpansion<> solver;
  solver.threads = threads;
  solver.min_parallel_size = 0;  // propose side by side however small the problem
  solver.ties_to_alpha = ties_to_alpha;
  solver.on_move = [&t](const std::vector<int>& l, double e) {
    t.moves.push_back(l);
    t.move_energies.push_back(e);
  };
  int calls = 0;
  const restitch::Progress progress([&](std::string_view, double) { return stop_after < 0 || ++calls < stop_after; });
  t.code = solver.solve(p, start, t.report, progress).code();
  t.labels = start;
  return t;
}

void check_same_trace(const SolveTrace& a, const SolveTrace& b) {
  const auto same_bits = [](const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0);
  };
  CHECK(a.code == b.code);
  CHECK(a.labels == b.labels);
  CHECK(a.moves == b.moves);
  CHECK(same_bits(a.move_energies, b.move_energies));
  CHECK(std::memcmp(&a.report.energy, &b.report.energy, sizeof(double)) == 0);
  CHECK(a.report.cycles == b.report.cycles);
  CHECK(a.report.expansions == b.report.expansions);
  CHECK(a.report.moves_accepted == b.report.moves_accepted);
  CHECK(a.report.converged == b.report.converged);
  CHECK(a.report.non_metric_detected == b.report.non_metric_detected);
  CHECK(same_bits(a.report.cycle_energies, b.report.cycle_energies));
}

// A problem whose terms may be read from several threads, and that throws when an edge is asked for
// labels (0, 2): that only happens on a labelling the sequential run has already left (see the test).
struct ThrowsOnStaleLabelling : TableMrf {
  using TableMrf::TableMrf;
  double pairwise(int e, int a, int b) const {
    if (a == 0 && b == 2) throw std::runtime_error("asked for (0, 2)");
    return TableMrf::pairwise(e, a, b);
  }
};

}  // namespace

TEST_CASE("solver: moves proposed on several threads give the sequential run bit for bit", "[solver][threads]") {
  // With threads > 1 the next expansions are proposed side by side on the current labelling and taken in
  // order up to the first accepted one (AlphaExpansion::threads). Labels, energies, every accepted move,
  // cycles, expansions, the non-metric flag and a cancel at the same progress call must equal the
  // sequential run's, on metric and non-metric problems, with both tie rules.
  Rng rng(0x5eed0110);
  int accepted = 0, cancelled = 0;
  for (int k = 0; k < 12; ++k) {
    const int n = 30 + 15 * k, m = 3 + k % 6;
    const Pairwise kind = k % 3 == 0 ? Pairwise::arbitrary : (k % 3 == 1 ? Pairwise::potts : Pairwise::truncated_linear);
    const TableMrf p = random_problem(rng, n, m, kind, 2, k % 4 == 0 ? 0.1 : 0.0);
    const std::vector<int> start = random_labels(rng, n, m);
    INFO("problem " << k << ": " << n << " nodes, " << m << " labels");
    for (const bool ties : {false, true}) {
      const SolveTrace one = traced_solve(p, start, 1, ties);
      REQUIRE(one.code == StatusCode::ok);
      accepted += one.report.moves_accepted;
      for (const int threads : {2, 3, 5}) {
        INFO(threads << " threads, ties_to_alpha " << ties);
        check_same_trace(one, traced_solve(p, start, threads, ties));
      }
    }
    // Cancelled at the 3rd progress call: the same labelling so far.
    const SolveTrace cut = traced_solve(p, start, 1, false, 3);
    cancelled += cut.code == StatusCode::cancelled;
    check_same_trace(cut, traced_solve(p, start, 2, false, 3));
  }
  CHECK(accepted >= 24);  // moves to disagree about
  CHECK(cancelled >= 8);
  // A proposal computed on a labelling the run has left is dropped, whatever it did: here proposing
  // label 2 on the all-0 start throws, but label 1 is accepted first (every node prefers it), so the
  // sequential run never asks for (0, 2); neither may the threaded one let it count.
  ThrowsOnStaleLabelling p(50, 3);
  for (int i = 0; i < 50; ++i) p.set_unary(i, 0, 10.0), p.set_unary(i, 1, 0.0), p.set_unary(i, 2, 5.0);
  for (int i = 0; i + 1 < 50; ++i) p.add_edge(i, i + 1, {0, 1, 1, 1, 0, 1, 1, 1, 0});
  const SolveTrace one = traced_solve(p, std::vector<int>(50, 0), 1);
  REQUIRE(one.code == StatusCode::ok);
  CHECK(one.labels == std::vector<int>(50, 1));
  check_same_trace(one, traced_solve(p, std::vector<int>(50, 0), 2));
  // An exception from a proposal that counts is reported as the sequential run reports it.
  ThrowsOnStaleLabelling q(50, 3);
  for (int i = 0; i < 50; ++i) q.set_unary(i, 0, 10.0), q.set_unary(i, 1, 20.0), q.set_unary(i, 2, 5.0);
  for (int i = 0; i + 1 < 50; ++i) q.add_edge(i, i + 1, {0, 1, 1, 1, 0, 1, 1, 1, 0});
  const SolveTrace fails = traced_solve(q, std::vector<int>(50, 0), 1);
  CHECK(fails.code == StatusCode::internal);
  CHECK(traced_solve(q, std::vector<int>(50, 0), 2).code == StatusCode::internal);
}

TEST_CASE("solver: threads are used only where the problem's terms may be read at once", "[solver][threads]") {
  // A problem without terms_thread_safe() is read from the calling thread only (its terms may fill a
  // cache on first use): the pairwise calls all come from the calling thread, whatever `threads` says.
  struct Recording : ChainProblem {
    mutable std::vector<std::thread::id> callers;
    double pairwise(int e, int a, int b) const {
      callers.push_back(std::this_thread::get_id());  // would race if called from several threads
      return ChainProblem::pairwise(e, a, b);
    }
  };
  Rng rng(0x5eed0111);
  Recording p;
  p.n = 400;
  p.m = 6;
  p.weight = 0.3;
  for (int k = 0; k < p.n * p.m; ++k) p.u.push_back(rng.uniform01());
  STATIC_REQUIRE_FALSE(restitch::detail::has_terms_thread_safe<Recording>::value);
  AlphaExpansion<> solver;
  solver.threads = 4;
  solver.min_parallel_size = 0;
  std::vector<int> labels(400, 0);
  SolveReport report;
  REQUIRE(solver.solve(p, labels, report).ok());
  REQUIRE(!p.callers.empty());
  CHECK(std::all_of(p.callers.begin(), p.callers.end(), [](std::thread::id id) { return id == std::this_thread::get_id(); }));
  STATIC_REQUIRE(restitch::detail::has_terms_thread_safe<TableMrf>::value);
}

// ---------------------------------------------------------------------------
// File format.

namespace {

std::string temp_path(const std::string& name) {
#ifdef RESTITCH_TEST_TMP
  const std::filesystem::path dir = RESTITCH_TEST_TMP;
#else
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
#endif
  return (dir / ("solver_test_" + name)).string();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

}  // namespace

TEST_CASE("solver: MRF files round-trip exactly", "[solver]") {
  Rng rng(0x5eed0201);
  TableMrf p = random_problem(rng, 9, 4, Pairwise::truncated_linear, 2, 0.1);
  // Awkward doubles.
  p.set_unary(0, 0, 1.0 / 3.0);
  p.set_unary(0, 1, -0.0);
  p.set_unary(0, 2, 4.9406564584124654e-324);
  p.set_unary(0, 3, 1.7976931348623157e308);
  p.set_unary(1, 0, 0.1);
  p.set_pairwise(0, 1, 2, 2.0 / 3.0 + 1e-9);
  const std::string path = temp_path("roundtrip.mrf");
  REQUIRE(restitch::write_mrf(path, p).ok());
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
  const restitch::Result<TableMrf> q = restitch::read_mrf(path);
  REQUIRE(q.ok());
  CHECK(q->node_count() == p.node_count());
  CHECK(q->label_count() == p.label_count());
  REQUIRE(q->edge_count() == p.edge_count());
  for (int e = 0; e < p.edge_count(); ++e) CHECK(q->edge(e) == p.edge(e));
  CHECK(same_bits(q->unary_values(), p.unary_values()));
  CHECK(same_bits(q->pairwise_values(), p.pairwise_values()));

  // The same problem gives the same solve (drop the huge value first: it is finite but not a sensible term).
  p.set_unary(0, 3, 5);
  REQUIRE(restitch::write_mrf(path, p).ok());  // overwrites
  const restitch::Result<TableMrf> r = restitch::read_mrf(path);
  REQUIRE(r.ok());
  std::vector<int> l1(9, 0), l2(9, 0);
  SolveReport s1, s2;
  REQUIRE(AlphaExpansion<>().solve(p, l1, s1, restitch::Progress()).ok());
  REQUIRE(AlphaExpansion<>().solve(*r, l2, s2, restitch::Progress()).ok());
  CHECK(l1 == l2);
  CHECK(std::memcmp(&s1.energy, &s2.energy, sizeof(double)) == 0);
  std::remove(path.c_str());
}

TEST_CASE("solver: MRF files written by hand", "[solver]") {
  const std::string path = temp_path("hand.mrf");
  write_text(path,
             "# a comment\r\nrestitch-mrf 1\r\nnodes 2 labels 2 edges 1\r\n\r\n0 1.5\r\n\t2  -3e-1\r\n"
             "1 0\r\n0 1\r\n1 0\r\n");
  const restitch::Result<TableMrf> p = restitch::read_mrf(path);
  REQUIRE(p.ok());
  CHECK(p->unary(0, 1) == 1.5);
  CHECK(p->unary(1, 1) == -0.3);
  CHECK(p->edge(0) == std::pair<int, int>(1, 0));
  CHECK(p->pairwise(0, 0, 1) == 1);
  CHECK(p->pairwise(0, 1, 1) == 0);
  std::remove(path.c_str());
}

TEST_CASE("solver: malformed MRF files give clear errors", "[solver]") {
  struct Case {
    const char* text;
    StatusCode code;
    const char* where;  // "path:LINE:" suffix expected in the message
    const char* what;   // a word the message must contain
  };
  const std::string header = "restitch-mrf 1\n";
  const Case cases[] = {
      {"", StatusCode::parse_error, ":1:", "empty"},
      {"hello 1\n", StatusCode::parse_error, ":1:", "header"},
      {"restitch-mrf 2\n", StatusCode::unsupported, ":1:", "version 2"},
      {"restitch-mrf 1\nnodes 2 labels x edges 0\n", StatusCode::parse_error, ":2:", "labels"},
      {"restitch-mrf 1\nnodes 2 labels 2\n", StatusCode::parse_error, ":2:", "nodes N labels M edges E"},
      {"restitch-mrf 1\nnodes 2 labels 2 edges 0\n1 2\n3\n", StatusCode::parse_error, ":4:", "found 1"},
      {"restitch-mrf 1\nnodes 2 labels 2 edges 0\n1 2\n3 abc\n", StatusCode::parse_error, ":4:", "'abc'"},
      {"restitch-mrf 1\nnodes 1 labels 2 edges 0\n1 nan\n", StatusCode::parse_error, ":3:", "finite"},
      {"restitch-mrf 1\nnodes 1 labels 2 edges 0\ninf 1\n", StatusCode::parse_error, ":3:", "finite"},
      {"restitch-mrf 1\nnodes 2 labels 1 edges 1\n1\n2\n0 5\n0\n", StatusCode::parse_error, ":5:", "edge 0"},
      {"restitch-mrf 1\nnodes 2 labels 1 edges 1\n1\n2\n1 1\n0\n", StatusCode::parse_error, ":5:", "itself"},
      {"restitch-mrf 1\nnodes 2 labels 1 edges 2\n1\n2\n0 1\n0\n", StatusCode::parse_error, ":7:", "ends early"},
      {"restitch-mrf 1\nnodes 2 labels 1 edges 0\n1\n2\n3\n", StatusCode::parse_error, ":5:", "after the last"},
      {"restitch-mrf 1\nnodes 100000 labels 1000 edges 1000\n", StatusCode::too_large, ":2:", "at most"},
      {"restitch-mrf 1\nnodes 1000000000 labels 1 edges 0\n", StatusCode::too_large, ":2:", "nodes"},
      {"restitch-mrf 1\nnodes 1 labels 0 edges 0\n", StatusCode::parse_error, ":2:", "label"},
  };
  const std::string path = temp_path("bad.mrf");
  int k = 0;
  for (const Case& c : cases) {
    write_text(path, c.text);
    const restitch::Result<TableMrf> r = restitch::read_mrf(path);
    INFO("case " << k++ << ": " << r.status().message());
    REQUIRE_FALSE(r.ok());
    CHECK(r.status().code() == c.code);
    CHECK(r.status().message().find(path + c.where) == 0);
    CHECK(r.status().message().find(c.what) != std::string::npos);
  }
  std::remove(path.c_str());

  const restitch::Result<TableMrf> missing = restitch::read_mrf(temp_path("does-not-exist.mrf"));
  CHECK(missing.status().code() == StatusCode::io_error);

  // Many labels and no node nor edge is an empty problem, read without a table of labels squared (found by
  // fuzz_mrf: 77777 labels asked for 48 GB).
  const restitch::Result<TableMrf> wide = restitch::parse_mrf("restitch-mrf 1\nnodes 0 labels 77777 edges 0\n", "wide.mrf");
  REQUIRE(wide.ok());
  CHECK(wide->node_count() == 0);
  CHECK(wide->label_count() == 77777);

  // The writer refuses what the reader would refuse, and leaves nothing behind.
  TableMrf p(1, 1);
  p.set_unary(0, 0, std::numeric_limits<double>::infinity());
  const std::string out = temp_path("inf.mrf");
  CHECK(restitch::write_mrf(out, p).code() == StatusCode::invalid_argument);
  CHECK_FALSE(std::filesystem::exists(out));
  CHECK_FALSE(std::filesystem::exists(out + ".tmp"));
  CHECK(restitch::write_mrf(temp_path("no-such-dir/x.mrf"), TableMrf(1, 1)).code() == StatusCode::io_error);
}
