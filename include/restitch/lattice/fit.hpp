// restitch/lattice/fit.hpp - fits the lattice of principal offsets to a mesh: canonical space, grid phase, cells.
//
// docs/method.md 1.7. Given the three axes (principal offsets and dummies,
// normalized units; see offsets/principal.hpp), A = [v1 v2 v3] and canonical
// coordinates c = A^-1 (p - o). This header chooses the origin o, i.e. the
// phase of the cell planes c_a = integer along each axis, and counts the
// input cells. The result is a restitch::Lattice in MODEL units.
//
// Grid phase (restitch's addition; the paper leaves it open): cell
// boundaries should cut as little surface as possible, so that a cell holds
// whole parts and seams fall in gaps. Per axis a, independently:
//  * Let m_a be the minimum canonical coordinate of the mesh vertices. The
//    candidate phases are phi_k = k / K, k = 0 .. K-1 (K = 64), i.e. planes
//    c_a = m_a + phi_k + n for all integers n.
//  * The cost of a phase is the number of dense surface samples within a band
//    of half-width `band` (normalized length, default one dense spacing,
//    0.02) of any of its planes, measured as true distance to the plane. It
//    estimates the surface area in the band: about 2 * band * (length of the
//    cut) for surface crossing the plane, and the whole area of a face lying
//    in or next to the plane, so a plane that grazes or coincides with a face
//    (which makes clipping fragile) costs as much as one that cuts through it.
//  * The phase is the minimum cost. Ties (common: every plane in an empty gap
//    costs 0): the centre of the widest circular run of consecutive
//    candidates at the minimum cost (lower index for an even-length run);
//    among equally wide runs, the one starting at the smallest index; if every
//    candidate costs the same, phase 0. So seams sit in the middle of gaps.
//
// Cells: along axis a the boundaries are the planes m_a + phi + n. Cell 0
// starts at the last boundary at or below m_a, and the cells end at the first
// boundary at or above the maximum M_a of the vertices' canonical coordinates.
// End slivers: if the geometry in the first (last) cell fills less than
// `sliver` (0.5) of its width, that cell is dropped and its geometry belongs
// to its neighbour (the stitcher clamps canonical coordinates < 0 into cell 0
// and >= cells[a] into the last cell). So no cell is less than half full of
// geometry along its axis, and an end cell holds at most 1.5 cells of it (for
// example, the side panel of a shelf joins the end compartment). An axis keeps
// at least one cell. Dummy axes are treated exactly like real ones, with their
// own length (0.2 normalized).
//
// End planes (Lattice::end_low, end_high): where an end cap starts when an
// output end is copied from a cell that is not the input's end cell (the
// stitcher, docs/method.md section 3). When the geometry reaches past the
// outer plane of the end cell (or exactly to it) and the whole end cell
// repeats its neighbour, the cell plane: the cap is the overhang. When it
// stops short of it (the end cell is not full, the grid reaches past the
// model) or the end's own parts reach into the end cell, the cap must start
// inside the end cell, before the model's end and past the end's parts, so
// that the output ends where a model with fewer repeats would: the end plane
// is then the cheapest position (the phase cost above)
// among the candidates strictly inside the end cell's filled part (at least
// one band away from the model's end) and inside the end cell's PERIODIC
// part, ties broken as for the phase (centre of the widest run). The periodic
// part is what the end cell shares with its neighbour one period inward: the
// end cell's dense samples each have a sample of the neighbour within 1.5
// bands once moved by one period inward, and the neighbour's samples one in
// the end cell once moved outward (those past the model's end aside); it
// reaches from the inner cell plane toward the end up to a band before the
// first sample that fails either test. So a cap does not cut through an
// end's own parts (a fence's end post, a panel). Without a candidate the cap
// is the whole end cell (end_low 1, end_high 0) when there are three cells or
// more; with two, each end's comparison meets the other end, and the cell
// plane stays. With two cells the neighbour test is left out: the other end
// cell's samples that fail moved outward are those that fail its own test,
// its end's content (a valve under the first of two sections), not content
// this end lacks.
//
// Ends reaching across a plane: before the end planes, an end cell whose own
// part (where it fails the periodic comparison) reaches its inner plane, within
// a band, and whose neighbour fails it only next to that plane, less than
// `sliver` of it, joins that neighbour (its geometry becomes the new end cell's
// overhang): a fence post the phase cut 0.0135 from its face no longer leaves
// that piece in the picket cell beside it. Needs three cells; once per end.
//
// Contract: `mesh` passes restitch::validate; `norm` is the analysis's
// normalization; `dense` holds normalized surface samples (may be empty: then
// every phase costs 0 and phase 0 is used); `axes.axes` are linearly
// independent (principal offsets are >= 60 degrees apart and dummies are
// orthogonal to them). Cost: O(#dense + #V + #F) plus O(K) per axis.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/detail/point_tree.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/normalization.hpp"
#include "restitch/offsets/principal.hpp"
#include "restitch/status.hpp"

