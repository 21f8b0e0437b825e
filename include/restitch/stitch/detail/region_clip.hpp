// restitch/stitch/detail/region_clip.hpp - copying one input triangle into one region: whole, or clipped.
//
// A triangle whose cells all lie in the region (and that needs no overhang
// cut) is copied untouched. Otherwise it is clipped (stitch.hpp): first the
// overhang cuts at planes 0 and cells[a] that this region does not keep, then
// a binary space partition over its cell range until each piece lies in cells
// all in or all out of the region; pieces in the region are emitted as fans,
// slivers dropped. The region is passed explicitly to every call (`Region`),
// so nothing here depends on which region was processed before. An end cap
// (regions.hpp) is a Region too: its cells are its owner's cells on one end
// face, its triangles are always clipped, and only their part beyond that
// end's plane is kept; its owner keeps only the part before that plane.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "restitch/lattice/grid.hpp"
#include "restitch/mesh.hpp"
#include "restitch/stitch/detail/cache.hpp"
#include "restitch/stitch/detail/clip.hpp"
#include "restitch/stitch/detail/output.hpp"
#include "restitch/stitch/detail/regions.hpp"

namespace restitch::detail {

/// One region (or end cap) as the clipper needs it.
struct Region {
  std::int32_t id = -1;     ///< the output vertices' region: index into StitchRegions::translation
  std::int32_t owner = -1;  ///< the region whose cells these are (id, for a region)
  int cap_axis = -1, cap_side = 0, cap_face = 0;  ///< an end cap: which end (else cap_axis = -1)
  double cap_plane = 0;                         ///< an end cap keeps c_a < plane (low end) or >= plane (high)
  Eigen::Array3i d = Eigen::Array3i::Zero();  ///< its shift
  std::array<bool, 3> keep_low{}, keep_high{};  ///< keeps the overhang below plane 0 / beyond plane cells[a]
  std::uint8_t cut_mask = 0;                    ///< overhang flags (ClipStitchCache::overhang) that force a cut
  /// A region whose end is capped inside its source cell: keeps c_a >= end_from[a] and c_a < end_to[a].
  std::array<double, 3> end_from{{-INFINITY, -INFINITY, -INFINITY}}, end_to{{INFINITY, INFINITY, INFINITY}};
  bool end_cut = false;  ///< some end_from / end_to is finite

  template <class = void>
  Region(const StitchRegions& regions, std::int32_t r, const CellGrid& out, const Eigen::Array3i& cells_in)
      : id(r), owner(r), d(regions.shift[std::size_t(r)]) {
    set_keep(out, cells_in);
    for (const StitchRegions::Cap& c : regions.caps) {  // the caps at planes inside a cell cut this region
      if (c.owner != r || !c.cuts_owner) continue;
      (c.side == 0 ? end_from : end_to)[std::size_t(c.axis)] = c.owner_plane;
      end_cut = true;
    }
  }
  /// End cap c of `regions`.
  template <class = void>
  Region(const StitchRegions& regions, std::size_t c, const CellGrid& out, const Eigen::Array3i& cells_in)
      : id(std::int32_t(regions.size() + c)), owner(regions.caps[c].owner), cap_axis(regions.caps[c].axis),
        cap_side(regions.caps[c].side), cap_face(regions.caps[c].face), cap_plane(regions.caps[c].plane),
        d(regions.caps[c].shift) {
    set_keep(out, cells_in);
  }

  /// The overhang flag (ClipStitchCache::overhang) of a cap's end; 0 for a region.
  std::uint8_t cap_flag() const {
    return cap_axis < 0 ? 0 : std::uint8_t((cap_side == 0 ? 1u : 8u) << cap_axis);
  }

