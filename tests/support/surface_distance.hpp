// tests/support/surface_distance.hpp - test-only oracle: distance between two triangle surfaces.
//
// `symmetric_surface_distance(a, b, spacing)` approximates the symmetric
// Hausdorff distance between the triangle surfaces of `a` and `b` (model
// units): every triangle is sampled in rows at most `spacing` apart, points
// at most `spacing` apart along each row (its corners and edge points
// included), and each sample's EXACT distance to the other surface (closest
// point on the nearest triangle, found through an AABB tree) is taken; the
// result is the largest such distance in either direction. Identical
// surfaces with different triangulations give ~0 (float rounding of the
// positions), a surface shifted by delta gives ~delta, and a part present on
// one side only gives about that part's distance to the rest. It is a lower
// bound of the true Hausdorff distance that converges as spacing -> 0; a
// region smaller than `spacing` can be missed only between samples of one
// triangle, never a whole triangle (its corners are always sampled).
//
// Deterministic. Cost: O(S log #F) with S ~ area / spacing^2 +
// perimeters / spacing samples; memory O(#F) (samples are not stored). Degenerate (zero-area) triangles are handled as
// segments.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "restitch/mesh.hpp"

namespace restitch {
namespace test {

/// The point of segment [a, b] closest to p.
inline Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                                const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  if (!(l2 > 0)) return a;
  const double t = std::clamp((p - a).dot(ab) / l2, 0.0, 1.0);
  return a + t * ab;
}

/// The point of the (solid) triangle abc closest to p. Classifies p against
/// the Voronoi regions of the corners, edges and face by barycentric
/// coordinates; a degenerate triangle is treated as its three edges.
inline Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                                 const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, n = ab.cross(ac);
  const double scale = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
  if (!(n.squaredNorm() > 1e-24 * scale * scale)) {  // degenerate: nearest of the three edges
    const Eigen::Vector3d q[3] = {closest_point_on_segment(p, a, b), closest_point_on_segment(p, b, c),
                                  closest_point_on_segment(p, c, a)};
    int best = 0;
    for (int k = 1; k < 3; ++k)
      if ((q[k] - p).squaredNorm() < (q[best] - p).squaredNorm()) best = k;
    return q[best];
  }
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;  // corner a
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;  // corner b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;  // edge ab
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;  // corner c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)  // edge bc
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;  // inside the face
  return a + (vb / denom) * ab + (vc / denom) * ac;
}

/// Corner k of face f, in double precision.
inline Eigen::Vector3d corner(const Mesh& m, Eigen::Index f, int k) {
  return m.V.row(m.F(f, k)).transpose().cast<double>();
}

/// Exact unsigned distance from points to a triangle surface, through an AABB tree.
class TriangleSurface {
 public:
  explicit TriangleSurface(const Mesh& m) {
    const Eigen::Index nf = m.F.rows();
    tri_.resize(std::size_t(nf));
    for (Eigen::Index f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) tri_[std::size_t(f)][std::size_t(k)] = corner(m, f, k);
    order_.resize(tri_.size());
    for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = int(i);
    if (!tri_.empty()) build(0, int(tri_.size()));
  }

  bool empty() const { return tri_.empty(); }

