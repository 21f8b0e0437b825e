// restitch/offsets/snap.hpp - snapping an offset onto the mesh's own vertices.
//
// ICP on Poisson-disk samples (refine.hpp) finds an offset to a fraction of
// the sample spacing. A resize by k steps moves the far end by k times the
// offset, so its error grows k-fold; man-made models are usually built by
// copying, and then their *vertices* repeat exactly. `snap_offset` refines t
// by translation-only ICP of the mesh vertices onto themselves: pair every
// vertex v with the nearest vertex w to v + t within a radius r, set t to the
// mean of (w - v) over the pairs, and halve r, from `start_radius` down to
// `end_radius`. For exactly repeated geometry the pairs are exact copies and t
// becomes exact to float precision. Hand-placed repeats whose copies differ by
// more than `end_radius` lose their pairs as the radius shrinks, and keep the
// sample-based offset (below).
//
// The result is kept only when it is supported: at least `min_pairs` pairs
// and `min_share` of the vertices at the final radius (the share a repeat
// of two copies already reaches is 1/2 of the repeated part; 5% leaves room
// for models whose repeated part is small). Otherwise the input t is returned
// unchanged and `snapped` is false: the model's repeat is not a copy of
// vertices (different tessellations), and the sample-based offset stands.
//
// All lengths are in the units of the points given (the analysis passes
// normalized coordinates). Then one step of the tessellation away is tried
// (the vertices left unpaired vote for a shift; see snap_offset). Above
// `max_queries` vertices (65,536) only an even stride of that many look for
// partners (pairs and shares count those); all are partners. Cost: O(#V) to
// build the grid, then O(min(#V, max_queries)) hash-grid look-ups per
// iteration (27 cells per vertex at the first radius, 1 to 8 from the second
// on), 10 iterations at the defaults, plus, when some vertices stay unpaired,
// one voting pass (27 cells of a coarser grid) and 3 more iterations.
// Deterministic.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "restitch/detail/cell_hash.hpp"

namespace restitch {

struct SnapOptions {
  double start_radius = 0.02;  ///< the dense sample spacing: ICP's result is within it
  double end_radius = 2e-5;    ///< about 100 float ulps of a normalized coordinate
  std::size_t min_pairs = 8;
  double min_share = 0.05;
  /// At most this many vertices look for a partner (an even stride of the points, in their order; every
  /// point can be a partner); 0: all. Exact pairs fix the offset to float precision whatever their number,
  /// and on a 1M-triangle mesh (500k vertices) one snap took 1.5 s. Below the bound nothing changes; above
  /// it min_pairs counts among the queries, so a repeat of fewer than about min_pairs x #points /
  /// max_queries copied vertices (60 of 500k) no longer snaps.
  std::size_t max_queries = 65536;
};

struct SnapResult {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  bool snapped = false;
  std::size_t pairs = 0;  ///< vertex pairs at the final radius (among the querying vertices, SnapOptions::max_queries)
};

/// Refines `t` so that `points` + t lands on `points` (see the header comment).
/// `points`: #P by 3, unique positions.
template <class = void>
SnapResult snap_offset(const Eigen::Matrix<double, Eigen::Dynamic, 3>& points, const Eigen::Vector3d& t,
                              const SnapOptions& options = {}) {
  SnapResult result;
  result.offset = t;
  const Eigen::Index n = points.rows();
  if (n == 0 || !t.allFinite()) return result;
  // The vertices that look for partners: all, or an even stride of max_queries of them.
  const Eigen::Index m =
      options.max_queries > 0 && std::size_t(n) > options.max_queries ? Eigen::Index(options.max_queries) : n;
  auto query = [n, m](Eigen::Index k) { return m == n ? k : Eigen::Index((std::uint64_t(k) * std::uint64_t(n)) / std::uint64_t(m)); };
  // Hash grid with cells of start_radius: a query at radius r <= start_radius looks at 27 cells.
  const double h = options.start_radius;
  auto cell = [h](const Eigen::Vector3d& p) {  // saturated: a finite but huge offset must not overflow
    return detail::Cell{detail::cell_index(p.x(), h), detail::cell_index(p.y(), h), detail::cell_index(p.z(), h)};
  };
  detail::CellChains grid{std::size_t(n)};
  for (Eigen::Index i = 0; i < n; ++i) grid.insert(cell(points.row(i).transpose()), std::int32_t(i));

  // The vertex nearest to q within r (ties: the lower index), or -1, in a grid `g` of cells `cell_of` makes.
  // It looks at the cells the ball of radius r around q touches (r widened by 1e-9 against rounding): 27 at r
  // = the cell size, one to eight once r is below half of it.
  auto nearest_in = [&](const detail::CellChains& g, const auto& cell_of, const Eigen::Vector3d& q, double r) {
    double best = r * r;
    Eigen::Index hit = -1;
    const double reach = r * (1 + 1e-9);
    const detail::Cell lo = cell_of((q.array() - reach).matrix()), hi = cell_of((q.array() + reach).matrix());
    g.for_each_in(lo, hi, [&](std::int32_t j) {
      const double d2 = (points.row(j).transpose() - q).squaredNorm();
      if (d2 < best || (d2 == best && hit >= 0 && j < hit)) best = d2, hit = j;
    });
    return hit;
  };
  auto nearest = [&](const Eigen::Vector3d& q, double r) { return nearest_in(grid, cell, q, r); };
  // Translation-only ICP of the vertices from `cur`, radius halving from r0 down to end_radius: the
  // offset and its pairs at the last radius (0 pairs when some radius had fewer than min_pairs).
  auto descend = [&](Eigen::Vector3d cur, double r0) {
    std::size_t pairs = 0;
    for (double r = r0; r >= options.end_radius * 0.999; r *= 0.5) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      pairs = 0;
      for (Eigen::Index k = 0; k < m; ++k) {
        const Eigen::Index i = query(k);
        const Eigen::Index hit = nearest(points.row(i).transpose() + cur, r);
        if (hit >= 0) sum += points.row(hit).transpose() - points.row(i).transpose(), ++pairs;
      }
      if (pairs < options.min_pairs) return std::make_pair(cur, std::size_t(0));
      cur = sum / double(pairs);
    }
    return std::make_pair(cur, pairs);
  };

