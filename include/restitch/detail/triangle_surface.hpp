// restitch/detail/triangle_surface.hpp - exact distance from points to a triangle surface (internal).
//
// `TriangleSurface` holds a mesh's triangles (double precision) under a balanced AABB tree (median
// splits, at most 4 triangles per leaf); `distance(p)` is the exact unsigned distance from p to the
// nearest point of the surface (closest point on the nearest triangle), `distance_within(p, r)` the same
// below r and r otherwise, searching only the part of the tree within r. Degenerate (zero-area)
// triangles count as their three edges. Used by the structure of a model (restitch/lattice/structure.hpp)
// and by the tests' surface-distance oracle. Deterministic. Cost: O(#F log #F) to build, O(log #F)
// per query for a small bound; memory O(#F).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch::detail {

/// The point of segment [a, b] closest to p.
template <class = void>
Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
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
template <class = void>
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
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
  template <class = void>
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
  template <class = void>
  double distance(const Eigen::Vector3d& p) const {
    return distance_within(p, std::numeric_limits<double>::infinity());
  }

  /// The same when it is below `bound`, else `bound` (the search stops at it: cheaper for a small bound).
  template <class = void>
  double distance_within(const Eigen::Vector3d& p, double bound) const {
    double best2 = bound * bound;
    if (nodes_.empty()) return bound;
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

  template <class = void>
  Eigen::Vector3d centroid(int t) const {
    const auto& x = tri_[std::size_t(t)];
    return (x[0] + x[1] + x[2]) / 3.0;
  }

  template <class = void>
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

}  // namespace restitch::detail
