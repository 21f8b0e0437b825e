// restitch/retarget/centring.hpp - a centred part moved the half period that whole periods cannot (docs/method.md 2.10).
//
// A part kept at the centre (restitch/lattice/structure.hpp) of a model whose length is a whole number of
// periods plus the part's own offset comes out half a period off the new centre at every odd change:
// copies move by whole periods, the centre by half of each. A modeller moves the part alone where what
// lies around it lets it slide: a box header's key notch in a plain front wall slides half a pitch along
// the wall while the pins under it stay. `centre_part` does that on the stitched result R (before
// placement, in the input's frame), on a grid of cells finer than the period:
//
//   * Seeds: the cells within a sample spacing of the part's content (SingularPart::content, moved with
//     the part's shift) where R has it and where it belongs, half a period on. The region S they start
//     copies R moved by that half period h. Where the part goes, what R has that R moved lacks is lost:
//     content that repeats at the period and crosses the axis (a slat half a period from a rail) stops
//     the move.
//   * Coincide, in a box: every sample of R in it, moved back by h, lies on R within the structure's
//     tolerance, and so does every sample that h moves into it (R and R moved are the same surface there).
//   * Flood: across a face of S where R and R moved do not coincide (the face grown by one sample spacing
//     every way: every surface that crosses the face has samples that near), the cell beyond joins S, and
//     must itself be plain (coincide whole): a pin or a slat the move would carry out of step with its
//     neighbours stops it. A face where they coincide is a seam the stitcher welds shut.
//   * Groove: beside S along the axis, within a period, each cell that S leaves and that holds content
//     repeating at the period (it coincides with itself one period on) must be plain too: a part next to
//     repeated content along the axis (a rail between slats) keeps a distance to it that half a period
//     would change. The output's end cells are the model's ends, whose distance is what the move sets.
//   * S, its box of cells where that fits (plain, on plain faces, allowed), stays within the part's output
//     cells and one on either side; the stitch must open no more boundary than R has (by length: a cut
//     through an open edge leaves its length as it was). Otherwise the part stays where whole periods put
//     it, and the planned "part off centre" warning stands.
//
// The grid: along the resized axis 2 m cells a period, m the whole number that makes a cell nearest to two
// sample spacings (a face's neighbourhood, one spacing either side, then spans a cell: the faces to choose
// from lie as close as the test can tell apart); across, R's extent in cells as long, coarser until the
// grid holds at most `max_cells`. The stitch runs on the coarsest grid that keeps S's box and the move
// whole (the stitcher partitions a triangle over the cells it crosses).
//
// Resolution: the part's content marks cells a spacing around it, and a face is tested a spacing either
// side, so content that repeats (a pin) nearer the part than about three spacings shares a cell with it or
// with a face the part's flood crosses or with the groove beside it, and stops the move. Where the move
// stops at such a cell, it is tried once more on samples and cells of half the spacing (the part's content
// keeps its own spacing): four times the samples, only where the first try stops at content.
//
// Cost: a Poisson-disk sample of R at the analysis' dense spacing, a tree over R's triangles, bounded
// point-to-surface queries for the samples of the cells and faces tested, and one stitch of R.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <numeric>
#include <vector>

#include "restitch/detail/triangle_surface.hpp"
#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/lattice/structure.hpp"
#include "restitch/mesh.hpp"
#include "restitch/mesh_boundary.hpp"
#include "restitch/normalization.hpp"
#include "restitch/sampling/poisson_disk.hpp"
#include "restitch/status.hpp"
#include "restitch/stitch/stitch.hpp"

