// restitch/retarget/seams.hpp - where the seams of a labelling lie and how well they close (docs/method.md 2.8, 2.9).
//
// After the labels are solved: `move_seams` moves each plane between output cells where copies meet
// to where the two copies continue each other (2.9), `measure_seams` measures every seam on the
// geometry (2.8), and `face_labels` says which label each
// output face lies in (for display). All read the dense samples through CellSlabs.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "restitch/energy/seam_geometry.hpp"
#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/retarget/report.hpp"
#include "restitch/retarget/request.hpp"

namespace restitch {

/// The planes between output cells as they lie after seams moved (docs/method.md 2.9): plane i along
/// axis a at i + j[a][i] / K, |j| < K / 2 (so a cell keeps at least 2 / K of its width), j[a] empty when
/// no plane of axis a moved.
struct MovedPlanes {
  static constexpr int K = 16;
  std::array<std::vector<int>, 3> j;

  bool moved(int a) const { return !j[std::size_t(a)].empty(); }
  bool any() const { return moved(0) || moved(1) || moved(2); }
  /// The same for the s-th K-th of a cell (s = 0 .. K cells - 1) along a moved axis.
  template <class = void>
  int cell_of_part(int a, int s, int cells) const {
    const std::vector<int>& J = j[std::size_t(a)];
    const int i = s / K;
    if (i + 1 < cells && s >= (i + 1) * K + J[std::size_t(i + 1)]) return i + 1;
    if (i > 0 && s < i * K + J[std::size_t(i)]) return i - 1;
    return i;
  }
};



// Every seam of a labelling, measured on the geometry (docs/method.md 2.8): face neighbours with
// different labels, and end cells whose label differs from their anchor. The mismatch of a seam
// between x (label di) and x' = x + e (label dj): the sources x - di and x - dj compared at their
// plane toward e (CellSlabs::plane_mismatch, either side of it), or x' - di and x' - dj at theirs
// toward -e when that is smaller (the same plane; it matters where one pair has a cell outside). An
// end cell x with label d and anchor d' (outer seam, where the stitcher puts an end cap): the cells
// x - d and x - d' compared on either side of the end plane (Lattice::end_low / end_high;
// CellSlabs::plane_mismatch).
template <class = void>
void measure_seams(CellSlabs& slabs, const Lattice& grid, const RetargetOptions& options, const Eigen::Array3i& k,
                   const Eigen::Array3i& cells_out, const std::vector<Eigen::Array3i>& shift, const MovedPlanes& planes,
                   RetargetReport& rep) {
  const CellGrid out(cells_out);
  rep.seam_energy = options.seam_energy;
  rep.sample_spacing = slabs.spacing();
  rep.seam_tolerance = options.seam_tolerance > 0 ? options.seam_tolerance : 3 * slabs.spacing();
  auto measure = [&](const Eigen::Array3i& x, const Eigen::Array3i& y, const Eigen::Array3i& di,
                     const Eigen::Array3i& dj, bool outer) {
    const Eigen::Array3i e = y - x;
    SeamReport seam{x, y, di, dj, 0.0, outer};
    // An end faces nothing in the output, whatever the labels: only its own side counts.
    if (outer) {
      const int a = e[0] != 0 ? 0 : e[1] != 0 ? 1 : 2;  // an end differs from its anchor along one axis
      const double f = e[a] < 0 ? grid.end_low[a] : grid.end_high[a];
      seam.mismatch = slabs.plane_mismatch(x - di, x - dj, a, f);
    } else {  // the plane between x and y, seen from either pair of sources
      const int a = e[0] != 0 ? 0 : e[1] != 0 ? 1 : 2;
      const int j = planes.moved(a) ? planes.j[std::size_t(a)][std::size_t(y[a])] : 0;
      seam.offset = double(j) / planes.K;
      const auto between = [&](const Eigen::Array3i& d1, const Eigen::Array3i& d2, int c, double lo, double hi) {
        if ((d1 == d2).all()) return 0.0;
        if (j == 0)
          return std::min(slabs.plane_mismatch(x - d1, x - d2, a, 1.0, c, lo, hi),
                          slabs.plane_mismatch(y - d1, y - d2, a, 0.0, c, lo, hi));
        // the cut lies inside y (j > 0) or inside x (j < 0): that cell's two sources there
        return j > 0 ? slabs.plane_mismatch(y - d1, y - d2, a, seam.offset, c, lo, hi)
                     : slabs.plane_mismatch(x - d1, x - d2, a, 1.0 + seam.offset, c, lo, hi);
      };
      // On an output end face along another resized axis c, a label not anchored to that end gets an
      // end cap (restitch/stitch/detail/regions.hpp): beyond the end plane (Lattice end_low / end_high,
      // inside the cell or at its plane) and in the overhang past the cell, the anchored copy holds the
      // face; only between the end planes do the labels' own copies meet. So the seam is measured in
      // parts along c, the end's part between the anchored labels (overhang included), the rest between
      // di and dj (overhang excluded); the largest counts (docs/method.md 2.8). On an output one cell
      // long along c both ends' caps meet in the cell.
      int c = -1;
      bool low = false, high = false;
      for (int b = 0; b < 3 && c < 0; ++b) {
        if (b == a || k[b] == 0) continue;
        low = x[b] == 0;
        high = x[b] == cells_out[b] - 1;
        if ((low && (di[b] != 0 || dj[b] != 0)) || (high && (di[b] != k[b] || dj[b] != k[b]))) c = b;
      }
      if (c < 0) {
        seam.mismatch = between(di, dj, -1, 0.0, 1.0);
      } else {
        const auto anchored = [&](const Eigen::Array3i& d, int anchor) {  // the label a cap copies with
          Eigen::Array3i v = d;
          v[c] = anchor;
          return v;
        };
        double lo = 0.0, hi = 1.0;  // the part of the face the labels' own copies hold, along c
        if (low) {
          lo = grid.end_low[c];
          seam.mismatch = between(anchored(di, 0), anchored(dj, 0), c, -INFINITY, lo);
        }
        if (high) {
          hi = grid.end_high[c];
          seam.mismatch = std::max(seam.mismatch, between(anchored(di, k[c]), anchored(dj, k[c]), c, hi, INFINITY));
        }
        if (lo < hi) seam.mismatch = std::max(seam.mismatch, between(di, dj, c, lo, hi));
      }
    }
    rep.max_seam_mismatch = std::max(rep.max_seam_mismatch, seam.mismatch);
    rep.seams.push_back(seam);
  };
  for (std::int64_t xi = 0; xi < out.size(); ++xi) {
    const Eigen::Array3i x = out.cell(xi), di = shift[std::size_t(xi)];
    for (int a = 0; a < 3; ++a) {
      Eigen::Array3i y = x;
      y[a] += 1;
      if (out.inside(y)) {
        const Eigen::Array3i& dj = shift[std::size_t(out.index(y))];
        if ((di != dj).any()) measure(x, y, di, dj, false);
      }
      if (k[a] == 0) continue;
      for (int side = 0; side < 2; ++side) {  // anchored ends
        if (side == 0 ? x[a] != 0 : x[a] != out.dims[a] - 1) continue;
        Eigen::Array3i anchor = di, outside = x;
        anchor[a] = side == 0 ? 0 : k[a];
        outside[a] += side == 0 ? -1 : 1;
        if ((anchor != di).any()) measure(x, outside, di, anchor, true);
      }
    }
  }
}


// The label of the output cell each face's centroid lies in (with the planes as they lie).
template <class = void>
std::vector<int> face_labels(const Lattice& grid, const Mesh& m, const RetargetReport& rep,
                             const std::vector<int>& labelling) {
  const CellGrid out(rep.cells_out);
  std::vector<int> fl(m.triangle_count(), 0);
  const Eigen::Matrix3d Ainv = grid.A.inverse();
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int corner = 0; corner < 3; ++corner)
      for (int i = 0; i < 3; ++i) c[i] += double(m.V(m.F(f, corner), i)) / 3.0;
    fl[std::size_t(f)] = labelling[std::size_t(out.index(rep.cell_of(Ainv * (c - grid.origin))))];
  }
  return fl;
}


