// Test-only: synthetic point clouds and meshes with known repeats (or none), shared by the offset tests.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/mesh.hpp"
#include "support/mesh_builders.hpp"

namespace restitch::test {

using Eigen::Vector3d;

// Uniform in [0, 1) from the raw engine output (portable across standard libraries).
inline double unit(std::mt19937_64& rng) { return double(rng() >> 11) * (1.0 / 9007199254740992.0); }

// Jittered-grid samples on the surface of an axis-aligned box, spacing s.
inline void sample_box(std::vector<Vector3d>& P, std::vector<Vector3d>& N, const Vector3d& lo, const Vector3d& hi, double s,
                std::mt19937_64& rng) {
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const int nu = std::max(1, int(std::round((hi[u] - lo[u]) / s)));
      const int nv = std::max(1, int(std::round((hi[v] - lo[v]) / s)));
      for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
          Vector3d p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = lo[u] + (hi[u] - lo[u]) * (i + 0.2 + 0.6 * unit(rng)) / nu;
          p[v] = lo[v] + (hi[v] - lo[v]) * (j + 0.2 + 0.6 * unit(rng)) / nv;
          Vector3d n = Vector3d::Zero();
          n[axis] = side ? 1 : -1;
          P.push_back(p);
          N.push_back(n);
        }
    }
}

inline PointSet to_point_set(const std::vector<Vector3d>& P, const std::vector<Vector3d>& N) {
  PointSet s;
  s.points.resize(Eigen::Index(P.size()), 3);
  s.normals.resize(Eigen::Index(P.size()), 3);
  for (std::size_t i = 0; i < P.size(); ++i) {
    s.points.row(Eigen::Index(i)) = P[i].cast<float>().transpose();
    s.normals.row(Eigen::Index(i)) = N[i].cast<float>().transpose();
  }
  return s;
}

// A 4 x 3 lattice of identical boxes (generators t1, t2), sampled at spacing 0.02.
inline const Vector3d kT1(0.37, 0.0, 0.0), kT2(0.08, 0.33, 0.0);
inline PointSet lattice_cloud(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vector3d> P, N;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vector3d o = Vector3d(-0.7, -0.5, -0.1) + i * kT1 + j * kT2;
      sample_box(P, N, o, o + Vector3d(0.2, 0.14, 0.2), 0.02, rng);
      sample_box(P, N, o + Vector3d(0.05, 0.14, 0.05), o + Vector3d(0.09, 0.24, 0.09), 0.02, rng);  // a peg
    }
  return to_point_set(P, N);
}


// A single irregular object: a few boxes of different random sizes at random places.
inline Mesh random_boxes(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Mesh m;
  const int n = 3 + int(rng() % 4);
  for (int b = 0; b < n; ++b) {
    const Vector3d lo(2 * unit(rng), 2 * unit(rng), 2 * unit(rng));
    const Vector3d size(0.2 + unit(rng), 0.2 + unit(rng), 0.2 + unit(rng));
    add_box(m, lo, lo + size);
  }
  return m;
}

// True when g equals one of `found` up to sign, within `rel` of its length and `degrees`.
inline bool recovered(const Vector3d& g, const std::vector<Vector3d>& found, double rel, double degrees) {
  for (const Vector3d& f : found) {
    const Vector3d s = f.dot(g) < 0 ? Vector3d(-f) : f;
    const double angle = std::acos(std::min(1.0, s.dot(g) / (s.norm() * g.norm()))) * 180.0 / 3.14159265358979323846;
    if (std::abs(s.norm() - g.norm()) <= rel * g.norm() && angle <= degrees) return true;
  }
  return false;
}

}  // namespace restitch::test