  /// Distance from p to the nearest point of the surface; +infinity for an empty surface.
  double distance(const Eigen::Vector3d& p) const {
    double best2 = std::numeric_limits<double>::infinity();
    if (nodes_.empty()) return best2;
    // The tree is balanced (median splits), so its depth is below 64 and the
    // stack (at most two entries per level) never overflows.
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[std::size_t(stack[--top])];
      if (node.box.squaredExteriorDistance(p) >= best2) continue;
      if (node.left < 0) {
        for (int i = node.begin; i < node.end; ++i) {
          const auto& t = tri_[std::size_t(order_[std::size_t(i)])];
          best2 = std::min(best2, (closest_point_on_triangle(p, t[0], t[1], t[2]) - p).squaredNorm());
        }
        continue;
      }
      // Visit the nearer child first (pushed last).
      const double dl = nodes_[std::size_t(node.left)].box.squaredExteriorDistance(p);
      const double dr = nodes_[std::size_t(node.right)].box.squaredExteriorDistance(p);
      RESTITCH_ASSERT(top + 2 <= 128, "AABB tree deeper than expected");
      if (dl < dr) {
        stack[top++] = node.right;
        stack[top++] = node.left;
      } else {
        stack[top++] = node.left;
        stack[top++] = node.right;
      }
    }
    return std::sqrt(best2);
  }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  // children, -1 for a leaf
    int begin = 0, end = 0;     // range of order_ for a leaf
  };

  Eigen::Vector3d centroid(int t) const {
    const auto& x = tri_[std::size_t(t)];
    return (x[0] + x[1] + x[2]) / 3.0;
  }

  int build(int begin, int end) {
    const int id = int(nodes_.size());
    nodes_.emplace_back();
    Eigen::AlignedBox3d box, cbox;
    for (int i = begin; i < end; ++i) {
      const auto& t = tri_[std::size_t(order_[std::size_t(i)])];
      for (const auto& v : t) box.extend(v);
      cbox.extend(centroid(order_[std::size_t(i)]));
    }
    nodes_[std::size_t(id)].box = box;
    if (end - begin <= 4) {
      nodes_[std::size_t(id)].begin = begin;
      nodes_[std::size_t(id)].end = end;
      return id;
    }
    int axis = 0;
    cbox.sizes().maxCoeff(&axis);
    const int mid = (begin + end) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int x, int y) {
      const double cx = centroid(x)(axis), cy = centroid(y)(axis);
      return cx < cy || (cx == cy && x < y);
    });
    const int l = build(begin, mid);
    const int r = build(mid, end);
    nodes_[std::size_t(id)].left = l;
    nodes_[std::size_t(id)].right = r;
    return id;
  }

  std::vector<std::array<Eigen::Vector3d, 3>> tri_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

/// Calls f(point) for every sample of the surface. Per triangle, with ab
/// its longest edge and c the opposite corner: rows parallel to ab at
/// heights t = j / rows (rows = ceil(height / spacing)), each row sampled at
/// ceil(row length / spacing) + 1 evenly spaced points, ends included. So
/// the corners and edges are sampled, no two neighbouring samples are
/// farther apart than `spacing` (times sqrt 2), and the sample count is
/// about area / spacing^2 + perimeter / spacing even for slivers.
template <class F>
void for_each_surface_sample(const Mesh& m, double spacing, F&& f) {
  RESTITCH_ASSERT(spacing > 0, "surface sampling needs a positive spacing");
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
    Eigen::Vector3d p[3] = {corner(m, t, 0), corner(m, t, 1), corner(m, t, 2)};
    int longest = 0;  // edge (longest, longest + 1)
    for (int k = 1; k < 3; ++k)
      if ((p[(k + 1) % 3] - p[k]).norm() > (p[(longest + 1) % 3] - p[longest]).norm()) longest = k;
    const Eigen::Vector3d a = p[longest], b = p[(longest + 1) % 3], c = p[(longest + 2) % 3];
    const Eigen::Vector3d ab = b - a;
    const double base = ab.norm();
    const double height = base > 0 ? ab.cross(c - a).norm() / base : 0.0;
    const int rows = std::max(1, int(std::ceil(height / spacing)));
    for (int j = 0; j <= rows; ++j) {
      const double s = double(j) / rows;
      const Eigen::Vector3d r0 = a + s * (c - a), r1 = b + s * (c - b);
      const int steps = j == rows ? 0 : std::max(1, int(std::ceil((r1 - r0).norm() / spacing)));
      for (int i = 0; i <= steps; ++i) f(steps == 0 ? r0 : Eigen::Vector3d(r0 + (double(i) / steps) * (r1 - r0)));
    }
  }
}

/// Largest distance from a sample of `from` to the surface of `to`.
inline double one_sided_surface_distance(const Mesh& from, const Mesh& to, double spacing) {
  const TriangleSurface surface(to);
  double worst = 0;
  for_each_surface_sample(from, spacing,
                          [&](const Eigen::Vector3d& p) { worst = std::max(worst, surface.distance(p)); });
  return worst;
}

/// Symmetric (Hausdorff-like) distance between the two triangle surfaces; see the top of this file.
inline double symmetric_surface_distance(const Mesh& a, const Mesh& b, double spacing) {
  return std::max(one_sided_surface_distance(a, b, spacing), one_sided_surface_distance(b, a, spacing));
}

}  // namespace test
}  // namespace restitch
