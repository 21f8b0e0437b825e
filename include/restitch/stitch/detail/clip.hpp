// restitch/stitch/detail/clip.hpp - clipping convex polygons against cell planes (the stitcher's geometry kernel).
//
// Canonical space (one unit per cell, stitch.hpp): `cell_range` gives the
// clamped cells an interval touches under the half-open rule; `split_polygon`
// splits a polygon by one plane c_axis = k with every attribute interpolated.
// Both are exact in the sense the stitcher relies on: a triangle lying in a
// plane goes to the cell above it, and two triangles sharing an edge compute
// the same cut points bit for bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "restitch/status.hpp"

namespace restitch::detail {

/// Cell index of a canonical interval [m, M] along an axis with n cells (half-open cells, clamped ends).
template <class = void>
void cell_range(double m, double M, int n, std::int32_t& lo, std::int32_t& hi) {
  const double top = double(n - 1);
  double l = std::floor(m), h = (M > m) ? std::ceil(M) - 1.0 : l;
  l = std::min(std::max(l, 0.0), top);
  h = std::min(std::max(h, 0.0), top);
  lo = std::int32_t(l);
  hi = std::int32_t(h);
}

/// A convex polygon during clipping: n vertices of `stride` doubles each
/// (canonical xyz, model xyz, then the attribute channels), and for each
/// vertex the input vertex it is an untouched copy of (-1 for a cut point).
struct ClipPolygon {
  std::vector<double> d;
  std::vector<std::int64_t> src;
  int n = 0;
  void clear() { n = 0; }
  template <class = void>
  void reserve_for(int count, int stride) {
    if (int(src.size()) < count) {
      src.resize(std::size_t(count));
      d.resize(std::size_t(count) * std::size_t(stride));
    }
  }
  template <class = void>
  void push(const double* v, std::int64_t s, int stride) {
    reserve_for(n + 1, stride);
    std::copy(v, v + stride, d.data() + std::size_t(n) * std::size_t(stride));
    src[std::size_t(n)] = s;
    ++n;
  }
  const double* vertex(int i, int stride) const { return d.data() + std::size_t(i) * std::size_t(stride); }
};

/// Splits `in` by the plane c_axis = k. Half-open rule: a polygon entirely
/// at or above k (including one lying in the plane) goes to `high`, one
/// entirely at or below k (and not in the plane) to `low`; otherwise vertices
/// on the plane go to both and edges crossing it strictly are cut. The cut
/// point is interpolated from the edge's lower end, so the two triangles
/// sharing an edge compute the same bits.
template <class = void>
void split_polygon(const ClipPolygon& in, int axis, double k, int stride, ClipPolygon& low, ClipPolygon& high) {
  low.clear();
  high.clear();
  bool all_ge = true, all_le = true;
  for (int i = 0; i < in.n; ++i) {
    const double v = in.vertex(i, stride)[axis];
    all_ge = all_ge && v >= k;
    all_le = all_le && v <= k;
  }
  if (all_ge || all_le) {
    ClipPolygon& dst = all_ge ? high : low;
    for (int i = 0; i < in.n; ++i) dst.push(in.vertex(i, stride), in.src[std::size_t(i)], stride);
    return;
  }
  double cut[64];
  RESTITCH_ASSERT(stride <= 64, "too many attribute channels for the clipper");
  for (int i = 0; i < in.n; ++i) {
    const int j = (i + 1 == in.n) ? 0 : i + 1;
    const double* p = in.vertex(i, stride);
    const double* q = in.vertex(j, stride);
    const double vp = p[axis], vq = q[axis];
    if (vp <= k) low.push(p, in.src[std::size_t(i)], stride);
    if (vp >= k) high.push(p, in.src[std::size_t(i)], stride);
    if ((vp < k && vq > k) || (vp > k && vq < k)) {
      const double* a = vp < vq ? p : q;  // lower end
      const double* b = vp < vq ? q : p;
      const double t = (k - a[axis]) / (b[axis] - a[axis]);
      for (int c = 0; c < stride; ++c) cut[c] = a[c] + t * (b[c] - a[c]);
      cut[axis] = k;
      low.push(cut, -1, stride);
      high.push(cut, -1, stride);
    }
  }
}

}  // namespace restitch::detail
