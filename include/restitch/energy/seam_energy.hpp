// restitch/energy/seam_energy.hpp - the labelling energy of docs/method.md 2.3-2.4.
//
// CellDescriptors groups the analysis' feature descriptors by the grid cell
// their feature lies in (canonical floor, clamped into the grid like the
// stitcher). Only the Poisson-disk features enter the sets, not the mesh
// vertices: they cover the surface evenly at one spacing whatever the
// tessellation, so a cell's set describes its geometry rather than how finely
// it was triangulated (a Hausdorff distance is ruled by its worst point, and a
// densely tessellated detail would otherwise dominate), and they are few
// enough that a new pair of cells costs well under a millisecond and measures the distance between two cells'
// descriptor sets: the Hausdorff distance under the L2 descriptor distance (default), or the mean of nearest distances,
// symmetrised (an option; not a metric, so the solver's non-metric detection may fire). Distances between two cells are
// computed once and cached for the life of the object, so repeated retargets
// of one analysis (the live slider) only compute pairs they have not seen.
//
// SeamMrf is the labelling problem for one request, in the solver's problem
// contract (restitch/solver/mrf.hpp):
//   nodes   output cells, x = i + U_out (j + V_out k)
//   labels  shifts d with d_a between 0 and k_a (either sign), k = grid steps
//   unary   0 if x - d is inside the input grid, else `forbidden`; plus the
//           anchored ends (restitch's addition): along every resized axis a,
//           a cell on the low face of the output has a virtual neighbour
//           outside whose label is d with its a-component set to 0, and a cell
//           on the high face one whose a-component is k_a; that pairwise cost
//           is added to the unary. (Setting only the a-component, rather than
//           the whole label to 0 or k, keeps corners consistent: the top-left
//           cell of a shelf grown in x and y must copy the input's top-left.)
//   pairwise for neighbours x, x' (26- or 6-neighbourhood) with labels di, dj:
//           D(x - di, x - dj) + D(x' - di, x' - dj), where D is the cell-set
//           distance, 0 for two empty cells, `empty_mismatch` for one empty
//           and one not; a cell outside the input grid counts as empty.
//           Built on CellSlabs instead (restitch/energy/seam_geometry.hpp,
//           RetargetOptions::seam_energy geometry), D(a, b) becomes the slab
//           mismatch G(a, b; e) toward the neighbour e across the seam (model
//           units), with CellSlabs' empty_mismatch and forbidden = 1000 x it.
// Constants: descriptor distances are at most 2 * r, r the largest descriptor
// norm (2 for unit-norm SHOT); empty_mismatch = 1000 * 2r dominates any seam,
// forbidden = 1000 * empty_mismatch dominates any sum of seams; both are
// finite, as the solver needs, and far below its capacity limit (1e15).
//
// Cost: building the per-request tables is O(cells_in * label differences)
// lookups; each new cell pair costs O(n_a * n_b * D) flops.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/energy/seam_geometry.hpp"
#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"

namespace restitch {

enum class SetDistance { hausdorff, mean_nearest };

/// Feature descriptors grouped by input cell, with cached set distances.
class CellDescriptors {
 public:
  CellDescriptors() = default;

  /// Groups the features of `analysis` by the cells of `grid` (model units).
  template <class = void>
  CellDescriptors(const Analysis& analysis, const Lattice& grid, SetDistance kind)
      : descriptors_(&analysis.descriptors), grid_(grid.cells), kind_(kind) {
    const Eigen::Index n =
        std::min<Eigen::Index>(analysis.features.points.rows(), Eigen::Index(analysis.sampled_features));
    members_.assign(std::size_t(grid_.size()), {});
    const Eigen::Matrix3d Ainv = grid.A.inverse();
    for (Eigen::Index i = 0; i < n; ++i) {
      if (i >= analysis.descriptors.rows() || !analysis.descriptors.row(i).allFinite()) continue;
      const Eigen::Vector3d p =
          analysis.normalization.to_model(analysis.features.points.row(i).cast<double>().transpose());
      members_[std::size_t(grid_.index(grid_.cell_of(Ainv * (p - grid.origin))))].push_back(int(i));
    }
    double r = 0;
    for (Eigen::Index i = 0; i < analysis.descriptors.rows(); ++i)
      if (analysis.descriptors.row(i).allFinite()) r = std::max(r, double(analysis.descriptors.row(i).norm()));
    max_distance_ = r > 0 ? 2 * r : 2.0;
  }

