// restitch/solver/alpha_expansion.hpp - the default solver policy:
// alpha-expansion (Boykov, Veksler, Zabih, PAMI 2001) over a max-flow back end.
//
// Satisfies the solver policy contract of restitch/solver/mrf.hpp:
//
//   restitch::AlphaExpansion<> solver;            // PushRelabelMaxFlow<double> inside
//   restitch::SolveReport report;
//   std::vector<int> labels(problem.node_count(), 0);  // initial labelling
//   restitch::Status s = solver.solve(problem, labels, report, progress);
//
// The algorithm. Labels are visited in the order 0, 1, ..., M-1, again and
// again. For label alpha, every node either keeps its label or switches to
// alpha (nodes already at alpha stay). That binary problem is built with the
// Kolmogorov-Zabih construction: for an edge whose two nodes are both free to
// move, with current labels (a, b),
//   A = E(a, b), B = E(a, alpha), C = E(alpha, b), D = E(alpha, alpha),
// the term is A + (C - A) x_i + (D - C) x_j + (B + C - A - D)(1 - x_i) x_j,
// an edge of capacity B + C - A - D >= 0 plus terminal capacities. The
// minimum cut (max-flow back end; source side = takes alpha, see
// in_source_segment: a node that could go either way keeps its label;
// `ties_to_alpha` makes it take alpha instead, gco-v3.0's rule) gives
// the best expansion move. The move is applied only if the TRUE energy of
// the new labelling, evaluated term by term, is lower (strictly, by more than
// 1e-12 of the magnitude of the terms the move touches, so rounding never
// counts as progress); so the energy never rises, whatever the terms. The
// solver stops when M expansions in a row (one full cycle over the labels,
// starting anywhere) have not lowered the energy: the result is then a local
// minimum with respect to every expansion move. For metric pairwise terms it
// is within 2c of the global minimum (BVZ Theorem 6.1; c = ratio of the
// largest to the smallest non-zero pairwise value), and it is the global
// minimum for two labels with a submodular term.
//
// Non-metric terms. When B + C < A + D (the term violates the condition of
// check_metric(), restitch/solver/mrf.hpp) the binary term is not submodular
// and cannot be cut exactly. It is truncated as in Rother et al., "Digital
// Tapestry", CVPR 2005: D is lowered to B + C - A (the edge gets capacity 0),
// report.non_metric_detected is set (only when the violation exceeds 1e-12 of
// the four magnitudes), and the acceptance test above still rejects any move
// that would raise the true energy. The result is then no longer guaranteed
// to be a local minimum for every expansion move.
//
// Magnitudes. Terms must be finite (solve() returns invalid_argument for NaN
// or infinity, or for sums beyond the double range). Forbidden assignments
// are large finite constants such as 1e9. Capacities are doubles: a node's
// terminal capacity sums the differences of its incident terms, so next to
// forbidden terms of 1e9 on 26 edges, small terms are still resolved to about
// 26 * 1e9 * 2^-53 = 3e-6 in the cut. Supported: |term| <= 1e12 (small terms
// resolved to ~3e-3 then). Capacities are clamped to 1e15 when the graph is
// built; whether a move is taken is decided by the TRUE energy change,
// summed with compensation, so neither clamping nor rounding in the graph can
// make the energy rise; they can only make a proposed move less good. The
// back end's capacity type must be floating point.
//
// Determinism: labels, edges and arcs are visited in a fixed order, no
// randomness: the same input gives the same labels bit for bit. With
// `threads` > 1 the next moves are proposed on several threads, but taken in
// the sequential order on the labelling the sequential loop shows them
// (AlphaExpansion::threads), so the result does not depend on the count.
// Memory: O(N + E) scratch allocated once per solve() and thread (plus the
// back end's graph, reused across moves through reset()); no allocation
// inside the label loop. Cost per expansion: N unary and about 3 E pairwise calls, one
// max-flow, then pairwise calls for the edges of nodes that moved.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/detail/parallel.hpp"
#include "restitch/progress.hpp"
#include "restitch/solver/max_flow_bk.hpp"
#include "restitch/solver/max_flow_push_relabel.hpp"
#include "restitch/solver/mrf.hpp"
#include "restitch/status.hpp"

