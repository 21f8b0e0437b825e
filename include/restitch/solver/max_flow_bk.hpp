// restitch/solver/max_flow_bk.hpp - the max-flow back-end contract and a
// Boykov-Kolmogorov max-flow written for restitch.
//
// Alpha-expansion (restitch/solver/alpha_expansion.hpp) reduces every
// expansion move to a minimum s-t cut. The max-flow algorithm behind it is a
// policy; any type that satisfies this contract can be plugged in:
//
//   struct MyMaxFlow {
//     using capacity_type = Cap;  // a signed arithmetic type (double, int64_t)
//     // Forgets every node and edge; keeps the memory it has (a back end is
//     // reset once per expansion move). The hints are the expected sizes.
//     void reset(int node_count_hint, int edge_count_hint);
//     // Appends n nodes (ids are 0, 1, 2, ... in order of creation) and
//     // returns the id of the first one.
//     int add_node(int n = 1);
//     // ADDS cap_source to the capacity of the edge source -> i and cap_sink
//     // to that of i -> sink. Both >= 0.
//     void add_tweights(int i, Cap cap_source, Cap cap_sink);
//     // Adds the edges i -> j (capacity cap) and j -> i (capacity rev_cap).
//     // Both >= 0, i != j. Parallel edges are allowed.
//     void add_edge(int i, int j, Cap cap, Cap rev_cap);
//     // Computes a maximum flow and returns its value.
//     Cap max_flow();
//     // After max_flow(): whether node i is on the source side of THE
//     // minimum cut whose source side is smallest, i.e. whether i can be
//     // reached from the source through edges with residual capacity left.
//     // Every minimum cut puts those nodes on the source side; a node that
//     // could go either way is therefore reported on the SINK side. The
//     // answer does not depend on the algorithm (nor on the order in which
//     // paths were found), so two back ends give identical segmentations.
//     bool in_source_segment(int i) const;
//   };
//
// `is_max_flow_v<T>` checks the contract at compile time; AlphaExpansion
// static_asserts it with a readable message.
//
// BkMaxFlow<Cap> is the algorithm of Y. Boykov and V. Kolmogorov, "An
// experimental comparison of min-cut/max-flow algorithms for energy
// minimization in vision", PAMI 26(9), 2004: two search trees, one grown from
// the source and one from the sink, alternate a growth stage (active nodes
// claim free neighbours until the trees touch), an augmentation stage (push
// the bottleneck along the s-t path found; saturated tree edges leave orphans)
// and an adoption stage (each orphan looks for a new parent in its own tree
// whose root is a terminal, choosing the one closest to the terminal, with the
// paper's time stamp / distance marks; an orphan with none becomes free and
// its children become orphans). During growth a node of the same tree that
// is farther from the terminal is re-hung under the scanning node (keeps paths
// short; the stamp/distance order rules out cycles). Active nodes and orphans
// are processed first in, first out; the orphans an augmentation leaves are
// adopted nearest-to-the-terminal first (their descendants then find them
// valid), and an orphan stops looking once it finds a root as parent.
// Terminal edges are folded into one signed residual per node (positive: to
// the source, negative: to the sink): the flow that could go
// source -> i -> sink directly is counted at once. Before the trees are grown,
// max_flow() pushes flow along every path source -> i -> j -> sink (one pass
// over the edges in add_edge order): on expansion graphs this does most of the
// short augmentations at a fraction of their cost (measured 1.2-2.3x faster
// solves). Edges are recorded by add_edge and laid out grouped by tail node
// (compressed rows) when max_flow() starts, so every scan of a node's arcs
// reads consecutive memory.
//
// Contract of BkMaxFlow beyond the above:
//   * max_flow() may be called again after more add_* calls; it continues from
//     the current flow. in_source_segment() is valid after max_flow() and until
//     the next add_* or reset().
//   * No recursion (every walk is a loop), no threads, no randomness: the same
//     calls give the same flow and the same cut, bit for bit.
//   * Capacities: Cap is a signed arithmetic type. With an integer Cap the sum
//     of all capacities must fit in Cap (no overflow check). With a floating
//     Cap every capacity must be finite; the result is exact when all
//     capacities and partial sums are exactly representable (integers below
//     2^53); otherwise rounding may leave tiny residuals (no loop: every
//     augmentation saturates at least one edge exactly).
//   * Memory: about 28 + sizeof(Cap) bytes per node and 32 + 4 sizeof(Cap)
//     per add_edge call (the call's record and its two arcs), kept across
//     reset(). Laying out the arcs costs O(V + E) per max_flow() call that
//     follows add_* calls.
//   * Cost: O(V E^2 |C|) in the worst case (as the paper); near linear on the
//     grid-like graphs of an expansion move.
#pragma once