 private:
  template <class = void>
  void set_keep(const CellGrid& out, const Eigen::Array3i& cells_in) {
    for (int a = 0; a < 3; ++a) {
      keep_low[std::size_t(a)] = d(a) == 0;
      keep_high[std::size_t(a)] = d(a) == out.dims(a) - cells_in(a);
      if (!keep_low[std::size_t(a)]) cut_mask |= std::uint8_t(1u << a);
      if (!keep_high[std::size_t(a)]) cut_mask |= std::uint8_t(8u << a);
    }
  }
};

/// Does input cell (i, j, k), moved by r's shift, land in r's cells (for a cap: on its end face)?
template <class = void>
bool holds_source_cell(const StitchRegions& regions, const CellGrid& out, const Region& r, int i, int j,
                              int k) {
  if (r.cap_axis < 0) return regions.holds_source_cell(out, r.id, i, j, k);
  const Eigen::Array3i x = Eigen::Array3i(i, j, k) + r.d;  // the cap's own (anchored) shift
  return x(r.cap_axis) == r.cap_face && out.inside(x(0), x(1), x(2)) &&
         regions.region_of[std::size_t(out.index(x))] == r.owner;
}

class RegionClipper {
 public:
  template <class = void>
  RegionClipper(const Mesh& in, const ClipStitchCache& cache, const VertexLayout& layout, const CellGrid& out,
                const StitchRegions& regions, StitchOutput& output)
      : in_(in), cache_(cache), L_(layout), out_(out), regions_(regions), o_(output), vbuf_(std::size_t(layout.stride)) {}

  /// Copies or clips input triangle f into region r; returns true when it was clipped.
  template <class = void>
  bool add_triangle(const Region& r, std::uint32_t f) {
    const std::int32_t* range = cache_.range(f);
    const std::uint32_t g = in_.FG(Eigen::Index(f));
    if (whole(r, f, range)) {
      const std::uint32_t a = o_.copy_vertex(in_.F(Eigen::Index(f), 0), g, r.id);
      const std::uint32_t b = o_.copy_vertex(in_.F(Eigen::Index(f), 1), g, r.id);
      const std::uint32_t c = o_.copy_vertex(in_.F(Eigen::Index(f), 2), g, r.id);
      o_.add_face(a, b, c, g);
      return false;
    }
    // The triangle as a polygon in work_[0]; overhang cuts first.
    if (work_.size() < 2) work_.resize(2), spare_.resize(2);
    work_[0].clear();
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = in_.F(Eigen::Index(f), k);
      L_.load(in_, cache_, v, vbuf_.data());
      work_[0].push(vbuf_.data(), v, L_.stride);
    }
    if (!cut_overhang(r, cache_.overhang(f))) return true;
    bsp(r, 0, {{range[0], range[1], range[2]}}, {{range[3], range[4], range[5]}}, g);
    return true;
  }

 private:
  // No overhang cut needed, and every cell of its range in the region (a
  // one-cell triangle came from that cell's bucket, so its cell is in).
  template <class = void>
  bool whole(const Region& r, std::uint32_t f, const std::int32_t* range) const {
    if (r.cap_axis >= 0) return false;  // a cap keeps only what lies beyond its end's plane
    if ((cache_.overhang(f) & r.cut_mask) != 0) return false;
    if (r.end_cut)
      for (int a = 0; a < 3; ++a)  // its cells reach an end plane inside a cell: clip
        if (double(range[a]) < r.end_from[std::size_t(a)] || double(range[3 + a]) + 1 > r.end_to[std::size_t(a)])
          return false;
    if (range[0] == range[3] && range[1] == range[4] && range[2] == range[5]) return true;
    for (int k = range[2]; k <= range[5]; ++k)
      for (int j = range[1]; j <= range[4]; ++j)
        for (int i = range[0]; i <= range[3]; ++i)
          if (!holds_source_cell(regions_, out_, r, i, j, k)) return false;
    return true;
  }