  /// The input cells the features are grouped by.
  const CellGrid& grid() const { return grid_; }
  bool empty(int cell) const { return members_[std::size_t(cell)].empty(); }
  std::size_t features_in(int cell) const { return members_[std::size_t(cell)].size(); }
  double max_distance() const { return max_distance_; }

  /// Set distance between two non-empty input cells (cached).
  template <class = void>
  double distance(int a, int b) {
    if (a == b) return 0.0;
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
    auto it = cache_.find(key);
    if (it != cache_.end()) return it->second;
    const double d = compute(members_[std::size_t(a)], members_[std::size_t(b)]);
    cache_.emplace(key, d);
    return d;
  }
  std::size_t cached_pairs() const { return cache_.size(); }

 private:
  template <class = void>
  double compute(const std::vector<int>& A, const std::vector<int>& B) const {
    const DescriptorMatrix& D = *descriptors_;
    DescriptorMatrix X(A.size(), D.cols()), Y(B.size(), D.cols());
    for (std::size_t i = 0; i < A.size(); ++i) X.row(Eigen::Index(i)) = D.row(A[i]);
    for (std::size_t j = 0; j < B.size(); ++j) Y.row(Eigen::Index(j)) = D.row(B[j]);
    Eigen::MatrixXf d2 = (-2.0f * X * Y.transpose()).eval();
    d2.colwise() += X.rowwise().squaredNorm();
    d2.rowwise() += Y.rowwise().squaredNorm().transpose();
    d2 = d2.cwiseMax(0.0f);
    const Eigen::VectorXf row_min = d2.rowwise().minCoeff().cwiseSqrt();
    const Eigen::VectorXf col_min = d2.colwise().minCoeff().transpose().cwiseSqrt();
    if (kind_ == SetDistance::hausdorff) return double(std::max(row_min.maxCoeff(), col_min.maxCoeff()));
    return 0.5 * (double(row_min.mean()) + double(col_min.mean()));
  }

  const DescriptorMatrix* descriptors_ = nullptr;
  CellGrid grid_;
  SetDistance kind_ = SetDistance::hausdorff;
  std::vector<std::vector<int>> members_;
  std::unordered_map<std::uint64_t, double> cache_;
  double max_distance_ = 2.0;
};

/// The labelling problem of one retarget request (solver problem contract).
class SeamMrf {
 public:
  /// `k`: grid steps per axis; the output grid is the input cells + k.
  template <class = void>
  SeamMrf(CellDescriptors& cells, const Eigen::Array3i& k, Neighbourhood nb)
      : in_(cells.grid()), out_(cells.grid().dims + k), k_(k), span_(2 * k.abs() + 1) {
    empty_mismatch_ = 1000.0 * cells.max_distance();
    forbidden_ = 1000.0 * empty_mismatch_;
    build_labels();
    build_table(cells);
    build_edges(nb);
    build_lookup();
    build_unary();
  }

  /// The same problem with the geometric pairwise term (seam_geometry.hpp): the descriptor distance D is
  /// replaced by G(x - di, x - dj; e), the slab mismatch toward the neighbour e across the seam. Terms
  /// are computed on first use (the solver asks for few of them) and kept in `slabs`.
  template <class = void>
  SeamMrf(CellSlabs& slabs, const Eigen::Array3i& k, Neighbourhood nb)
      : in_(slabs.grid()), out_(slabs.grid().dims + k), k_(k), span_(2 * k.abs() + 1), slabs_(&slabs) {
    empty_mismatch_ = slabs.empty_mismatch();
    forbidden_ = 1000.0 * empty_mismatch_;
    build_labels();
    dirs_ = 27;
    const std::size_t entries = std::size_t(in_.size()) * dirs_ * std::size_t(span_.size());
    if (entries <= dense_table_limit) table_.assign(entries, std::nan(""));
    build_edges(nb);
    build_lookup();
    build_unary();
  }

