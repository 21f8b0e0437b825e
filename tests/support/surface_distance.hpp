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

#include "restitch/detail/triangle_surface.hpp"
#include "restitch/mesh.hpp"

namespace restitch {
namespace test {

using detail::closest_point_on_segment;
using detail::closest_point_on_triangle;
using detail::corner;
using detail::TriangleSurface;

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
