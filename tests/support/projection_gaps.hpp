// tests/support/projection_gaps.hpp - test-only measure of detached pieces along a direction.
//
// `widest_projection_gap(m, d)` projects every triangle of `m` on the unit
// direction `d` (an interval [min, max] of p.d over its corners), takes the
// union of the intervals and returns the widest hole between them (model
// units; 0 when the projection is one interval). A resize that leaves a piece
// detached along the axis it grew on (the original, a gap, then a copy) shows
// as a hole the input's projection does not have. Cost O(#F log #F).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <utility>
#include <vector>

#include "restitch/mesh.hpp"

namespace restitch {
namespace test {

inline double widest_projection_gap(const Mesh& m, const Eigen::Vector3d& d) {
  const Eigen::Vector3f u = d.normalized().cast<float>();
  std::vector<std::pair<double, double>> iv;
  iv.reserve(std::size_t(m.F.rows()));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    double lo = 0, hi = 0;
    for (int k = 0; k < 3; ++k) {
      const double x = double(m.V.row(m.F(f, k)).dot(u.transpose()));
      lo = k == 0 ? x : std::min(lo, x);
      hi = k == 0 ? x : std::max(hi, x);
    }
    iv.emplace_back(lo, hi);
  }
  std::sort(iv.begin(), iv.end());
  double widest = 0;
  for (std::size_t i = 1, reach = 0; i < iv.size(); ++i) {
    if (iv[i].first > iv[reach].second) widest = std::max(widest, iv[i].first - iv[reach].second);
    if (iv[i].second > iv[reach].second) reach = i;
  }
  return widest;
}

}  // namespace test
}  // namespace restitch