  /// Ends inside end cells (Lattice::end_low / end_high, restitch/lattice/fit.hpp): an output cell that
  /// is not on the output's low (high) face along a resized axis a but copies the input's first (last)
  /// cell along a, whose end plane lies inside that cell, carries the model's end into the middle of the
  /// result (the grid reaches past the model there, so the end is not an overhang the stitcher would
  /// cut off). It costs `empty_mismatch`, as a missing surface does; added to the unary table.
  template <class = void>
  void penalise_inner_ends(const Eigen::Array3d& end_low, const Eigen::Array3d& end_high) {
    const int n = node_count(), m = label_count();
    for (int x = 0; x < n; ++x) {
      const Eigen::Array3i cx = out_.cell(x);
      for (int l = 0; l < m; ++l) {
        const Eigen::Array3i s = cx - labels_[std::size_t(l)];
        if (!in_.inside(s)) continue;
        for (int a = 0; a < 3; ++a) {
          if (k_[a] == 0) continue;
          const bool low = end_low[a] > 0 && s[a] == 0 && cx[a] != 0;
          const bool high = end_high[a] < 1 && s[a] == in_.dims[a] - 1 && cx[a] != out_.dims[a] - 1;
          if (low || high) unary_[std::size_t(x) * std::size_t(m) + std::size_t(l)] += forbidden_;
        }
      }
    }
  }

  /// Content that occurs once (docs/method.md 2.10; restitch/lattice/structure.hpp): input slab `slab`
  /// along resized axis a may be copied only with shift `shift` along a (any other label of a node that
  /// would copy it costs `forbidden`, so it is never copied twice); with `place`, the output slab
  /// `slab + shift` must copy it (any other shift along a there costs `forbidden`, so it is not lost). A
  /// placed slab also starts the labelling there (initial_labels). Added to the unary table.
  template <class = void>
  void pin_slab(int a, int slab, int shift, bool place) {
    const int n = node_count(), m = label_count();
    for (int x = 0; x < n; ++x) {
      const Eigen::Array3i cx = out_.cell(x);
      for (int l = 0; l < m; ++l) {
        const int d = labels_[std::size_t(l)][a];
        if ((cx[a] - d == slab || (place && cx[a] == slab + shift)) && d != shift)
          unary_[std::size_t(x) * std::size_t(m) + std::size_t(l)] += forbidden_;
      }
    }
    if (place) pins_[std::size_t(a)].push_back({slab + shift, shift});
  }

  /// Runs between parts (docs/method.md 2.10, Runs keep their side): along resized axis a, `input_run[j]`
  /// is the run of input slab j (-1: a part's slab) and `output_run[x]` the run output slab x lies in (-1:
  /// a part's place). An output slab of run r copying an input slab of another run costs `forbidden`,
  /// where run r has input slabs of its own. Added to the unary table.
  template <class = void>
  void keep_runs(int a, const std::vector<int>& input_run, const std::vector<int>& output_run) {
    const int n = node_count(), m = label_count();
    std::vector<char> held(input_run.size() + 1, 0);  // runs that hold input slabs
    for (const int r : input_run)
      if (r >= 0 && std::size_t(r) < held.size()) held[std::size_t(r)] = 1;
    for (int x = 0; x < n; ++x) {
      const Eigen::Array3i cx = out_.cell(x);
      if (cx[a] < 0 || std::size_t(cx[a]) >= output_run.size()) continue;
      const int r = output_run[std::size_t(cx[a])];
      if (r < 0 || std::size_t(r) >= held.size() || !held[std::size_t(r)]) continue;
      for (int l = 0; l < m; ++l) {
        const int j = cx[a] - labels_[std::size_t(l)][a];
        if (j >= 0 && std::size_t(j) < input_run.size() && input_run[std::size_t(j)] >= 0 &&
            input_run[std::size_t(j)] != r)
          unary_[std::size_t(x) * std::size_t(m) + std::size_t(l)] += forbidden_;
      }
    }
  }