namespace restitch {

namespace detail {

/// Back ends that can skip finding the sink segment (PushRelabelMaxFlow::sink_segment).
template <class T, class = void>
struct has_sink_segment_option : std::false_type {};
template <class T>
struct has_sink_segment_option<T, std::void_t<decltype(std::declval<T&>().sink_segment = true)>> : std::true_type {};

/// Relative threshold a move's energy change must beat to be accepted.
inline constexpr double move_slack = 1e-12;
/// Capacities are clamped to this when an expansion graph is built.
inline constexpr double max_expansion_capacity = 1e15;

/// The state of one alpha-expansion run: current labels and their cached
/// terms, plus scratch reused by every move.
template <class Problem, class MaxFlow>
class ExpansionRun {
 public:
  ExpansionRun(const Problem& problem, std::vector<int>& labels, bool ties_to_alpha = false)
      : p_(problem), labels_(labels), ties_to_alpha_(ties_to_alpha) {}

  /// Validates the problem and the initial labels; caches the current terms.
  Status start() {
    n_ = p_.node_count();
    m_ = p_.label_count();
    e_ = p_.edge_count();
    if (n_ < 0 || m_ < 0 || e_ < 0)
      return error(StatusCode::invalid_argument, "the labelling problem reports a negative size");
    if (n_ > 0 && m_ < 1) return error(StatusCode::invalid_argument, "the labelling problem has nodes but no labels");
    if (labels_.empty() && n_ > 0) labels_.assign(static_cast<std::size_t>(n_), 0);
    if (static_cast<long long>(labels_.size()) != n_)
      return error(StatusCode::invalid_argument, "the initial labelling holds " + std::to_string(labels_.size()) +
                                                     " labels for " + std::to_string(n_) + " nodes");
    for (int i = 0; i < n_; ++i)
      if (labels_[idx(i)] < 0 || labels_[idx(i)] >= m_)
        return error(StatusCode::invalid_argument, "initial label " + std::to_string(labels_[idx(i)]) + " of node " +
                                                       std::to_string(i) + " is outside [0, " + std::to_string(m_) +
                                                       ")");
    ends_.resize(idx(e_));
    for (int e = 0; e < e_; ++e) {
      ends_[idx(e)] = p_.edge(e);
      const int i = ends_[idx(e)].first, j = ends_[idx(e)].second;
      if (i < 0 || i >= n_ || j < 0 || j >= n_ || i == j)
        return error(StatusCode::invalid_argument,
                     "edge " + std::to_string(e) + " joins nodes " + std::to_string(i) + " and " + std::to_string(j) +
                         "; an edge needs two different nodes in [0, " + std::to_string(n_) + ")");
    }
    cur_unary_.resize(idx(n_));
    cur_pair_.resize(idx(e_));
    CompensatedSum s;
    for (int i = 0; i < n_; ++i) {
      const double u = p_.unary(i, labels_[idx(i)]);
      if (!std::isfinite(u)) return not_finite("unary term of node " + std::to_string(i));
      cur_unary_[idx(i)] = u;
      s.add(u);
    }
    for (int e = 0; e < e_; ++e) {
      const double w = p_.pairwise(e, labels_[idx(ends_[idx(e)].first)], labels_[idx(ends_[idx(e)].second)]);
      if (!std::isfinite(w)) return not_finite("pairwise term of edge " + std::to_string(e));
      cur_pair_[idx(e)] = w;
      s.add(w);
    }
    energy_ = s.value();
    return Status();
  }

