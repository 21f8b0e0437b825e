// restitch/detail/point_tree.hpp - a nanoflann k-d tree over the rows of a #P by 3 float matrix.
#pragma once

#include <cstddef>
#include <cstdint>
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
using PointSetTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointSetAdaptor>,
                                                         PointSetAdaptor, 3, std::uint32_t>;

}  // namespace restitch::detail
