// restitch/matcher/brute_force.hpp - the exact reference matcher (docs/method.md 1.3).
//
// BruteForceMatcher implements the matcher contract of matcher/matcher.hpp
// (read it for the exact answer) by looking at every pair:
//   1. Squared descriptor distances in float, |a|^2 + |b|^2 - 2 a.b, one
//      block x block Eigen matrix product at a time. The distance is
//      symmetric, so only blocks J >= I are computed and each pair serves
//      both features.
//   2. Per feature, every admissible target whose approximate distance could
//      still tie with the best one is kept as a candidate. "Could" uses a
//      rigorous float error bound E = 2 (4 gamma_D + 16 u) max|S|^2
//      (u = 2^-24, gamma_D = D u / (1 - D u)), so nothing is lost.
//   3. The candidates' distances are recomputed exactly (double) and the tie
//      rule picks the match. The result does not depend on the block order.
//
// Also here (detail): the shared machinery of exact matchers: input checks
// and compaction, the exact distance, the final tie-rule choice and the
// symmetric blocked pair scan.
//
// Cost: #F^2 D flops in float matrix products (half of the full product),
// plus O(#F^2) cheap comparisons and O(D) per candidate. Memory
// O(#F D + block^2 + candidates). Measured (g++ -O2, x86-64 default SSE2,
// one core of a shared machine, CPU time, synthetic unit descriptors):
// 10k x 352 in 1.3-1.5 s, 25k x 352 in 7.6-8.1 s. ReducedMatcher
// (matcher/reduced.hpp) gives the same answer 3x faster.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/detail/parallel.hpp"
#include "restitch/matcher/matcher.hpp"
#include "restitch/progress.hpp"
#include "restitch/status.hpp"

namespace restitch {

namespace detail {

using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// sum_k (double(a_k) - double(b_k))^2 in k order: the contract's distance, squared.
template <class = void>
double exact_squared_distance(const float* a, const float* b, Eigen::Index d) {
  double s = 0;
  for (Eigen::Index k = 0; k < d; ++k) {
    const double t = static_cast<double>(a[k]) - static_cast<double>(b[k]);
    s += t * t;
  }
  return s;
}

/// The features that take part (finite position and descriptor), compacted.
/// Compact index c corresponds to feature ids[c]; ids is increasing.
struct MatchProblem {
  std::vector<std::int32_t> ids;
  std::vector<Eigen::Vector3d> position;
  RowMatrixXf descriptor;  ///< compact rows
  double tau2 = 0;

  std::size_t size() const { return ids.size(); }
  /// dx^2 + dy^2 + dz^2 in this order (the contract's formula, independent of vectorization).
  template <class = void>
  double offset_squared(std::size_t i, std::size_t j) const {
    const double dx = position[j].x() - position[i].x(), dy = position[j].y() - position[i].y(),
                 dz = position[j].z() - position[i].z();
    return dx * dx + dy * dy + dz * dz;
  }
  bool admissible(std::size_t i, std::size_t j) const { return offset_squared(i, j) > tau2; }
};

/// Checks the input, sizes `out` (all unmatched) and builds the compact problem.
template <class = void>
Status prepare_matching(const PointSet& features, const DescriptorMatrix& descriptors, float tau,
                               std::vector<Match>& out, MatchProblem& p) {
  const Eigen::Index n = features.points.rows();
  if (descriptors.rows() != n)
    return error(StatusCode::invalid_argument, "the descriptor matrix has " + std::to_string(descriptors.rows()) +
                                                   " rows for " + std::to_string(n) + " features");
  if (n > 0 && descriptors.cols() == 0)
    return error(StatusCode::invalid_argument, "the descriptors have no values (0 columns)");
  if (!(tau >= 0) || !std::isfinite(tau))
    return error(StatusCode::invalid_argument, "the minimum offset tau must be a finite number >= 0");
  if (n > std::numeric_limits<std::int32_t>::max())
    return error(StatusCode::too_large, "more than 2^31 - 1 features cannot be matched");
  out.assign(static_cast<std::size_t>(n), Match{});
  p.ids.clear(), p.position.clear();
  for (Eigen::Index i = 0; i < n; ++i)
    if (features.points.row(i).allFinite() && descriptors.row(i).allFinite()) {
      p.ids.push_back(static_cast<std::int32_t>(i));
      p.position.push_back(features.points.row(i).transpose().cast<double>());
    }
  p.descriptor.resize(static_cast<Eigen::Index>(p.ids.size()), descriptors.cols());
  for (std::size_t c = 0; c < p.ids.size(); ++c)
    p.descriptor.row(static_cast<Eigen::Index>(c)) = descriptors.row(p.ids[c]);
  p.tau2 = static_cast<double>(tau) * static_cast<double>(tau);
  return {};
}

/// Applies the tie rule to the candidates of compact feature i (a superset of
/// its tie set, all admissible) and writes the match. Candidates may repeat.
template <class = void>
void choose_match(const MatchProblem& p, std::size_t i, const std::vector<std::int32_t>& candidates,
                         const TieRule& ties, std::vector<double>& scratch, std::vector<Match>& out) {
  if (candidates.empty()) return;
  const Eigen::Index d = p.descriptor.cols();
  scratch.resize(candidates.size());
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    scratch[k] = std::sqrt(exact_squared_distance(p.descriptor.row(static_cast<Eigen::Index>(i)).data(),
                                                  p.descriptor.row(candidates[k]).data(), d));
    best = std::min(best, scratch[k]);
  }
  std::int32_t pick = -1;
  double pick_offset = 0, pick_distance = 0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (!ties.ties(scratch[k], best)) continue;
    const std::int32_t j = candidates[k];
    const double off = p.offset_squared(i, static_cast<std::size_t>(j));
    if (pick < 0 || off < pick_offset || (off == pick_offset && j < pick))
      pick = j, pick_offset = off, pick_distance = scratch[k];
  }
  out[static_cast<std::size_t>(p.ids[i])] =
      Match{p.ids[static_cast<std::size_t>(pick)], static_cast<float>(pick_distance)};
}