  /// What one proposed expansion move does. Proposals for different labels on the same labelling can be
  /// computed at once, each into its own Move with its own Scratch (AlphaExpansion::threads).
  struct Move {
    int alpha = -1;
    bool improved = false;    // the move lowers the energy (by more than move_slack)
    bool non_metric = false;  // a binary term of this move had to be truncated
    double change = 0;        // the true energy change, when improved
    std::vector<char> moved;  // node takes alpha
    std::vector<double> new_unary;                 // unary term at alpha, of the nodes not at alpha
    std::vector<std::pair<int, double>> affected;  // edges of moved nodes and their new terms
  };
  /// The working memory of a proposal (kept by one thread: its graph stays in that core's cache).
  struct Scratch {
    std::vector<int> var;  // graph node of each problem node, -1 when at alpha
    std::vector<double> diff;
    MaxFlow graph;
  };

  /// Sizes a move and a scratch for this run (once; no allocation inside the label loop after that).
  void prepare(Move& mv) const {
    mv.moved.resize(idx(n_));
    mv.new_unary.resize(idx(n_));
    mv.affected.reserve(idx(e_));
  }
  void prepare(Scratch& sc) const {
    sc.var.resize(idx(n_));
    sc.diff.reserve(idx(n_));
    sc.graph.reset(n_, e_);
    if constexpr (has_sink_segment_option<MaxFlow>::value) sc.graph.sink_segment = ties_to_alpha_;
  }

  /// One expansion move for label alpha, proposed on the current labelling: fills mv, using sc (and writes
  /// nothing else: the run's state is only read, so proposals for several labels may run at once on their
  /// own moves and scratch). `mv.improved` says whether apply(mv) would lower the energy.
  /// (About 90 lines: the graph construction of one move is kept in one piece because it is the
  /// solver's hot loop and its steps share the per-move tables.)
  Status propose(int alpha, Move& mv, Scratch& sc) const {
    mv.alpha = alpha;
    mv.improved = false;
    mv.non_metric = false;
    mv.change = 0;
    std::vector<int>& var = sc.var;
    std::vector<char>& took = mv.moved;
    std::vector<double>& diff = sc.diff;
    std::vector<double>& new_unary = mv.new_unary;
    MaxFlow& graph = sc.graph;
    int nv = 0;
    for (int i = 0; i < n_; ++i) var[idx(i)] = labels_[idx(i)] == alpha ? -1 : nv++;
    if (nv == 0) return Status();

    graph.reset(nv, e_);
    graph.add_node(nv);
    diff.assign(idx(nv), 0.0);  // cost(takes alpha) - cost(keeps its label), per graph node
    for (int i = 0; i < n_; ++i) {
      const int v = var[idx(i)];
      if (v < 0) continue;
      const double u = p_.unary(i, alpha);
      new_unary[idx(i)] = u;
      diff[idx(v)] += u - cur_unary_[idx(i)];
    }
    for (int e = 0; e < e_; ++e) {
      const int i = ends_[idx(e)].first, j = ends_[idx(e)].second;
      const int vi = var[idx(i)], vj = var[idx(j)];
      if (vi < 0 && vj < 0) continue;  // both at alpha: constant
      const double A = cur_pair_[idx(e)];
      double D = p_.pairwise(e, alpha, alpha);
      if (vi < 0) {  // i already at alpha: A = E(alpha, b), a unary term on j
        diff[idx(vj)] += D - A;
        continue;
      }
      if (vj < 0) {
        diff[idx(vi)] += D - A;
        continue;
      }
      const double B = p_.pairwise(e, labels_[idx(i)], alpha);
      const double C = p_.pairwise(e, alpha, labels_[idx(j)]);
      double w = (B + C) - (A + D);
      if (!std::isfinite(w)) return not_finite("pairwise term of edge " + std::to_string(e), alpha);
      if (w < 0) {
        if (-w > expansion_slack * (std::fabs(A) + std::fabs(B) + std::fabs(C) + std::fabs(D))) mv.non_metric = true;
        D += w;  // truncation: D' = B + C - A
        w = 0;
      }
      diff[idx(vi)] += C - A;
      diff[idx(vj)] += D - C;
      if (w > 0) graph.add_edge(vj, vi, capacity(w), Cap(0));  // cut when i keeps and j takes alpha
    }
    for (int i = 0; i < n_; ++i) {
      const int v = var[idx(i)];
      if (v < 0) continue;
      const double d = diff[idx(v)];
      if (!std::isfinite(d)) return not_finite("unary or pairwise term at node " + std::to_string(i), alpha);
      if (d > 0)
        graph.add_tweights(v, Cap(0), capacity(d));
      else if (d < 0)
        graph.add_tweights(v, capacity(-d), Cap(0));
    }
    graph.max_flow();

    // The proposed labelling and its true energy change.
    CompensatedSum delta;
    double scale = 0;
    bool any = false;
    for (int i = 0; i < n_; ++i) {
      const int v = var[idx(i)];
      const bool moved = v >= 0 && takes_alpha(graph, v);
      took[idx(i)] = moved;
      if (!moved) continue;
      any = true;
      delta.add(new_unary[idx(i)] - cur_unary_[idx(i)]);
      scale += std::fabs(new_unary[idx(i)]) + std::fabs(cur_unary_[idx(i)]);
    }
    if (!any) return Status();
    mv.affected.clear();
    for (int e = 0; e < e_; ++e) {
      const int i = ends_[idx(e)].first, j = ends_[idx(e)].second;
      const bool mi = took[idx(i)], mj = took[idx(j)];
      if (!mi && !mj) continue;
      const double w = p_.pairwise(e, mi ? alpha : labels_[idx(i)], mj ? alpha : labels_[idx(j)]);
      mv.affected.emplace_back(e, w);
      delta.add(w - cur_pair_[idx(e)]);
      scale += std::fabs(w) + std::fabs(cur_pair_[idx(e)]);
    }
    const double change = delta.value();
    if (!(change < -move_slack * scale)) return Status();  // also rejects NaN
    mv.change = change;
    mv.improved = true;
    return Status();
  }