namespace restitch {

struct LatticeFitOptions {
  int phase_candidates = 64;  ///< K, candidate phases per axis
  double band = 0.02;         ///< half-width of the band around a cell plane, normalized length
  double sliver = 0.5;        ///< an end cell filled less than this share along its axis joins its neighbour
  /// Per axis, a candidate phase index in [0, K) to use instead of the cheapest one, or -1 (the default):
  /// for a caller that chooses the phase by something else (docs/method.md 1.7, a phase by structure).
  std::array<int, 3> phase{{-1, -1, -1}};
};

/// The fitted lattice with the normalized-unit view and diagnostics.
struct LatticeFit {
  Lattice lattice;                                              ///< model units
  Eigen::Matrix3d A_normalized = Eigen::Matrix3d::Identity();   ///< columns: the axes, normalized units
  Eigen::Vector3d origin_normalized = Eigen::Vector3d::Zero();  ///< canonical (0,0,0), normalized space
  Eigen::Array3d phase = Eigen::Array3d::Zero();                ///< chosen phi per axis, in [0, 1)
  Eigen::Array3d cut_share = Eigen::Array3d::Zero();            ///< share of dense samples in the chosen bands
  std::array<std::vector<std::size_t>, 3> phase_cost;           ///< per axis, the cost of each candidate phase
};

namespace detail {

/// Index of the chosen candidate given integer costs (the tie rule in the header).
template <class = void>
int choose_phase(const std::vector<std::size_t>& cost) {
  const int K = int(cost.size());
  const std::size_t best = *std::min_element(cost.begin(), cost.end());
  if (std::all_of(cost.begin(), cost.end(), [&](std::size_t c) { return c == best; })) return 0;
  int best_start = -1, best_len = 0;
  for (int s = 0; s < K; ++s) {
    // a run starts at s if s is minimal and its circular predecessor is not
    if (cost[std::size_t(s)] != best || cost[std::size_t((s + K - 1) % K)] == best) continue;
    int len = 0;
    while (len < K && cost[std::size_t((s + len) % K)] == best) ++len;
    if (len > best_len) best_len = len, best_start = s;
  }
  return (best_start + (best_len - 1) / 2) % K;
}

/// The candidate phases at which the cost has a local minimum: the centre of each circular run of equal
/// costs both of whose neighbours cost more (the lower centre for an even length), cheapest first, ties
/// by index. Empty when every candidate costs the same.
template <class = void>
std::vector<int> phase_minima(const std::vector<std::size_t>& cost) {
  const int K = int(cost.size());
  std::vector<int> out;
  if (K == 0 || std::all_of(cost.begin(), cost.end(), [&](std::size_t c) { return c == cost[0]; })) return out;
  for (int s = 0; s < K; ++s) {
    const std::size_t c = cost[std::size_t(s)];
    if (cost[std::size_t((s + K - 1) % K)] == c) continue;  // not the start of its run
    int len = 1;
    while (cost[std::size_t((s + len) % K)] == c) ++len;
    if (cost[std::size_t((s + K - 1) % K)] > c && cost[std::size_t((s + len) % K)] > c)
      out.push_back((s + (len - 1) / 2) % K);
  }
  std::stable_sort(out.begin(), out.end(), [&](int x, int y) { return cost[std::size_t(x)] < cost[std::size_t(y)]; });
  return out;
}

/// The end plane (header comment) among candidate positions j / K, j = j0 .. j1, of a cell, where
/// the phase cost of position j is cost[(k_phase + j) mod K]: the cheapest, ties to the centre of the
/// widest run (the lower one for an even length; among equal runs the first). -1 when j0 > j1.
template <class = void>
int choose_end(const std::vector<std::size_t>& cost, int k_phase, int j0, int j1) {
  if (j0 > j1) return -1;
  const int K = int(cost.size());
  const auto at = [&](int j) { return cost[std::size_t((k_phase + j) % K)]; };
  std::size_t best = at(j0);
  for (int j = j0; j <= j1; ++j) best = std::min(best, at(j));
  int best_start = -1, best_len = 0;
  for (int j = j0; j <= j1;) {
    if (at(j) != best) {
      ++j;
      continue;
    }
    int len = 0;
    while (j + len <= j1 && at(j + len) == best) ++len;
    if (len > best_len) best_len = len, best_start = j;
    j += len;
  }
  return best_start + (best_len - 1) / 2;
}

/// How far the periodic part of an end cell reaches (header comment, End planes), in relative canonical
/// coordinates of that cell along its axis (0 and 1 its planes). `rel(i)`: sample i's canonical
/// coordinate along the axis minus the end cell's lower plane; `inward`: +1 for the low end (the
/// neighbour is the next cell), -1 for the high end; `filled`: where the model ends inside the end cell
/// (low end: its start lo_rel; high end: the filled share). Returns the first failing sample's position
/// seen from the inner plane (low end: the largest; high end: the smallest), or the outer plane (0 for
/// the low end, 1 for the high end) when none fails. `tau`: the match distance (normalized units),
/// `tau_canonical` the same across the planes (canonical units). `neighbour`: also test the neighbour's
/// samples moved outward (false with two cells, where the neighbour is the other end cell).
template <class Rel>
double periodic_reach(const PointSet& dense, const PointSetTree& tree, const Eigen::Vector3d& period, Rel rel,
                      int inward, double filled, double tau_canonical, double tau, bool neighbour = true) {
  const bool high = inward < 0;
  double reach = high ? 1.0 : 0.0;
  const float tau2 = float(tau * tau);
  const auto matched = [&](Eigen::Index i, double sign) {
    const Eigen::Vector3d q = dense.points.row(i).cast<double>().transpose() + sign * period;
    const float qf[3] = {float(q[0]), float(q[1]), float(q[2])};
    NearestWithin nearest = NearestWithin::keeping(tau2);  // bounded: a miss costs little
    tree.findNeighbors(nearest, qf, nanoflann::SearchParams());
    return nearest.found && nearest.dist <= tau2;
  };
  for (Eigen::Index i = 0; i < dense.points.rows(); ++i) {
    const double r = rel(i);
    if (r >= 0 && r < 1) {  // in the end cell (its overhang aside): the counterpart one period inward
      if (!matched(i, double(inward))) reach = high ? std::min(reach, r) : std::max(reach, r);
    } else if (neighbour && (high ? (r >= -1 && r < 0) : (r >= 1 && r < 2))) {  // the neighbour: one period outward
      const double at = high ? r + 1 : r - 1;                     // where it would sit in the end cell
      const bool past_end = high ? at > filled - tau_canonical : at < filled + tau_canonical;
      if (!past_end && !matched(i, -double(inward))) reach = high ? std::min(reach, at) : std::max(reach, at);
    }
  }
  return reach;
}

/// Smallest integer n with n >= x, treating x within 1e-9 of an integer as that integer.
template <class = void>
long ceil_tolerant(double x) {
  const double r = std::round(x);
  return std::abs(x - r) <= 1e-9 ? long(r) : long(std::ceil(x));
}

}  // namespace detail

namespace detail {
/// fit_lattice, or with `from` (a fit of the same axes) along axis `only` alone, the others as in `from`.
template <class = void>
Result<LatticeFit> fit_lattice_axes(const Mesh& mesh, const Normalization& norm, const PointSet& dense,
                                    const PrincipalOffsets& axes, const LatticeFitOptions& options,
                                    const LatticeFit* from, int only) {
  if (options.phase_candidates < 1 || options.phase_candidates > 4096)
    return error(StatusCode::invalid_argument, "the number of candidate phases must be between 1 and 4096");
  if (!(options.band >= 0) || !std::isfinite(options.band))
    return error(StatusCode::invalid_argument, "the cut band half-width must be a non-negative finite length");
  if (!(options.sliver >= 0 && options.sliver <= 1))
    return error(StatusCode::invalid_argument, "the sliver share must lie in [0, 1]");
  for (const int k : options.phase)
    if (k < -1 || k >= options.phase_candidates)
      return error(StatusCode::invalid_argument, "a forced phase must be -1 or a candidate index below K");
  LatticeFit fit;
  Eigen::Matrix3d A;
  for (int a = 0; a < 3; ++a) A.col(a) = axes.axes[std::size_t(a)];
  Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
  if (!A.allFinite() || !lu.isInvertible() || std::abs(A.determinant()) < 1e-12)
    return error(StatusCode::invalid_argument, "the lattice axes are not linearly independent");
  const Eigen::Matrix3d Ainv = lu.inverse();

  // Canonical extent of the referenced vertices (relative to normalized origin 0).
  Eigen::Array3d lo = Eigen::Array3d::Constant(INFINITY), hi = Eigen::Array3d::Constant(-INFINITY);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = norm.to_normalized(mesh.V.row(mesh.F(f, k)).template cast<double>().transpose());
      const Eigen::Array3d c = (Ainv * p).array();
      lo = lo.min(c);
      hi = hi.max(c);
    }
  if (!(lo <= hi).all()) return error(StatusCode::invalid_mesh, "the mesh has no triangles to fit a lattice to");