// Where the seams go (docs/method.md 2.9). Per plane i (1 .. cells_out[a] - 1) of each axis a where
// output cells with different labels meet: the seams across it ask CellSlabs::seam_positions for
// every position within half a cell; the plane stays on the cell plane when no sample there fails to
// continue, and otherwise moves to the valid position with the fewest such samples (then the fewest
// samples changed, then cut, then the nearest the cell plane, then the lower), only when that is fewer
// than on the cell plane. Where a cell beside the plane meets a different label along another axis b (a
// staircase), the seams across b inside the strip the move sweeps change labels: they are counted too
// (CellSlabs::plane_fail_along), as they lie after the move less as they lay before; a plane of b such a
// seam lies on is then not moved, and a staircase on a plane of b that moved keeps the plane put. Every
// plane stays when an output end is copied from elsewhere (its end cap is cut at the lattice's end plane,
// in whole cells). The caller asks only with RetargetOptions::move_seams.
template <class = void>
MovedPlanes move_seams(CellSlabs& slabs, const Eigen::Array3i& k, const Eigen::Array3i& cells_out,
                       const std::vector<Eigen::Array3i>& shift) {
  MovedPlanes planes;
  const CellGrid out(cells_out);
  const CellGrid in = slabs.grid();
  const auto label = [&](const Eigen::Array3i& x) -> const Eigen::Array3i& {
    return shift[std::size_t(out.index(x))];
  };
  for (std::int64_t xi = 0; xi < out.size(); ++xi) {  // an end copied from elsewhere: end caps, keep cells
    const Eigen::Array3i x = out.cell(xi);
    for (int a = 0; a < 3; ++a) {
      if (x[a] == 0 && shift[std::size_t(xi)][a] != 0) return planes;
      if (x[a] == out.dims[a] - 1 && shift[std::size_t(xi)][a] != k[a]) return planes;
    }
  }
  constexpr int K = MovedPlanes::K, H = K / 2 - 1;
  // Planes that must stay: a staircase seam lies on them and a plane across them moved.
  std::array<std::vector<char>, 3> frozen;
  for (int a = 0; a < 3; ++a) frozen[std::size_t(a)].assign(std::size_t(cells_out[a]) + 1, 0);
  for (int a = 0; a < 3; ++a)
    for (int i = 1; i < cells_out[a]; ++i) {
      if (frozen[std::size_t(a)][std::size_t(i)]) continue;
      std::vector<std::int64_t> fail(2 * H + 1, 0), cut(2 * H + 1, 0), changed(2 * H + 1, 0), swept(2 * H + 1, 0);
      std::vector<char> valid(2 * H + 1, 1);
      std::vector<std::pair<int, int>> crossing;  // (axis b, plane) of the staircase seams
      bool seam = false;
      // Each pair of cells across the plane: x in column i - 1, y in column i.
      const auto each_pair = [&](auto&& f) {
        for (std::int64_t xi = 0; xi < out.size(); ++xi) {
          const Eigen::Array3i x = out.cell(xi);
          if (x[a] != i - 1) continue;
          Eigen::Array3i y = x;
          y[a] = i;
          f(x, y);
        }
      };
      each_pair([&](const Eigen::Array3i& x, const Eigen::Array3i& y) {
        for (const Eigen::Array3i& z : {x, y})
          for (int b = 0; b < 3; ++b)
            for (const int step : {-1, 1}) {
              Eigen::Array3i n = z;
              n[b] += step;
              if (b != a && out.inside(n) && (label(n) != label(z)).any())
                crossing.emplace_back(b, step > 0 ? n[b] : z[b]);
            }
        const Eigen::Array3i &di = label(x), &dj = label(y);
        if ((di == dj).all()) return;
        seam = true;
        const CellSlabs::SeamPositions& p = slabs.seam_positions(x - di, a, dj - di, K);
        for (std::size_t q = 0; q < valid.size(); ++q) {
          fail[q] += p.fail[q];
          cut[q] += p.cut[q];
          changed[q] += p.changed[q];
          valid[q] = char(valid[q] && p.valid[q]);
        }
      });
      if (!seam || !valid[H] || fail[H] == 0) continue;
      bool blocked = false;
      for (const auto& [b, plane] : crossing)
        blocked = blocked || (b < a && planes.moved(b) && planes.j[std::size_t(b)][std::size_t(plane)] != 0);
      if (blocked) continue;
      // Staircases: the seams across b from each side's cell z (z, z + e_b), inside the strip a move of
      // j / K sweeps (cells of column i for j > 0, of column i - 1 for j < 0), which then take the labels
      // of the cells across the plane: as they lie after the move less as they lay before.
      each_pair([&](const Eigen::Array3i& x, const Eigen::Array3i& y) {
        for (int side = 0; side < 2; ++side) {
          const Eigen::Array3i z = side == 0 ? x : y, across = side == 0 ? y : x;
          for (int b = 0; b < 3; ++b) {
            if (b == a) continue;
            Eigen::Array3i n = z, n_across = across;
            n[b] += 1;
            n_across[b] += 1;
            if (!out.inside(n)) continue;
            const Eigen::Array3i &lz = label(z), &ln = label(n), &mz = label(across), &mn = label(n_across);
            if ((lz == ln).all() && (mz == mn).all()) continue;
            // The failing samples of the seam between z (labels d1) and n (d2), per K-th of the cell.
            const auto fails = [&](const Eigen::Array3i& d1, const Eigen::Array3i& d2, int part) -> std::int64_t {
              if ((d1 == d2).all()) return 0;
              return slabs.plane_fail_along(z - d1, b, +1, d1 - d2, a, K)[std::size_t(part)] +
                     slabs.plane_fail_along(n - d2, b, -1, d2 - d1, a, K)[std::size_t(part)];
            };
            const bool sources = in.inside(z - mz) && in.inside(n - mn);
            for (int j = -H; j <= H; ++j) {
              if (j == 0 || (side == 1) != (j > 0)) continue;  // the strip lies in z's column
              if (!sources) {
                valid[std::size_t(j + H)] = 0;
                continue;
              }
              for (int part = j > 0 ? 0 : K + j; part < (j > 0 ? j : K); ++part)
                swept[std::size_t(j + H)] += fails(mz, mn, part) - fails(lz, ln, part);
            }
          }
        }
      });
      for (std::size_t q = 0; q < fail.size(); ++q) fail[q] += swept[q];
      int best = H;
      const auto key = [&](int q) {
        return std::make_tuple(fail[std::size_t(q)], changed[std::size_t(q)], cut[std::size_t(q)], std::abs(q - H), q);
      };
      for (int q = 0; q <= 2 * H; ++q)
        if (valid[std::size_t(q)] && fail[std::size_t(q)] < fail[H] && key(q) < key(best)) best = q;
      if (best == H) continue;
      if (!planes.moved(a)) planes.j[std::size_t(a)].assign(std::size_t(cells_out[a]) + 1, 0);
      planes.j[std::size_t(a)][std::size_t(i)] = best - H;
      for (const auto& [b, plane] : crossing) frozen[std::size_t(b)][std::size_t(plane)] = 1;
    }
  return planes;
}


}  // namespace restitch
