// restitch/energy/seam_geometry.hpp - a seam cost measured on the geometry at the seam (docs/method.md 2.4b).
//
// CellSlabs compares the input surface around one face (or edge, or corner)
// of two input cells, translated onto each other: the "slab" of cell c toward
// direction e (each component -1, 0 or 1, not all 0) is the part of c within
// `half_width` (model units) of its face on every axis where e is non-zero.
// Points are the analysis' dense Poisson-disk samples (Analysis::dense), taken
// relative to their cell's corner, so two cells that hold the same geometry
// hold the same relative points up to sampling.
//
//   mismatch(c1, c2, e) = max( h(Q1 -> R2), h(Q2 -> R1) )        model units
//
// where Qi are the samples in the slab of ci toward e (at most `max_queries`,
// an even stride of them), Ri the samples around that slab (the slab widened
// by `half_width` on every side, across the face too), and h(Q -> R) the
// largest distance from a point of Q to its nearest point of R. Two slabs of
// the same geometry cost at most about one sample spacing (Poisson-disk
// samples of a surface lie within a spacing of each other), a slab against a
// copy of itself shifted by s costs s (when s is below the slab's width).
// Cells are clamped as in the stitcher: geometry outside the input grid
// belongs to the end cell, so an end cell's slab toward the outside includes
// its overhang. A cell outside the input grid is empty. Both slabs empty: 0;
// one slab with samples and nothing around the other (R empty): the constant
// `empty_mismatch` = 1000 x the cell diagonal, larger than any distance
// between two points of two neighbouring cells, so a missing surface outweighs
// any misplaced one.
//
// Half-width: 2 x the sample spacing s (the median nearest-neighbour distance
// of the dense samples, model units). A slab must hold at least one layer of
// samples of a surface crossing the face at a slant (width >= s) and its
// neighbourhood must contain the counterpart of every sample (a further s):
// narrower misses surfaces, wider compares geometry that the seam does not
// touch. It is capped at half a cell.
//
// Caching: mismatches are computed once per (cell pair, direction) for the
// life of the object; slabs are gathered on first use. Cost of a new pair:
// O(max_queries x |R|) flops (|R| the samples around a slab).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nanoflann.hpp>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/detail/point_tree.hpp"
#include "restitch/detail/triangle_surface.hpp"
#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"

namespace restitch {

/// Which pairwise term the labelling problem uses (docs/method.md 2.4, 2.4b).
enum class SeamEnergy {
  geometry,   ///< the surfaces at the seam compared (CellSlabs), model units
  descriptor  ///< the paper's: descriptor sets of whole cells compared (CellDescriptors); the default
};

inline const char* seam_energy_name(SeamEnergy e) { return e == SeamEnergy::geometry ? "geometry" : "descriptor"; }
/// "geometry" or "descriptor"; false for anything else (`out` untouched).
template <class = void>
bool parse_seam_energy(const std::string& name, SeamEnergy& out) {
  if (name == "geometry") return out = SeamEnergy::geometry, true;
  if (name == "descriptor") return out = SeamEnergy::descriptor, true;
  return false;
}

namespace detail {

/// The median distance from a point of `P` to its nearest other point (an even stride of at most 4000
/// points asks); 0 with fewer than two points. Cost O(n log n).
template <class = void>
double median_nearest_distance(const MatrixX3f& P) {
  const Eigen::Index n = P.rows();
  if (n < 2) return 0.0;
  using Tree = PointSetTree;
  PointSetAdaptor adaptor{&P};
  Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  const Eigen::Index m = std::min<Eigen::Index>(n, 4000);
  std::vector<double> d;
  d.reserve(std::size_t(m));
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = k * n / m;
    const float q[3] = {P(i, 0), P(i, 1), P(i, 2)};
    std::uint32_t idx[2];
    float d2[2];
    const std::size_t found = tree.knnSearch(q, 2, idx, d2);
    if (found == 2) d.push_back(std::sqrt(double(d2[1])));
  }
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(d.size() / 2), d.end());
  return d[d.size() / 2];
}
}  // namespace detail

/// Dense samples grouped by cell, with cached slab mismatches (see the file comment).
class CellSlabs {
 public:
  /// Query points per slab at most (an even stride of them): bounds the cost of a new pair.
  static constexpr std::size_t max_queries = 256;

  CellSlabs() = default;