  const int K = options.phase_candidates;
  // A k-d tree over the dense samples, for the end planes (built on first need).
  detail::PointSetAdaptor adaptor{&dense.points};
  std::unique_ptr<detail::PointSetTree> tree;
  const auto dense_tree = [&]() -> const detail::PointSetTree& {
    if (!tree) {
      tree = std::make_unique<detail::PointSetTree>(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
      tree->buildIndex();
    }
    return *tree;
  };
  Eigen::Array3i cells;
  Eigen::Array3d start;
  const Eigen::Array3d from_start =
      from ? Eigen::Array3d((Ainv * from->origin_normalized).array()) : Eigen::Array3d::Zero();
  for (int a = 0; a < 3; ++a) {
    if (from && a != only) {  // as fitted before
      start[a] = from_start[a];
      cells[a] = from->lattice.cells[a];
      fit.phase[a] = from->phase[a];
      fit.cut_share[a] = from->cut_share[a];
      fit.phase_cost[std::size_t(a)] = from->phase_cost[std::size_t(a)];
      fit.lattice.end_low[a] = from->lattice.end_low[a];
      fit.lattice.end_high[a] = from->lattice.end_high[a];
      continue;
    }
    // Phase: count samples near the planes of each candidate.
    const double row_norm = Ainv.row(a).norm();  // canonical units per normalized length
    const double h = options.band * row_norm;    // band half-width, canonical units
    std::vector<std::size_t> cost(std::size_t(K), 0);
    if (h < 0.5) {
      for (Eigen::Index i = 0; i < dense.points.rows(); ++i) {
        const double c = Ainv.row(a).dot(dense.points.row(i).cast<double>().transpose()) - lo[a];
        const double u = c - std::floor(c);  // in [0, 1)
        const long k_lo = long(std::ceil((u - h) * K)), k_hi = long(std::floor((u + h) * K));
        for (long k = k_lo; k <= k_hi && k < k_lo + K; ++k) ++cost[std::size_t(((k % K) + K) % K)];
      }
    }
    const int k = options.phase[std::size_t(a)] >= 0 ? options.phase[std::size_t(a)] : detail::choose_phase(cost);
    fit.phase[a] = double(k) / K;
    fit.cut_share[a] = dense.points.rows() ? double(cost[std::size_t(k)]) / double(dense.points.rows()) : 0.0;
    fit.phase_cost[std::size_t(a)] = cost;

    // Cells: boundaries at s0 + n.
    const double s0 = lo[a] + fit.phase[a];
    long first = fit.phase[a] > 0 ? -1 : 0;         // last boundary at or below lo
    long last = detail::ceil_tolerant(hi[a] - s0);  // first boundary at or above hi
    if (last <= first) last = first + 1;
    const double low_fill = (s0 + double(first + 1)) - lo[a];
    const double high_fill = hi[a] - (s0 + double(last - 1));
    if (last - first > 1 && low_fill < options.sliver) ++first;
    if (last - first > 1 && high_fill < options.sliver) --last;
    start[a] = s0 + double(first);
    cells[a] = int(last - first);

    const double margin = std::max(h, 1e-9);
    const Eigen::Vector3d period = A.col(a);
    const double tau = 1.5 * options.band, tau_canonical = tau * row_norm;
    const Eigen::RowVector3d to_axis = Ainv.row(a);
    const auto rel_from = [&](double plane) {
      return [&dense, to_axis, plane](Eigen::Index i) {
        return to_axis.dot(dense.points.row(i).cast<double>()) - plane;
      };
    };
    // Ends reaching across a plane (header comment): the end cell joins its neighbour when its own part
    // runs up to the plane between them and on into the neighbour, less than `sliver` of it.
    if (dense.points.rows() > 0 && cells[a] >= 3) {
      const double reach_end = detail::periodic_reach(dense, dense_tree(), period, rel_from(start[a]), +1,
                                                      lo[a] - start[a], tau_canonical, tau);
      if (reach_end >= 1 - margin) {
        const double reach_next = detail::periodic_reach(dense, dense_tree(), period, rel_from(start[a] + 1), +1,
                                                         -1.0, tau_canonical, tau);
        if (reach_next > 0 && reach_next <= options.sliver) start[a] += 1, --cells[a];
      }
    }
    if (dense.points.rows() > 0 && cells[a] >= 3) {
      const double last = start[a] + double(cells[a] - 1);
      const double reach_end = detail::periodic_reach(dense, dense_tree(), period, rel_from(last), -1,
                                                      hi[a] - last, tau_canonical, tau);
      if (reach_end <= margin) {
        const double reach_next =
            detail::periodic_reach(dense, dense_tree(), period, rel_from(last - 1), -1, 2.0, tau_canonical, tau);
        if (reach_next < 1 && reach_next >= 1 - options.sliver) --cells[a];
      }
    }

    // End planes: inside an end cell the geometry does not fill, within its periodic part (header comment).
    const double lo_rel = lo[a] - start[a], hi_rel = hi[a] - start[a];  // the model's ends, cells from start
    const double high_room = hi_rel - double(cells[a] - 1);  // filled share of the last cell
    if (cells[a] >= 2 && dense.points.rows() > 0) {
      // With two cells the neighbour is the other end cell: its samples that fail moved outward are the
      // ones that fail its own comparison (the same samples, the same move), its own end's content (a valve
      // under the first of two sections), not content this end lacks. Each is the end of the cell it is in.
      const bool neighbour = cells[a] >= 3;
      const double reach_low = detail::periodic_reach(dense, dense_tree(), period, rel_from(start[a]), +1, lo_rel,
                                                      tau_canonical, tau, neighbour);
      if (lo_rel > margin || reach_low > 0) {
        const double from = std::max(lo_rel, reach_low) + margin;
        const int j = detail::choose_end(cost, k, int(std::floor(from * K)) + 1, K - 1);
        if (j > 0) fit.lattice.end_low[a] = double(j) / K;
        else if (j < 0 && reach_low > 0 && cells[a] >= 3) fit.lattice.end_low[a] = 1.0;  // the whole cell (header)
      }
      const double reach_high = detail::periodic_reach(dense, dense_tree(), period,
                                                       rel_from(start[a] + double(cells[a] - 1)), -1, high_room,
                                                       tau_canonical, tau, neighbour);
      if (high_room < 1 - margin || reach_high < 1) {
        const double to = std::min(high_room, reach_high) - margin;
        const int j = detail::choose_end(cost, k, 1, int(std::ceil(to * K)) - 1);
        if (j > 0) fit.lattice.end_high[a] = double(j) / K;
        else if (j < 0 && reach_high < 1 && cells[a] >= 3) fit.lattice.end_high[a] = 0.0;  // the whole cell (header)
      }
    }
  }
  fit.A_normalized = A;
  fit.origin_normalized = A * start.matrix();
  fit.lattice.A = A / norm.scale;
  fit.lattice.origin = norm.to_model(fit.origin_normalized);
  fit.lattice.cells = cells;
  fit.lattice.dummy = axes.dummy;
  return fit;
}
}  // namespace detail

/// Fits the lattice (see header). Errors: invalid options or a singular axis
/// matrix (invalid_argument); a mesh without referenced vertices (invalid_mesh).
template <class = void>
Result<LatticeFit> fit_lattice(const Mesh& mesh, const Normalization& norm, const PointSet& dense,
                               const PrincipalOffsets& axes, const LatticeFitOptions& options = {}) {
  return detail::fit_lattice_axes(mesh, norm, dense, axes, options, nullptr, -1);
}

/// fit_lattice along axis `k` alone (its phase, cells and end planes), the other axes as in `from`, a fit of
/// the same axes and options: the same lattice as fit_lattice gives with those options, at a third of the
/// cost or less (every axis is fitted on its own). Errors as fit_lattice's.
template <class = void>
Result<LatticeFit> refit_axis(const Mesh& mesh, const Normalization& norm, const PointSet& dense,
                              const PrincipalOffsets& axes, const LatticeFitOptions& options, const LatticeFit& from,
                              int k) {
  if (k < 0 || k > 2) return error(StatusCode::invalid_argument, "the axis to refit must be 0, 1 or 2");
  return detail::fit_lattice_axes(mesh, norm, dense, axes, options, &from, k);
}

}  // namespace restitch
