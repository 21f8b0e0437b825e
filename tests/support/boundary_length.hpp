// tests/support/boundary_length.hpp - test-only: the total length of a mesh's open (boundary) edges, and
// its surface area.
//
// Edges as restitch/mesh_boundary.hpp counts them (positions welded at the stitcher's weld tolerance,
// an edge used by exactly one face), summed by length in model units. A seam that crosses an edge the
// input already had open splits it in two: the count of open edges grows, their length does not, so
// "stitching opened nothing" is a statement about the length. Cost O(#F log #F).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "restitch/mesh.hpp"
#include "restitch/mesh_boundary.hpp"

namespace restitch::test {

/// The sum of the triangles' areas (model units squared). A result with the surface of the truth in place
/// and the same area holds nothing more (no piece of a part copied twice over a face). Cost O(#F).
inline double surface_area(const Mesh& m) {
  double a = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) a += 0.5 * double_area(m, f);
  return a;
}

inline double open_boundary_length(const Mesh& m) {
  const std::vector<std::uint32_t> rep = weld_positions(m, weld_tolerance_of(m));
  std::vector<std::array<std::uint32_t, 2>> edges;
  edges.reserve(std::size_t(m.F.rows()) * 3);
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
    const std::uint32_t c[3] = {rep[m.F(t, 0)], rep[m.F(t, 1)], rep[m.F(t, 2)]};
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
    for (int k = 0; k < 3; ++k) edges.push_back({std::min(c[k], c[(k + 1) % 3]), std::max(c[k], c[(k + 1) % 3])});
  }
  std::sort(edges.begin(), edges.end());
  double length = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) length += double((m.V.row(edges[i][0]) - m.V.row(edges[i][1])).norm());
    i = j;
  }
  return length;
}

}  // namespace restitch::test