namespace restitch {

/// Whether part p, resized by k cells along its axis with CellStructure::shift_of, lies farther from the
/// new centre than it lay from the old one (half a period: whole periods cannot centre it), and the way
/// (+1, -1) it would move to lie as it did; 0 when it lies as near as before.
inline int centring_move(const SingularPart& p, int k) {
  if (p.anchor != PartAnchor::centre) return 0;
  const double after = CellStructure::offset_after(p, k);
  if (!(std::abs(after) > std::abs(p.offset) + 1e-9)) return 0;
  return p.offset - after > 0 ? 1 : -1;
}

/// Options of centre_part.
struct CentringOptions {
  double tolerance = 0;   ///< model units: the structure's (R and R moved coincide within it)
  double spacing = 0;     ///< model units: the analysis' dense sample spacing (of the part's content)
  double weld = 1e-6;     ///< the stitcher's weld tolerance (fraction of the diagonal), for the open-edge count
  std::int64_t max_cells = std::int64_t(1) << 20;  ///< cells of the fine grid at most
  std::uint64_t seed = 0x5eed;  ///< of R's samples
};

namespace detail {

/// How one try of centre_part ended.
enum class CentringTry {
  moved,
  stopped_at_content,  ///< a cell the flood reached or the groove holds is not plain: finer samples may
                       ///< separate it from the part
  not_moved
};

/// One try of centre_part, on samples and cells of spacing `spacing` (o.spacing: the content's).
template <class StitchFn>
Status centre_part_at(const Mesh& R, const Lattice& grid, const Eigen::Array3i& cells_out, const SingularPart& p,
                      int d, int move, const CentringOptions& o, double spacing, StitchFn& stitch, Mesh& out,
                      CentringTry& how) {
  how = CentringTry::not_moved;
  const int a = p.axis;
  const Eigen::Vector3d v = grid.A.col(a);
  const double period = v.norm();
  // The fine grid: m cells a half period along a, cells as long across R's extent (file comment).
  const int m = std::max(1, int(std::lround(0.5 * period / (2 * spacing))));
  Lattice F;
  F.A = grid.A;
  F.origin = grid.origin;
  const Eigen::Matrix3d Ainv = grid.A.inverse();
  Eigen::Array3d lo = Eigen::Array3d::Constant(INFINITY), hi = Eigen::Array3d::Constant(-INFINITY);
  for (Eigen::Index i = 0; i < R.V.rows(); ++i) {
    const Eigen::Array3d c = (Ainv * (R.V.row(i).template cast<double>().transpose() - grid.origin)).array();
    lo = lo.min(c), hi = hi.max(c);
  }
  double cell = period / (2 * m);  // across: as along a
  if (std::int64_t(cells_out[a]) * 2 * m > o.max_cells) return {};
  for (;;) {
    std::int64_t total = std::int64_t(cells_out[a]) * 2 * m;
    for (int b = 0; b < 3; ++b) {
      if (b == a) continue;
      const double len = (hi[b] - lo[b]) * grid.A.col(b).norm();
      F.cells[b] = std::max(1, int(std::ceil(len / cell - 1e-9)));
      total *= F.cells[b];
    }
    if (total <= o.max_cells) break;
    cell *= 1.5;  // coarser across the axis until the grid fits
  }
  F.cells[a] = cells_out[a] * 2 * m;
  F.A.col(a) = v / (2 * m);
  for (int b = 0; b < 3; ++b) {
    if (b == a) continue;
    F.origin += lo[b] * grid.A.col(b);
    F.A.col(b) = grid.A.col(b) * ((hi[b] - lo[b]) / F.cells[b]);
    if (!(hi[b] > lo[b])) F.A.col(b) = grid.A.col(b);  // a flat model across b: one cell of any size
  }
  F.end_low.setZero(), F.end_high.setOnes();
  F.dummy = {{false, false, false}};
  const Eigen::Matrix3d Finv = F.A.inverse();
  const CellGrid G(F.cells);
  const Eigen::Vector3d h = double(move) * 0.5 * v;  // the move, model units
  const int hm = move * m;                           // the move, fine cells along a

  // R's samples by fine cell, and its surface.
  Normalization norm = Normalization::of(bounding_box(R));
  Result<PointSet> samples = poisson_disk_sample(R, norm, spacing * norm.scale, o.seed);
  if (!samples.ok()) return {};  // too many samples or no area: the part stays
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::vector<std::uint32_t>> by_cell(std::size_t(G.size()));
  for (Eigen::Index i = 0; i < samples->points.rows(); ++i) {
    const Eigen::Vector3d q = norm.to_model(samples->points.row(i).template cast<double>().transpose());
    by_cell[std::size_t(G.index(G.cell_of(Finv * (q - F.origin))))].push_back(std::uint32_t(pts.size()));
    pts.push_back(q);
  }
  const detail::TriangleSurface surface(R);
  const auto on = [&](const Eigen::Vector3d& q) { return surface.distance_within(q, 2 * o.tolerance) <= o.tolerance; };

  const auto unit = [](int b) {
    Eigen::Array3i e = Eigen::Array3i::Zero();
    e[b] = 1;
    return e;
  };
  // The cells S may hold: the part's output cells and one on either side, inside the grid once moved.
  const int first = std::max(0, (p.first + d - 1) * 2 * m), last = std::min(F.cells[a], (p.last + d + 2) * 2 * m) - 1;
  const auto allowed = [&](const Eigen::Array3i& c) { return c[a] >= first && c[a] <= last && G.inside(c - hm * unit(a)); };
  // Whether R and R moved by h coincide in a box of fine canonical coordinates: the samples of R in it,
  // moved back by h, and those that h moves into it, lie on R.
  // `by`: the move in fine cells along a (hm, or a whole period for coincide_moved).
  const auto coincide_moved = [&](const Eigen::Array3d& box_lo, const Eigen::Array3d& box_hi, int by) {
    const Eigen::Vector3d step = double(by) * F.A.col(a);
    for (const int before : {0, 1}) {  // 0: samples in the box; 1: samples one move before it
      Eigen::Array3d lo_t = box_lo, hi_t = box_hi;
      if (before) lo_t[a] -= by, hi_t[a] -= by;
      const Eigen::Vector3d mv = before ? step : Eigen::Vector3d(-step);
      Eigen::Array3i c0, c1;
      for (int e = 0; e < 3; ++e)
        c0[e] = std::max(0, int(std::floor(lo_t[e]))), c1[e] = std::min(F.cells[e] - 1, int(std::floor(hi_t[e])));
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
          for (int x = c0[0]; x <= c1[0]; ++x)
            for (const std::uint32_t i : by_cell[std::size_t(G.index(x, y, z))]) {
              const Eigen::Array3d t = (Finv * (pts[i] - F.origin)).array();
              if ((t < lo_t).any() || (t > hi_t).any()) continue;
              if (!on(pts[i] + mv)) return false;
            }
    }
    return true;
  };
  const auto coincide_in = [&](const Eigen::Array3d& box_lo, const Eigen::Array3d& box_hi) {
    return coincide_moved(box_lo, box_hi, hm);
  };
  // Around the face of cell c toward -b (side 0) or +b (side 1): the face grown by a spacing every way.
  Eigen::Array3d grow;
  for (int b = 0; b < 3; ++b) grow[b] = spacing / F.A.col(b).norm();
  const Eigen::Array3d reach = grow * (o.spacing / spacing);  // a content sample's: its own spacing
  const auto coincide_at_face = [&](const Eigen::Array3i& c, int b, int side) {
    Eigen::Array3d box_lo = c.cast<double>() - grow, box_hi = c.cast<double>() + 1 + grow;
    box_lo[b] = c[b] + side - grow[b], box_hi[b] = c[b] + side + grow[b];
    return coincide_in(box_lo, box_hi);
  };

  // Seeds: the part's content where R has it and where it belongs.
  std::vector<char> in_s(std::size_t(G.size()), 0);
  std::deque<std::int64_t> queue;
  const auto add = [&](const Eigen::Array3i& c) {
    if (!allowed(c)) return false;
    const std::int64_t x = G.index(c);
    if (!in_s[std::size_t(x)]) in_s[std::size_t(x)] = 1, queue.push_back(x);
    return true;
  };
  // A content sample stands for the surface within a spacing of it: every cell that reaches that near is a
  // seed (a notch's side whose lowest strip lies in the cell below its samples).
  std::vector<char> where_it_is(std::size_t(G.size()), 0);  // seeds at the part's place in R
  for (const Eigen::Vector3d& q : p.content) {
    const Eigen::Vector3d at = q + double(d) * v;
    for (const int there : {0, 1}) {
      const Eigen::Array3d t = (Finv * (at + double(there) * h - F.origin)).array();
      Eigen::Array3i c0, c1;
      for (int e = 0; e < 3; ++e)
        c0[e] = std::clamp(int(std::floor(t[e] - reach[e])), 0, F.cells[e] - 1),
        c1[e] = std::clamp(int(std::floor(t[e] + reach[e])), 0, F.cells[e] - 1);
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int yy = c0[1]; yy <= c1[1]; ++yy)
          for (int x = c0[0]; x <= c1[0]; ++x) {
            if (!add(Eigen::Array3i(x, yy, z))) return {};
            if (!there) where_it_is[std::size_t(G.index(x, yy, z))] = 1;
          }
    }
  }
  // Where the part goes, the move replaces R by R moved. What R has there and R moved lacks is lost; where
  // that is content repeating at the period (on R a period up or down) and not plain (moved along the axis
  // by the structure's plain shift, half a spacing and at least twice the tolerance, it leaves the
  // surface: it crosses the axis), the part would take the place of a slat or a pin of the run beside it
  // (a rail half a period from the next slat).
  {
    const Eigen::Vector3d u = v / period * std::max(0.5 * o.spacing, 2 * o.tolerance);
    for (std::int64_t x = 0; x < G.size(); ++x) {
      if (!in_s[std::size_t(x)] || where_it_is[std::size_t(x)]) continue;
      for (const std::uint32_t i : by_cell[std::size_t(x)]) {
        const Eigen::Vector3d& q = pts[i];
        if (on(q - h) || (on(q + u) && on(q - u))) continue;
        if (on(q + v) || on(q - v)) {
          how = CentringTry::stopped_at_content;
          return {};
        }
      }
    }
  }
  // The flood: a face across which R and R moved differ takes the cell beyond into S.
  while (!queue.empty()) {
    const Eigen::Array3i c = G.cell(queue.front());
    queue.pop_front();
    for (int b = 0; b < 3; ++b)
      for (const int side : {0, 1}) {
        const Eigen::Array3i n = c + (side ? 1 : -1) * unit(b);
        if (!G.inside(n) || in_s[std::size_t(G.index(n))] || coincide_at_face(c, b, side)) continue;
        // A cell without the part's content joins only where R and R moved coincide in it (a plain wall): what
        // repeats (a slat, a pin) would come out half a period out of step with its neighbours.
        if (!coincide_in(n.cast<double>(), n.cast<double>() + 1)) {
          how = CentringTry::stopped_at_content;
          return {};
        }
        if (!add(n)) return {};
      }
  }
  // S as found follows the cells, so its faces cut whatever crosses them, a long face many times. A box of
  // cells around it serves instead where one can (its other cells plain and allowed, its faces on plain
  // surfaces): a seam at six planes at most. Its length along a is made a whole number of moves where the
  // cells beyond allow (the stitch grid's cells along a can then be the move's length, below).
  Eigen::Array3i b0 = F.cells, b1 = Eigen::Array3i::Constant(-1);
  for (std::int64_t x = 0; x < G.size(); ++x)
    if (in_s[std::size_t(x)]) b0 = b0.min(G.cell(x)), b1 = b1.max(G.cell(x));
  const auto box_fits = [&](const Eigen::Array3i& lo_c, const Eigen::Array3i& hi_c) {
    for (int z = lo_c[2]; z <= hi_c[2]; ++z)
      for (int y = lo_c[1]; y <= hi_c[1]; ++y)
        for (int x = lo_c[0]; x <= hi_c[0]; ++x) {
          const Eigen::Array3i c(x, y, z);
          if (!allowed(c)) return false;
          if (!in_s[std::size_t(G.index(c))] && !coincide_in(c.cast<double>(), c.cast<double>() + 1)) return false;
          for (int b = 0; b < 3; ++b)
            for (const int side : {0, 1})
              if ((side ? c[b] == hi_c[b] : c[b] == lo_c[b]) && G.inside(c + (side ? 1 : -1) * unit(b)) &&
                  !coincide_at_face(c, b, side))
                return false;
        }
    return true;
  };
  bool box = false;
  {
    const int len = b1[a] - b0[a] + 1, need = (std::abs(hm) - len % std::abs(hm)) % std::abs(hm);
    for (int below = 0; below <= need && !box; ++below) {
      Eigen::Array3i lo_c = b0, hi_c = b1;
      lo_c[a] -= below, hi_c[a] += need - below;
      if (lo_c[a] >= 0 && hi_c[a] < F.cells[a] && box_fits(lo_c, hi_c)) box = true, b0 = lo_c, b1 = hi_c;
    }
    if (!box) box = box_fits(b0, b1);
    if (box)
      for (int z = b0[2]; z <= b1[2]; ++z)
        for (int y = b0[1]; y <= b1[1]; ++y)
          for (int x = b0[0]; x <= b1[0]; ++x) in_s[std::size_t(G.index(x, y, z))] = 1;
  }
  // Beside the part along its axis, within a period, what S leaves must be plain too (a groove it slides
  // in): a part next to content that repeats (a rail between slats) keeps a distance to it that a half
  // period would change, and the runs on either side would no longer match. The output's end cells are
  // the model's ends, whose distance to a centred part is what the move sets right.
  std::vector<char> plain(std::size_t(G.size()), 0);  // 1: coincides, 2: does not, 0: not yet tested
  for (std::int64_t x = 0; x < G.size(); ++x) {
    if (!in_s[std::size_t(x)]) continue;
    Eigen::Array3i n = G.cell(x);
    for (n[a] = std::max(first, 2 * m); n[a] <= std::min(last, F.cells[a] - 2 * m - 1); ++n[a]) {  // not the ends
      const std::int64_t y = G.index(n);
      if (in_s[std::size_t(y)] || plain[std::size_t(y)] == 1) continue;
      if (plain[std::size_t(y)] == 0)
        plain[std::size_t(y)] = by_cell[std::size_t(y)].empty() || coincide_in(n.cast<double>(), n.cast<double>() + 1) ||
                                        !coincide_moved(n.cast<double>(), n.cast<double>() + 1, 2 * hm)
                                    ? 1
                                    : 2;
      if (plain[std::size_t(y)] == 2) {
        how = CentringTry::stopped_at_content;
        return {};
      }
    }
  }
  // The stitch: on the fine grid, or, for a box, on a grid of as few cells as keep the box's planes and the
  // move whole (along a: a whole divisor of both; across: the box's own length), so that the stitcher's
  // cuts (a partition over each triangle's cells) do not split the triangles that cross it cell by cell.
  Lattice L = F;
  Eigen::Array3i step = Eigen::Array3i::Ones(), from = Eigen::Array3i::Zero();
  if (box)
    for (int b = 0; b < 3; ++b) {
      const int len = b1[b] - b0[b] + 1;
      step[b] = b == a ? std::gcd(len, std::abs(hm)) : len;
      from[b] = b0[b] - step[b] * ((b0[b] + step[b] - 1) / step[b]);
      L.cells[b] = (F.cells[b] - from[b] + step[b] - 1) / step[b];
      L.A.col(b) = F.A.col(b) * step[b];
      L.origin += double(from[b]) * F.A.col(b);
    }
  const CellGrid LG(L.cells);
  std::vector<Eigen::Array3i> shift(std::size_t(LG.size()), Eigen::Array3i::Zero());
  for (std::int64_t x = 0; x < LG.size(); ++x) {
    const Eigen::Array3i c = from + LG.cell(x) * step;  // its first fine cell
    if (G.inside(c) && in_s[std::size_t(G.index(c))]) shift[std::size_t(x)][a] = hm / step[a];
  }
  Mesh result;
  StitchReport st;
  RESTITCH_TRY(stitch(R, L, L.cells, shift, result, st));
  // Open edges: their length, which a cut through an open edge (two pieces) or a move of one leaves as it was;
  // a seam that the two sides do not continue adds to it.
  const auto open_length = [&](const Mesh& mesh) {
    double length = 0;
    for (const BoundaryEdge& e : boundary_edges_at(mesh, weld_tolerance_of(mesh, o.weld)))
      length += double((mesh.V.row(e.a) - mesh.V.row(e.b)).norm());
    return length;
  };
  if (result.empty() || open_length(result) > open_length(R) + o.tolerance) return {};
  out = std::move(result);
  how = CentringTry::moved;
  return {};
}

}  // namespace detail