  /// Takes a move proposed on the current labelling (mv.improved): its nodes take alpha.
  void apply(const Move& mv) {
    for (int i = 0; i < n_; ++i)
      if (mv.moved[idx(i)]) {
        labels_[idx(i)] = mv.alpha;
        cur_unary_[idx(i)] = mv.new_unary[idx(i)];
      }
    for (const auto& ew : mv.affected) cur_pair_[idx(ew.first)] = ew.second;
    energy_ += mv.change;
  }

  /// Records that a move proposed on the current labelling was used (taken or not): its non-metric flag
  /// counts (a proposal computed on a labelling the run has since left counts for nothing).
  void count(const Move& mv) { non_metric_ = non_metric_ || mv.non_metric; }

  double energy() const { return energy_; }
  bool non_metric() const { return non_metric_; }
  int nodes() const { return n_; }
  int labels() const { return m_; }
  int edges() const { return e_; }

 private:
  using Cap = typename MaxFlow::capacity_type;
  static std::size_t idx(int i) { return static_cast<std::size_t>(i); }
  static Cap capacity(double x) { return static_cast<Cap>(std::min(x, max_expansion_capacity)); }
  static Status not_finite(const std::string& what, int alpha = -1) {
    return error(StatusCode::invalid_argument,
                 (alpha >= 0 ? "while expanding label " + std::to_string(alpha) + ", a " : std::string("the ")) + what +
                     " is not finite (NaN, infinity or beyond the double range); use a large finite constant such as "
                     "1e9 for forbidden assignments");
  }

  const Problem& p_;
  std::vector<int>& labels_;
  int n_ = 0, m_ = 0, e_ = 0;
  double energy_ = 0;
  bool non_metric_ = false;
  std::vector<std::pair<int, int>> ends_;  // edge endpoints, cached
  std::vector<double> cur_unary_, cur_pair_;
  bool ties_to_alpha_ = false;

