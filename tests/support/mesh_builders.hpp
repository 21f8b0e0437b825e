// Test-only: small meshes built by hand.
#pragma once

#include "restitch/mesh.hpp"

namespace restitch::test {

// Adds an axis-aligned box [lo, hi] (12 triangles, outward normals) to a mesh.
inline void add_box(Mesh& m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Index base = m.V.rows();
  m.V.conservativeResize(base + 8, 3);
  for (int c = 0; c < 8; ++c)
    m.V.row(base + c) =
        Eigen::Vector3f(float(c & 1 ? hi.x() : lo.x()), float(c & 2 ? hi.y() : lo.y()), float(c & 4 ? hi.z() : lo.z()));
  static const int quads[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  const Eigen::Index f0 = m.F.rows();
  m.F.conservativeResize(f0 + 12, 3);
  for (int q = 0; q < 6; ++q) {
    const auto* k = quads[q];
    m.F.row(f0 + 2 * q) << std::uint32_t(base + k[0]), std::uint32_t(base + k[1]), std::uint32_t(base + k[2]);
    m.F.row(f0 + 2 * q + 1) << std::uint32_t(base + k[0]), std::uint32_t(base + k[2]), std::uint32_t(base + k[3]);
  }
  m.FG = VectorXu::Zero(m.F.rows());
  if (m.groups.empty()) m.groups.push_back(Group{});
}

}  // namespace restitch::test