  auto [cur, pairs] = descend(t, options.start_radius);
  if (pairs < options.min_pairs) return result;
  // A step of the tessellation away. Where copies lie on uniformly tessellated parts (a board meshed every
  // 0.025 along its depth), the offset one tessellation step off the true one still maps those parts'
  // vertices exactly, and the descent stays there: ICP's start was within a sample spacing of both. The
  // true offset maps every copied vertex, so it maps more. So, once: the vertices left unpaired at the
  // last radius vote, each with the vector from its image to the nearest vertex within twice the start
  // radius (binned at twice the end radius); the descent runs again from the most voted shift, from the
  // radius 2^-7 of the start one (so it ends at the same last radius as the first descent and the pair
  // counts compare), and replaces the offset when it ends with more pairs and within twice the start
  // radius of t. Cost: one pass over the vertices with a query in a grid of cells that wide (27 cells),
  // and three more descent passes when some vertices voted.
  double last = options.start_radius;
  while (last * 0.5 >= options.end_radius * 0.999) last *= 0.5;
  const double wide = 2 * options.start_radius, bin = 2 * options.end_radius;
  if (pairs < std::size_t(m)) {
    auto wide_cell = [wide](const Eigen::Vector3d& p) {
      return detail::Cell{detail::cell_index(p.x(), wide), detail::cell_index(p.y(), wide),
                          detail::cell_index(p.z(), wide)};
    };
    detail::CellChains coarse{std::size_t(n)};
    for (Eigen::Index i = 0; i < n; ++i) coarse.insert(wide_cell(points.row(i).transpose()), std::int32_t(i));
    std::map<detail::Cell, std::pair<std::size_t, Eigen::Vector3d>> votes;
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Vector3d q = points.row(query(k)).transpose() + cur;
      if (nearest(q, last) >= 0) continue;
      const Eigen::Index hit = nearest_in(coarse, wide_cell, q, wide);
      if (hit < 0) continue;
      const Eigen::Vector3d r = points.row(hit).transpose() - q;
      auto& v = votes[detail::Cell{detail::cell_index(r.x(), bin), detail::cell_index(r.y(), bin),
                                    detail::cell_index(r.z(), bin)}];
      if (v.first == 0) v.second = Eigen::Vector3d::Zero();
      ++v.first;
      v.second += r;
    }
    const std::pair<std::size_t, Eigen::Vector3d>* top = nullptr;  // most votes; map order breaks ties
    for (const auto& kv : votes)
      if (!top || kv.second.first > top->first) top = &kv.second;
    if (top && top->first >= options.min_pairs) {
      const auto [alt, alt_pairs] = descend(cur + top->second / double(top->first), last * 4);
      if (alt_pairs > pairs && (alt - t).norm() <= wide) cur = alt, pairs = alt_pairs;
    }
  }
  if (pairs < options.min_pairs || double(pairs) < options.min_share * double(m)) return result;
  result.offset = cur;
  result.snapped = true;
  result.pairs = pairs;
  return result;
}

