// restitch/lattice/structure.hpp - what repeats along each lattice axis, and what occurs once (docs/method.md 2.10).
//
// A model is rarely n copies of one module: a connector's housing reaches past its first pin, a box
// header has one key notch in the middle, a radiator one valve, a cabinet a tall drawer under short
// ones. Along each lattice axis a, slabs i and j (every input cell with index i, or j, along a) are
// *copies* when each one's surface, moved onto the other by (j - i) periods, lies on the model's surface:
// every dense sample of slab i moved by (j - i) v_a, and of slab j moved back, is within the tolerance of
// the mesh (exact point-to-triangle distance, so the test does not depend on the sampling or on how either
// copy is triangulated). A slab *repeats* when a neighbour is a copy of it (it is periodic), or when a
// periodic slab farther away is (a box header's plain column between the shroud's end and a notched
// column). So a slot next to each end, whose modules are copies of each other but not of the periodic
// plain modules between them, occurs once at each end. Neighbours whose content does not change along the
// axis (a housing's plain wall past its last pin: copies at any shift, so no sign of the period) are not
// taken as repeating. Where no two neighbours are copies, slabs farther apart that are, around slabs
// that are copies of none, repeat (a box header of five columns: its two plain ones around the notch;
// CellStructure::far_copies). Three modules A B A between the ends are decided by their difference: the one whose
// difference from the other is plain repeats (a slot next to each end around a plain module: the middle repeats), the
// third of them compared over its whole end cell where it lies past an end plane. Along an axis of three cells or more
// where nothing repeats so (a door between two windows; a key notch that reaches every column) whole periods cannot
// tell what occurs once: the axis is *undecided* and resized as the paper does, with a
// warning, from three whole slabs between the end planes, or two of which one is inside the model. Two
// whole end slabs that are no copies are the model's two ends, which the anchored ends and the end caps
// keep: no parts, no warning. The model's ends beyond their end planes are left out (the stitcher keeps them
// at the ends: end caps), and so are samples that move there. From three cells on, an end slab whose
// periodic part (what repeats its neighbour, measured on the surface) is at least half its cell is
// compared over that part instead: its end plane is where the cap is cut most cheaply, which may lie
// far below where the end's own content begins (two short drawers over a tall one, the top in the
// upper drawer's cell); the end still occupies its output end cell (parts_fit). Copies found only so, around a
// surface both sides of the run share and the run lacks all along (a key notch that reaches every column), are
// kept but marked (CellStructure::end_read): the run may be a gap in one part. Tolerance: 1e-3 of the bounding-box
// diagonal, 15 times the coarsest copies the weld closes (6.4e-5, docs/method.md 3) and below any part a
// modeller places on purpose. A slab that does not repeat holds content that occurs once: consecutive
// such slabs form a *part*. A part is anchored
//   * to the low end when it holds the first slab, or its centre (the middle of its own content: where
//     the model differs from itself a period either side) lies nearer the low end of the model than the high end
//     by more than half a period;
//   * to the high end likewise;
//   * to the centre otherwise (its centre within half a period of the model's centre, plus one sample
//     spacing, how closely the centre is measured: whole periods cannot tell closer), where a resize
//     keeps it as near the new centre as whole periods allow.
// A resize keeps every part once, at the same distance from the end it is anchored to, or at the
// centre (docs/method.md 2.10: constraints on the labelling, restitch/retarget/labelling.hpp), and
// places the model so the content at its origin stays where it was (restitch/placement.hpp).
//
// Cost: an AABB tree over the triangles (O(#F log #F)), then bounded point-to-surface queries: two per
// dense sample and axis for the neighbours, one per sample of two neighbours found copies (the plain
// test), a test that stops at its first sample off the surface per other slab a slab that does not
// repeat next door is compared with (every pair of slabs where none does), and, in an end part of three
// slabs or more, per phase one sample spacing apart, three such tests on windows of one period (a run of
// the repeat out of phase inside it, whose middle slab then repeats: the part is split around it), and,
// per part, up to three per sample of its slabs and their two neighbours (its centre); along an axis read
// through an end only, per sample beside the run on a surface along it, one per spacing until one lands on
// the surface (most stop at the first); for what occurs once from the surface alone (CellStructure::once), two
// per dense sample and axis, a hashed grid over those that occur once, and per group up to 2 n + 2 tests of
// its (at most once_samples) samples moved, one query each (most stop within half of them). Once per Retargeter.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/detail/cell_hash.hpp"
#include "restitch/detail/disjoint_sets.hpp"
#include "restitch/detail/triangle_surface.hpp"
#include "restitch/energy/seam_geometry.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"

