// restitch/mesh_boundary.hpp - how many boundary (open) edges a mesh has, seen geometrically.
//
// Definition (what a modeller's "select boundary edges" shows once coincident
// vertices are merged):
//   1. Positions are welded over the whole mesh, all groups together,
//      attributes ignored: each vertex, in index order, joins the lowest
//      earlier representative whose position lies within `tol` (Euclidean).
//      tol = max(relative_tolerance x bounding-box diagonal, 8 float ulps of
//      the largest |coordinate|): the stitcher's weld tolerance
//      (ClipStitcher::weld_tolerance, default 1e-6), so "closed" means closed
//      at the precision the stitcher welds at.
//   2. Faces whose welded corners are not three distinct points are ignored.
//   3. An edge is an unordered pair of welded corners; a boundary edge is one
//      used by exactly one face. (Edges used by three or more faces are
//      non-manifold, not boundary, and are not counted.)
// A closed 2-manifold has 0; so does a mesh whose texture seams or hard
// edges split vertices, since positions are welded.
//
// Cost O(#V) expected for the weld (a hash grid of cells 2 tol wide: a
// partner at most tol away lies in the vertex's cell or, per axis, the
// neighbour on the nearer side: 8 cells) plus O(#F) to bucket the edges by
// their lower corner (each bucket, a vertex's few edges, sorted). Memory
// O(#V + #F).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <vector>

#include "restitch/detail/cell_hash.hpp"
#include "restitch/mesh.hpp"

namespace restitch {

/// The weld tolerance of mesh m (see the file comment), in model units.
template <class = void>
double weld_tolerance_of(const Mesh& m, double relative_tolerance = 1e-6) {
  return std::max(relative_tolerance * bounding_box(m).size().norm(), 8.0 * double(FLT_EPSILON) * max_abs_coordinate(m));
}

/// The representative of every vertex when positions within `tol` are welded
/// (step 1 of the file comment). rep[i] <= i, and rep[rep[i]] == rep[i].
template <class = void>
std::vector<std::uint32_t> weld_positions(const Mesh& m, double tol) {
  const std::size_t nv = m.vertex_count();
  std::vector<std::uint32_t> rep(nv);
  for (std::size_t i = 0; i < nv; ++i) rep[i] = std::uint32_t(i);
  if (nv < 2 || !(tol > 0)) return rep;
  const double h = 2.0 * tol, tol2 = tol * tol;
  const float* V = m.V.data();
  const auto cell_of = [h](const float* p) {
    return detail::Cell{detail::cell_index(p[0], h), detail::cell_index(p[1], h), detail::cell_index(p[2], h)};
  };
  detail::CellChains grid(nv);
  for (std::size_t i = 0; i < nv; ++i) grid.insert(cell_of(V + 3 * i), std::int32_t(i));
  for (std::size_t i = 0; i < nv; ++i) {
    const float* p = V + 3 * i;
    const detail::Cell c = cell_of(p);
    std::array<int, 3> side{};
    for (int a = 0; a < 3; ++a) {
      const double u = double(p[a]) / h;
      side[std::size_t(a)] = (u - std::floor(u)) < 0.5 ? -1 : 1;
    }
    std::uint32_t best = std::uint32_t(i);
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx)
          grid.for_each(detail::Cell{c[0] + dx * side[0], c[1] + dy * side[1], c[2] + dz * side[2]},
                        [&](std::int32_t j) {
                          const std::uint32_t u = std::uint32_t(j);
                          if (u >= best || rep[u] != u) return;
                          double d2 = 0;
                          for (int a = 0; a < 3; ++a) {
                            const double d = double(p[a]) - double(V[3 * std::size_t(u) + std::size_t(a)]);
                            d2 += d * d;
                          }
                          if (d2 <= tol2) best = u;
                        });
    rep[i] = best;
  }
  return rep;
}

/// A boundary edge: the welded representatives (weld_positions) of its two corners, a < b, and the one
/// face that uses it.
struct BoundaryEdge {
  std::uint32_t a = 0, b = 0;
  std::uint32_t face = 0;
};

/// The boundary edges of m with its vertices welded by `rep` (weld_positions of m: one entry per vertex,
/// its position's representative), ordered by a, then b.
template <class = void>
std::vector<BoundaryEdge> boundary_edges_welded(const Mesh& m, const std::vector<std::uint32_t>& rep) {
  // Edges bucketed by their lower corner (a counting sort), each bucket sorted by the higher one:
  // O(#F) plus tiny sorts, instead of one O(#F log #F) sort.
  const std::size_t nv = m.vertex_count();
  std::vector<std::uint32_t> start(nv + 1, 0);
  auto each_edge = [&](auto&& f) {
    for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
      const std::uint32_t c[3] = {rep[m.F(t, 0)], rep[m.F(t, 1)], rep[m.F(t, 2)]};
      if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
      for (int k = 0; k < 3; ++k) f(std::min(c[k], c[(k + 1) % 3]), std::max(c[k], c[(k + 1) % 3]), std::uint32_t(t));
    }
  };
  each_edge([&](std::uint32_t a, std::uint32_t, std::uint32_t) { ++start[a + 1]; });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> other(start[nv]);  // (higher corner, face)
  each_edge([&](std::uint32_t a, std::uint32_t b, std::uint32_t t) { other[fill[a]++] = {b, t}; });
  std::vector<BoundaryEdge> open;
  for (std::size_t v = 0; v < nv; ++v) {
    auto* b = other.data() + start[v];
    auto* e = other.data() + start[v + 1];
    std::sort(b, e);
    for (auto* i = b; i != e;) {
      auto* j = i + 1;
      while (j != e && j->first == i->first) ++j;
      if (j - i == 1) open.push_back({std::uint32_t(v), i->first, i->second});
      i = j;
    }
  }
  return open;
}

/// The boundary edges of m with positions welded at `tol` (see the file comment), ordered by a, then b.
template <class = void>
std::vector<BoundaryEdge> boundary_edges_at(const Mesh& m, double tol) {
  return boundary_edges_welded(m, weld_positions(m, tol));
}

/// How many boundary edges m has with positions welded at `tol`.
template <class = void>
std::size_t boundary_edge_count_at(const Mesh& m, double tol) {
  return boundary_edges_at(m, tol).size();
}

/// Boundary edges of m at its weld tolerance (relative to the bounding-box diagonal).
template <class = void>
std::size_t boundary_edge_count(const Mesh& m, double relative_tolerance = 1e-6) {
  return boundary_edge_count_at(m, weld_tolerance_of(m, relative_tolerance));
}

}  // namespace restitch