  // ---- the labelling-problem contract ----
  int node_count() const { return int(out_.size()); }
  int label_count() const { return int(labels_.size()); }
  double unary(int node, int label) const { return unary_[std::size_t(node) * labels_.size() + label]; }
  int edge_count() const { return int(edges_.size()); }
  std::pair<int, int> edge(int e) const { return edges_[std::size_t(e)]; }
  /// The descriptor term's table is filled when the problem is made, so its terms may be read from
  /// several threads at once; the geometric term computes entries on first use (AlphaExpansion::threads).
  bool terms_thread_safe() const { return !slabs_; }
  template <class = void>
  double pairwise(int e, int li, int lj) const {
    if (li == lj) return 0.0;
    const auto [x, y] = edges_[std::size_t(e)];
    const std::array<std::uint8_t, 2>& t = edge_dirs_[std::size_t(e)];
    return node_seam(x, t[0], li, lj) + node_seam(y, t[1], li, lj);
  }

  /// The output cells (the nodes, in linear order).
  const CellGrid& out_grid() const { return out_; }
  const std::vector<Eigen::Array3i>& labels() const { return labels_; }
  /// Label index of shift d, -1 if d is not a label.
  template <class = void>
  int label_of(const Eigen::Array3i& d) const {
    for (int l = 0; l < label_count(); ++l)
      if ((labels_[l] == d).all()) return l;
    return -1;
  }
  double forbidden() const { return forbidden_; }
  double empty_mismatch() const { return empty_mismatch_; }
  /// Which pairwise term this problem uses.
  SeamEnergy energy() const { return slabs_ ? SeamEnergy::geometry : SeamEnergy::descriptor; }

  /// A starting labelling: the input's own layout stretched, i.e. each cell
  /// copies the nearest end (label 0 in the low part, k in the high part), or
  /// with placed slabs (pin_slab) the nearest of those and the ends.
  template <class = void>
  std::vector<int> initial_labels() const {
    std::vector<int> lab(static_cast<std::size_t>(node_count()));
    for (int x = 0; x < node_count(); ++x) {
      const Eigen::Array3i cx = out_.cell(x);
      Eigen::Array3i d = Eigen::Array3i::Zero();
      for (int a = 0; a < 3; ++a) d[a] = initial_shift(a, cx[a]);
      lab[std::size_t(x)] = label_of(d);
    }
    return lab;
  }

  /// The shift along axis a that initial_labels gives output index i: the nearest end's (0 in the low
  /// half, k in the high half), or with placed slabs the nearest of them and the ends (the lower on a tie).
  template <class = void>
  int initial_shift(int a, int i) const {
    const std::vector<std::pair<int, int>>& pins = pins_[std::size_t(a)];
    if (pins.empty()) return (2 * i >= out_.dims[a]) ? k_[a] : 0;
    int best_at = 0, shift = 0;  // the low end first
    const auto consider = [&](int at, int d) {
      const int dist = std::abs(i - at), best = std::abs(i - best_at);
      if (dist < best || (dist == best && at < best_at)) best_at = at, shift = d;
    };
    for (const auto& [at, d] : pins) consider(at, d);
    consider(out_.dims[a] - 1, k_[a]);
    return shift;
  }

  /// How many pairwise terms separable_labels() evaluates (its cost).
  template <class = void>
  double separable_terms() const {
    int resized = 0;
    double per_sweep = 0;
    for (int a = 0; a < 3; ++a)
      if (k_[a] != 0) ++resized, per_sweep += double(std::abs(k_[a]) + 1) * double(std::abs(k_[a]) + 1) * edge_count();
    return (resized > 1 ? 2 : 1) * per_sweep;
  }