  // Whether graph node v takes alpha: on the source side of the smallest minimum cut (a node that could go
  // either way keeps its label), or, with ties_to_alpha and a back end that reports the sink side, of the
  // largest (such a node takes alpha, gco-v3.0's choice).
  bool takes_alpha(const MaxFlow& graph, int v) const {
    if constexpr (has_sink_segment_v<MaxFlow>)
      if (ties_to_alpha_) return !graph.in_sink_segment(v);
    return graph.in_source_segment(v);
  }
};

template <class P, class = void>
struct has_terms_thread_safe : std::false_type {};
template <class P>
struct has_terms_thread_safe<P, std::void_t<decltype(std::declval<const P&>().terms_thread_safe())>> : std::true_type {};

/// Helper threads for AlphaExpansion::threads. The caller and the helpers propose the expansion moves
/// of positions 0, 1, 2, ... (position p expands label p mod M), each into its own slot, up to `slots`
/// positions past the last one the caller took (one only after an accepted move: moves tend to be
/// accepted in runs, early in a solve, and rejected in runs, at its end, where proposing ahead pays);
/// the caller takes them in order (take), proposing the next one itself while the one it waits for is
/// still being computed, so no core waits while there is work. Before the caller changes the labelling
/// it holds the helpers (hold: none starts a proposal, the running ones finish), and resume drops every
/// proposal made on the old labelling and starts again from the next position. The destructor stops the helpers and joins them (a running proposal finishes
/// first). A helper that cannot be started is not used.
template <class Run>
class ProposalPipeline {
 public:
  using Move = typename Run::Move;
  ProposalPipeline(const Run& run, int helpers, int labels, long long positions)
      : run_(run),
        labels_(labels),
        last_(positions),
        slots_(std::size_t(2 * (helpers + 1))),
        scratch_(std::size_t(helpers + 1)) {
    for (Slot& s : slots_) run.prepare(s.mv);
    for (auto& sc : scratch_) run.prepare(sc);
    for (int k = 0; k < helpers; ++k) {
      try {
        threads_.emplace_back([this, k] { loop(scratch_[std::size_t(k) + 1]); });
      } catch (const std::system_error&) {
        break;
      }
    }
  }
  ProposalPipeline(const ProposalPipeline&) = delete;
  ProposalPipeline& operator=(const ProposalPipeline&) = delete;
  ~ProposalPipeline() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      quit_ = true;
    }
    work_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

  /// The proposal of position pos (the next one, in order), with its status; rethrows what it threw.
  const Move& take(long long pos, Status& status) {
    Slot& s = slot(pos);
    std::unique_lock<std::mutex> lock(mutex_);
    while (!(s.pos == pos && s.ready)) {
      if (can_start())
        propose_next(lock, scratch_[0]);  // pos itself when nobody started it, else one further ahead
      else
        done_.wait(lock);
    }
    if (s.failed) std::rethrow_exception(s.failed);
    status = s.status;
    return s.mv;
  }
  /// Position pos was taken and left the labelling as it was: its slot is free.
  void release(long long pos) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      taken_ = pos + 1;
      ahead_ = (long long)slots_.size();  // a rejected move: the next ones are likely rejected too
    }
    work_.notify_all();
  }
  /// The caller is about to change the labelling: no proposal starts, and this returns when none runs.
  void hold() {
    std::unique_lock<std::mutex> lock(mutex_);
    held_ = true;
    done_.wait(lock, [&] { return running_ == 0; });
  }
  /// The labelling changed at position pos: every proposal made after it is dropped; go on from pos + 1.
  void resume(long long pos) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (Slot& s : slots_) s.pos = -1, s.ready = false;
      next_ = taken_ = pos + 1;
      ahead_ = 1;  // after an accepted move, one at a time until one is rejected (nothing to drop)
      held_ = false;
    }
    work_.notify_all();
  }

 private:
  struct Slot {
    Move mv;
    Status status;
    std::exception_ptr failed;
    long long pos = -1;
    bool ready = false;
  };
  Slot& slot(long long pos) { return slots_[std::size_t(pos % (long long)slots_.size())]; }

  bool can_start() const { return !held_ && next_ < last_ && next_ < taken_ + ahead_; }

  // Proposes position next_ into its slot with `scratch` (the lock is released while it is computed).
  void propose_next(std::unique_lock<std::mutex>& lock, typename Run::Scratch& scratch) {
    const long long p = next_++;
    Slot& s = slot(p);
    s.pos = p;
    s.ready = false;
    s.failed = nullptr;
    ++running_;
    lock.unlock();
    try {
      s.status = run_.propose(int(p % labels_), s.mv, scratch);
    } catch (...) {
      s.failed = std::current_exception();
    }
    lock.lock();
    s.ready = true;
    --running_;
  }

  void loop(typename Run::Scratch& scratch) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      work_.wait(lock, [&] { return quit_ || can_start(); });
      if (quit_) return;
      propose_next(lock, scratch);
      done_.notify_all();
    }
  }

  const Run& run_;
  const int labels_;
  const long long last_;  // no position at or past this is proposed (max_cycles * M)
  std::vector<Slot> slots_;
  std::vector<typename Run::Scratch> scratch_;  // the caller's, then one per helper
  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable work_, done_;
  long long next_ = 0;   // the next position a helper proposes
  long long taken_ = 0;  // positions before this one were taken by the caller
  long long ahead_ = 1;  // how far past taken_ proposals may start: 1 after an accepted move, else slots
  int running_ = 0;      // proposals being computed
  bool held_ = false, quit_ = false;
};

}  // namespace detail

