// restitch/solver/max_flow_push_relabel.hpp - a push-relabel max-flow back end,
// the default of AlphaExpansion: with it the bench's synthetic problem (1000
// nodes, 26-neighbourhood, 30 labels) solves 2.6x faster than with BkMaxFlow,
// and the expansion problems dumped from the models 1.0-2.4x (docs/benchmarks.md).
//
// Satisfies the max-flow back-end contract of restitch/solver/max_flow_bk.hpp
// (reset, add_node, add_tweights, add_edge, max_flow, in_source_segment) and
// the optional in_sink_segment, with the same cut: in_source_segment(i) says
// whether i is reachable from the source in the residual graph of a maximum
// flow (the smallest minimum-cut source side), in_sink_segment(i) whether i
// reaches the sink (the smallest sink side). Both are properties of the
// network, not of the algorithm, so with exact arithmetic this back end and
// BkMaxFlow give the same segmentation and alpha-expansion the same moves.
//
// The algorithm: A. V. Goldberg and R. E. Tarjan, "A new approach to the
// maximum-flow problem", JACM 35(4), 1988, with the heuristics of
// B. V. Cherkassky and A. V. Goldberg, "On implementing the push-relabel
// method for the maximum flow problem", Algorithmica 19, 1997:
//   Phase 1 (a maximum preflow). Every source arc is saturated; each node
//     carries a distance label, a lower bound on its residual distance to the
//     sink. An active node (excess > 0, label <= n) is discharged: its excess
//     goes to the sink when it has a residual sink arc, then along admissible
//     arcs (residual > 0, head one label lower) from its current arc on; when
//     none is left it is relabelled to one more than its lowest residual
//     neighbour. Active nodes are taken first in, first out. Global
//     relabelling (exact labels by a backward breadth-first search from the
//     sink) runs at the start and whenever the relabelling work since the
//     last one exceeds 6 n + 2 E (a relabel costs 12 plus the node's number
//     of arcs; after Cherkassky and Goldberg); a node that cannot reach the sink
//     gets label n + 1 (n: the number of nodes) and is never active again.
//   Phase 2 (a maximum flow). The excess left on nodes that cannot reach the
//     sink is returned to the source by the same discharge loop aimed at the
//     source: labels are residual distances to it, and a node's "terminal"
//     capacity is the flow still on its source arc. The flow into the sink
//     does not change.
//   The segments are then two breadth-first searches of the residual graph,
//   forward from the source and backward from the sink.
// Why not Boykov-Kolmogorov here: on expansion graphs whose nodes almost all
// carry terminal capacity, BkMaxFlow finds one short augmenting path per
// saturated edge (measured: about 3,500 paths and 4,300 orphan adoptions per
// move on the 1000-node 26-neighbourhood bench problem, 91% of solve time),
// where push-relabel moves excess in bulk.
//
// Contract beyond the back-end contract:
//   * max_flow() may be called again after more add_* calls: it solves the
//     whole graph again from zero flow (the value returned is the maximum flow
//     of everything added since reset()). in_source_segment() and
//     in_sink_segment() are valid after max_flow() and until the next add_* or
//     reset().
//   * No recursion, no threads, no randomness: the same calls give the same
//     flow and the same cut, bit for bit.
//   * Capacities: Cap is a signed arithmetic type. With an integer Cap the sum
//     of all capacities must fit in Cap. With a floating Cap every capacity
//     must be finite; results are exact when every capacity and partial sum is
//     exactly representable, otherwise rounding may leave tiny residuals (a
//     node's excess below rounding is still pushed; every loop is bounded by
//     the labels, which only rise, to n).
//   * Memory: about 24 + 4 sizeof(Cap) bytes per node and 24 + 4 sizeof(Cap)
//     per add_edge call (its record and two arcs), kept across reset().
//   * Cost: O(V^3) in the worst case (FIFO selection). Measured on the
//     bench's synthetic problem: per move (about 1,000 nodes and 21,000
//     arcs) 6,800 pushes, 1,800 relabels and 4 global relabellings.
#pragma once

#include <algorithm>
#include <type_traits>
#include <vector>