namespace restitch {

namespace detail {

/// Whether more than half of `samples`, moved by `move`, lie within `tolerance` of `surface`: the content
/// they sample is there (a majority, so that no two disjoint places both hold most of it).
template <class = void>
bool held_at(const TriangleSurface& surface, const std::vector<Eigen::Vector3d>& samples, const Eigen::Vector3d& move,
             double tolerance) {
  const std::size_t need = samples.size() / 2 + 1;
  std::size_t on = 0, off = 0;
  for (const Eigen::Vector3d& q : samples) {
    ++(surface.distance_within(q + move, 2 * tolerance) <= tolerance ? on : off);
    if (on >= need) return true;
    if (off + need > samples.size()) return false;
  }
  return false;
}

/// The groups of `points` linked by steps of at most `link` (single linkage), largest first (a tie: the one
/// with the lowest first point first), each in the points' order.
template <class = void>
std::vector<std::vector<Eigen::Vector3d>> linked_groups(const std::vector<Eigen::Vector3d>& points, double link) {
  std::vector<std::vector<Eigen::Vector3d>> groups;
  if (points.empty() || !(link > 0)) return groups;
  const auto cell_of = [link](const Eigen::Vector3d& p) {
    return Cell{cell_index(p.x(), link), cell_index(p.y(), link), cell_index(p.z(), link)};
  };
  CellChains chains(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) chains.insert(cell_of(points[i]), std::int32_t(i));
  DisjointSets sets(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Cell c = cell_of(points[i]);
    chains.for_each_in(Cell{c[0] - 1, c[1] - 1, c[2] - 1}, Cell{c[0] + 1, c[1] + 1, c[2] + 1}, [&](std::int32_t j) {
      if (std::size_t(j) < i && (points[std::size_t(j)] - points[i]).norm() <= link) sets.join(std::uint32_t(i), std::uint32_t(j));
    });
  }
  std::vector<int> group_of(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    int& g = group_of[sets.find(std::uint32_t(i))];
    if (g < 0) g = int(groups.size()), groups.emplace_back();
    groups[std::size_t(g)].push_back(points[i]);
  }
  std::stable_sort(groups.begin(), groups.end(), [](const auto& x, const auto& y) { return x.size() > y.size(); });
  return groups;
}

}  // namespace detail

/// Where a part that occurs once is kept when the model is resized along its axis.
enum class PartAnchor { low, high, centre };

inline const char* part_anchor_name(PartAnchor a) {
  return a == PartAnchor::low ? "low end" : a == PartAnchor::high ? "high end" : "centre";
}

/// Consecutive slabs along one lattice axis that are copies of neither neighbour.
struct SingularPart {
  int axis = 0;
  int first = 0, last = 0;  ///< slab indices along the axis, inclusive
  PartAnchor anchor = PartAnchor::low;
  /// Its centre minus the model's centre along the axis, in periods (a centred part: within +-1/2).
  double offset = 0;
  /// How closely `offset` is measured, in periods: one sample spacing (CellStructure::spacing).
  double precision = 0;
  /// A copy of the next part along its axis, or of the previous one (as many slabs, each a copy of its
  /// counterpart): content that occurs more than once, which a period that makes it a part has missed
  /// (docs/method.md 1.12).
  bool repeated = false;
  /// Where its own content lies (model units): the samples of its difference from the repeated background
  /// that place its centre (`offset`); empty without a repeating slab. A centred part is moved by half a
  /// period where whole periods cannot centre it (restitch/retarget/centring.hpp) around these.
  std::vector<Eigen::Vector3d> content;
};

struct CellStructure {
  /// Per lattice axis, per slab: the slab it was found a copy of (its neighbours first), itself for the
  /// slab of a run out of phase and for the plain middle of three modules A B A (one period of what
  /// repeats: docs/method.md 2.10), or -1 when it does not repeat;
  /// empty along an axis of one cell and along dummy axes.
  std::array<std::vector<int>, 3> copy_of;
  /// Per axis: no two neighbouring slabs are copies, so what occurs once is not decided (no parts).
  std::array<bool, 3> undecided{{false, false, false}};
  /// Per axis: no two neighbouring slabs are copies, but slabs farther apart are, around content that
  /// occurs once, and they were taken as what repeats (docs/method.md 2.10).
  std::array<bool, 3> far_copies{{false, false, false}};
  /// Per axis: the slabs found copies all hold an end slab compared over its periodic part, which matches
  /// its neighbour by construction, and both sides of the run of repeating slabs have a surface it lacks
  /// all along: the run may be a gap in one part, not a repeat (docs/method.md 2.10, Copies read through an
  /// end; warned "short repeat").
  std::array<bool, 3> end_read{{false, false, false}};
  /// Per axis: read by three modules A B A whose middle repeats, where nothing repeats next door: B's
  /// difference from the A's is plain and theirs from B is not, so each A holds something B lacks, kept once
  /// as a part (docs/method.md 2.10, The plain one repeats).
  std::array<bool, 3> plain_middle{{false, false, false}};
  /// Per axis: what repeats is a run of neighbouring copies that the model's two sides share a wall around
  /// and it lacks all along, and nothing else repeats, or nothing repeats and a whole slab inside the model
  /// lacks such a wall: what a resize copies may be a gap in one part (a key notch over every pin), not a
  /// repeat (docs/method.md 2.10, A gap is no repeat; warned "short repeat").
  std::array<bool, 3> gap_run{{false, false, false}};
  /// Per axis: what occurs once along it, found from the surface alone, whatever the slabs were read as
  /// (docs/method.md 2.11, Content once): groups of dense samples (model units) whose surface, moved one period
  /// either way, is not the model's (at most once_groups of the largest, of once_samples samples each), that
  /// the model holds at no other whole number of periods either. The result check ("part count") counts how
  /// many times the output holds each. Empty along an axis of one cell, and for a structure of one axis.
  std::array<std::vector<std::vector<Eigen::Vector3d>>, 3> once;
  static constexpr std::size_t once_groups = 32, once_samples = 64;
  std::vector<SingularPart> parts;  ///< by axis, then index
  Eigen::Array3i cells = Eigen::Array3i::Ones();
  /// Per axis: the model's extent in canonical coordinates (its samples' lowest and highest).
  Eigen::Array3d extent_low = Eigen::Array3d::Zero(), extent_high = Eigen::Array3d::Zero();
  /// Per axis: the model's low (high) end lies inside its end cell (its end plane is not the outer cell
  /// plane), so an output's end cell holds the end, whatever the end slab's periodic part repeats.
  std::array<bool, 3> end_inside_low{{false, false, false}}, end_inside_high{{false, false, false}};
  /// Per axis: one sample spacing in periods, how closely a position along the axis is measured.
  Eigen::Array3d spacing = Eigen::Array3d::Zero();
  double tolerance = 0;  ///< model units

  /// How far from the model's centre along axis a a centre still counts as the centre, in periods: half a
  /// period (whole periods cannot tell closer) plus one sample spacing (how closely it is measured).
  double centre_band(int a) const { return 0.5 + spacing[a]; }
  /// How far from the model's centre along axis a an origin lies at the centre, in periods, wherever it is:
  /// a quarter period, halfway to pin 1 of a two-pin part (half a period from its centre), so a key or a
  /// marker at one end of a package built about its centre, which moves the box's centre by less, does
  /// not make its origin pin 1 (docs/method.md 2.7); at least one sample spacing.
  double centre_near(int a) const { return std::max(centre_quarter, spacing[a]); }
  /// The quarter period of centre_near, also used where no structure is known (restitch/placement.hpp).
  static constexpr double centre_quarter = 0.25;