/// Moves part p of the stitched result R (input frame, output cells `cells_out` of lattice `grid`, the
/// part copied with shift `d` cells along its axis) by half a period the way `move` (+1, -1) says, alone,
/// with `stitch(mesh, lattice, cells_out, shift, out, report)` (the stitcher's plain call): see the file
/// comment. `moved` says whether it was; when not, `out` is untouched. Errors: the stitcher's.
template <class StitchFn>
Status centre_part(const Mesh& R, const Lattice& grid, const Eigen::Array3i& cells_out, const SingularPart& p, int d,
                   int move, const CentringOptions& o, StitchFn&& stitch, Mesh& out, bool& moved) {
  moved = false;
  if (move == 0 || p.content.empty() || R.empty() || !(o.spacing > 0) || !(o.tolerance > 0)) return {};
  detail::CentringTry how = detail::CentringTry::not_moved;
  RESTITCH_TRY(detail::centre_part_at(R, grid, cells_out, p, d, move, o, o.spacing, stitch, out, how));
  if (how == detail::CentringTry::stopped_at_content)  // content nearer than the samples tell apart
    RESTITCH_TRY(detail::centre_part_at(R, grid, cells_out, p, d, move, o, 0.5 * o.spacing, stitch, out, how));
  moved = how == detail::CentringTry::moved;
  return {};
}

}  // namespace restitch
