// tests/support/components.hpp - test-only: the connected pieces of a mesh as a modeller sees them.
//
// `welded_components(m)` welds positions as mesh_boundary.hpp does (the
// stitcher's weld tolerance), joins the corners of every face, and returns
// each connected piece's bounding box. A part cut by a seam shows as a piece
// whose box no piece of the input has; two halves of different parts spliced
// together show the same way. Cost O(#V + #F) after the weld.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <numeric>
#include <vector>

#include "restitch/mesh.hpp"
#include "restitch/mesh_boundary.hpp"

namespace restitch {
namespace test {

struct Piece {
  Eigen::Vector3d lo, hi;
  Eigen::Vector3d size() const { return hi - lo; }
};

inline std::vector<Piece> welded_components(const Mesh& m) {
  const std::vector<std::uint32_t> rep = weld_positions(m, weld_tolerance_of(m));
  std::vector<std::uint32_t> parent(rep.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = find(rep[m.F(f, 0)]), b = find(rep[m.F(f, k)]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<int> index(rep.size(), -1);
  std::vector<Piece> out;
  std::vector<char> used(rep.size(), 0);
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[m.F(f, k)] = 1;
  for (std::size_t v = 0; v < rep.size(); ++v) {
    if (!used[v]) continue;
    const std::uint32_t r = find(rep[v]);
    const Eigen::Vector3d p = m.V.row(Eigen::Index(v)).cast<double>().transpose();
    if (index[r] < 0) {
      index[r] = int(out.size());
      out.push_back({p, p});
    } else {
      Piece& c = out[std::size_t(index[r])];
      c.lo = c.lo.cwiseMin(p);
      c.hi = c.hi.cwiseMax(p);
    }
  }
  return out;
}

/// Pieces of `out` whose box size matches no piece of `in` within `tol` (pieces for which `skip` holds
/// are not counted).
template <class Skip>
int unmatched_pieces(const std::vector<Piece>& out, const std::vector<Piece>& in, double tol, Skip skip) {
  int bad = 0;
  for (const Piece& c : out) {
    if (skip(c)) continue;
    bool match = false;
    for (const Piece& d : in) match = match || (c.size() - d.size()).cwiseAbs().maxCoeff() <= tol;
    bad += !match;
  }
  return bad;
}

}  // namespace test
}  // namespace restitch