  /// A second starting labelling (docs/method.md 2.5): the best labelling whose shift along each
  /// resized axis a depends only on the cell's index along a (seams that run straight through the
  /// model), found axis by axis by dynamic programming over the chain of slices (exact for one
  /// resized axis; two sweeps from initial_labels() otherwise). Alpha-expansion changes one label at
  /// a time, so where a good labelling needs two neighbouring cells changed together (a fence's post
  /// tops) it can stop short of it; from here it need not. Ties go to the smaller shift. Cost: per
  /// resized axis and sweep, (|k_a| + 1)^2 pairwise terms per edge.
  template <class = void>
  std::vector<int> separable_labels() const {
    std::array<std::vector<int>, 3> f;  // per axis and index along it: |d_a|
    std::array<int, 3> m{};             // shifts per axis
    for (int a = 0; a < 3; ++a) {
      m[std::size_t(a)] = std::abs(k_[a]) + 1;
      f[std::size_t(a)].resize(std::size_t(out_.dims[a]));
      for (int i = 0; i < out_.dims[a]; ++i) f[std::size_t(a)][std::size_t(i)] = std::abs(initial_shift(a, i));
    }
    // Label index with axis a's shift replaced by t (labels are ordered x fastest, build_labels).
    const auto label = [&](const Eigen::Array3i& c, int a, int t) {
      int u[3];
      for (int b = 0; b < 3; ++b) u[b] = b == a ? t : f[std::size_t(b)][std::size_t(c[b])];
      return u[0] + m[0] * (u[1] + m[1] * u[2]);
    };
    const int sweeps = (k_ != 0).count() > 1 ? 2 : 1;  // one axis: one exact pass
    for (int sweep = 0; sweep < sweeps; ++sweep)
      for (int a = 0; a < 3; ++a) {
        if (k_[a] == 0) continue;
        const int U = out_.dims[a], M = m[std::size_t(a)];
        std::vector<double> slice(std::size_t(U) * M, 0.0), step(std::size_t(std::max(U - 1, 0)) * M * M, 0.0);
        for (int x = 0; x < node_count(); ++x) {
          const Eigen::Array3i c = out_.cell(x);
          for (int t = 0; t < M; ++t) slice[std::size_t(c[a]) * M + t] += unary(x, label(c, a, t));
        }
        for (int e = 0; e < edge_count(); ++e) {
          const auto [x, y] = edges_[std::size_t(e)];
          const Eigen::Array3i cx = out_.cell(x), cy = out_.cell(y);
          if (cx[a] == cy[a]) {
            for (int t = 0; t < M; ++t) slice[std::size_t(cx[a]) * M + t] += pairwise(e, label(cx, a, t), label(cy, a, t));
            continue;
          }
          const bool x_low = cx[a] < cy[a];  // neighbours differ by one along a
          double* s = &step[std::size_t(std::min(cx[a], cy[a])) * M * M];
          for (int t = 0; t < M; ++t)      // t: the lower slice's shift
            for (int u = 0; u < M; ++u) {  // u: the upper slice's
              const int lx = label(cx, a, x_low ? t : u), ly = label(cy, a, x_low ? u : t);
              s[t * M + u] += pairwise(e, lx, ly);
            }
        }
        // Viterbi along the chain; strict improvement only, so ties keep the smaller shift.
        std::vector<double> best(slice.begin(), slice.begin() + M);
        std::vector<int> from(std::size_t(U) * M, 0);
        for (int i = 1; i < U; ++i) {
          std::vector<double> reached(static_cast<std::size_t>(M));
          for (int u = 0; u < M; ++u) {
            double b = INFINITY;
            int arg = 0;
            for (int t = 0; t < M; ++t) {
              const double v = best[std::size_t(t)] + step[std::size_t(i - 1) * M * M + std::size_t(t * M + u)];
              if (v < b) b = v, arg = t;
            }
            reached[std::size_t(u)] = b + slice[std::size_t(i) * M + u];
            from[std::size_t(i) * M + u] = arg;
          }
          best.swap(reached);
        }
        int t = int(std::min_element(best.begin(), best.end()) - best.begin());
        for (int i = U - 1; i >= 0; --i) {
          f[std::size_t(a)][std::size_t(i)] = t;
          t = from[std::size_t(i) * M + t];
        }
      }
    std::vector<int> lab(static_cast<std::size_t>(node_count()));
    for (int x = 0; x < node_count(); ++x) lab[std::size_t(x)] = label(out_.cell(x), -1, 0);
    return lab;
  }

 private:
  static int sign(int v) { return v < 0 ? -1 : 1; }
  // Geometric terms kept in a dense per-request table up to this many entries, else in a hash map.
  static constexpr std::size_t dense_table_limit = std::size_t(1) << 22;

  // Labels: every shift with d_a between 0 and k_a, x fastest.
  template <class = void>
  void build_labels() {
    for (int w = 0; w <= std::abs(k_[2]); ++w)
      for (int v = 0; v <= std::abs(k_[1]); ++v)
        for (int u = 0; u <= std::abs(k_[0]); ++u)
          labels_.push_back(Eigen::Array3i(sign(k_[0]) * u, sign(k_[1]) * v, sign(k_[2]) * w));
  }