/// How closely the copies of a repeat coincide, measured on the vertices (the weld tolerance a resize
/// needs to join them; Retargeter, docs/method.md 3, "Measured weld tolerance").
struct RepeatPrecision {
  /// The weld tolerance the measure gives, relative to `diagonal`: `base` when the copies' vertices pair
  /// within it (exact copies) or pair at no rung, else twice the rung by which they all paired.
  double tolerance = 0;
  /// Per offset: the share of the querying points whose nearest point to p + t lies within base * 2^k
  /// of the diagonal, k = 0 .. RepeatPrecisionOptions::rungs - 1.
  std::vector<std::vector<double>> shares;
};

struct RepeatPrecisionOptions {
  int rungs = 7;          ///< radii base, 2 base, ..., 64 base: the tolerance is at most 64 base (6.4e-5 at 1e-6)
  double agree = 0.95;    ///< a rung holds the pairs when its share is at least this fraction of the next one's
  double min_share = 0.05;  ///< as SnapOptions::min_share: fewer pairs are no repeat's copies
  /// At most this many points look for a partner (an even stride; all are partners). The shares are
  /// estimates: with 16,384 queries a share's standard error is under 0.4%, well inside the 5% the
  /// rung test allows, and the measure stays under about 0.1 s at a million triangles.
  std::size_t max_queries = 16384;
  /// The measure gives up (the base stays) after this many candidate points looked at per query and
  /// offset on average: where many vertices crowd into one cell (a tiny detailed part in a huge box)
  /// the grid no longer bounds the work, and the measure is an improvement, not a requirement.
  double max_visits_per_query = 256;
};

/// Measures how precisely `points` (#P by 3; a position given twice counts twice) repeat at each of
/// `offsets` (same units):
/// the share of points with a point within r of p + t, for r = base * 2^k * diagonal. The copies of a
/// repeat pair up at their precision and the share then stops growing; so the first rung k whose share
/// reaches min_share and holds `agree` of the next rung's is where the pairs are complete. k = 0: the
/// copies are exact at `base`, which stays; k >= 1: the tolerance is base * 2^(k+1), one rung of margin
/// (the pairs the next rung still adds, at most 1 - agree of them, are joined too); no such k below the
/// last rung: the vertices do not repeat within the largest radius (different tessellations, hand-placed
/// copies), and `base` stays. The result is the largest over the offsets. Cost: O(#P) to build a grid of
/// cells twice the largest radius, then at most 8 cells per query and offset. Deterministic.
template <class = void>
RepeatPrecision repeat_precision(const Eigen::Matrix<double, Eigen::Dynamic, 3>& points,
                                        const std::vector<Eigen::Vector3d>& offsets, double diagonal, double base,
                                        const RepeatPrecisionOptions& options = {}) {
  RepeatPrecision result;
  result.tolerance = base;
  const Eigen::Index n = points.rows();
  const int rungs = std::max(options.rungs, 2);
  const double r_max = base * std::ldexp(1.0, rungs - 1) * diagonal;
  if (n == 0 || !(r_max > 0) || !std::isfinite(r_max)) return result;
  const Eigen::Index m =
      options.max_queries > 0 && std::size_t(n) > options.max_queries ? Eigen::Index(options.max_queries) : n;
  auto query = [n, m](Eigen::Index k) { return m == n ? k : Eigen::Index((std::uint64_t(k) * std::uint64_t(n)) / std::uint64_t(m)); };
  const double h = 2 * r_max;  // a ball of radius r_max touches at most 2 cells per axis
  auto cell = [h](const Eigen::Vector3d& p) {
    return detail::Cell{detail::cell_index(p.x(), h), detail::cell_index(p.y(), h), detail::cell_index(p.z(), h)};
  };
  detail::CellChains grid{std::size_t(n)};
  for (Eigen::Index i = 0; i < n; ++i) grid.insert(cell(points.row(i).transpose()), std::int32_t(i));
  const double visit_budget = options.max_visits_per_query * double(m) * double(offsets.size());
  double visits = 0;
  std::vector<std::vector<double>> shares;
  double tolerance = base;
  for (const Eigen::Vector3d& t : offsets) {
    if (!t.allFinite()) continue;
    std::vector<std::size_t> within(std::size_t(rungs), 0);  // points whose nearest lies within rung k
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Vector3d q = points.row(query(k)).transpose() + t;
      double best = r_max * r_max;
      bool hit = false;
      const detail::Cell lo = cell((q.array() - r_max).matrix()), hi = cell((q.array() + r_max).matrix());
      grid.for_each_in(lo, hi, [&](std::int32_t j) {
        const double d2 = (points.row(j).transpose() - q).squaredNorm();
        if (d2 <= best) best = d2, hit = true;
        ++visits;
      });
      if (visits > visit_budget) return result;  // gave up: the base, no shares
      if (!hit) continue;
      const double d = std::sqrt(best);
      for (int r = rungs - 1; r >= 0 && d <= base * std::ldexp(1.0, r) * diagonal; --r) ++within[std::size_t(r)];
    }
    std::vector<double> share(static_cast<std::size_t>(rungs));
    for (int r = 0; r < rungs; ++r) share[std::size_t(r)] = double(within[std::size_t(r)]) / double(m);
    for (int r = 0; r + 1 < rungs; ++r)
      if (share[std::size_t(r)] >= options.min_share && share[std::size_t(r)] >= options.agree * share[std::size_t(r) + 1]) {
        if (r > 0) tolerance = std::max(tolerance, base * std::ldexp(1.0, r + 1));
        break;
      }
    shares.push_back(std::move(share));
  }
  result.tolerance = tolerance;
  result.shares = std::move(shares);
  return result;
}

