// restitch/stitch/detail/regions.hpp - the regions of a labelling: maximal 6-connected cells sharing one label.
//
// A region is what the stitcher copies in one piece: its cells, its shift d
// and its translation A d. An output cell whose source x - d lies outside the
// input grid belongs to no region (region -1) and stays empty. Regions are
// numbered by their first output cell in linear order; each one's cells are
// listed in ascending linear order.
//
// End caps. A region with cells on an end face of the output (x_a = 0 or
// x_a = U_out - 1) whose shift is not anchored to that end (d_a != 0, or
// d_a != U_out - U_in) cannot carry the input's end: its own source cell is
// not the input's end cell. For each such (region, axis, side) a cap is
// listed: the input's end cells (s_a = 0 or U_in - 1, the other components
// those of the region's sources) from the end plane outward (Lattice::end_low
// / end_high: the cell plane, so the overhang, unless the end cell is not
// full or does not wholly repeat its neighbour), copied with the anchored shift d' (d with d_a set to the anchor), so
// it lands at the output's end; the region's face cells are cut at the same
// plane. So an output one cell long still gets both ends (docs/method.md
// section 3). Caps are numbered after the regions (their translations follow
// the regions'). Cost O(#output cells).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"

namespace restitch::detail {

struct StitchRegions {
  std::vector<std::int32_t> region_of;  ///< per output cell, -1 = empty
  std::vector<Eigen::Array3i> shift;    ///< label shift d of each region
  std::vector<Eigen::Vector3d> translation;  ///< A d of each region, model units
  std::vector<std::uint32_t> start, cells;   ///< CSR: cells of region r are cells[start[r] .. start[r + 1])

  /// An end cap (see the file comment): for region `owner`'s cells on the face x_axis = face, the input's
  /// end cells from the end plane outward, copied with `shift`; its translation is
  /// translation[size() + index].
  struct Cap {
    std::int32_t owner = -1;
    int axis = 0, side = 0;  ///< side 0: the low end (below plane); 1: the high end (from plane on)
    int face = 0;            ///< the output face's cell index along axis (0 or U_out - 1)
    double plane = 0;        ///< the end plane, canonical coordinate along axis in the input
    double owner_plane = 0;  ///< the same plane in the owner's source cell (where the owner is cut)
    bool cuts_owner = false; ///< the plane is not the cell's outer plane: the owner keeps only what lies before it
    Eigen::Array3i shift = Eigen::Array3i::Zero();
  };
  std::vector<Cap> caps;

  std::size_t size() const { return shift.size(); }

  /// Does input cell (i, j, k), moved by region r's shift, land in region r?
  template <class = void>
  bool holds_source_cell(const CellGrid& out, std::int32_t r, int i, int j, int k) const {
    const Eigen::Array3i& d = shift[std::size_t(r)];
    const std::int64_t x = std::int64_t(i) + d(0), y = std::int64_t(j) + d(1), z = std::int64_t(k) + d(2);
    if (!out.inside(x, y, z)) return false;
    return region_of[std::size_t(x + out.dims(0) * (y + std::int64_t(out.dims(1)) * z))] == r;
  }
};

/// The regions of `cell_shift` (one label per output cell of `out`, linear order) over the input `lattice`.
template <class = void>
StitchRegions build_regions(const Lattice& lattice, const CellGrid& out,
                                   const std::vector<Eigen::Array3i>& cell_shift) {
  StitchRegions g;
  const std::size_t n = cell_shift.size();
  const CellGrid in(lattice.cells);
  g.region_of.assign(n, -1);
  std::vector<std::uint8_t> valid(n, 0);
  for (std::size_t x = 0; x < n; ++x) {
    const Eigen::Array3i c = out.cell(std::int64_t(x));
    const Eigen::Array3i& d = cell_shift[x];
    valid[x] = in.inside(std::int64_t(c[0]) - d(0), std::int64_t(c[1]) - d(1), std::int64_t(c[2]) - d(2));
  }
  std::vector<std::uint32_t> queue;
  g.start.assign(1, 0);
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (!valid[seed] || g.region_of[seed] >= 0) continue;
    const std::int32_t r = std::int32_t(g.shift.size());
    g.shift.push_back(cell_shift[seed]);
    queue.assign(1, std::uint32_t(seed));
    g.region_of[seed] = r;
    for (std::size_t q = 0; q < queue.size(); ++q)
      out.for_each_neighbour(queue[q], Neighbourhood::n6, [&](int y) {
        if (valid[std::size_t(y)] && g.region_of[std::size_t(y)] < 0 &&
            (cell_shift[std::size_t(y)] == cell_shift[seed]).all()) {
          g.region_of[std::size_t(y)] = r;
          queue.push_back(std::uint32_t(y));
        }
      });
    std::sort(queue.begin(), queue.end());
    g.cells.insert(g.cells.end(), queue.begin(), queue.end());
    g.start.push_back(std::uint32_t(g.cells.size()));
  }
  for (const Eigen::Array3i& d : g.shift) g.translation.push_back(lattice.shift(d));
  // End caps, region by region, axis by axis, low side first.
  for (std::int32_t r = 0; r < std::int32_t(g.size()); ++r)
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        const int face = side == 0 ? 0 : out.dims(a) - 1;
        const int anchor = side == 0 ? 0 : out.dims(a) - in.dims(a);
        const Eigen::Array3i& d = g.shift[std::size_t(r)];
        if (d(a) == anchor) continue;
        bool on_face = false;
        for (std::uint32_t q = g.start[std::size_t(r)]; q < g.start[std::size_t(r) + 1] && !on_face; ++q)
          on_face = out.cell(g.cells[q])(a) == face;
        if (!on_face) continue;
        StitchRegions::Cap cap;
        cap.owner = r;
        cap.axis = a;
        cap.side = side;
        cap.face = face;
        cap.shift = d;
        cap.shift(a) = anchor;
        const int source = face - d(a);  // the owner's source cell along a
        cap.plane = side == 0 ? lattice.end_low(a) : double(in.dims(a) - 1) + lattice.end_high(a);
        cap.owner_plane = double(source) + (side == 0 ? lattice.end_low(a) : lattice.end_high(a));
        cap.cuts_owner = side == 0 ? lattice.end_low(a) > 0 : lattice.end_high(a) < 1;
        g.caps.push_back(cap);
      }
  for (const StitchRegions::Cap& c : g.caps) g.translation.push_back(lattice.shift(c.shift));
  return g;
}

}  // namespace restitch::detail