  /// Groups the dense samples of `analysis` by the cells of `grid` (model units). `spacing` (model units):
  /// the sample spacing; 0 estimates it (median nearest-neighbour distance of the samples).
  template <class = void>
  CellSlabs(const Analysis& analysis, const Lattice& grid, double spacing = 0)
      : grid_(grid.cells), A_(grid.A), origin_(grid.origin) {
    Ainv_ = A_.inverse();
    const MatrixX3f& P = analysis.dense.points;
    if (!(spacing > 0))
      spacing = detail::median_nearest_distance(P) / (analysis.normalization.scale > 0 ? analysis.normalization.scale : 1);
    double diagonal = 0;
    for (int a = 0; a < 3; ++a) diagonal += A_.col(a).norm();
    if (!(spacing > 0)) spacing = 1e-3 * diagonal;
    spacing_ = spacing;
    half_width_ = 2 * spacing_;
    empty_mismatch_ = 1000.0 * diagonal;
    for (int a = 0; a < 3; ++a) {
      const double per_unit = Ainv_.row(a).norm();  // canonical units per model unit across the planes of a
      width_[a] = std::min(0.5, half_width_ * per_unit);
      margin_[a] = std::min(1.0, half_width_ * per_unit);
    }
    members_.assign(std::size_t(grid_.size()), {});
    points_.resize(std::size_t(P.rows()));
    canonical_.resize(std::size_t(P.rows()));
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      const Eigen::Vector3d p = analysis.normalization.to_model(P.row(i).cast<double>().transpose());
      if (!p.allFinite()) continue;
      points_[std::size_t(i)] = p;
      canonical_[std::size_t(i)] = Ainv_ * (p - origin_);
      members_[std::size_t(grid_.index(grid_.cell_of(canonical_[std::size_t(i)])))].push_back(int(i));
    }
    slabs_.assign(std::size_t(grid_.size()) * 27, {});
  }

  const CellGrid& grid() const { return grid_; }
  /// The sample spacing and the slab half-width (2 x spacing), model units.
  double spacing() const { return spacing_; }
  double half_width() const { return half_width_; }
  /// The input's surface, against which seam_positions tests continuation exactly: a sample moved to the
  /// other copy is continued when it lies within `tolerance` (model units) of the surface, the gap the
  /// stitcher closes (its zipper's, restitch/stitch/detail/zipper.hpp). Without it, the samples' 1.5
  /// spacings. `mesh` must outlive this; its surface is built on first use.
  void set_surface(const Mesh& mesh, double tolerance) {
    surface_mesh_ = &mesh;
    surface_tolerance_ = tolerance;
    surface_.reset();
    positions_cache_.clear();
    along_cache_.clear();
  }

  /// The cost of samples in one slab against nothing around the other (model units).
  double empty_mismatch() const { return empty_mismatch_; }
  /// Samples in the slab of inside cell c toward e (after the stride cap), and around it.
  template <class = void>
  std::size_t queries(const Eigen::Array3i& c, const Eigen::Array3i& e) { return slab(c, e).q.size(); }
  template <class = void>
  std::size_t around(const Eigen::Array3i& c, const Eigen::Array3i& e) { return slab(c, e).r.size(); }

  /// The mismatch of input cells c1 and c2 (either may lie outside the grid) around their face, edge or
  /// corner toward e (model units; cached). Symmetric in c1, c2.
  template <class = void>
  double mismatch(const Eigen::Array3i& c1, const Eigen::Array3i& c2, const Eigen::Array3i& e) {
    if ((c1 == c2).all()) return 0.0;
    const bool in1 = grid_.inside(c1), in2 = grid_.inside(c2);
    if (!in1 && !in2) return 0.0;
    if (!in1 || !in2) return slab(in1 ? c1 : c2, e).q.empty() ? 0.0 : empty_mismatch_;
    int a = grid_.index(c1), b = grid_.index(c2);
    if (a > b) std::swap(a, b);
    const std::uint64_t key = ((std::uint64_t(std::uint32_t(a)) << 32 | std::uint32_t(b)) * 27) + direction(e);
    auto it = cache_.find(key);
    if (it != cache_.end()) return it->second;
    const double d = compare(slab(grid_.cell(a), e), slab(grid_.cell(b), e));
    cache_.emplace(key, d);
    return d;
  }
  std::size_t cached_pairs() const { return cache_.size(); }

  /// The mismatch of input cells c1 and c2 (either may lie outside the grid, as for mismatch) at the plane
  /// at relative canonical
  /// position f (0 <= f <= 1) of axis a: the seam of an end cap (restitch/stitch/stitch.hpp), at the
  /// end plane (Lattice::end_low / end_high; the cell plane 0 or 1, or inside the cell), or of two
  /// neighbours (the seam report, retarget.hpp). The smaller of the two sides: the slabs just below the
  /// plane compared, and those just above it (when either side agrees, the geometry crosses the cut
  /// unbroken). A slab is the space within the half-width of the plane, relative to the cell: past a
  /// cell plane it holds the next cell's samples, or an end cell's overhang (not the whole overhang:
  /// the slab is not widened to infinity along a). Pairs of inside cells are cached (per cell pair,
  /// axis and f), as mismatch is: the live slider asks for the same seams again.
  /// `cut_axis` (another axis, or -1 for none): only the part of the plane with relative canonical
  /// coordinate in [cut_lo, cut_hi) along it, as given: an end cell's overhang along cut_axis counts only
  /// where the range reaches past 0 or 1 (-INFINITY, INFINITY). The seam report's parts of a face on an
  /// output end, where an end cap holds one part and the labels' own copies another (retarget.hpp).
  template <class = void>
  double plane_mismatch(const Eigen::Array3i& c1, const Eigen::Array3i& c2, int a, double f, int cut_axis = -1,
                        double cut_lo = 0.0, double cut_hi = 1.0) {
    if ((c1 == c2).all()) return 0.0;
    const bool in1 = grid_.inside(c1), in2 = grid_.inside(c2);
    if (!in1 && !in2) return 0.0;
    const auto restrict_cut = [&](double lo[3], double hi[3]) {
      if (cut_axis >= 0 && cut_axis != a) lo[cut_axis] = cut_lo, hi[cut_axis] = cut_hi;
    };
    if (!in1 || !in2) {  // an empty cell against samples at the plane: a missing surface
      double lo[3], hi[3];
      for (int b = 0; b < 3; ++b) lo[b] = 0.0, hi[b] = 1.0;
      restrict_cut(lo, hi);
      lo[a] = f - width_[a];
      hi[a] = f + width_[a];
      Slab s;
      fill_slab(s, in1 ? c1 : c2, lo, hi, a, cut_axis);
      return s.q.empty() ? 0.0 : empty_mismatch_;
    }
    const int i1 = grid_.index(c1), i2 = grid_.index(c2);
    const auto key = std::make_tuple(std::min(i1, i2), std::max(i1, i2), a, f, cut_axis, cut_lo, cut_hi);
    const auto hit = plane_cache_.find(key);
    if (hit != plane_cache_.end()) return hit->second;
    double side[2];
    for (int k = 0; k < 2; ++k) {
      double lo[3], hi[3];
      for (int b = 0; b < 3; ++b) lo[b] = 0.0, hi[b] = 1.0;
      restrict_cut(lo, hi);
      lo[a] = k == 0 ? f - width_[a] : f;
      hi[a] = k == 0 ? f : f + width_[a];
      Slab s1, s2;
      fill_slab(s1, c1, lo, hi, a, cut_axis);
      fill_slab(s2, c2, lo, hi, a, cut_axis);
      side[k] = compare(s1, s2);
    }
    const double d = std::min(side[0], side[1]);
    plane_cache_.emplace(key, d);
    return d;
  }

  /// Where a seam can lie (docs/method.md 2.9): output cells x and y = x + e_a copied with shifts di and
  /// dj, given as the input cell s = x - di and the shift difference delta = dj - di. Candidate planes
  /// t_j = 1 + j / K along a, in cells from x's lower plane, j = -J .. J with J = K / 2 - 1 (K >= 4).
  /// Near a cut at t the result holds x's copy below t and y's from t on. A sample of the input that
  /// lands within one sample spacing below t from x's copy, or from t on from y's, is *continued* when,
  /// moved by the shift difference (toward the other copy's source), it lies within the stitcher's gap of
  /// the input's surface (set_surface): the other copy has surface there too, close enough for the seam
  /// to close. Without a surface set: when the input has a sample within 1.5 spacings of it (the match
  /// distance of the end planes' periodic part, lattice/fit.hpp). fail[j + J] counts the samples near t_j that are not
  /// continued, cut[j + J] all samples near t_j (the surface the cut crosses), changed[j + J] the samples
  /// between the cell plane and t_j, of either copy, that are not continued (what moving the cut there
  /// adds to the result or takes from it: the copy that now holds that slab has them and the other had
  /// not, or the other way round), valid[j + J] whether
  /// both copies exist there: t > 1 needs input cell y - di = s + e_a, t < 1 needs x - dj = s - delta
  /// (s and s + e_a - delta, the copies' own cells, must lie in the input, else nothing is valid).
  /// Cells are clamped as in the stitcher. Cached per (s, a, delta, K). Cost of a new one: O(n (log N
  /// + J)) for the n samples of those four cells (an AABB tree over the N input triangles with a surface
  /// set, else a k-d tree over all N samples; built on first use).
  struct SeamPositions {
    std::vector<int> fail, cut, changed;
    std::vector<char> valid;
  };
  template <class = void>
  const SeamPositions& seam_positions(const Eigen::Array3i& s, int a, const Eigen::Array3i& delta, int K) {
    const auto key = std::make_tuple(grid_.inside(s) ? grid_.index(s) : -1, a, delta[0], delta[1], delta[2], K);
    const auto hit = positions_cache_.find(key);
    if (hit != positions_cache_.end()) return hit->second;
    SeamPositions& out = positions_cache_[key];
    const int J = K / 2 - 1;
    out.fail.assign(std::size_t(2 * J + 1), 0);
    out.cut.assign(std::size_t(2 * J + 1), 0);
    out.changed.assign(std::size_t(2 * J + 1), 0);
    out.valid.assign(std::size_t(2 * J + 1), 1);
    Eigen::Array3i e = Eigen::Array3i::Zero();
    e[a] = 1;
    if (!grid_.inside(s) || !grid_.inside(s + e - delta)) {
      std::fill(out.valid.begin(), out.valid.end(), char(0));
      return out;
    }
    for (int j = -J; j <= J; ++j)
      if ((j > 0 && !grid_.inside(s + e)) || (j < 0 && !grid_.inside(s - delta))) out.valid[std::size_t(j + J)] = 0;
    const double h = spacing_ * Ainv_.row(a).norm();  // one spacing across the planes of a, in cells
    const Eigen::Vector3d move = A_ * delta.cast<double>().matrix();  // model units
    // side 0: x's copy (below the cut), from input cells s and s + e_a; its samples moved by -move must
    // meet a sample. side 1: y's copy (from the cut on), cells s - delta and s - delta + e_a; by +move.
    for (int side = 0; side < 2; ++side) {
      const Eigen::Array3i lower = side == 0 ? Eigen::Array3i(s) : Eigen::Array3i(s - delta);
      for (const Eigen::Array3i& c : {lower, Eigen::Array3i(lower + e)}) {
        if (!grid_.inside(c)) continue;
        for (const int i : members_[std::size_t(grid_.index(c))]) {
          const double w = canonical_[std::size_t(i)][a] - double(lower[a]);  // from x's lower plane
          if (w < 0.5 - h || w >= 1.5 + h) continue;
          const bool found = continued(points_[std::size_t(i)] + (side == 0 ? -move : move));
          for (int j = -J; j <= J; ++j) {
            const double t = 1.0 + double(j) / K;
            if (!found && (j < 0 ? (w >= t && w < 1.0) : (w >= 1.0 && w < t))) ++out.changed[std::size_t(j + J)];
            if (side == 0 ? (w < t - h || w >= t) : (w < t || w >= t + h)) continue;
            ++out.cut[std::size_t(j + J)];
            if (!found) ++out.fail[std::size_t(j + J)];
          }
        }
      }
    }
    return out;
  }

  /// A seam across the planes of b seen along another axis a (docs/method.md 2.9, Staircases): per K-th of
  /// input cell c along a (K entries), the samples of c within one sample spacing of its plane along b
  /// (the upper plane for toward = +1, the lower for -1) that, moved by A delta (the shift difference
  /// toward the other copy's source), are not continued (the test of seam_positions). A sample outside
  /// the cell along a counts in no part. All zero for a cell outside the grid. Cached per (c, b, toward,
  /// delta, a, K); cost of a new one: one bounded distance query per sample near the plane.
  template <class = void>
  const std::vector<int>& plane_fail_along(const Eigen::Array3i& c, int b, int toward, const Eigen::Array3i& delta,
                                           int a, int K) {
    const auto key = std::make_tuple(grid_.inside(c) ? grid_.index(c) : -1, b, toward, delta[0], delta[1], delta[2], a, K);
    const auto hit = along_cache_.find(key);
    if (hit != along_cache_.end()) return hit->second;
    std::vector<int>& out = along_cache_[key];
    out.assign(std::size_t(K), 0);
    if (!grid_.inside(c)) return out;
    const double h = spacing_ * Ainv_.row(b).norm();  // one spacing across the planes of b, in cells
    const Eigen::Vector3d move = A_ * delta.cast<double>().matrix();
    for (const int i : members_[std::size_t(grid_.index(c))]) {
      const double wb = canonical_[std::size_t(i)][b] - double(c[b]), wa = canonical_[std::size_t(i)][a] - double(c[a]);
      if (toward > 0 ? (wb < 1.0 - h || wb >= 1.0) : (wb < 0.0 || wb >= h)) continue;
      if (wa < 0.0 || wa >= 1.0) continue;
      if (!continued(points_[std::size_t(i)] + move)) ++out[std::size_t(std::min(K - 1, int(wa * K)))];
    }
    return out;
  }

  /// The index 0..26 of a direction (components -1, 0, 1; x fastest).
  template <class = void>
  static std::size_t direction(const Eigen::Array3i& e) {
    return std::size_t((e[0] + 1) + 3 * ((e[1] + 1) + 3 * (e[2] + 1)));
  }

 private:
  struct Slab {
    bool built = false;
    std::vector<Eigen::Vector3d> q, r;  // relative to the cell's corner origin + A c, model units
  };

  template <class = void>
  const Slab& slab(const Eigen::Array3i& c, const Eigen::Array3i& e) {
    Slab& s = slabs_[std::size_t(grid_.index(c)) * 27 + direction(e)];
    if (s.built) return s;
    s.built = true;
    // Slab interval per axis (relative canonical coordinate), before and after widening; end cells
    // reach to infinity outward (clamping).
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = e[a] > 0 ? 1 - width_[a] : 0.0;
      hi[a] = e[a] < 0 ? width_[a] : 1.0;
    }
    fill_slab(s, c, lo, hi);
    return s;
  }

  // The samples of cell c with relative canonical coordinates in [lo, hi) per axis (a bound at the
  // cell's own plane 0 or 1 of an end cell reaches to infinity outward: clamping), and those around
  // it (the interval widened by the margin, from c and its neighbours). Along `exact_axis` (a plane
  // slab) the interval is not clamped and may reach into the neighbours there: their samples count.
  // Along `cut_axis` it is not clamped either (plane_mismatch's cut range, as given).
  template <class = void>
  void fill_slab(Slab& s, const Eigen::Array3i& c, double lo[3], double hi[3], int exact_axis = -1,
                 int cut_axis = -1) {
    for (int a = 0; a < 3; ++a) {
      if (a == exact_axis || a == cut_axis) continue;
      if (c[a] == 0 && lo[a] == 0.0) lo[a] = -INFINITY;
      if (c[a] == grid_.dims[a] - 1 && hi[a] == 1.0) hi[a] = INFINITY;
    }
    const Eigen::Vector3d corner = origin_ + A_ * c.cast<double>().matrix();
    std::vector<int> in_slab;
    const auto gather = [&](const Eigen::Array3i& from) {
      for (const int i : members_[std::size_t(grid_.index(from))]) {
        const Eigen::Vector3d u = canonical_[std::size_t(i)] - c.cast<double>().matrix();
        bool inside = true;
        for (int a = 0; a < 3; ++a) inside = inside && u[a] >= lo[a] && u[a] < hi[a];
        if (inside) in_slab.push_back(i);
      }
    };
    gather(c);
    if (exact_axis >= 0)  // a plane slab may reach into the neighbours along its axis: their samples too
      for (const int step : {-1, 1}) {
        Eigen::Array3i nc = c;
        nc[exact_axis] += step;
        if (grid_.inside(nc)) gather(nc);
      }
    const std::size_t n = in_slab.size(), m = std::min(n, max_queries);
    for (std::size_t k = 0; k < m; ++k) s.q.push_back(points_[std::size_t(in_slab[k * n / m])] - corner);
    // Around: the slab widened by the margin on every side, from the cell and its neighbours.
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Array3i nc = c + Eigen::Array3i(dx, dy, dz);
          if (!grid_.inside(nc)) continue;
          for (const int i : members_[std::size_t(grid_.index(nc))]) {
            const Eigen::Vector3d u = canonical_[std::size_t(i)] - c.cast<double>().matrix();
            bool near = true;
            for (int a = 0; a < 3; ++a) near = near && u[a] >= lo[a] - margin_[a] && u[a] < hi[a] + margin_[a];
            if (near) s.r.push_back(points_[std::size_t(i)] - corner);
          }
        }
  }

  // max over q of the distance to its nearest r.
  template <class = void>
  static double directed(const std::vector<Eigen::Vector3d>& Q, const std::vector<Eigen::Vector3d>& R) {
    double worst = 0;
    for (const Eigen::Vector3d& q : Q) {
      double best = INFINITY;
      for (const Eigen::Vector3d& r : R) {
        const double d2 = (q - r).squaredNorm();
        if (d2 < best) {
          best = d2;
          if (best <= worst) break;  // cannot raise the maximum any more
        }
      }
      worst = std::max(worst, best);
    }
    return std::sqrt(worst);
  }

  template <class = void>
  double compare(const Slab& s1, const Slab& s2) const {
    if (s1.q.empty() && s2.q.empty()) return 0.0;
    double d = 0;
    if (!s1.q.empty()) {
      if (s2.r.empty()) return empty_mismatch_;
      d = std::max(d, directed(s1.q, s2.r));
    }
    if (!s2.q.empty()) {
      if (s1.r.empty()) return empty_mismatch_;
      d = std::max(d, directed(s2.q, s1.r));
    }
    return d;
  }

  CellGrid grid_;
  Eigen::Matrix3d A_ = Eigen::Matrix3d::Identity(), Ainv_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double spacing_ = 0, half_width_ = 0, empty_mismatch_ = 1000;
  double width_[3] = {0.5, 0.5, 0.5}, margin_[3] = {1, 1, 1};
  std::vector<Eigen::Vector3d> points_, canonical_;
  std::vector<std::vector<int>> members_;
  std::vector<Slab> slabs_;
  std::unordered_map<std::uint64_t, double> cache_;
  std::map<std::tuple<int, int, int, double, int, double, double>, double> plane_cache_;  // plane_mismatch of inside cells
  struct SampleTree {  // every finite sample (model units, float) under a k-d tree; built on first use
    MatrixX3f points;
    detail::PointSetAdaptor adaptor{&points};
    std::unique_ptr<detail::PointSetTree> tree;
  };
  std::shared_ptr<SampleTree> tree_;
  std::map<std::tuple<int, int, int, int, int, int>, SeamPositions> positions_cache_;
  std::map<std::tuple<int, int, int, int, int, int, int, int>, std::vector<int>> along_cache_;
  const Mesh* surface_mesh_ = nullptr;  // set_surface
  double surface_tolerance_ = 0;
  std::shared_ptr<detail::TriangleSurface> surface_;

  // Whether a sample moved to the other copy (model units) is continued there: within the stitcher's gap
  // of the input's surface (set_surface), else within 1.5 spacings of a sample.
  template <class = void>
  bool continued(const Eigen::Vector3d& q) {
    if (surface_mesh_ && !surface_) surface_ = std::make_shared<detail::TriangleSurface>(*surface_mesh_);
    if (surface_) return surface_->distance_within(q, surface_tolerance_) < surface_tolerance_;
    const float qf[3] = {float(q[0]), float(q[1]), float(q[2])};
    detail::NearestWithin nearest = detail::NearestWithin::keeping(2.25 * spacing_ * spacing_);
    sample_tree().findNeighbors(nearest, qf, nanoflann::SearchParams());
    return nearest.found;
  }

  template <class = void>
  const detail::PointSetTree& sample_tree() {
    if (tree_) return *tree_->tree;
    tree_ = std::make_shared<SampleTree>();
    std::size_t n = 0;
    for (const std::vector<int>& m : members_) n += m.size();
    tree_->points.resize(Eigen::Index(n), 3);
    Eigen::Index r = 0;
    for (const std::vector<int>& m : members_)
      for (const int i : m) tree_->points.row(r++) = points_[std::size_t(i)].cast<float>().transpose();
    tree_->adaptor.points = &tree_->points;
    tree_->tree = std::make_unique<detail::PointSetTree>(3, tree_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree_->tree->buildIndex();
    return *tree_->tree;
  }
};

}  // namespace restitch