#include "restitch/solver/max_flow_bk.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// Goldberg-Tarjan push-relabel max-flow / min-cut. See the top of this file.
template <class Cap = double>
class PushRelabelMaxFlow {
  static_assert(std::is_arithmetic_v<Cap> && std::is_signed_v<Cap>,
                "PushRelabelMaxFlow<Cap>: Cap must be a signed arithmetic type such as double or std::int64_t");

 public:
  using capacity_type = Cap;

  /// Whether max_flow() also finds the sink segment (a backward search of the whole graph). On by
  /// default; off, in_sink_segment() must not be called (alpha-expansion's default tie rule only asks
  /// for the source segment and turns it off: one search fewer per move).
  bool sink_segment = true;

  PushRelabelMaxFlow() = default;
  PushRelabelMaxFlow(int node_count_hint, int edge_count_hint) { reset(node_count_hint, edge_count_hint); }

  /// Forgets all nodes and edges, keeps the allocated memory.
  void reset(int node_count_hint = 0, int edge_count_hint = 0) {
    terminal_.clear();
    edges_.clear();
    if (node_count_hint > 0) terminal_.reserve(static_cast<std::size_t>(node_count_hint));
    if (edge_count_hint > 0) edges_.reserve(static_cast<std::size_t>(edge_count_hint));
    direct_flow_ = 0;
    solved_ = false;
  }

  /// Appends n >= 0 nodes; returns the id of the first.
  int add_node(int n = 1) {
    RESTITCH_ASSERT(n >= 0, "PushRelabelMaxFlow::add_node: n must be >= 0");
    const int first = node_count();
    terminal_.resize(terminal_.size() + static_cast<std::size_t>(n), Cap(0));
    solved_ = false;
    return first;
  }

  int node_count() const { return static_cast<int>(terminal_.size()); }
  int edge_count() const { return static_cast<int>(edges_.size()); }

  /// Adds to the terminal capacities of node i. What could flow
  /// source -> i -> sink directly is counted as flow at once; the node keeps
  /// the signed difference (> 0: to the source, < 0: to the sink).
  void add_tweights(int i, Cap cap_source, Cap cap_sink) {
    RESTITCH_ASSERT(i >= 0 && i < node_count(), "PushRelabelMaxFlow::add_tweights: node id out of range");
    RESTITCH_ASSERT(cap_source >= 0 && cap_sink >= 0, "PushRelabelMaxFlow::add_tweights: capacities must be >= 0");
    direct_flow_ += detail::fold_terminal(terminal_[static_cast<std::size_t>(i)], cap_source, cap_sink);
    solved_ = false;
  }

  /// Adds the edges i -> j (cap) and j -> i (rev_cap).
  void add_edge(int i, int j, Cap cap, Cap rev_cap) {
    RESTITCH_ASSERT(i >= 0 && i < node_count() && j >= 0 && j < node_count(),
                    "PushRelabelMaxFlow::add_edge: node id out of range");
    RESTITCH_ASSERT(i != j, "PushRelabelMaxFlow::add_edge: an edge needs two different nodes");
    RESTITCH_ASSERT(cap >= 0 && rev_cap >= 0, "PushRelabelMaxFlow::add_edge: capacities must be >= 0");
    edges_.push_back(Edge{i, j, cap, rev_cap});
    solved_ = false;
  }

  /// Computes a maximum flow of everything added since reset(); returns its value.
  Cap max_flow() {
    build_arcs();
    const std::size_t n = terminal_.size();
    excess_.assign(n, Cap(0));
    to_sink_.assign(n, Cap(0));
    on_source_.assign(n, Cap(0));
    for (std::size_t v = 0; v < n; ++v) {
      if (terminal_[v] > 0)
        excess_[v] = on_source_[v] = terminal_[v];  // phase 1 starts with every source arc saturated
      else
        to_sink_[v] = -terminal_[v];
    }
    flow_ = direct_flow_;
    discharge_all(to_sink_, flow_);  // phase 1: a maximum preflow
    if (std::any_of(excess_.begin(), excess_.end(), [](Cap e) { return e > 0; })) {
      Cap returned = 0;
      discharge_all(on_source_, returned);  // phase 2: the excess back to the source
    }
    mark_segments();
    solved_ = true;
    return flow_;
  }