/// The shifts along direction `t` shorter than |t| at which vertices repeat: vertices on one line parallel
/// to t (their position across t in one grid cell 4 `radius` wide: a line that straddles a cell boundary
/// loses some pairs, which a proposal can afford) and their differences along it, gathered within
/// 2 `radius`, most pairs first; at most `count` of them, each with at least `min_pairs` pairs and at least
/// `min_length` long. Proposals for docs/method.md 1.12 (a slat pitch no whole division of a run with its
/// rail reaches), which tests each on the exact surface. Pairs are counted up to `max_pairs` in all (lines
/// in the order of their cells), so that a mesh of long straight runs of vertices costs
/// O(#V log #V + max_pairs log max_pairs). Deterministic.
template <class = void>
std::vector<Eigen::Vector3d> vertex_lags(const Eigen::Matrix<double, Eigen::Dynamic, 3>& points, const Eigen::Vector3d& t,
                                         double radius, double min_length, std::size_t min_pairs, std::size_t count,
                                         std::size_t max_pairs = std::size_t(1) << 22) {
  std::vector<Eigen::Vector3d> out;
  const double len = t.norm();
  if (!(len > 0) || !(radius > 0) || points.rows() < 2) return out;
  const Eigen::Vector3d d = t / len;
  const Eigen::Vector3d u = d.unitOrthogonal(), w = d.cross(u);
  const double h = 4 * radius;
  struct Key {
    std::int64_t a, b;
    double along;
    bool operator<(const Key& o) const { return a != o.a ? a < o.a : b != o.b ? b < o.b : along < o.along; }
  };
  std::vector<Key> keys;
  keys.reserve(std::size_t(points.rows()));
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Vector3d p = points.row(i).transpose();
    keys.push_back({detail::cell_index(p.dot(u), h), detail::cell_index(p.dot(w), h), p.dot(d)});
  }
  std::sort(keys.begin(), keys.end());
  std::vector<double> lags;
  for (std::size_t i = 0; i < keys.size() && lags.size() < max_pairs; ++i)
    for (std::size_t j = i + 1; j < keys.size() && keys[j].a == keys[i].a && keys[j].b == keys[i].b; ++j) {
      const double lag = keys[j].along - keys[i].along;
      if (lag >= len - radius) break;
      if (lag >= min_length) lags.push_back(lag);
    }
  std::sort(lags.begin(), lags.end());
  std::vector<std::pair<std::size_t, double>> groups;  // (pairs, mean lag)
  for (std::size_t i = 0; i < lags.size();) {
    std::size_t j = i;
    double sum = 0;
    while (j < lags.size() && lags[j] - lags[i] <= 2 * radius) sum += lags[j++];
    if (j - i >= min_pairs) groups.push_back({j - i, sum / double(j - i)});
    i = j;
  }
  std::stable_sort(groups.begin(), groups.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  for (std::size_t g = 0; g < groups.size() && out.size() < count; ++g) out.push_back(groups[g].second * d);
  return out;
}

}  // namespace restitch