  // Cuts work_[0] at the overhang planes the region does not keep (and, for a cap, away from the
  // overhang it copies); false when nothing is left.
  template <class = void>
  bool cut_overhang(const Region& r, std::uint8_t flags) {
    const Eigen::Array3i& cells = cache_.lattice().cells;
    if (r.cap_axis >= 0) {
      split_polygon(work_[0], r.cap_axis, r.cap_plane, L_.stride, work_[1], spare_[1]);
      std::swap(work_[0], r.cap_side == 0 ? work_[1] : spare_[1]);  // c_a < plane, or c_a >= plane
      if (work_[0].n < 3) return false;
    }
    if (r.end_cut)
      for (int a = 0; a < 3; ++a) {
        if (std::isfinite(r.end_from[std::size_t(a)])) {  // keep c_a >= end_from
          split_polygon(work_[0], a, r.end_from[std::size_t(a)], L_.stride, work_[1], spare_[1]);
          std::swap(work_[0], spare_[1]);
        }
        if (std::isfinite(r.end_to[std::size_t(a)])) {  // keep c_a < end_to
          split_polygon(work_[0], a, r.end_to[std::size_t(a)], L_.stride, work_[1], spare_[1]);
          std::swap(work_[0], work_[1]);
        }
        if (work_[0].n < 3) return false;
      }
    for (int a = 0; a < 3; ++a) {
      if (!r.keep_low[std::size_t(a)] && (flags & (1u << a))) {  // keep c_a >= 0
        split_polygon(work_[0], a, 0.0, L_.stride, work_[1], spare_[1]);
        std::swap(work_[0], spare_[1]);
      }
      if (!r.keep_high[std::size_t(a)] && (flags & (8u << a))) {  // keep c_a < cells[a]
        split_polygon(work_[0], a, double(cells(a)), L_.stride, work_[1], spare_[1]);
        std::swap(work_[0], work_[1]);
      }
      if (work_[0].n < 3) return false;
    }
    return true;
  }

  // Tight clamped cell range of a polygon.
  template <class = void>
  void polygon_range(const ClipPolygon& p, std::array<int, 3>& lo, std::array<int, 3>& hi) const {
    for (int a = 0; a < 3; ++a) {
      double m = INFINITY, M = -INFINITY;
      for (int i = 0; i < p.n; ++i) {
        const double v = p.vertex(i, L_.stride)[a];
        m = std::min(m, v);
        M = std::max(M, v);
      }
      std::int32_t l, h;
      cell_range(m, M, cache_.lattice().cells(a), l, h);
      lo[std::size_t(a)] = std::max(lo[std::size_t(a)], int(l));
      hi[std::size_t(a)] = std::min(hi[std::size_t(a)], int(h));
    }
  }