/// Rigorous bound on |float(|a|^2 + |b|^2 - 2 a.b) - |a - b|^2| for rows of
/// dimension `dim` whose squared norms are at most `max_sq` (the float products
/// and norms, plus the three float operations combining them, with a factor
/// 2 to spare).
template <class = void>
double float_distance_error(Eigen::Index dim, double max_sq) {
  const double u = 0x1.0p-24;
  const double du = static_cast<double>(dim) * u;
  const double gamma = du / (1.0 - du);
  return 2.0 * (4.0 * gamma + 16.0 * u) * max_sq + 1e-30;
}

/// A float >= x (rounding up), for thresholds compared against float values.
template <class = void>
float float_at_least(double x) {
  if (!(x < static_cast<double>(std::numeric_limits<float>::max()))) return std::numeric_limits<float>::infinity();
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

/// The float threshold of the tie set: with b the best float squared distance of a feature, its
/// true best d* <= sqrt(b + err), and a target can tie only if its float squared distance is at
/// most upper(sqrt(b + err))^2 + err (err: float_distance_error of the descriptors' rows).
struct FloatTieBound {
  double err = 0;
  TieRule ties;
  template <class = void>
  float operator()(float b) const {
    const double u = std::sqrt(std::max(0.0, double(b) + err));
    const double t = ties.upper(u);
    return float_at_least(t * t + err);
  }
};

/// The largest squared norm of the descriptor rows (double), for float_distance_error.
template <class = void>
double max_squared_norm(const RowMatrixXf& d) {
  double max_sq = 0;
  for (Eigen::Index r = 0; r < d.rows(); ++r) max_sq = std::max(max_sq, d.row(r).cast<double>().squaredNorm());
  return max_sq;
}

/// Visits every admissible ordered pair (i, j), i != j, of the rows of `emb`
/// whose float squared distance d2 = |e_i|^2 + |e_j|^2 - 2 e_i.e_j satisfies
/// d2 <= state.threshold[i], calling state.offer(i, j, d2). Blocks J >= I only,
/// so each product serves both (i, j) and (j, i). One state per worker
/// (detail/parallel.hpp; `states.size()` workers, each row block I a task):
/// a state has `std::vector<float> threshold` (one per row, which its offer
/// may lower at any time) and `offer`; worker w only touches states[w], so
/// the caller merges them after (each pair is offered to exactly one state;
/// the float d2 of a pair does not depend on the worker). Reports progress in
/// [lo, hi] of "matching".
template <class State>
Status scan_pairs(const MatchProblem& p, const RowMatrixXf& emb, std::vector<State>& states,
                  const Progress& progress, double lo, double hi) {
  const Eigen::Index n = emb.rows();
  const Eigen::Index block = 512;
  const Eigen::VectorXf sq = emb.rowwise().squaredNorm();
  std::vector<RowMatrixXf> products(states.size());
  const std::size_t blocks = std::size_t((n + block - 1) / block);
  const double total_blocks = double(blocks) * double(blocks + 1) / 2;
  const auto row_block = [&](std::size_t task, int worker) {
    State& state = states[std::size_t(worker)];
    RowMatrixXf& g = products[std::size_t(worker)];
    float* threshold = state.threshold.data();
    const Eigen::Index I = Eigen::Index(task) * block, bi = std::min(block, n - I);
    for (Eigen::Index J = I; J < n; J += block) {
      const Eigen::Index bj = std::min(block, n - J);
      g.noalias() = emb.middleRows(I, bi) * emb.middleRows(J, bj).transpose();
      for (Eigen::Index a = 0; a < bi; ++a) {
        const std::size_t i = static_cast<std::size_t>(I + a);
        const float si = sq[I + a];
        const float* row = g.row(a).data();
        const float* sqj = sq.data() + J;
        float* thj = threshold + J;
        for (Eigen::Index b = (I == J ? a + 1 : 0); b < bj; ++b) {
          const float d2 = si + sqj[b] - 2.0f * row[b];
          const bool fi = d2 <= threshold[i], fj = d2 <= thj[b];
          if (!(fi || fj)) continue;
          const std::size_t j = static_cast<std::size_t>(J + b);
          if (!p.admissible(i, j)) continue;
          if (fi) state.offer(i, j, d2);
          if (fj) state.offer(j, i, d2);
        }
      }
    }
  };
  // Blocks done after the first `t` row blocks: row block k holds blocks - k blocks.
  const auto tick = [&](std::size_t t) {
    const double done = double(t) * double(blocks) - double(t) * double(t - 1) / 2;
    return progress.report("matching", lo + (hi - lo) * std::min(1.0, done / total_blocks));
  };
  if (!parallel_tasks(int(states.size()), blocks, row_block, tick))
    return error(StatusCode::cancelled, "cancelled while matching features");
  return {};
}

}  // namespace detail

