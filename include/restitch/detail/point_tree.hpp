// restitch/detail/point_tree.hpp - a nanoflann k-d tree over the rows of a #P by 3 float matrix.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>

#include "restitch/mesh.hpp"

namespace restitch::detail {

/// nanoflann adaptor over the rows of a #P by 3 float matrix (a PointSet's points), without copying them.
struct PointSetAdaptor {
  const MatrixX3f* points;
  std::size_t kdtree_get_point_count() const { return std::size_t(points->rows()); }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return (*points)(Eigen::Index(i), Eigen::Index(d)); }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};
/// nanoflann result set (the findNeighbors contract): the nearest point whose squared distance is
/// below `bound2`, none when there is none. The bound prunes the search: a query that lands in empty
/// space visits a few nodes instead of descending to the nearest far-away point. Same answer as an
/// unbounded one-nearest search whenever that one lies below the bound (the tree is traversed in the
/// same order, a pruned branch holds no point below the bound, and the first of equal distances wins
/// in both).
struct NearestWithin {
  float dist;
  std::uint32_t index = 0;
  bool found = false;
  explicit NearestWithin(float bound2) : dist(bound2) {}
  /// For a caller that keeps a point when its squared distance, recomputed in double, is at most
  /// `max_d2`: the float bound widened by a relative 1e-4 so the float search never drops such a point.
  template <class = void>
  static NearestWithin keeping(double max_d2) {
    return NearestWithin(float(max_d2 * (1 + 1e-4)) + std::numeric_limits<float>::min());
  }
  std::size_t size() const { return found ? 1 : 0; }
  bool full() const { return found; }
  float worstDist() const { return dist; }
  template <class = void>
  bool addPoint(float d, std::uint32_t i) {  // a leaf offers every point below the worstDist() it began with
    if (d < dist) dist = d, index = i, found = true;
    return true;
  }
};

using PointSetTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointSetAdaptor>,
                                                         PointSetAdaptor, 3, std::uint32_t>;

}  // namespace restitch::detail