  // Counts the cells of a box that belong to the region.
  template <class = void>
  std::int64_t count_in(const Region& r, const std::array<int, 3>& lo, const std::array<int, 3>& hi) const {
    std::int64_t c = 0;
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) c += holds_source_cell(regions_, out_, r, i, j, k);
    return c;
  }

  // The splitting plane of a box with cells both in and out of the region:
  // best one that separates cells in the region from cells out of it (both
  // sides uniform), else one with a side all out (it is dropped at once), else
  // one with a side all in; ties go to the first, axis by axis, low to high.
  // So cuts fall on the region's boundary. Without any, the middle of the
  // longest axis.
  template <class = void>
  std::pair<int, int> split_plane(const Region& r, const std::array<int, 3>& lo, const std::array<int, 3>& hi,
                                  std::int64_t in_count, std::int64_t total) const {
    int axis = -1, plane = 0, score = 0;
    for (int a = 0; a < 3; ++a) {
      const std::size_t ua = std::size_t(a);
      for (int k = lo[ua] + 1; k <= hi[ua]; ++k) {
        std::array<int, 3> h1 = hi;
        h1[ua] = k - 1;
        const std::int64_t c1 = count_in(r, lo, h1), c2 = in_count - c1;
        const std::int64_t n1 = total / (hi[ua] - lo[ua] + 1) * (k - lo[ua]), n2 = total - n1;
        const bool u1 = c1 == 0 || c1 == n1, u2 = c2 == 0 || c2 == n2;
        const int sc = (u1 && u2) ? 3 : (c1 == 0 || c2 == 0) ? 2 : (u1 || u2) ? 1 : 0;
        if (sc > score) score = sc, axis = a, plane = k;
      }
    }
    if (axis < 0) {
      int best = -1;
      for (int a = 0; a < 3; ++a)
        if (hi[std::size_t(a)] - lo[std::size_t(a)] > best) best = hi[std::size_t(a)] - lo[std::size_t(a)], axis = a;
      plane = (lo[std::size_t(axis)] + hi[std::size_t(axis)] + 1) / 2;
    }
    return {axis, plane};
  }

  // Recursively splits work_[depth] until each piece lies in cells that are
  // all in, or all out of, the region; emits the pieces that are in.
  // Level L splits work_[L] into work_[L + 1] (low) and spare_[L + 1] (high);
  // deeper levels never touch spare_[L + 1], so the high piece waits there.
  template <class = void>
  void bsp(const Region& r, std::size_t depth, std::array<int, 3> lo, std::array<int, 3> hi, std::uint32_t group) {
    if (work_.size() < depth + 2) work_.resize(depth + 2), spare_.resize(depth + 2);
    polygon_range(work_[depth], lo, hi);
    for (int a = 0; a < 3; ++a)
      if (lo[std::size_t(a)] > hi[std::size_t(a)]) return;
    const std::int64_t total = std::int64_t(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    const std::int64_t in_count = count_in(r, lo, hi);
    if (in_count == 0) return;
    if (in_count == total) {
      emit(r, work_[depth], group);
      return;
    }
    const auto [axis, plane] = split_plane(r, lo, hi, in_count, total);
    split_polygon(work_[depth], axis, double(plane), L_.stride, work_[depth + 1], spare_[depth + 1]);
    std::array<int, 3> h1 = hi, l2 = lo;
    h1[std::size_t(axis)] = plane - 1;
    l2[std::size_t(axis)] = plane;
    if (work_[depth + 1].n >= 3) bsp(r, depth + 1, lo, h1, group);
    if (spare_[depth + 1].n >= 3) {
      std::swap(work_[depth + 1], spare_[depth + 1]);
      bsp(r, depth + 1, l2, hi, group);
    }
  }

  // A convex piece in the region, fanned into triangles; slivers dropped.
  template <class = void>
  void emit(const Region& r, const ClipPolygon& p, std::uint32_t group) {
    if (p.n < 3) return;
    const double tol2 = cache_.tolerance() * cache_.tolerance();
    auto model = [&](int i) {
      const double* x = p.vertex(i, L_.stride);
      return Eigen::Vector3d(x[3], x[4], x[5]);
    };
    const Eigen::Vector3d p0 = model(0);
    double area = 0;
    for (int i = 1; i + 1 < p.n; ++i) area += 0.5 * (model(i) - p0).cross(model(i + 1) - p0).norm();
    if (area < tol2) return;
    ids_.resize(std::size_t(p.n));
    for (int i = 0; i < p.n; ++i) {
      const std::int64_t s = p.src[std::size_t(i)];
      ids_[std::size_t(i)] =
          s >= 0 ? o_.copy_vertex(std::uint32_t(s), group, r.id) : o_.cut_vertex(p.vertex(i, L_.stride), group, r.id);
    }
    for (int i = 1; i + 1 < p.n; ++i) {
      if (0.5 * (model(i) - p0).cross(model(i + 1) - p0).norm() < tol2) continue;
      o_.add_face(ids_[0], ids_[std::size_t(i)], ids_[std::size_t(i) + 1], group);
    }
  }

  const Mesh& in_;
  const ClipStitchCache& cache_;
  const VertexLayout& L_;
  const CellGrid& out_;
  const StitchRegions& regions_;
  StitchOutput& o_;
  std::vector<ClipPolygon> work_, spare_;  // BSP polygons per depth
  std::vector<double> vbuf_;
  std::vector<std::uint32_t> ids_;
};

}  // namespace restitch::detail