  /// Whether slab i along axis a repeats (true along an axis without a structure).
  bool repeats(int a, int i) const {
    const std::vector<int>& c = copy_of[std::size_t(a)];
    return c.empty() || c[std::size_t(i)] >= 0;
  }
  /// The part holding slab i along axis a, or null when slab i repeats.
  const SingularPart* part_of(int a, int i) const {
    for (const SingularPart& p : parts)
      if (p.axis == a && p.first <= i && i <= p.last) return &p;
    return nullptr;
  }
  /// The label shift along a that keeps part p where it belongs in a resize by k cells along a: 0 for
  /// the low end, k for the high end; for the centre, the whole number of cells d that brings it nearest
  /// the new centre (which moves by k / 2: |offset + d - k / 2| least), and of two equally near (within
  /// what the part's centre is measured to: their misses differ by twice its error) the one on the side
  /// of the centre the part was on (above it for a part exactly centred). A part off the centre by half a
  /// period in a model of odd length (a rail after ceil(n / 2) of n slats) is so kept exactly, whichever
  /// way the measurement rounds its half.
  static int shift_of(const SingularPart& p, int k) {
    if (p.anchor != PartAnchor::centre) return p.anchor == PartAnchor::low ? 0 : k;
    const double want = 0.5 * k - p.offset;  // d with the part exactly at the new centre
    const int below = int(std::floor(want)), above = below + 1;
    const double miss_below = want - below, miss_above = above - want;  // how far each lands from it
    if (std::abs(miss_below - miss_above) > 2 * p.precision + 1e-9) return miss_below < miss_above ? below : above;
    return p.offset < -p.precision ? below : above;  // a tie: stay on the part's side (above when centred)
  }
  /// How far part p lies from the centre after a resize by k along its axis with shift_of (periods).
  static double offset_after(const SingularPart& p, int k) { return p.offset + shift_of(p, k) - 0.5 * k; }
};

/// "cells 3-4 (centre)" style description of a part, 1-based as the CLI counts cells.
inline std::string describe_part(const SingularPart& p) {
  const std::string cells = p.first == p.last ? "cell " + std::to_string(p.first + 1)
                                              : "cells " + std::to_string(p.first + 1) + "-" + std::to_string(p.last + 1);
  return cells + " along axis " + std::to_string(p.axis + 1) + " (kept at the " + part_anchor_name(p.anchor) + ")";
}

/// Whether the parts along axis a still fit, in order and apart, when it changes by k cells: each
/// part's slabs land at slab + CellStructure::shift_of inside the output, after the previous part's, and
/// off an output end cell that holds the model's end (end_inside_low, _high) unless the part holds that end.
template <class = void>
bool parts_fit(const CellStructure& s, int a, int k) {
  const int n = s.cells[a], out = n + k;
  int next_free = s.end_inside_low[std::size_t(a)] ? 1 : 0;
  for (const SingularPart& p : s.parts) {
    if (p.axis != a) continue;
    const int d = CellStructure::shift_of(p, k);
    const int end = p.last == n - 1 || !s.end_inside_high[std::size_t(a)] ? out : out - 1;
    if ((p.first > 0 && p.first + d < next_free) || p.last + d >= end) return false;
    next_free = p.last + d + 1;
  }
  return true;
}

/// The structure of `mesh` on the label grid `grid` (model units), from the dense samples of `analysis`
/// (see the file comment). `tolerance`: model units (0: 1e-3 of the bounding-box diagonal). Dummy axes and
/// axes of one cell have no parts. `mesh_surface`: the mesh's triangles under their tree, when the caller
/// has them (null: built here). `end_parts`: compare an end slab over its periodic part where that is at
/// least half its cell (docs/method.md 2.10); false compares end slabs whole (a divisor's check, 1.12).
/// `only_axis` >= 0: that lattice axis alone (the others are left as along an axis of one cell), for a
/// caller that reads no other: the analysis checking one period (1.12, 1.14).
template <class = void>
CellStructure cell_structure(const Mesh& mesh, const Analysis& analysis, const Lattice& grid, double tolerance = 0,
                             const detail::TriangleSurface* mesh_surface = nullptr, bool end_parts = true,
                             int only_axis = -1) {
  CellStructure s;
  s.cells = grid.cells;
  s.tolerance = tolerance > 0 ? tolerance : 1e-3 * bounding_box(mesh).size().norm();
  if (!(s.tolerance > 0)) return s;
  const Eigen::Matrix3d Ainv = grid.A.inverse();
  const MatrixX3f& P = analysis.dense.points;
  const MatrixX3f& N = analysis.dense.normals;  // a uniform scale: the same directions in model units
  std::vector<Eigen::Vector3d> points, canonical, normals;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const Eigen::Vector3d p = analysis.normalization.to_model(P.row(i).template cast<double>().transpose());
    if (!p.allFinite()) continue;
    points.push_back(p);
    canonical.push_back(Ainv * (p - grid.origin));
    normals.push_back(N.rows() == P.rows() ? Eigen::Vector3d(N.row(i).template cast<double>().transpose())
                                           : Eigen::Vector3d::Zero());
  }
  // The sample spacing (model units): how closely a part's centre is measured.
  const double spacing = detail::median_nearest_distance(P) / (analysis.normalization.scale > 0 ? analysis.normalization.scale : 1);
  std::unique_ptr<detail::TriangleSurface> own;  // built for the first axis that needs it, unless given
  const detail::TriangleSurface* surface = mesh_surface;
  for (int a = 0; a < 3; ++a) {
    const int n = grid.cells[a];
    if (grid.dummy[a] || n < 2 || (only_axis >= 0 && a != only_axis)) continue;
    if (!surface) own = std::make_unique<detail::TriangleSurface>(mesh), surface = own.get();
    const double lo = grid.end_low[a], hi = double(n - 1) + grid.end_high[a];
    const Eigen::Vector3d v = grid.A.col(a);
    std::vector<std::vector<std::size_t>> slab(static_cast<std::size_t>(n));  // the samples compared, by slab
    double m0 = INFINITY, m1 = -INFINITY;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const double t = canonical[k][a];
      m0 = std::min(m0, t), m1 = std::max(m1, t);
      if (t >= lo && t < hi) slab[std::size_t(std::clamp(int(std::floor(t)), 0, n - 1))].push_back(k);
    }
    s.extent_low[a] = m0, s.extent_high[a] = m1;
    s.spacing[a] = spacing / v.norm();
    const auto off_surface = [&](std::size_t k, double shift) {
      return surface->distance_within(points[k] + shift * v, 2 * s.tolerance) > s.tolerance;
    };
    // What occurs once along a, from the surface alone (docs/method.md 2.11, Content once): the samples whose
    // surface, moved one period either way, is not the model's (past the model's end there is none; a sample
    // both of whose moves leave the model tells nothing), linked at two sample spacings (the samples of one
    // surface lie about one apart). A group of fewer than four is within a spacing or two: no content a
    // modeller would count. The largest once_groups, once_samples of each (evenly), bound the result check's
    // cost; a group the model holds at another whole number of periods too (two slots, one next to each end)
    // does not occur once.
    if (only_axis < 0) {
      std::vector<Eigen::Vector3d> lone;
      for (std::size_t k = 0; k < points.size(); ++k) {
        const double t = canonical[k][a];
        if (t + 1 > m1 && t - 1 < m0) continue;
        if (off_surface(k, 1) && off_surface(k, -1)) lone.push_back(points[k]);
      }
      for (std::vector<Eigen::Vector3d>& g : detail::linked_groups(lone, 2 * spacing)) {
        if (g.size() < 4 || s.once[std::size_t(a)].size() >= CellStructure::once_groups) break;
        if (g.size() > CellStructure::once_samples) {
          std::vector<Eigen::Vector3d> kept;
          for (std::size_t i = 0; i < CellStructure::once_samples; ++i)
            kept.push_back(g[i * g.size() / CellStructure::once_samples]);
          g.swap(kept);
        }
        // A group whose surface runs along a (moved its own length along a either way, at least two spacings,
        // most of it lands on the surface: a stretch of top face whose copy a period away is a dimple's floor
        // on one side and nothing on the other) has nothing of its own: its neighbours' content differs.
        double g0 = INFINITY, g1 = -INFINITY;
        for (const Eigen::Vector3d& q : g) {
          const double t = Ainv.row(a).dot(q - grid.origin);
          g0 = std::min(g0, t), g1 = std::max(g1, t);
        }
        const double length = std::max(g1 - g0, 2 * s.spacing[a]);
        if (detail::held_at(*surface, g, length * v, s.tolerance) && detail::held_at(*surface, g, -length * v, s.tolerance))
          continue;
        bool recurs = false;
        for (int j = 2; j <= n + 1 && !recurs; ++j)
          recurs = detail::held_at(*surface, g, double(j) * v, s.tolerance) ||
                   detail::held_at(*surface, g, -double(j) * v, s.tolerance);
        if (!recurs) s.once[std::size_t(a)].push_back(std::move(g));
      }
    }
    // Where an end plane lies inside its end cell, the cell's periodic part (docs/method.md 1.7: its samples
    // moved one period inward, and its neighbour's moved outward up to the model's end, lie on the surface)
    // may reach past it: the end plane is where the end cap is cut most cheaply, not where the end's content
    // begins. An end slab is compared over its periodic part when that is at least half the cell (an end
    // cell must be half full, 1.7), and samples moved into its end beyond it are then not compared (the end
    // is kept by the end caps); with less, the end slab is the end, not a copy, as before.
    s.end_inside_low[std::size_t(a)] = lo > 0;
    s.end_inside_high[std::size_t(a)] = hi < double(n);
    double lo_cmp = lo, hi_cmp = hi;
    bool low_partial = false, high_partial = false;
    if (end_parts && n >= 3) {
      if (lo > 0) {
        double reach = 0;
        for (std::size_t k = 0; k < points.size(); ++k) {
          const double t = canonical[k][a];
          if (t >= 0 && t < 1 && off_surface(k, 1)) reach = std::max(reach, t);
          if (t >= 1 && t < 2 && t - 1 > m0 + s.spacing[a] && off_surface(k, -1)) reach = std::max(reach, t - 1);
        }
        reach = std::min(reach + s.spacing[a], lo);
        if (reach <= 0.5) lo_cmp = reach, low_partial = true;
      }
      if (hi < double(n)) {
        const double base = double(n - 1);
        double reach = 1;
        for (std::size_t k = 0; k < points.size(); ++k) {
          const double t = canonical[k][a] - base;
          if (t >= 0 && t < 1 && off_surface(k, -1)) reach = std::min(reach, t);
          if (t >= -1 && t < 0 && t + 1 < m1 - base - s.spacing[a] && off_surface(k, 1)) reach = std::min(reach, t + 1);
        }
        reach = std::max(reach - s.spacing[a], hi - base);
        if (reach >= 0.5) hi_cmp = base + reach, high_partial = true;
      }
      if (low_partial || high_partial)
        for (std::vector<std::size_t>& b : slab) b.clear();
      for (std::size_t k = 0; (low_partial || high_partial) && k < points.size(); ++k) {
        const double t = canonical[k][a];
        if (t >= lo_cmp && t < hi_cmp) slab[std::size_t(std::clamp(int(std::floor(t)), 0, n - 1))].push_back(k);
      }
    }
    // Slab i's samples moved by `shift` periods lie on the surface, and not in the model's end (where the
    // other slab is the end, not a copy, and nothing could be compared); past an end slab's periodic part,
    // they are not compared.
    const auto lands = [&](int i, int shift) {
      for (const std::size_t k : slab[std::size_t(i)]) {
        const double t = canonical[k][a] + shift;
        if (t < lo_cmp || t >= hi_cmp) {
          if ((t < lo_cmp && low_partial && t >= 0) || (t >= hi_cmp && high_partial && t < double(n))) continue;
          return false;
        }
        if (off_surface(k, double(shift))) return false;
      }
      return true;
    };
    // An end slab with nothing compared (its whole cell is the model's end) is the end, not a copy.
    const auto copies = [&](int i, int j) {
      for (const int e : {i, j})
        if ((e == 0 || e == n - 1) && slab[std::size_t(e)].empty()) return false;
      return lands(i, j - i) && lands(j, i - j);
    };
    // Neighbours i and i + 1 whose content does not change along a (each one's samples, moved toward the
    // other by a shift no period can be, land on the surface where compared: every surface in them runs
    // along a, like a housing's plain wall past its last pin) are copies at any shift: being copies says
    // nothing of the period, so they are not taken as repeating (docs/method.md 2.10). The shift: half a
    // sample spacing (a period is at least a spacing, 1.12), and at least twice the tolerance, so that a
    // surface across a moved by it lands off itself.
    const double slide = std::max(0.5 * spacing, 2 * s.tolerance) / v.norm();
    // `toward` (+1 or -1 slabs away, 0 for every sample): only the samples the comparison with that slab
    // looked at, those it moved inside the periodic part (`lands`).
    const auto plain_shift = [&](int from, double shift, int toward = 0) {
      for (const std::size_t k : slab[std::size_t(from)]) {
        const double t = canonical[k][a] + shift, there = canonical[k][a] + toward;
        if (toward != 0 && (there < lo_cmp || there >= hi_cmp)) continue;
        if (t >= lo_cmp && t < hi_cmp && off_surface(k, shift)) return false;
      }
      return true;
    };
    const auto plain = [&](int i) { return plain_shift(i, slide) && plain_shift(i + 1, -slide); };
    // An end slab compared over its periodic part, and its neighbour, plain where compared: what tells them
    // apart, if anything, is the neighbour's content that lands in the end, not compared (the handle of a
    // tall drawer's front, over the plinth's cell whose periodic part is plain front). Their being copies
    // then says no more than plain neighbours' do; they are taken as copies only where one of them is a copy
    // of a third slab too, so that what they hold repeats past the pair (a bookshelf's last compartment,
    // whose divider lands in the side panel's cell, and whose end cell is a copy of another compartment's).
    // docs/method.md 2.10, Plain neighbours.
    const auto end_read = [&](int e) { return (e == 0 && low_partial) || (e == n - 1 && high_partial); };
    const auto plain_compared = [&](int i) {
      return (end_read(i) || end_read(i + 1)) && plain_shift(i, slide, 1) && plain_shift(i + 1, -slide, -1);
    };
    // Two end slabs, both compared over their periodic parts and plain there (a chest's plinth cell and its
    // top's, plain front), are copies at any shift: as a third copy, or as a copy farther away, they say
    // nothing. A whole slab a copy of an end slab does (the bookshelf's compartment).
    const auto plain_ends = [&](int i, int j) {
      if (!end_read(i) || !end_read(j)) return false;
      const double toward = j > i ? slide : -slide;
      return plain_shift(i, toward, j - i) && plain_shift(j, -toward, i - j);
    };
    const auto copy_of_third = [&](int i) {
      for (int j = 0; j < n; ++j)
        if (j != i && j != i + 1 &&
            ((copies(i, j) && !plain_ends(i, j)) || (copies(i + 1, j) && !plain_ends(i + 1, j))))
          return true;
      return false;
    };
    // Slab i alone: its samples moved either way by the slide, those still inside it, land on the surface.
    // Moved past its planes they would meet its neighbours' content (a key notch's edge a hundredth of a
    // pitch past the plane of a cell of plain wall), which says nothing of whether its own content changes.
    const auto plain_alone = [&](int i) {
      for (const double shift : {slide, -slide})
        for (const std::size_t k : slab[std::size_t(i)]) {
          const double t = canonical[k][a] + shift;
          if (t >= std::max(lo_cmp, double(i)) && t < std::min(hi_cmp, double(i + 1)) && off_surface(k, shift))
            return false;
        }
      return true;
    };
    std::vector<int>& copy_of = s.copy_of[std::size_t(a)];
    copy_of.assign(std::size_t(n), -1);
    for (int i = 0; i + 1 < n; ++i)
      if (copies(i, i + 1) && !plain(i) && (!plain_compared(i) || copy_of_third(i))) {
        if (copy_of[std::size_t(i)] < 0) copy_of[std::size_t(i)] = i + 1;
        copy_of[std::size_t(i + 1)] = i;
      }
    const auto whole_slab = [&](int i) { return i >= lo - 1e-9 && i + 1 <= hi + 1e-9; };  // between the end planes
    // The model's two sides of the range [t0, t1) along a share a surface the range lacks all along: a sample
    // on one side, on a surface along a (a wall's face, not an end's), moved to every place inside the range
    // one sample spacing apart, lands off the surface, and moved to some place on the other side lands on it
    // (a shroud's front wall at both ends, and the notch between them all along the range; not the narrow gap
    // between two drawer fronts, which a move by part of a period puts on a front). A `wall` must also run
    // unbroken from the sample to the model's end on its side, and over the last period at the model's other
    // end, facing the same way there, at least one period long at each end: a wall the range interrupts (a
    // shroud's front wall from the notch's edge to the shroud's end; not a slot's floor next to each end, a
    // rail between two runs of slats, or a fence's posts, narrower than a picket pitch). `wall_between_ends`:
    // a wall, with only samples between the end planes looked at. `found`: where given, every such sample;
    // otherwise the first ends the search.
    const Eigen::Vector3d along = v.normalized();
    const double lack_step = std::max(s.spacing[a], 1e-3);
    // Sample k moved to every place in [u0, u1) one step apart lands on the surface.
    const auto unbroken = [&](std::size_t k, double u0, double u1) {
      for (double u = u0 + 0.5 * lack_step; u < u1; u += lack_step)
        if (off_surface(k, u - canonical[k][a])) return false;
      return true;
    };
    // The samples within two steps of each end of the model along a, where a surface the range lacks must be
    // found at the other end; sample k moved by `shift` periods lands next to one of them (within 1.5 sample
    // spacings, as samples of one surface lie) that faces the same way (normals within 60 degrees): the same
    // wall continued, not a face turned the other way (the underside of a sheared facade's overhanging floor at
    // one end, where the other end has the top of a floor below).
    std::vector<std::size_t> end_low_samples, end_high_samples;
    for (std::size_t k = 0; k < points.size(); ++k) {
      if (canonical[k][a] <= m0 + 2 * lack_step) end_low_samples.push_back(k);
      if (canonical[k][a] >= m1 - 2 * lack_step) end_high_samples.push_back(k);
    }
    const auto same_face_at = [&](std::size_t k, double shift, const std::vector<std::size_t>& near) {
      const Eigen::Vector3d q = points[k] + shift * v;
      for (const std::size_t j : near)
        if ((points[j] - q).norm() <= 1.5 * spacing && normals[j].dot(normals[k]) >= 0.5) return true;
      return false;
    };
    enum class Lack { anywhere, wall, wall_between_ends };
    const auto lacks_all_along = [&](double t0, double t1, Lack how, std::vector<std::size_t>* found) {
      const bool between_ends = how == Lack::wall_between_ends, wall = how != Lack::anywhere;
      for (std::size_t k = 0; k < points.size(); ++k) {
        const double t = canonical[k][a];
        // Along a: the normal at least 60 degrees from it (not an end's face, nor a chamfer's at 45 degrees).
        if (std::abs(normals[k].dot(along)) > 0.5 || (t >= t0 && t < t1)) continue;
        if (between_ends && (t < lo_cmp || t >= hi_cmp)) continue;
        const bool below = t < t0;
        if (wall && (below ? t - m0 : m1 - t) < 1) continue;  // a wall at least a period long on its side
        bool lacked = true;
        for (double u = t0 + 0.5 * lack_step; u < t1 && lacked; u += lack_step) lacked = off_surface(k, u - t);
        if (!lacked) continue;
        if (wall && !(below ? unbroken(k, m0, t) : unbroken(k, t, m1))) continue;
        const double o0 = below ? t1 : m0, o1 = below ? m1 : t0;  // the other side
        bool shared = false;
        if (wall) {
          const double end = below ? m1 - 0.5 * lack_step : m0 + 0.5 * lack_step;
          shared = (below ? unbroken(k, m1 - 1, m1) : unbroken(k, m0, m0 + 1)) &&
                   same_face_at(k, end - t, below ? end_high_samples : end_low_samples);
        } else {
          for (double u = o0 + 0.5 * lack_step; u < o1 && !shared; u += lack_step) shared = !off_surface(k, u - t);
        }
        if (!shared) continue;
        if (!found) return true;
        found->push_back(k);
      }
      return found && !found->empty();
    };
    // A run of neighbours that are copies, which the model's two sides share a surface around and it lacks
    // all along (lacks_all_along, between the end planes), may be a gap in one part (a key notch over three
    // pins, whose middle columns are copies: the notch widened with the pins), not what repeats (docs/method.md
    // 2.10, A gap is no repeat). It is set aside while other slabs are found to repeat, next door or farther
    // apart around it, that have that surface (a box header's columns beside the notch, with their front
    // wall); where none is, it is kept, and the axis is marked (CellStructure::gap_run, warned "short repeat").
    // An end slab compared over its periodic part (its other samples are the end's).
    const auto partial = [&](int i) { return (i == 0 && low_partial) || (i == n - 1 && high_partial); };
    std::vector<char> gap(std::size_t(n), 0);
    std::vector<std::size_t> lacked;  // the samples of the surface the gaps lack
    const std::vector<int> next_door = copy_of;
    for (int i = 0; i < n;) {
      if (copy_of[std::size_t(i)] < 0) {
        ++i;
        continue;
      }
      int j = i;
      while (j + 1 < n && copy_of[std::size_t(j + 1)] >= 0) ++j;
      // Whole slabs inside the model, or an end slab compared over its periodic part, which is then what the
      // run spans of it (a key notch whose edge lies in pin 1's column past its end plane: the columns of
      // the other pins are copies of that column's periodic part).
      bool whole = true;
      for (int m = i; m <= j; ++m)
        whole = whole && ((whole_slab(m) && m > 0 && m < n - 1) || partial(m));
      if (whole && lacks_all_along(std::max(double(i), lo_cmp), std::min(double(j + 1), hi_cmp), Lack::wall_between_ends,
                                   &lacked))
        for (int m = i; m <= j; ++m) gap[std::size_t(m)] = 1, copy_of[std::size_t(m)] = -1;
      i = j + 1;
    }
    const bool gaps = std::find(gap.begin(), gap.end(), 1) != gap.end();
    // Whole slabs that are no copies leave the axis undecided when they are three, or two of which one is
    // inside the model: two end slabs are the model's two ends, which the anchored ends and end caps keep
    // (docs/method.md 2.3, 3). `first`: the first whole slab (they are consecutive), -1 for none.
    struct WholeSlabs {
      int count = 0, inside = 0, first = -1;
      bool undecided() const { return count >= 3 || (count == 2 && inside > 0); }
    };
    const auto whole_slabs = [&] {
      WholeSlabs w;
      for (int i = 0; i < n; ++i)
        if (whole_slab(i)) {
          if (w.first < 0) w.first = i;
          ++w.count, w.inside += i > 0 && i < n - 1;
        }
      return w;
    };
    // What tells three modules A B A apart where nothing repeats next door (docs/method.md 2.10, The plain
    // one repeats). Slab `from`'s difference from the slab `shift` away (its samples that land
    // off the surface when moved there) is plain: each such sample, moved either way along a by the slide and
    // still inside its slab, lands on the surface (a stretch of back wall where the other has a slot; not a
    // slot's side faces, which cross a). Over the samples compared, or with `whole_cell` over every sample of
    // the cell, end or not (a module in the end cell).
    const auto difference_plain = [&](int from, int shift, bool whole_cell = false) {
      const double c0 = whole_cell ? double(from) : std::max(lo_cmp, double(from));
      const double c1 = whole_cell ? double(from + 1) : std::min(hi_cmp, double(from + 1));
      for (std::size_t k = 0; k < points.size(); ++k) {
        const double t = canonical[k][a];
        if (t < c0 || t >= c1 || (!whole_cell && (t + shift < lo_cmp || t + shift >= hi_cmp))) continue;
        if (!off_surface(k, double(shift))) continue;
        for (const double d : {slide, -slide})
          if (t + d >= c0 && t + d < c1 && off_surface(k, d)) return false;
      }
      return true;
    };
    if (std::count(copy_of.begin(), copy_of.end(), -1) == n) {  // nothing repeats next door
      // Copies farther apart (docs/method.md 2.10): a box header of five columns (plain, notch edge, notch,
      // notch edge, plain) has its two plain columns 4 apart and no copies next door. They are taken as what
      // repeats, the only reading in which anything does, unless
      //   * two slabs 2 apart are copies (A B A: a connector's middle module repeats where a header's ends
      //     do; or two alternating parts, 1.12's multiple), or
      //   * two neighbouring slabs are copies of two neighbouring slabs as far away (a block that recurs: its
      //     length is the period, as with the alternately mirrored panels of a folding screen), or
      //   * no slab between two copies is a copy of none (nothing occurs once between them).
      std::vector<std::pair<int, int>> far;
      bool decided = true;
      int plain_middle = -1;  // B of an A B A whose B repeats
      for (int i = 0; i < n; ++i)
        for (int j = i + 2; j < n; ++j) {
          if (gap[std::size_t(i)] || gap[std::size_t(j)] || !copies(i, j) || plain_alone(i)) continue;
          decided = decided && j > i + 2 &&
                    std::find(far.begin(), far.end(), std::pair<int, int>{i - 1, j - 1}) == far.end();
          far.push_back({i, j});
        }
      // One A B A between the model's ends and nothing else (docs/method.md 2.10, The plain one repeats):
      // where B's difference from the A's is plain (its samples that land off an A, moved along a by the
      // plain test's shift within B, land on the surface: a stretch of wall where the A's have a slot) and
      // the A's difference from B is not, B repeats and each A is a part (a slot next to each end); the
      // other way round the A's repeat and B is a part (a notch in the middle); otherwise it stays
      // undecided. Between the ends: no whole slab outside it is a copy of an A or of B but for the end's
      // reach into it (plain wall and a polarisation key's end are none; alternating balusters, plain, ring,
      // plain, ring, whose first plain one holds a post's face too, are two modules of two, not three).
      // Slab k outside is a copy of slab l but for what the model's end brings less than half a cell into it
      // (as an end cell is read by its periodic part, 1.7): every sample of either that lands off the other
      // lies, in k, nearer the plane of k toward the end than half a cell.
      const auto copy_but_end = [&](int k, int l) {
        double reach = 0;
        for (const auto& [from, shift] : {std::pair<int, int>{k, l - k}, std::pair<int, int>{l, k - l}})
          for (const std::size_t q : slab[std::size_t(from)]) {
            const double t = canonical[q][a] + shift;
            if (t < lo_cmp || t >= hi_cmp || !off_surface(q, double(shift))) continue;
            const double in_k = from == k ? canonical[q][a] : t;
            reach = std::max(reach, k < l ? in_k - k : k + 1 - in_k);
          }
        return reach < 0.5;
      };
      const auto spans = [&](int i, int j) {
        for (int k = 0; k < n; ++k)
          if ((k < i || k > j) && whole_slab(k) && !plain_alone(k) && (copy_but_end(k, i) || copy_but_end(k, i + 1)))
            return false;
        return true;
      };
      if (!decided && far.size() == 1 && far[0].second == far[0].first + 2 && spans(far[0].first, far[0].second)) {
        const int i = far[0].first, m = i + 1;
        const bool middle_plain = difference_plain(m, -1) && difference_plain(m, 1);
        const bool ends_plain = difference_plain(i, 1) && difference_plain(i + 2, -1);
        if (middle_plain && !ends_plain) {
          plain_middle = m;
          far.clear();
        } else if (ends_plain && !middle_plain) {
          decided = true;
        }
      }
      if (!decided) far.clear();
      for (const auto& [i, j] : far) {
        if (copy_of[std::size_t(i)] < 0) copy_of[std::size_t(i)] = j;
        if (copy_of[std::size_t(j)] < 0) copy_of[std::size_t(j)] = i;
      }
      bool singular_between = false;
      for (const auto& [i, j] : far)
        for (int m = i + 1; m < j; ++m) singular_between = singular_between || copy_of[std::size_t(m)] < 0;
      if (singular_between) s.far_copies[std::size_t(a)] = true;
      else copy_of.assign(std::size_t(n), -1);
      if (plain_middle >= 0) {
        copy_of[std::size_t(plain_middle)] = plain_middle;  // one period of what repeats
        s.plain_middle[std::size_t(a)] = true;
      }
    }
    if (gaps) {
      // What else repeats must have the surface the gaps lack: some sample of it, moved to some place inside a
      // slab that repeats, lands on the surface. Otherwise (the runs of slats either side of a rail, which both
      // lack the rail's face) the gaps were no gaps, and the reading is as without them.
      bool others_have = false;
      for (int i = 0; i < n && !others_have; ++i) {
        if (copy_of[std::size_t(i)] < 0) continue;
        const double u0 = std::max(double(i), lo_cmp), u1 = std::min(double(i + 1), hi_cmp);
        for (const std::size_t k : lacked) {
          for (double u = u0 + 0.5 * lack_step; u < u1 && !others_have; u += lack_step)
            others_have = !off_surface(k, u - canonical[k][a]);
          if (others_have) break;
        }
      }
      const bool none = std::count(copy_of.begin(), copy_of.end(), -1) == n;
      if (none || !others_have) {  // the gaps are what repeats
        copy_of = next_door;
        s.far_copies[std::size_t(a)] = s.plain_middle[std::size_t(a)] = false;
        s.gap_run[std::size_t(a)] = none;
      }
    }
    if (std::count(copy_of.begin(), copy_of.end(), -1) == n) {  // nothing repeats
      const WholeSlabs whole = whole_slabs();
      s.undecided[std::size_t(a)] = whole.undecided();
      // Two whole slabs and, past the end plane beside one of them, an end cell that lies whole within the
      // model (docs/method.md 2.10, The plain one repeats, A module in the end cell): the end cell, compared
      // over its whole cell, may be the third module of an A B A (a connector's last pin with its slot, past
      // an end plane cut before it). Where it is a copy of the farther whole slab, B's difference from the
      // A's is plain and theirs from B is not, B repeats.
      if (whole.count == 2 && whole.inside > 0) {
        const int x = whole.first, y = whole.first + 1;
        int e = -1, b = -1, other = -1;  // the end cell, B, the whole A
        if (y + 1 == n - 1 && hi < double(n) && m1 >= double(n) - 1e-9) e = n - 1, b = y, other = x;
        else if (x == 1 && lo > 0 && m0 <= 1e-9) e = 0, b = x, other = y;
        // Cell `from`'s samples moved by `shift` land on the surface (every sample of the cell, end or not).
        const auto lands_whole = [&](int from, int shift) {
          for (std::size_t k = 0; k < points.size(); ++k)
            if (std::floor(canonical[k][a]) == double(from) && off_surface(k, double(shift))) return false;
          return true;
        };
        if (e >= 0 && lands_whole(e, other - e) && lands_whole(other, e - other)) {
          const bool middle_plain = difference_plain(b, other - b, true) && difference_plain(b, e - b, true);
          const bool ends_plain = difference_plain(other, b - other, true) && difference_plain(e, b - e, true);
          if (middle_plain && !ends_plain) {
            copy_of[std::size_t(b)] = b;  // one period of what repeats
            s.plain_middle[std::size_t(a)] = true;
            s.undecided[std::size_t(a)] = false;
          }
        }
      }
      if (std::count(copy_of.begin(), copy_of.end(), -1) == n) {
        // Nothing repeats, and the axis is not undecided: one whole slab between the end planes, or two at the
        // ends. A resize copies a whole slab inside the model; where one lacks all along a wall both sides
        // share (a 3-column box header's notch between its end planes, the front wall in the end cells), it may
        // be a gap in one part (docs/method.md 2.10, A gap is no repeat): warned.
        for (int i = 1; i + 1 < n && !s.undecided[std::size_t(a)] && !s.gap_run[std::size_t(a)]; ++i)
          s.gap_run[std::size_t(a)] = whole_slab(i) && lacks_all_along(double(i), double(i + 1), Lack::wall, nullptr);
        continue;
      }
    }
    // A slab that repeats next door is periodic. One that does not may still be a copy of a periodic one
    // farther away (a box header's plain column beside the shroud's end, whose neighbour has the notch),
    // unless the two are end slabs plain where compared (copies at any shift, as above).
    const std::vector<int> periodic = copy_of;
    for (int i = 0; i < n; ++i)
      for (int d = 2; d < n && copy_of[std::size_t(i)] < 0; ++d)
        for (const int j : {i - d, i + d})
          if (j >= 0 && j < n && periodic[std::size_t(j)] >= 0 && copy_of[std::size_t(i)] < 0 && copies(i, j) &&
              !plain_ends(i, j))
            copy_of[std::size_t(i)] = j;
    // Where a part's own content lies along a (docs/method.md 2.10, Anchors): the positions whose surface differs
    // from the surface one period either side, over the part's slabs and one slab either side of them
    // (a part's content can reach past its slabs: a rail as tall as the slat pitch, within the tolerance, whose
    // bottom falls in the slab below and reads there as a copy of the top rail's bottom). What it has that
    // neither neighbouring period has: its samples that land off the surface moved one period either way (a
    // rail's faces, a notch's sides and its floor where the wall is a period away). What it lacks that a
    // period has on both sides of it: a sample whose move by one period lands off the surface, at its moved
    // place, where the move by two periods lands on it again (a missing slat between two slats). Moves
    // that leave the compared range tell nothing, and are skipped. Where neither finds anything, the
    // difference from the nearest repeating slab (below) places it.
    const auto content_local = [&](int first, int last, std::vector<Eigen::Vector3d>& where) {
      const double t0 = std::max(lo_cmp, double(first - 1)), t1 = std::min(hi_cmp, double(last + 2));
      const auto inside = [&](double t) { return t >= lo_cmp && t < hi_cmp; };
      double lo_t = INFINITY, hi_t = -INFINITY;
      const auto note = [&](double t, const Eigen::Vector3d& at) {
        lo_t = std::min(lo_t, t), hi_t = std::max(hi_t, t);
        where.push_back(at);
      };
      for (std::size_t k = 0; k < points.size(); ++k) {
        const double t = canonical[k][a];
        if (t < t0 || t >= t1 || !inside(t + 1) || !inside(t - 1)) continue;
        const bool up = off_surface(k, 1), down = off_surface(k, -1);
        if (up && down) {
          note(t, points[k]);
          continue;
        }
        for (const int d : {1, -1})
          if ((d == 1 ? up : down) && t + d >= double(first) && t + d < double(last + 1) && inside(t + 2 * d) &&
              !off_surface(k, 2.0 * d))
            note(t + d, points[k] + double(d) * v);
      }
      return std::pair<double, double>{lo_t, hi_t};
    };
    // The difference of the part's slabs from the repeating slab nearest to each (the run on its side: a rail
    // between two runs of slats may shift one against the other): the samples of that slab moved onto the
    // part that land off the surface (what the part lacks: a key notch), at their moved place, and the
    // part's samples moved onto it that land off the surface (what it has more: the notch's sides), at their
    // own place. Their extent's middle, over the part's slabs, where the local difference above finds
    // nothing; the slabs' middle without a repeating slab.
    const auto content_centre = [&](int first, int last, std::vector<Eigen::Vector3d>& where) {
      const auto nearest_repeating = [&](int j) {  // the lower on a tie; -1 when none
        for (int d = 1; d < n; ++d)
          for (const int i : {j - d, j + d})
            if (i >= 0 && i < n && copy_of[std::size_t(i)] >= 0) return i;
        return -1;
      };
      double lo_t = INFINITY, hi_t = -INFINITY;
      const auto note_off = [&](int from, int shift, bool at_moved) {
        for (const std::size_t k : slab[std::size_t(from)]) {
          const double t = canonical[k][a] + shift;
          if (t < lo_cmp || t >= hi_cmp) continue;
          if (surface->distance_within(points[k] + double(shift) * v, 2 * s.tolerance) <= s.tolerance) continue;
          const double at = at_moved ? t : canonical[k][a];
          lo_t = std::min(lo_t, at), hi_t = std::max(hi_t, at);
          where.push_back(at_moved ? Eigen::Vector3d(points[k] + double(shift) * v) : points[k]);
        }
      };
      for (int j = first; j <= last; ++j)
        if (const int background = nearest_repeating(j); background >= 0) {
          note_off(background, j - background, true);
          note_off(j, background - j, false);
        }
      // Both sets of samples are the part's content (where it is, and where what it lacks would be: the
      // seeds of a centred part's move, restitch/retarget/centring.hpp); the local one places its centre.
      if (const auto [l0, l1] = content_local(first, last, where); l0 <= l1) return 0.5 * (l0 + l1);
      return lo_t <= hi_t ? 0.5 * (lo_t + hi_t) : 0.5 * double(first + last + 1);
    };
    // The parts along a: the runs of slabs that do not repeat (built again below when a run out of phase
    // splits one).
    const auto find_parts = [&]() {
      s.parts.erase(std::remove_if(s.parts.begin(), s.parts.end(), [a](const SingularPart& p) { return p.axis == a; }),
                    s.parts.end());
      for (int i = 0; i < n;) {
        if (copy_of[std::size_t(i)] >= 0) {
          ++i;
          continue;
        }
        SingularPart p;
        p.axis = a;
        p.first = i;
        while (i + 1 < n && copy_of[std::size_t(i + 1)] < 0) ++i;
        p.last = i++;
        const double centre = content_centre(p.first, p.last, p.content), to_low = centre - m0, to_high = m1 - centre;
        p.offset = 0.5 * (to_low - to_high);
        p.precision = s.spacing[a];
        if (p.first == 0)
          p.anchor = PartAnchor::low;
        else if (p.last == n - 1)
          p.anchor = PartAnchor::high;
        else if (std::abs(p.offset) <= s.centre_band(a))
          p.anchor = PartAnchor::centre;
        else
          p.anchor = to_low < to_high ? PartAnchor::low : PartAnchor::high;
        s.parts.push_back(p);
      }
      // Parts that are copies of the next one along a (docs/method.md 1.12): the same number of slabs, each a
      // copy of its counterpart.
      for (std::size_t i = s.parts.size(); i-- > 0;) {
        SingularPart& p = s.parts[i];
        if (p.axis != a || i + 1 >= s.parts.size() || s.parts[i + 1].axis != a) continue;
        SingularPart& q = s.parts[i + 1];
        if (q.last - q.first != p.last - p.first) continue;
        bool same = true;
        for (int j = p.first; j <= p.last && same; ++j) same = copies(j, j + (q.first - p.first));
        if (same) p.repeated = q.repeated = true;
      }
    };
    find_parts();
    // A run out of phase inside an end part: windows of one period at a phase other than the cells', swept
    // in steps of half a sample spacing and each short of one step at both ends (a run of exactly two fills
    // its two windows over two steps of phase only, which the sweep hits), whose samples moved onto each
    // other land on the surface, and whose content changes along a (the plain test above, on the first
    // window). An end part only: what a part kept at the centre holds is kept there whole on purpose (the
    // pins inside a centred key notch repeat, and the notch must not widen), while a run at an end, past a
    // rail, is a run the grow would leave out. Two windows, so three slabs at least; at the cells' own phase
    // (within two steps, one sample spacing: a run closer to the planes has no sample between its own
    // bounds and theirs to tell them apart) the windows are the part's slabs, no copies. The one slab that
    // lies inside the two windows is one period of the run (its copy one period on continues it), so it
    // repeats (copy_of: itself), and the part is split around it: the run grows with the others.
    std::vector<std::size_t> order;  // the samples by position along a, built for the first such part
    const double step = std::max(0.5 * s.spacing[a], 1e-3);
    std::vector<int> run_slabs;  // per run found, the slab inside its two windows
    for (const SingularPart& p : s.parts) {
      if (p.axis != a || p.last - p.first < 2 || (p.first > 0 && p.last < n - 1)) continue;
      if (order.empty()) {
        for (std::size_t k = 0; k < points.size(); ++k) order.push_back(k);
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
          return canonical[x][a] != canonical[y][a] ? canonical[x][a] < canonical[y][a] : x < y;
        });
      }
      const auto at = [&](double t) {  // the first sample of `order` at t or past it
        return std::size_t(std::lower_bound(order.begin(), order.end(), t,
                                            [&](std::size_t k, double v) { return canonical[k][a] < v; }) -
                           order.begin());
      };
      // The samples in [from + step, from + 1 - step), moved by `shift` periods, all land on the surface.
      const auto land = [&](double from, double shift) {
        const std::size_t i0 = at(from + step), i1 = at(from + 1 - step);
        for (std::size_t i = i0; i < i1; ++i)
          if (off_surface(order[i], shift)) return false;
        return i0 < i1;
      };
      // Up to the model's end, past an end plane: that plane is where the end cap is cut most cheaply, which
      // may lie below where the run ends (a run of two whose last slat's cell holds the top rail's bottom).
      const double low = std::max(double(p.first), m0), high = std::min(double(p.last + 1), m1);
      for (double w = low - step; w + 2 - step <= high; w += step) {
        const double phase = w - std::floor(w);
        const int inner = int(std::ceil(w));  // the slab inside the two windows: an end slab is the end
        if (std::min(phase, 1 - phase) < 2 * step || inner <= 0 || inner >= n - 1 || !land(w, 1) ||
            !land(w + 1, -1) || land(w, slide))
          continue;
        run_slabs.push_back(inner);  // inside the part: w lies a spacing or more off a cell plane
        break;
      }
    }
    for (const int i : run_slabs) copy_of[std::size_t(i)] = i;
    if (!run_slabs.empty()) find_parts();
    // Copies read through an end (docs/method.md 2.10): every two slabs found copies hold an end slab compared
    // over its periodic part, which matches its neighbour by construction, so that, those aside, the whole
    // slabs between the end planes are as many as would leave the axis undecided (three, or two of which one is
    // not an end slab) and none is a copy of another; and the model's two sides of the run of repeating slabs
    // share a surface the run lacks all along (lacks_all_along, over the whole model). The run may then be a
    // gap in one part, not a repeat.
    bool through_end = false, whole_copies = false;
    int r0 = n, r1 = -1;  // the run of repeating slabs
    for (int i = 0; i < n; ++i) {
      const int j = copy_of[std::size_t(i)];
      if (j >= 0 && j != i) (partial(i) || partial(j) ? through_end : whole_copies) = true;
      if (j >= 0) r0 = std::min(r0, i), r1 = std::max(r1, i + 1);
    }
    // With one whole slab only, the run's reach is the evidence: the surface it lacks must be a wall it
    // interrupts (lacks_all_along, Lack::wall), not the ends' own structure (two pickets between posts
    // narrower than their pitch lack the posts' faces all along).
    if (through_end && !whole_copies) {
      const WholeSlabs whole = whole_slabs();
      const double t0 = std::max(double(r0), lo_cmp), t1 = std::min(double(r1), hi_cmp);
      if (whole.undecided()) s.end_read[std::size_t(a)] = lacks_all_along(t0, t1, Lack::anywhere, nullptr);
      else if (whole.count == 1) s.end_read[std::size_t(a)] = lacks_all_along(t0, t1, Lack::wall, nullptr);
    }
  }
  return s;
}

}  // namespace restitch
