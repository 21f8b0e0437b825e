// restitch/solver/mrf.hpp - the labelling problem (a pairwise MRF), its
// energy, the expansion condition, and the solver policy contract.
//
// A labelling problem gives every node one of M labels. Its energy is
//
//   E(labels) = sum_i unary(i, labels[i]) + sum_e pairwise(e, labels[a_e], labels[b_e])
//
// where edge e joins nodes (a_e, b_e) = edge(e). In restitch a node is an
// output cell and a label a shift (docs/method.md section 2), but the solver knows
// nothing of that. Any type satisfying this contract is a problem:
//
//   struct MyProblem {
//     int node_count() const;                 // N >= 0
//     int label_count() const;                // M >= 1 when N > 0
//     double unary(int node, int label) const;
//     int edge_count() const;                 // E >= 0
//     std::pair<int, int> edge(int e) const;  // two different nodes in [0, N)
//     // label_i is the label of edge(e).first, label_j that of edge(e).second.
//     double pairwise(int e, int label_i, int label_j) const;
//   };
//
// Values must be finite: a forbidden assignment is a large finite constant
// (restitch's seam energy uses 1000 x 1000 x the largest descriptor distance, 2e6 for SHOT), never an infinity or NaN. The solver calls unary() and
// pairwise() many times (about 3 E + N per expansion move), so they should be
// cheap (a table look-up or a short formula); a problem object is only read.
// `is_labelling_problem_v<P>` checks the contract at compile time. Optional:
// `bool terms_thread_safe() const`, true when unary() and pairwise() may be
// called from several threads at once (no cache filled on first use), which
// lets AlphaExpansion::threads propose moves side by side.
//
// A solver policy minimises that energy. restitch ships AlphaExpansion
// (restitch/solver/alpha_expansion.hpp); examples/custom_solver.cpp plugs in
// its own. The contract:
//
//   struct MySolver {
//     // labels: in, the initial labelling (N values in [0, M); an EMPTY vector
//     //   means all zeros); out, the result. report is overwritten.
//     // Returns ok, invalid_argument (bad labels, non-finite terms, bad
//     // edges), or cancelled (labels then hold the best labelling so far).
//     template <class Problem>
//     restitch::Status solve(const Problem& problem, std::vector<int>& labels,
//                            restitch::SolveReport& report,
//                            const restitch::Progress& progress) const;
//   };
//
// `is_graph_solver_v<S>` checks it (with TableMrf as the probe problem).
//
// Also here: TableMrf (a problem stored as tables), energy(), and
// check_metric() (the condition alpha-expansion needs, checked exhaustively).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/progress.hpp"
#include "restitch/status.hpp"

namespace restitch {

namespace detail {
template <class P, class = void>
struct is_labelling_problem : std::false_type {};
template <class P>
struct is_labelling_problem<
    P, std::void_t<decltype(std::declval<const P&>().node_count()), decltype(std::declval<const P&>().label_count()),
                   decltype(std::declval<const P&>().unary(0, 0)), decltype(std::declval<const P&>().edge_count()),
                   decltype(std::declval<const P&>().edge(0)), decltype(std::declval<const P&>().pairwise(0, 0, 0))>>
    : std::bool_constant<std::is_convertible_v<decltype(std::declval<const P&>().node_count()), int> &&
                         std::is_convertible_v<decltype(std::declval<const P&>().label_count()), int> &&
                         std::is_convertible_v<decltype(std::declval<const P&>().unary(0, 0)), double> &&
                         std::is_convertible_v<decltype(std::declval<const P&>().edge_count()), int> &&
                         std::is_convertible_v<decltype(std::declval<const P&>().edge(0)), std::pair<int, int>> &&
                         std::is_convertible_v<decltype(std::declval<const P&>().pairwise(0, 0, 0)), double>> {};

/// Neumaier's compensated sum: the energy of a labelling with 1e9 "forbidden"
/// terms next to 0.01 ones stays exact to a few ulps of the result.
struct CompensatedSum {
  double sum = 0, carry = 0;
  template <class = void>
  void add(double x) {
    const double t = sum + x;
    carry += std::fabs(sum) >= std::fabs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  double value() const { return sum + carry; }
};

/// Relative slack of the expansion condition: a binary term with
/// A + D - B - C <= expansion_slack * (|A| + |B| + |C| + |D|) counts as
/// submodular (rounding of terms computed in floating point).
inline constexpr double expansion_slack = 1e-12;
}  // namespace detail

/// True when P satisfies the labelling problem contract above.
template <class P>
inline constexpr bool is_labelling_problem_v = detail::is_labelling_problem<P>::value;

/// A labelling problem held in tables: unary as N x M values, and for every
/// edge its two nodes and an M x M table (row = label of the first node).
/// Memory 8 (N M + E M^2) bytes; every accessor is O(1). Sizes and indices are
/// programmer errors (RESTITCH_ASSERT); read_mrf() validates files.
class TableMrf {
 public:
  TableMrf() = default;
  /// N nodes, M labels, all unary terms zero, no edges.
  TableMrf(int node_count, int label_count)
      : nodes_(node_count),
        labels_(label_count),
        unary_(static_cast<std::size_t>(node_count) * static_cast<std::size_t>(label_count), 0.0) {
    RESTITCH_ASSERT(node_count >= 0 && label_count >= 0, "TableMrf: sizes must be >= 0");
  }