  // Distances between input cells a and a + delta, |delta_a| <= |k_a|, for every input cell.
  template <class = void>
  void build_table(CellDescriptors& cells) {
    const int deltas = int(span_.size());
    const int n_in = int(in_.size());
    table_.assign(std::size_t(n_in) * deltas, 0.0);
    for (int c = 0; c < n_in; ++c) {
      const Eigen::Array3i a = in_.cell(c);
      for (int t = 0; t < deltas; ++t) {
        const Eigen::Array3i b = a + span_.cell(t) - k_.abs();
        table_[std::size_t(c) * deltas + t] = cell_distance(cells, a, b);
      }
    }
  }

  // Edges: the forward half of the neighbourhood, so each pair once.
  template <class = void>
  void build_edges(Neighbourhood nb) {
    const std::vector<Eigen::Array3i>& offsets = neighbour_offsets(nb, true);
    const int n = node_count();
    for (int x = 0; x < n; ++x) {
      const Eigen::Array3i cx = out_.cell(x);
      for (const Eigen::Array3i& o : offsets)
        if (out_.inside(cx + o)) edges_.push_back({x, out_.index(cx + o)});
    }
  }

  // Unary table: forbidden sources, plus the anchored ends (see the file comment).
  template <class = void>
  void build_unary() {
    const int n = node_count(), m = label_count();
    unary_.assign(std::size_t(n) * m, 0.0);
    for (int x = 0; x < n; ++x) {
      const Eigen::Array3i cx = out_.cell(x);
      for (int l = 0; l < m; ++l) {
        double u = in_.inside(cx - labels_[l]) ? 0.0 : forbidden_;
        for (int a = 0; a < 3; ++a) {
          // An output one cell long along a has every cell on both ends, and the stitcher caps whichever
          // end a label does not carry (docs/method.md 3, end caps): both ends are the input's whatever
          // the label, so the anchors say nothing there. Their costs differ from cell to cell, though,
          // and gave single cells the other label, whose caps meet their neighbours at T-junctions.
          if (k_[a] == 0 || out_.dims[a] == 1) continue;
          for (int side = 0; side < 2; ++side) {
            const bool on_face = side == 0 ? cx[a] == 0 : cx[a] == out_.dims[a] - 1;
            if (!on_face) continue;
            Eigen::Array3i anchor = labels_[l];
            anchor[a] = side == 0 ? 0 : k_[a];
            Eigen::Array3i outside = cx;
            outside[a] += side == 0 ? -1 : 1;
            u += seam(cx, outside - cx, labels_[l], anchor) + seam(outside, cx - outside, labels_[l], anchor);
          }
        }
        unary_[std::size_t(x) * m + l] = u;
      }
    }
  }

  template <class = void>
  double cell_distance(CellDescriptors& cells, const Eigen::Array3i& a, const Eigen::Array3i& b) const {
    const bool ia = in_.inside(a), ib = in_.inside(b);
    const bool ea = !ia || cells.empty(in_.index(a)), eb = !ib || cells.empty(in_.index(b));
    if (ea && eb) return 0.0;
    if (ea != eb) return empty_mismatch_;
    return cells.distance(in_.index(a), in_.index(b));
  }
  // The solver's lookups, so a pairwise term costs a few loads (the solver asks for about 3 E per move):
  // per node and label the input cell the node copies (-1 outside the input), per pair of labels the
  // index of their difference in span_, per edge the directions of its two cells toward each other.
  template <class = void>
  void build_lookup() {
    const int n = node_count(), m = label_count();
    source_.resize(std::size_t(n) * std::size_t(m));
    for (int x = 0; x < n; ++x) {
      const Eigen::Array3i cx = out_.cell(x);
      for (int l = 0; l < m; ++l) {
        const Eigen::Array3i s = cx - labels_[std::size_t(l)];
        source_[std::size_t(x) * std::size_t(m) + std::size_t(l)] = in_.inside(s) ? in_.index(s) : -1;
      }
    }
    difference_.resize(std::size_t(m) * std::size_t(m));
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
        difference_[std::size_t(i) * std::size_t(m) + std::size_t(j)] =
            std::uint32_t(span_.index(labels_[std::size_t(i)] - labels_[std::size_t(j)] + k_.abs()));
    edge_dirs_.resize(edges_.size());
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const Eigen::Array3i cx = out_.cell(edges_[e].first), cy = out_.cell(edges_[e].second);
      edge_dirs_[e] = {std::uint8_t(slabs_ ? CellSlabs::direction(cy - cx) : 0),
                       std::uint8_t(slabs_ ? CellSlabs::direction(cx - cy) : 0)};
    }
  }