namespace detail {
/// Brute force on a prepared problem (prepare_matching; `out` sized by it, at least 2 features):
/// the symmetric blocked scan on `threads` workers, then the exact re-ranking. Reports "matching"
/// progress in [0, 0.95] during the scan. ReducedMatcher calls it where brute force is faster.
template <class = void>
Status match_all_pairs(const MatchProblem& p, const TieRule& ties, int threads, std::vector<Match>& out,
                              const Progress& progress) {
  const std::size_t n = p.size();
  // Best float distance b seen: a target can tie only under bound(b) (FloatTieBound).
  const FloatTieBound bound{float_distance_error(p.descriptor.cols(), max_squared_norm(p.descriptor)), ties};

  // One state per worker (scan_pairs): its best float distance, threshold and candidates per feature.
  struct State {
    const FloatTieBound* bound;
    std::vector<float> threshold, best;
    std::vector<std::vector<std::pair<std::int32_t, float>>> cand;
    std::vector<std::uint32_t> prune_at;
    State(const FloatTieBound& b, std::size_t rows)
        : bound(&b),
          threshold(rows, std::numeric_limits<float>::infinity()),
          best(rows, std::numeric_limits<float>::infinity()),
          cand(rows),
          prune_at(rows, 32) {}
    void offer(std::size_t i, std::size_t j, float d2) {
      auto& c = cand[i];
      c.emplace_back(static_cast<std::int32_t>(j), d2);
      if (d2 < best[i]) best[i] = d2, threshold[i] = (*bound)(d2);
      if (c.size() >= prune_at[i]) {
        const float t = threshold[i];
        c.erase(std::remove_if(c.begin(), c.end(),
                               [t](const std::pair<std::int32_t, float>& e) { return e.second > t; }),
                c.end());
        prune_at[i] = static_cast<std::uint32_t>(std::max<std::size_t>(32, 2 * c.size()));
      }
    }
  };
  std::vector<State> states(std::size_t(resolve_threads(threads)), State(bound, n));
  RESTITCH_TRY(scan_pairs(p, p.descriptor, states, progress, 0.0, 0.95));

  // Merged: the threshold of the best float distance over all workers. A worker pruned only
  // above its own threshold, never below this one, so every candidate under it is still held.
  std::vector<std::int32_t> ids;
  std::vector<double> scratch;
  for (std::size_t i = 0; i < n; ++i) {
    float b = std::numeric_limits<float>::infinity();
    for (const State& st : states) b = std::min(b, st.best[i]);
    const float t = b < std::numeric_limits<float>::infinity() ? bound(b) : b;
    ids.clear();
    for (const State& st : states)
      for (const auto& e : st.cand[i])
        if (e.second <= t) ids.push_back(e.first);
    choose_match(p, i, ids, ties, scratch, out);
  }
  return {};
}
}  // namespace detail

/// The exact reference matcher (see the top of this header and matcher.hpp).
struct BruteForceMatcher {
  TieRule ties;
  /// Workers for the pair scan (detail/parallel.hpp; 0: every hardware thread). The matches are
  /// the same whatever the number.
  int threads = 1;

  template <class = void>
  Status match(const PointSet& features, const DescriptorMatrix& descriptors, float tau, std::vector<Match>& out,
               const Progress& progress = {}) const {
    return detail::guarded("BruteForceMatcher::match", [&]() -> Status {
      detail::MatchProblem p;
      RESTITCH_TRY(detail::prepare_matching(features, descriptors, tau, out, p));
      if (!progress.report("matching", 0.0)) return error(StatusCode::cancelled, "cancelled while matching features");
      if (p.size() < 2) return progress.report("matching", 1.0) ? Status() : error(StatusCode::cancelled, "cancelled");
      RESTITCH_TRY(detail::match_all_pairs(p, ties, threads, out, progress));
      if (!progress.report("matching", 1.0)) return error(StatusCode::cancelled, "cancelled while matching features");
      return {};
    });
  }
};

}  // namespace restitch