/// Alpha-expansion solver policy; see the top of this file.
template <class MaxFlow = PushRelabelMaxFlow<double>>
class AlphaExpansion {
  static_assert(is_max_flow_v<MaxFlow>,
                "AlphaExpansion<MaxFlow>: MaxFlow does not satisfy the max-flow back-end contract "
                "(capacity_type, reset, add_node, add_tweights, add_edge, max_flow, in_source_segment; "
                "see restitch/solver/max_flow_bk.hpp)");
  static_assert(std::is_floating_point_v<typename MaxFlow::capacity_type>,
                "AlphaExpansion<MaxFlow>: the back end's capacity_type must be floating point "
                "(integer capacities would round the energy's terms)");

 public:
  /// Called after every accepted move with the labelling and its energy
  /// (tracked by the solver); for tests and visualisation. Empty by default.
  using MoveObserver = std::function<void(const std::vector<int>& labels, double energy)>;

  /// At most this many passes over the labels (the solver usually stops far
  /// earlier, when no expansion lowers the energy; report.converged then).
  int max_cycles = 100;
  /// Which minimum cut an expansion takes when several have the same cost: false (default), the one that
  /// moves fewest nodes (a node that could go either way keeps its label); true, the one that moves most
  /// (it takes alpha, as gco-v3.0 does). Needs a back end with in_sink_segment (both of restitch's have it); with
  /// one that lacks it, solve() refuses (invalid_argument).
  bool ties_to_alpha = false;
  /// Threads that propose expansion moves: 1 (default) runs on the calling thread, 0 uses every hardware
  /// thread. With T > 1, T helper threads propose the next expansions in the label order ahead, each on
  /// its own graph, on the current labelling, while the calling thread takes their outcomes in that order;
  /// when one is accepted, those proposed after it are dropped and proposed again on the new labelling.
  /// Every expansion that counts is the one the sequential loop runs on the same labelling, so labels,
  /// energy and report are bit-identical whatever T; the gain is the rejected expansions computed side by
  /// side (a run ends with a whole cycle of them). Used only where the problem says its terms may be read from several threads at once
  /// (`bool terms_thread_safe() const`; a problem without it is read from one thread) and the problem has
  /// at least `min_parallel_size` nodes plus edges: below that an expansion takes about as long as
  /// handing it to another thread (docs/benchmarks.md). A WebAssembly build without threads runs on one.
  int threads = 1;
  int min_parallel_size = 4096;
  MoveObserver on_move;