  // seam() of output node x toward direction t (its index) with labels li, lj, from the lookups.
  template <class = void>
  double node_seam(int x, std::size_t t, int li, int lj) const {
    const std::size_t m = labels_.size();
    const int a = source_[std::size_t(x) * m + std::size_t(li)];
    if (a >= 0) return term(a, t, difference_[std::size_t(li) * m + std::size_t(lj)]);
    const int b = source_[std::size_t(x) * m + std::size_t(lj)];
    if (b >= 0) return term(b, t, difference_[std::size_t(lj) * m + std::size_t(li)]);
    return 0.0;  // both outside: both empty
  }

  // D(x - di, x - dj) (descriptor) or G(x - di, x - dj; o) (geometry), o the direction from x to the
  // neighbour across the seam, from the per-request table.
  template <class = void>
  double seam(const Eigen::Array3i& x, const Eigen::Array3i& o, const Eigen::Array3i& di,
              const Eigen::Array3i& dj) const {
    const Eigen::Array3i a = x - di, b = x - dj;
    const std::size_t t = slabs_ ? CellSlabs::direction(o) : 0;
    if (in_.inside(a)) return term(in_.index(a), t, std::size_t(span_.index(b - a + k_.abs())));
    if (in_.inside(b)) return term(in_.index(b), t, std::size_t(span_.index(a - b + k_.abs())));
    return 0.0;  // both outside: both empty
  }

  // The table's term for input cell c (its index), direction index t and label difference index u
  // (span_): D(c, c + delta), or G(c, c + delta; o) computed on first use.
  template <class = void>
  double term(int c, std::size_t t, std::size_t u) const {
    const std::size_t entry = (std::size_t(c) * dirs_ + t) * std::size_t(span_.size()) + u;
    if (!slabs_) return table_[entry];
    if (!table_.empty()) {
      double& v = table_[entry];
      if (std::isnan(v)) v = geometric(c, t, u);
      return v;
    }
    auto it = sparse_.find(entry);
    if (it != sparse_.end()) return it->second;
    const double v = geometric(c, t, u);
    sparse_.emplace(entry, v);
    return v;
  }
  template <class = void>
  double geometric(int c, std::size_t t, std::size_t u) const {
    const Eigen::Array3i cell = in_.cell(c), delta = span_.cell(std::int64_t(u)) - k_.abs();
    const Eigen::Array3i o(int(t % 3) - 1, int(t / 3 % 3) - 1, int(t / 9) - 1);  // inverse of direction()
    return slabs_->mismatch(cell, cell + delta, o);
  }

  CellGrid in_, out_;
  Eigen::Array3i k_;
  CellGrid span_;  // label differences: component a in [-|k_a|, |k_a|], stored shifted by |k_a|
  double empty_mismatch_ = 2000, forbidden_ = 2e6;
  CellSlabs* slabs_ = nullptr;  // the geometric term's source, or null for the descriptor term
  std::size_t dirs_ = 1;        // table entries per cell and label difference: 1, or 27 directions (geometry)
  std::vector<Eigen::Array3i> labels_;
  mutable std::vector<double> table_;  // geometry: filled on first use (NaN until then)
  std::vector<double> unary_;
  mutable std::unordered_map<std::size_t, double> sparse_;  // geometry, when the dense table would be too big
  std::vector<std::pair<int, int>> edges_;
  std::vector<int> source_;                          // per node and label: input cell index, -1 outside
  std::vector<std::uint32_t> difference_;            // per label pair (i, j): span_ index of d_i - d_j
  std::vector<std::array<std::uint8_t, 2>> edge_dirs_;  // per edge: direction index of each end toward the other
  std::array<std::vector<std::pair<int, int>>, 3> pins_;  // per axis: placed slabs (output index, shift)
};

}  // namespace restitch