  int node_count() const { return nodes_; }
  int label_count() const { return labels_; }
  int edge_count() const { return static_cast<int>(edges_.size()); }
  /// Its terms are plain tables: several threads may read them at once (AlphaExpansion::threads).
  bool terms_thread_safe() const { return true; }

  double unary(int node, int label) const { return unary_[unary_index(node, label)]; }
  void set_unary(int node, int label, double value) { unary_[unary_index(node, label)] = value; }

  template <class = void>
  std::pair<int, int> edge(int e) const {
    RESTITCH_ASSERT(e >= 0 && e < edge_count(), "TableMrf::edge: edge id out of range");
    return edges_[static_cast<std::size_t>(e)];
  }
  double pairwise(int e, int label_i, int label_j) const { return pairwise_[pairwise_index(e, label_i, label_j)]; }
  template <class = void>
  void set_pairwise(int e, int label_i, int label_j, double value) {
    pairwise_[pairwise_index(e, label_i, label_j)] = value;
  }

  /// Adds the edge (i, j), i != j, with an all-zero table; returns its id.
  template <class = void>
  int add_edge(int i, int j) {
    RESTITCH_ASSERT(i >= 0 && i < nodes_ && j >= 0 && j < nodes_, "TableMrf::add_edge: node id out of range");
    RESTITCH_ASSERT(i != j, "TableMrf::add_edge: an edge needs two different nodes");
    edges_.emplace_back(i, j);
    pairwise_.resize(pairwise_.size() + table_size(), 0.0);
    return edge_count() - 1;
  }
  /// Adds the edge (i, j) with `table` (M*M values, row-major, row = label of i).
  template <class = void>
  int add_edge(int i, int j, const std::vector<double>& table) {
    RESTITCH_ASSERT(table.size() == table_size(), "TableMrf::add_edge: the table must hold M*M values");
    const int e = add_edge(i, j);
    std::copy(table.begin(), table.end(), pairwise_.end() - static_cast<std::ptrdiff_t>(table_size()));
    return e;
  }

  /// Raw storage: unary row-major N x M; pairwise E tables of M x M, in edge order.
  const std::vector<double>& unary_values() const { return unary_; }
  const std::vector<double>& pairwise_values() const { return pairwise_; }

 private:
  std::size_t table_size() const { return static_cast<std::size_t>(labels_) * static_cast<std::size_t>(labels_); }
  template <class = void>
  std::size_t unary_index(int node, int label) const {
    RESTITCH_ASSERT(node >= 0 && node < nodes_ && label >= 0 && label < labels_,
                    "TableMrf::unary: node or label out of range");
    return static_cast<std::size_t>(node) * static_cast<std::size_t>(labels_) + static_cast<std::size_t>(label);
  }
  template <class = void>
  std::size_t pairwise_index(int e, int label_i, int label_j) const {
    RESTITCH_ASSERT(
        e >= 0 && e < edge_count() && label_i >= 0 && label_i < labels_ && label_j >= 0 && label_j < labels_,
        "TableMrf::pairwise: edge or label out of range");
    return static_cast<std::size_t>(e) * table_size() + static_cast<std::size_t>(label_i) * labels_ +
           static_cast<std::size_t>(label_j);
  }