  /// See the solver policy contract in restitch/solver/mrf.hpp. Progress is
  /// reported after every expansion as stage "alpha-expansion" with fraction
  /// 1 - 2^-(cycles done), which rises monotonically; a cancel leaves labels
  /// at the best labelling so far and returns StatusCode::cancelled.
  template <class Problem>
  Status solve(const Problem& problem, std::vector<int>& labels, SolveReport& report,
               const Progress& progress = Progress()) const {
    if constexpr (!has_sink_segment_v<MaxFlow>)  // an option that cannot be honoured is refused, not ignored
      if (ties_to_alpha)
        return error(StatusCode::invalid_argument,
                     "AlphaExpansion::ties_to_alpha needs a max-flow back end with in_sink_segment");
    return detail::guarded("AlphaExpansion::solve", [&]() -> Status {
      static_assert(is_labelling_problem_v<Problem>,
                    "AlphaExpansion::solve: the problem type does not satisfy the labelling problem contract "
                    "(node_count, label_count, unary, edge_count, edge, pairwise; see restitch/solver/mrf.hpp)");
      const auto t0 = std::chrono::steady_clock::now();
      report = SolveReport();
      using Run = detail::ExpansionRun<Problem, MaxFlow>;
      Run run(problem, labels, ties_to_alpha);
      const auto finish = [&](Status s) {
        report.non_metric_detected = run.non_metric();
        if (static_cast<long long>(labels.size()) == problem.node_count() && s.code() != StatusCode::invalid_argument)
          report.energy = energy(problem, labels);
        report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        return s;
      };

      Status s = run.start();
      report.nodes = run.nodes();
      report.labels = run.labels();
      report.edges = run.edges();
      if (!s.ok()) return finish(s);
      report.initial_energy = run.energy();
      const int m = run.labels();
      if (run.nodes() == 0 || m <= 1) {
        report.converged = true;  // nothing can move
        return finish(Status());
      }

      // Expansion p (p = 0, 1, 2, ...) is cycle p / M, label p mod M. With helper threads (`threads`) the
      // moves of the next positions are proposed ahead on the current labelling and taken here in order;
      // when one is accepted, the ones proposed after it are dropped and proposed again on the new
      // labelling. So every expansion that counts saw the labelling the sequential loop shows it.
      const long long last = static_cast<long long>(max_cycles) * m;
      const int helpers = std::min(helper_threads(problem, run), m - 1);
      std::optional<detail::ProposalPipeline<Run>> pipeline;
      typename Run::Move own;
      typename Run::Scratch scratch;
      if (helpers > 0) {
        pipeline.emplace(run, helpers, m, last);
      } else {
        run.prepare(own);
        run.prepare(scratch);
      }
      int failures_in_row = 0;
      for (long long p = 0; p < last; ++p) {
        const int cycle = static_cast<int>(p / m), alpha = static_cast<int>(p % m);
        report.cycles = cycle + 1;
        Status st;
        if (!pipeline) st = run.propose(alpha, own, scratch);
        const typename Run::Move& mv = pipeline ? pipeline->take(p, st) : own;
        if (!st.ok()) return finish(st);
        run.count(mv);
        ++report.expansions;
        if (mv.improved) {
          if (pipeline) pipeline->hold();
          run.apply(mv);
          if (pipeline) pipeline->resume(p);  // mv's slot may be reused from here on
          ++report.moves_accepted;
          failures_in_row = 0;
          if (on_move) on_move(labels, run.energy());
        } else {
          if (pipeline) pipeline->release(p);
          if (++failures_in_row >= m) {
            report.converged = true;
            report.cycle_energies.push_back(run.energy());
            return finish(Status());
          }
        }
        const double done = cycle + (alpha + 1.0) / m;
        if (!progress.report("alpha-expansion", 1.0 - std::pow(2.0, -done))) {
          report.cycle_energies.push_back(run.energy());
          return finish(error(StatusCode::cancelled, "alpha-expansion cancelled"));
        }
        if (alpha == m - 1) report.cycle_energies.push_back(run.energy());
      }
      return finish(Status());
    });
  }

 private:
  // How many helper threads propose moves (see `threads`); 0: the calling thread proposes them.
  template <class Problem, class Run>
  int helper_threads(const Problem& problem, const Run& run) const {
    if constexpr (!detail::has_terms_thread_safe<Problem>::value) {
      return 0;
    } else {
      if (threads == 1 || !problem.terms_thread_safe()) return 0;
      if (double(run.nodes()) + double(run.edges()) < double(min_parallel_size)) return 0;
      return resolve_threads(threads) - 1;  // the calling thread proposes too
    }
  }
};

}  // namespace restitch