  /// Whether node i is reachable from the source in the residual graph. Valid after max_flow().
  bool in_source_segment(int i) const {
    RESTITCH_ASSERT(solved_, "PushRelabelMaxFlow::in_source_segment: call max_flow() first");
    RESTITCH_ASSERT(i >= 0 && i < node_count(), "PushRelabelMaxFlow::in_source_segment: node id out of range");
    return (segment_[static_cast<std::size_t>(i)] & kSourceSide) != 0;
  }

  /// Whether node i reaches the sink in the residual graph. Valid after max_flow().
  bool in_sink_segment(int i) const {
    RESTITCH_ASSERT(solved_ && sink_segment, "PushRelabelMaxFlow::in_sink_segment: call max_flow() first, with sink_segment on");
    RESTITCH_ASSERT(i >= 0 && i < node_count(), "PushRelabelMaxFlow::in_sink_segment: node id out of range");
    return (segment_[static_cast<std::size_t>(i)] & kSinkSide) != 0;
  }

 private:
  static constexpr unsigned char kSourceSide = 1, kSinkSide = 2;
  struct Edge {
    int i, j;
    Cap cap, rev_cap;
  };
  struct Arc {
    int head;    // the node this arc points to
    int sister;  // the reverse arc
    Cap r_cap;   // residual capacity
  };

  // Arcs grouped by tail node (within a node in add_edge order), at the original capacities.
  void build_arcs() {
    detail::lay_out_arcs(terminal_.size(), edges_, first_, current_, arcs_, [](const Edge&, int, int) {});
  }

  // Exact labels: residual distance to the target (through `terminal`, the residual of each node's arc to
  // it: label 1 when > 0; at most n), n + 1 for a node that cannot reach it. Resets the current arcs.
  void global_relabel(const std::vector<Cap>& terminal) {
    const int n = node_count() + 1;  // the label of a node that cannot reach the target
    label_.assign(terminal_.size(), n);
    queue_.clear();
    for (std::size_t v = 0; v < terminal_.size(); ++v)
      if (terminal[v] > 0) {
        label_[v] = 1;
        queue_.push_back(static_cast<int>(v));
      }
    for (std::size_t k = 0; k < queue_.size(); ++k) {
      const int w = queue_[k];
      const int d = label_[static_cast<std::size_t>(w)] + 1;
      for (int a = first_[static_cast<std::size_t>(w)]; a < first_[static_cast<std::size_t>(w) + 1]; ++a) {
        const Arc& arc = arcs_[static_cast<std::size_t>(a)];  // w -> u; u reaches w through the sister arc
        if (label_[static_cast<std::size_t>(arc.head)] == n && arcs_[static_cast<std::size_t>(arc.sister)].r_cap > 0) {
          label_[static_cast<std::size_t>(arc.head)] = d;
          queue_.push_back(arc.head);
        }
      }
    }
    std::copy(first_.begin(), first_.end() - 1, current_.begin());
  }