  int nodes_ = 0;
  int labels_ = 0;
  std::vector<double> unary_;
  std::vector<std::pair<int, int>> edges_;
  std::vector<double> pairwise_;
};

/// The energy of `labels` (N values in [0, M)), summed with compensation in
/// node order then edge order (deterministic). Cost O(N + E) term calls.
template <class P>
double energy(const P& problem, const std::vector<int>& labels) {
  static_assert(is_labelling_problem_v<P>,
                "restitch::energy: the problem type does not satisfy the labelling problem contract "
                "(see restitch/solver/mrf.hpp)");
  const int n = problem.node_count();
  RESTITCH_ASSERT(static_cast<int>(labels.size()) == n, "restitch::energy: labels must hold one label per node");
  detail::CompensatedSum s;
  for (int i = 0; i < n; ++i) s.add(problem.unary(i, labels[static_cast<std::size_t>(i)]));
  const int m = problem.edge_count();
  for (int e = 0; e < m; ++e) {
    const std::pair<int, int> ij = problem.edge(e);
    s.add(problem.pairwise(e, labels[static_cast<std::size_t>(ij.first)], labels[static_cast<std::size_t>(ij.second)]));
  }
  return s.value();
}

/// Result of check_metric().
struct MetricCheck {
  bool ok = true;       ///< every expansion move of every edge is submodular
  int edge = -1;        ///< first violating edge (lowest id), -1 when ok
  int alpha = -1;       ///< the expansion label of the first violation
  int beta = -1;        ///< label of edge(e).first in it
  int gamma = -1;       ///< label of edge(e).second in it
  double excess = 0;    ///< E(alpha,alpha) + E(beta,gamma) - E(beta,alpha) - E(alpha,gamma) > 0
  std::string message;  ///< empty when ok
};

/// Checks exactly the condition under which every alpha-expansion move is a
/// submodular binary problem (Kolmogorov-Zabih), so that the max-flow finds
/// the best expansion move:
///
///   for every edge e and labels alpha, beta, gamma:
///     E(alpha, alpha) + E(beta, gamma) <= E(beta, alpha) + E(alpha, gamma)
///
/// with E = pairwise(e, ., .), up to a relative slack of 1e-12 of the sum of
/// the four magnitudes. Nothing else is assumed: E need not be symmetric and
/// E(a, a) need not be zero. For a symmetric E with a zero diagonal the
/// condition is the triangle inequality E(b, g) <= E(b, a) + E(a, g), i.e. E
/// is a metric (E(a, b) = 0 for a != b allowed). Unary terms play no part. The first violation in the order (edge,
/// alpha, beta, gamma) is reported. Cost O(E M^3) term calls (M = 30, E = 13 000: 3.5e8; a debug check, not for every
/// solve).
template <class P>
MetricCheck check_metric(const P& problem) {
  static_assert(is_labelling_problem_v<P>,
                "restitch::check_metric: the problem type does not satisfy the labelling problem contract "
                "(see restitch/solver/mrf.hpp)");
  MetricCheck r;
  const int m = problem.label_count();
  const int edges = problem.edge_count();
  for (int e = 0; e < edges; ++e)
    for (int a = 0; a < m; ++a) {
      const double d = problem.pairwise(e, a, a);
      for (int b = 0; b < m; ++b) {
        if (b == a) continue;  // trivially holds
        const double eb = problem.pairwise(e, b, a);
        for (int g = 0; g < m; ++g) {
          if (g == a) continue;
          const double ebg = problem.pairwise(e, b, g), eg = problem.pairwise(e, a, g);
          const double excess = (d + ebg) - (eb + eg);
          const double slack =
              detail::expansion_slack * (std::fabs(d) + std::fabs(ebg) + std::fabs(eb) + std::fabs(eg));
          if (excess > slack || std::isnan(excess)) {
            r.ok = false;
            r.edge = e;
            r.alpha = a;
            r.beta = b;
            r.gamma = g;
            r.excess = excess;
            r.message = "edge " + std::to_string(e) + " violates the expansion condition: E(" + std::to_string(a) +
                        "," + std::to_string(a) + ") + E(" + std::to_string(b) + "," + std::to_string(g) + ") > E(" +
                        std::to_string(b) + "," + std::to_string(a) + ") + E(" + std::to_string(a) + "," +
                        std::to_string(g) + ") by " + std::to_string(excess);
            return r;
          }
        }
      }
    }
  return r;
}

/// What a solver reports. Filled by every solver policy.
struct SolveReport {
  int nodes = 0;                       ///< N
  int labels = 0;                      ///< M
  int edges = 0;                       ///< E
  double initial_energy = 0;           ///< energy of the labelling passed in
  double energy = 0;                   ///< energy of the labelling returned (energy())
  int cycles = 0;                      ///< passes over the labels begun (the last may be partial)
  int expansions = 0;                  ///< moves tried (max-flow solves for alpha-expansion)
  int moves_accepted = 0;              ///< moves that lowered the energy
  bool converged = false;              ///< stopped because no move lowers the energy (not max_cycles or cancel)
  bool non_metric_detected = false;    ///< a move met a non-submodular term and truncated it
  double ms = 0;                       ///< wall time of solve(), std::chrono::steady_clock; reported, not asserted
  std::vector<double> cycle_energies;  ///< energy after each pass (non-increasing)
};

namespace detail {
template <class S, class P, class = void>
struct is_graph_solver : std::false_type {};
template <class S, class P>
struct is_graph_solver<S, P,
                       std::void_t<decltype(std::declval<const S&>().solve(
                           std::declval<const P&>(), std::declval<std::vector<int>&>(), std::declval<SolveReport&>(),
                           std::declval<const Progress&>()))>>
    : std::is_same<decltype(std::declval<const S&>().solve(std::declval<const P&>(), std::declval<std::vector<int>&>(),
                                                           std::declval<SolveReport&>(),
                                                           std::declval<const Progress&>())),
                   Status> {};
}  // namespace detail

/// True when S satisfies the solver policy contract above for problem type P.
template <class S, class P = TableMrf>
inline constexpr bool is_graph_solver_v = detail::is_graph_solver<S, P>::value;

}  // namespace restitch