#include <algorithm>
#include <climits>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/status.hpp"

namespace restitch {

namespace detail {
template <class T, class = void>
struct is_max_flow : std::false_type {};
template <class T>
struct is_max_flow<
    T, std::void_t<typename T::capacity_type, decltype(std::declval<T&>().reset(0, 0)),
                   decltype(std::declval<T&>().add_node(1)),
                   decltype(std::declval<T&>().add_tweights(0, std::declval<typename T::capacity_type>(),
                                                            std::declval<typename T::capacity_type>())),
                   decltype(std::declval<T&>().add_edge(0, 0, std::declval<typename T::capacity_type>(),
                                                        std::declval<typename T::capacity_type>())),
                   decltype(std::declval<T&>().max_flow()), decltype(std::declval<const T&>().in_source_segment(0))>>
    : std::bool_constant<std::is_arithmetic_v<typename T::capacity_type> &&
                         std::is_signed_v<typename T::capacity_type> &&
                         std::is_convertible_v<decltype(std::declval<T&>().add_node(1)), int> &&
                         std::is_convertible_v<decltype(std::declval<T&>().max_flow()), typename T::capacity_type> &&
                         std::is_convertible_v<decltype(std::declval<const T&>().in_source_segment(0)), bool>> {};
}  // namespace detail

/// True when T satisfies the max-flow back-end contract above.
template <class T>
inline constexpr bool is_max_flow_v = detail::is_max_flow<T>::value;

namespace detail {
template <class T, class = void>
struct has_sink_segment : std::false_type {};
template <class T>
struct has_sink_segment<T, std::void_t<decltype(std::declval<const T&>().in_sink_segment(0))>> : std::true_type {};
}  // namespace detail

/// True when the back end also reports the sink side (optional: `bool in_sink_segment(int) const`, whether
/// node i reaches the sink in the residual graph); AlphaExpansion::ties_to_alpha needs it.
template <class T>
inline constexpr bool has_sink_segment_v = detail::has_sink_segment<T>::value;

namespace detail {

/// Adds terminal capacities to a node's signed residual `r` (> 0: from the source, < 0: to the sink) and
/// returns what can flow source -> node -> sink directly, which a back end counts as flow at once.
template <class Cap>
Cap fold_terminal(Cap& r, Cap cap_source, Cap cap_sink) {
  if (r > 0)
    cap_source += r;
  else
    cap_sink -= r;
  r = cap_source - cap_sink;
  return std::min(cap_source, cap_sink);
}

/// Lays the two arcs of every edge out grouped by tail node (a counting sort; within a node in edge
/// order): node i's arcs are arcs[first[i]] .. arcs[first[i + 1] - 1], each {head, sister, residual}
/// starting at the edge's cap (i -> j) or rev_cap (j -> i). `placed(edge, arc_ij, arc_ji)` is told where
/// each edge's arcs went. `cursor` is scratch. Cost O(n + E).
template <class Edge, class Arc, class Placed>
void lay_out_arcs(std::size_t n, std::vector<Edge>& edges, std::vector<int>& first, std::vector<int>& cursor,
                  std::vector<Arc>& arcs, Placed&& placed) {
  first.assign(n + 1, 0);
  for (const Edge& e : edges) {
    ++first[static_cast<std::size_t>(e.i) + 1];
    ++first[static_cast<std::size_t>(e.j) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  arcs.resize(2 * edges.size());
  cursor.assign(first.begin(), first.end() - 1);
  for (Edge& e : edges) {
    const int a = cursor[static_cast<std::size_t>(e.i)]++;
    const int b = cursor[static_cast<std::size_t>(e.j)]++;
    arcs[static_cast<std::size_t>(a)] = Arc{e.j, b, e.cap};
    arcs[static_cast<std::size_t>(b)] = Arc{e.i, a, e.rev_cap};
    placed(e, a, b);
  }
}

}  // namespace detail

/// Boykov-Kolmogorov max-flow / min-cut. See the top of this file.
template <class Cap = double>
class BkMaxFlow {
  static_assert(std::is_arithmetic_v<Cap> && std::is_signed_v<Cap>,
                "BkMaxFlow<Cap>: Cap must be a signed arithmetic type such as double or std::int64_t");

 public:
  using capacity_type = Cap;

  BkMaxFlow() = default;
  BkMaxFlow(int node_count_hint, int edge_count_hint) { reset(node_count_hint, edge_count_hint); }

  /// Forgets all nodes and edges, keeps the allocated memory. Cost O(1) plus
  /// growing the reserve to the hints.
  void reset(int node_count_hint = 0, int edge_count_hint = 0) {
    nodes_.clear();
    edges_.clear();
    arcs_.clear();
    orphans_.clear();
    if (node_count_hint > 0) {
      nodes_.reserve(static_cast<std::size_t>(node_count_hint));
      first_.reserve(static_cast<std::size_t>(node_count_hint) + 1);
      active_.reserve(static_cast<std::size_t>(node_count_hint));
    }
    if (edge_count_hint > 0) {
      edges_.reserve(static_cast<std::size_t>(edge_count_hint));
      arcs_.reserve(2 * static_cast<std::size_t>(edge_count_hint));
    }
    flow_ = 0;
    solved_ = false;
    built_ = false;
  }

  /// Appends n >= 0 nodes; returns the id of the first. Cost O(n).
  int add_node(int n = 1) {
    RESTITCH_ASSERT(n >= 0, "BkMaxFlow::add_node: n must be >= 0");
    const int first = node_count();
    nodes_.resize(nodes_.size() + static_cast<std::size_t>(n));
    solved_ = false;
    built_ = false;
    return first;
  }

  int node_count() const { return static_cast<int>(nodes_.size()); }
  /// Number of add_edge calls since reset().
  int edge_count() const { return static_cast<int>(edges_.size()); }

  /// Adds to the terminal capacities of node i. Cost O(1).
  void add_tweights(int i, Cap cap_source, Cap cap_sink) {
    RESTITCH_ASSERT(i >= 0 && i < node_count(), "BkMaxFlow::add_tweights: node id out of range");
    RESTITCH_ASSERT(cap_source >= 0 && cap_sink >= 0, "BkMaxFlow::add_tweights: capacities must be >= 0");
    // The node keeps only the residual difference; what could flow
    // source -> i -> sink directly is counted as flow now.
    flow_ += detail::fold_terminal(nodes_[i].terminal_cap, cap_source, cap_sink);
    solved_ = false;
  }

  /// Adds the edges i -> j (cap) and j -> i (rev_cap). Cost O(1) amortised.
  void add_edge(int i, int j, Cap cap, Cap rev_cap) {
    RESTITCH_ASSERT(i >= 0 && i < node_count() && j >= 0 && j < node_count(),
                    "BkMaxFlow::add_edge: node id out of range");
    RESTITCH_ASSERT(i != j, "BkMaxFlow::add_edge: an edge needs two different nodes");
    RESTITCH_ASSERT(cap >= 0 && rev_cap >= 0, "BkMaxFlow::add_edge: capacities must be >= 0");
    edges_.push_back(Edge{i, j, -1, -1, cap, rev_cap});
    solved_ = false;
    built_ = false;
  }

  /// Computes a maximum flow; returns its value (including the flow counted
  /// by add_tweights). Cost: see the top of this file.
  Cap max_flow() {
    build_arcs();
    push_short_paths();
    start_trees();
    int current = -1;  // the active node being scanned; kept across augmentations
    for (;;) {
      int p = current;
      if (p < 0 || nodes_[p].parent == kFree) {
        p = pop_active();
        if (p < 0) break;
      }
      const int bridge = grow(p);
      if (bridge < 0) {
        current = -1;  // p has no residual edge out of its tree: it is passive now
        continue;
      }
      current = p;
      augment(bridge);
      adopt_orphans();
    }
    solved_ = true;
    return flow_;
  }

  /// Whether node i is reachable from the source in the residual graph
  /// (see the contract above). Valid after max_flow(). Cost O(1).
  bool in_source_segment(int i) const {
    RESTITCH_ASSERT(solved_, "BkMaxFlow::in_source_segment: call max_flow() first");
    RESTITCH_ASSERT(i >= 0 && i < node_count(), "BkMaxFlow::in_source_segment: node id out of range");
    return nodes_[i].parent != kFree && !nodes_[i].in_sink_tree;
  }

  /// Whether node i reaches the sink in the residual graph: on the sink side of every minimum cut
  /// (the nodes in neither segment could go either way). Valid after max_flow(). Cost O(1).
  bool in_sink_segment(int i) const {
    RESTITCH_ASSERT(solved_, "BkMaxFlow::in_sink_segment: call max_flow() first");
    RESTITCH_ASSERT(i >= 0 && i < node_count(), "BkMaxFlow::in_sink_segment: node id out of range");
    return nodes_[i].parent != kFree && nodes_[i].in_sink_tree;
  }

  /// The flow value so far.
  Cap flow() const { return flow_; }

 private:
  // Values of Node::parent that are not arc ids.
  static constexpr int kFree = -1;      // in no tree
  static constexpr int kTerminal = -2;  // a root: its parent is the source (or sink)
  static constexpr int kOrphan = -3;    // lost its parent; adoption pending

  // One add_edge call. arc_ij / arc_ji locate its two arcs once built.
  struct Edge {
    int i, j;
    int arc_ij, arc_ji;
    Cap cap, rev_cap;  // original capacities; residuals after a rebuild
  };
  // Arcs are stored grouped by tail node (arcs of node i are
  // first_[i] .. first_[i+1]-1), so scans read memory in order.
  struct Arc {
    int head;    // the node this arc points to
    int sister;  // the reverse arc
    Cap r_cap;   // residual capacity
  };
  struct Node {
    int parent = kFree;    // arc from this node to its parent, or kFree / kTerminal / kOrphan
    int parent_node = -1;  // head of `parent` when it is an arc (saves a load on tree walks)
    int stamp = 0;         // the adoption stage in which `distance` was last made exact
    int distance = 0;      // number of edges to the terminal (an estimate unless stamp is current)
    bool in_sink_tree = false;
    bool queued = false;   // in the active queue
    Cap terminal_cap = 0;  // > 0: residual source -> node; < 0: residual node -> sink
  };

  // Lays the arcs out grouped by tail node (counting sort; within a node in
  // the order of the add_edge calls). Residuals of a previous max_flow()
  // carry over. Cost O(V + E).
  void build_arcs() {
    if (built_) return;
    const int n = node_count();
    if (!arcs_.empty())  // continuing: keep the residuals of the current flow
      for (Edge& e : edges_)
        if (e.arc_ij >= 0) {
          e.cap = arcs_[static_cast<std::size_t>(e.arc_ij)].r_cap;
          e.rev_cap = arcs_[static_cast<std::size_t>(e.arc_ji)].r_cap;
        }
    detail::lay_out_arcs(static_cast<std::size_t>(n), edges_, first_, cursor_, arcs_, [](Edge& e, int a, int b) {
      e.arc_ij = a;
      e.arc_ji = b;
    });
    built_ = true;
  }

  // Before the search: pushes flow along every path source -> i -> j -> sink
  // (edges in the order of add_edge, then the reverse arcs). Cheap, and it
  // removes most of the short augmenting paths the trees would find one by
  // one. Cost O(E).
  void push_short_paths() {
    for (Edge& e : edges_) {
      Node& ni = nodes_[static_cast<std::size_t>(e.i)];
      Node& nj = nodes_[static_cast<std::size_t>(e.j)];
      if (ni.terminal_cap > 0 && nj.terminal_cap < 0)
        push_pair(ni, nj, e.arc_ij);
      else if (nj.terminal_cap > 0 && ni.terminal_cap < 0)
        push_pair(nj, ni, e.arc_ji);
    }
  }
  void push_pair(Node& from, Node& to, int arc) {
    Arc& a = arcs_[static_cast<std::size_t>(arc)];
    const Cap f = std::min(std::min(from.terminal_cap, static_cast<Cap>(-to.terminal_cap)), a.r_cap);
    if (f <= 0) return;
    a.r_cap -= f;
    arcs_[static_cast<std::size_t>(a.sister)].r_cap += f;
    from.terminal_cap -= f;
    to.terminal_cap += f;
    flow_ += f;
  }

  // Residual capacity of the tree edge between a node and its parent, in the
  // direction flow goes (parent -> node in the source tree, node -> parent in
  // the sink tree). `arc` is the node's parent arc (node -> parent).
  Cap tree_cap(const Node& n, int arc) const {
    return n.in_sink_tree ? arcs_[arc].r_cap : arcs_[arcs_[arc].sister].r_cap;
  }

  void push_active(int i) {
    Node& n = nodes_[i];
    if (n.queued) return;
    n.queued = true;
    // Each node is queued at most once, so the ring never holds more than
    // node_count() entries.
    std::size_t slot = active_head_ + active_size_;
    if (slot >= active_.size()) slot -= active_.size();
    active_[slot] = i;
    ++active_size_;
  }

  int pop_active() {
    while (active_size_ > 0) {
      const int i = active_[active_head_];
      if (++active_head_ == active_.size()) active_head_ = 0;
      --active_size_;
      nodes_[i].queued = false;
      if (nodes_[i].parent != kFree) return i;  // skip nodes that became free while queued
    }
    return -1;
  }

  // Every node with terminal capacity starts as a root of its tree and active.
  void start_trees() {
    active_.assign(nodes_.size(), 0);
    active_head_ = 0;
    active_size_ = 0;
    orphans_.clear();
    stage_ = 0;
    for (int i = 0; i < node_count(); ++i) {
      Node& n = nodes_[i];
      n.stamp = 0;
      n.queued = false;
      if (n.terminal_cap != 0) {
        n.parent = kTerminal;
        n.in_sink_tree = n.terminal_cap < 0;
        n.distance = 1;
        push_active(i);
      } else {
        n.parent = kFree;
        n.in_sink_tree = false;
        n.distance = 0;
      }
    }
  }

  // Growth stage for the active node p: claims every free neighbour reachable
  // through a residual edge in the tree's direction. Returns the arc
  // (source-tree node -> sink-tree node) where the trees touch, or -1.
  int grow(int p) {
    Node& np = nodes_[p];
    const bool sink = np.in_sink_tree;
    const int end = first_[p + 1];
    for (int a = first_[p]; a < end; ++a) {
      const Arc& arc = arcs_[a];
      // Source tree grows along p -> q; sink tree along q -> p.
      if ((sink ? arcs_[arc.sister].r_cap : arc.r_cap) <= 0) continue;
      const int q = arc.head;
      Node& nq = nodes_[q];
      if (nq.parent == kFree) {
        nq.parent = arc.sister;  // q -> p
        nq.parent_node = p;
        nq.in_sink_tree = sink;
        nq.stamp = np.stamp;
        nq.distance = np.distance + 1;
        push_active(q);
      } else if (nq.in_sink_tree != sink) {
        return sink ? arc.sister : a;
      } else if (nq.stamp <= np.stamp && nq.distance > np.distance) {
        // Same tree, and p is closer to the terminal: hang q under p to keep
        // paths short. No cycle: along any tree path towards the root the
        // pair (stamp, -distance) never decreases, so q cannot be an
        // ancestor of p.
        nq.parent = arc.sister;
        nq.parent_node = p;
        nq.stamp = np.stamp;
        nq.distance = np.distance + 1;
      }
    }
    return -1;
  }

  void make_orphan(int i) {
    nodes_[i].parent = kOrphan;
    orphans_.push_back(i);
  }

  // Pushes the bottleneck along source -> ... -> tail(bridge) -> head(bridge)
  // -> ... -> sink. Saturated tree edges leave orphans.
  void augment(int bridge) {
    const int v = arcs_[bridge].head;                // in the sink tree
    const int u = arcs_[arcs_[bridge].sister].head;  // in the source tree
    Cap f = arcs_[bridge].r_cap;
    for (int x = u;;) {
      const Node& n = nodes_[x];
      if (n.parent == kTerminal) {
        f = std::min(f, n.terminal_cap);
        break;
      }
      f = std::min(f, arcs_[arcs_[n.parent].sister].r_cap);
      x = n.parent_node;
    }
    for (int x = v;;) {
      const Node& n = nodes_[x];
      if (n.parent == kTerminal) {
        f = std::min(f, static_cast<Cap>(-n.terminal_cap));
        break;
      }
      f = std::min(f, arcs_[n.parent].r_cap);
      x = n.parent_node;
    }

    arcs_[bridge].r_cap -= f;
    arcs_[arcs_[bridge].sister].r_cap += f;
    for (int x = u;;) {
      Node& n = nodes_[x];
      if (n.parent == kTerminal) {
        n.terminal_cap -= f;
        if (n.terminal_cap <= 0) make_orphan(x);
        break;
      }
      Arc& up = arcs_[n.parent];  // x -> parent
      Arc& down = arcs_[up.sister];
      down.r_cap -= f;
      up.r_cap += f;
      const int next = up.head;
      if (down.r_cap <= 0) make_orphan(x);
      x = next;
    }
    const std::size_t sink_side = orphans_.size();
    for (int x = v;;) {
      Node& n = nodes_[x];
      if (n.parent == kTerminal) {
        n.terminal_cap += f;
        if (n.terminal_cap >= 0) make_orphan(x);
        break;
      }
      Arc& up = arcs_[n.parent];  // x -> parent
      up.r_cap -= f;
      arcs_[up.sister].r_cap += f;
      const int next = up.head;
      if (up.r_cap <= 0) make_orphan(x);
      x = next;
    }
    flow_ += f;
    // Orphans were found walking away from the bridge; adopt those nearest
    // their terminal first, so that their descendants find them valid.
    std::reverse(orphans_.begin() + static_cast<std::ptrdiff_t>(sink_side), orphans_.end());
    std::reverse(orphans_.begin(), orphans_.begin() + static_cast<std::ptrdiff_t>(sink_side));
  }

  // Adoption stage: FIFO over the orphans (new ones are appended).
  void adopt_orphans() {
    ++stage_;
    for (std::size_t k = 0; k < orphans_.size(); ++k) adopt(orphans_[k]);
    orphans_.clear();
  }

  void adopt(int p) {
    const bool sink = nodes_[p].in_sink_tree;
    int best_arc = -1;
    int best_distance = INT_MAX;
    const int end = first_[p + 1];
    for (int a = first_[p]; a < end; ++a) {
      const Arc& arc = arcs_[a];
      // q may become p's parent if the tree edge q -> p (source tree) or
      // p -> q (sink tree) has residual capacity.
      if ((sink ? arc.r_cap : arcs_[arc.sister].r_cap) <= 0) continue;
      const int q = arc.head;
      if (nodes_[q].parent == kFree || nodes_[q].in_sink_tree != sink) continue;
      // Walk up from q: does its path end at a terminal (valid) or at an
      // orphan (invalid)? Nodes already checked in this stage carry an
      // exact distance and end the walk early.
      int steps = 0;
      int j = q;
      bool valid = false;
      int d = 0;
      for (;;) {
        Node& nj = nodes_[j];
        if (nj.stamp == stage_) {
          d = steps + nj.distance;
          valid = true;
          break;
        }
        if (nj.parent == kTerminal) {
          nj.stamp = stage_;
          nj.distance = 1;
          d = steps + 1;
          valid = true;
          break;
        }
        if (nj.parent < 0) break;  // kOrphan (a free node cannot lie on a tree path)
        ++steps;
        j = nj.parent_node;
      }
      if (!valid) continue;
      if (d < best_distance) {
        best_distance = d;
        best_arc = a;
      }
      // Mark the walked path with exact distances.
      for (int k = q, dk = d; nodes_[k].stamp != stage_; k = nodes_[k].parent_node, --dk) {
        nodes_[k].stamp = stage_;
        nodes_[k].distance = dk;
      }
      if (best_distance == 1) break;  // a root: no parent can be closer
    }

    Node& np = nodes_[p];
    if (best_arc >= 0) {
      np.parent = best_arc;
      np.parent_node = arcs_[best_arc].head;
      np.stamp = stage_;
      np.distance = best_distance + 1;
      return;
    }
    // No valid parent: p becomes free. Neighbours in the same tree that could
    // grow into p again become active; its children become orphans.
    np.parent = kFree;
    for (int a = first_[p]; a < end; ++a) {
      const Arc& arc = arcs_[a];
      const int q = arc.head;
      Node& nq = nodes_[q];
      if (nq.parent == kFree || nq.in_sink_tree != sink) continue;
      if ((sink ? arc.r_cap : arcs_[arc.sister].r_cap) > 0) push_active(q);
      if (nq.parent >= 0 && nq.parent_node == p) make_orphan(q);
    }
  }

  std::vector<Node> nodes_;
  std::vector<Edge> edges_;  // in the order of add_edge
  std::vector<int> first_;   // arcs of node i: first_[i] .. first_[i+1]-1
  std::vector<int> cursor_;  // scratch of build_arcs
  std::vector<Arc> arcs_;
  std::vector<int> active_;  // ring buffer of active nodes, FIFO
  std::size_t active_head_ = 0;
  std::size_t active_size_ = 0;
  std::vector<int> orphans_;
  int stage_ = 0;  // number of adoption stages so far (time stamp)
  Cap flow_ = 0;
  bool solved_ = false;
  bool built_ = false;  // arcs_ reflects every add_edge call
};

}  // namespace restitch