  // Discharges every node with excess until none can move its excess closer to the target whose per-node
  // arc residuals are `terminal`; what reaches the target is added to `arrived`.
  void discharge_all(std::vector<Cap>& terminal, Cap& arrived) {
    const std::size_t nodes = terminal_.size();
    const int n = node_count() + 1;  // the label of a node that cannot reach the target
    current_.resize(nodes);
    global_relabel(terminal);
    active_.assign(nodes, 0);
    queued_.assign(nodes, 0);
    std::size_t head = 0, size = 0;
    auto push_active = [&](int v) {
      if (queued_[static_cast<std::size_t>(v)] || label_[static_cast<std::size_t>(v)] >= n) return;
      queued_[static_cast<std::size_t>(v)] = 1;
      std::size_t slot = head + size;
      if (slot >= active_.size()) slot -= active_.size();
      active_[slot] = v;
      ++size;
    };
    for (std::size_t v = 0; v < nodes; ++v)
      if (excess_[v] > 0) push_active(static_cast<int>(v));
    const long long relabel_budget = 6LL * n + static_cast<long long>(arcs_.size());
    long long work = 0;
    while (size > 0) {
      const int v = active_[head];
      if (++head == active_.size()) head = 0;
      --size;
      const std::size_t vi = static_cast<std::size_t>(v);
      queued_[vi] = 0;
      Cap& ex = excess_[vi];
      while (ex > 0 && label_[vi] < n) {
        if (terminal[vi] > 0) {  // its label is 1: straight to the target
          const Cap f = std::min(ex, terminal[vi]);
          terminal[vi] -= f;
          ex -= f;
          arrived += f;
          continue;
        }
        const int end = first_[vi + 1];
        const int want = label_[vi] - 1;
        int a = current_[vi];
        for (; a < end; ++a) {
          Arc& arc = arcs_[static_cast<std::size_t>(a)];
          if (arc.r_cap <= 0 || label_[static_cast<std::size_t>(arc.head)] != want) continue;
          const Cap f = std::min(ex, arc.r_cap);
          arc.r_cap -= f;
          arcs_[static_cast<std::size_t>(arc.sister)].r_cap += f;
          ex -= f;
          excess_[static_cast<std::size_t>(arc.head)] += f;
          push_active(arc.head);
          if (ex <= 0) break;
        }
        current_[vi] = a < end ? a : end;
        if (ex <= 0) break;
        // Relabel: one more than the lowest residual neighbour (n = node count + 1: cannot reach the target).
        int lowest = n;
        for (int b = first_[vi]; b < end; ++b) {
          const Arc& arc = arcs_[static_cast<std::size_t>(b)];
          if (arc.r_cap > 0) lowest = std::min(lowest, label_[static_cast<std::size_t>(arc.head)] + 1);
        }
        label_[vi] = std::min(lowest, n);
        current_[vi] = first_[vi];
        work += 12 + (end - first_[vi]);
      }
      if (work > relabel_budget && size > 0) {
        work = 0;
        global_relabel(terminal);
        // Keep the queue's order; drop the nodes that cannot reach the target.
        std::size_t kept = 0;
        for (std::size_t k = 0; k < size; ++k) {
          std::size_t slot = head + k;
          if (slot >= active_.size()) slot -= active_.size();
          const int w = active_[slot];
          if (label_[static_cast<std::size_t>(w)] < n) {
            std::size_t to = head + kept;
            if (to >= active_.size()) to -= active_.size();
            active_[to] = w;
            ++kept;
          } else {
            queued_[static_cast<std::size_t>(w)] = 0;
          }
        }
        size = kept;
      }
    }
  }

  // The two segments. Source side: a forward search from the source's residual arcs. Sink side: the nodes
  // global relabelling towards the sink finds a residual path from (its backward search).
  void mark_segments() {
    const std::size_t n = terminal_.size();
    segment_.assign(n, 0);
    queue_.clear();
    for (std::size_t v = 0; v < n; ++v)
      if (on_source_[v] < terminal_[v]) {
        segment_[v] = kSourceSide;
        queue_.push_back(static_cast<int>(v));
      }
    for (std::size_t k = 0; k < queue_.size(); ++k) {
      const std::size_t w = static_cast<std::size_t>(queue_[k]);
      for (int a = first_[w]; a < first_[w + 1]; ++a) {
        const Arc& arc = arcs_[static_cast<std::size_t>(a)];
        const std::size_t u = static_cast<std::size_t>(arc.head);
        if (segment_[u] || !(arc.r_cap > 0)) continue;
        segment_[u] = kSourceSide;
        queue_.push_back(static_cast<int>(u));
      }
    }
    if (!sink_segment) return;
    global_relabel(to_sink_);
    for (std::size_t v = 0; v < n; ++v)
      if (label_[v] <= node_count()) segment_[v] |= kSinkSide;
  }

  std::vector<Cap> terminal_;  // per node: > 0 capacity from the source, < 0 to the sink (net)
  std::vector<Edge> edges_;    // in the order of add_edge
  std::vector<int> first_;     // arcs of node i: first_[i] .. first_[i+1]-1
  std::vector<Arc> arcs_;
  std::vector<Cap> excess_, to_sink_, on_source_;  // on_source_: flow on the source arc (returnable)
  std::vector<int> label_, current_, queue_, active_;
  std::vector<char> queued_;
  std::vector<unsigned char> segment_;
  Cap direct_flow_ = 0, flow_ = 0;
  bool solved_ = false;
};

}  // namespace restitch
