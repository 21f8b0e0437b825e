// restitch/stitch/detail/weld.hpp - welding coincident seam vertices of a stitched output.
//
// The rule (stitch.hpp): seam vertices (cut vertices, and copies of input
// vertices lying on a cell plane) weld to an earlier one when the positions
// are within the tolerance, the groups are equal, every attribute channel the
// group carries agrees within `attribute_tolerance` (tangent w exactly), and
// they are not two untouched copies made by the same region. Each candidate,
// in vertex order, joins the lowest earlier representative it is compatible
// with. A candidate that joins none but lies within the tolerance of an
// earlier representative it may not join (another group, or attributes that
// differ: a UV seam, a hard edge) takes that vertex's position, and stays its
// own vertex (`snap_to`): the surface closes, the attribute seam stays.
// Candidates are found through a hash grid of cells 2 tol wide: a
// partner at most tol away lies, along each axis, in the candidate's cell or
// in the neighbour on the side of the nearer cell face, so 8 cells are looked
// at. Cost O(s) expected for s seam vertices.
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
#include "restitch/stitch/detail/cache.hpp"
#include "restitch/stitch/detail/output.hpp"

namespace restitch::detail {

template <class = void>
std::vector<std::uint32_t> identity_map(std::size_t n) {
  std::vector<std::uint32_t> m(n);
  for (std::size_t i = 0; i < n; ++i) m[i] = std::uint32_t(i);
  return m;
}

template <class = void>
double squared_distance(const float* pi, const float* pj) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double d = double(pi[a]) - double(pj[a]);
    d2 += d * d;
  }
  return d2;
}

/// Are output vertices i and j two untouched input vertices copied by one region? Such a pair is never
/// welded nor moved onto each other: the stitcher does not change the input's own topology.
template <class = void>
bool same_region_copies(const StitchOutput& o, std::uint32_t i, std::uint32_t j) {
  return !o.is_cut(i) && !o.is_cut(j) && o.region(i) == o.region(j);
}

/// Do output vertices i and j (positions pi, pj) weld? See the file comment.
template <class = void>
bool weld_compatible(const StitchOutput& o, const Mesh& in, const VertexLayout& L, float attribute_tolerance,
                            std::uint32_t i, std::uint32_t j, const float* pi, const float* pj, double tol2) {
  if (o.group(i) != o.group(j)) return false;
  if (same_region_copies(o, i, j)) return false;
  if (squared_distance(pi, pj) > tol2) return false;
  const AttributeSet& at = in.groups[o.group(i)].attributes;
  const float e = attribute_tolerance;
  auto close = [e](const float* x, const float* y, int n) {
    for (int k = 0; k < n; ++k)
      if (!(std::abs(x[k] - y[k]) <= e)) return false;
    return true;
  };
  if (L.has_n && at.normals && !close(o.normal(i), o.normal(j), 3)) return false;
  if (L.has_t && at.tangents && (!close(o.tangent(i), o.tangent(j), 3) || o.tangent(i)[3] != o.tangent(j)[3]))
    return false;
  for (int s = 0; s < std::min(L.uv_sets, at.uv_sets); ++s)
    if (!close(o.texcoord(i, s), o.texcoord(j, s), 2)) return false;
  if (L.has_c && at.color_components > 0 && !close(o.color(i), o.color(j), std::min(at.color_components, 4)))
    return false;
  return true;
}

/// The representative of every output vertex after welding (itself when not
/// welded); `welded` counts the vertices that were merged away; the tolerance
/// used goes to `tolerance_used` when given. `snap_to` (every vertex: the one
/// whose position it takes, itself when none; left empty when no vertex takes
/// another's) and `snapped` (how many do) are the geometric part, for
/// StitchOutput::snap_positions.
template <class = void>
std::vector<std::uint32_t> weld_map(const StitchOutput& o, const Mesh& in, const ClipStitchCache& cache,
                                           const VertexLayout& L, float attribute_tolerance, std::size_t& welded,
                                           std::vector<std::uint32_t>& snap_to, std::size_t& snapped,
                                           double* tolerance_used = nullptr) {
  const std::size_t nv = o.vertex_count();
  std::vector<std::uint32_t> rep_of = identity_map(nv);
  snap_to.clear();
  // Seam vertices in vertex order, with their positions.
  std::vector<std::uint32_t> ids;
  std::vector<std::array<float, 3>> pos;
  double max_abs = cache.max_abs_coord();
  for (std::uint32_t i = 0; i < std::uint32_t(nv); ++i)
    if (o.is_cut(i) || cache.on_plane(o.source(i))) {
      std::array<float, 3> p{};  // filled by position()
      o.position(i, p.data());
      for (int a = 0; a < 3; ++a) max_abs = std::max(max_abs, double(std::abs(p[std::size_t(a)])));
      ids.push_back(i);
      pos.push_back(p);
    }
  const double tol = std::max(cache.tolerance(), 8.0 * double(FLT_EPSILON) * max_abs);
  if (tolerance_used) *tolerance_used = tol;
  if (ids.size() < 2) return rep_of;
  const double tol2 = tol * tol, h = 2.0 * tol;
  CellChains grid(ids.size());
  const auto cell_of = [h](const std::array<float, 3>& p) {
    return Cell{cell_index(p[0], h), cell_index(p[1], h), cell_index(p[2], h)};
  };
  for (std::size_t k = 0; k < ids.size(); ++k) grid.insert(cell_of(pos[k]), std::int32_t(k));
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Cell c = cell_of(pos[k]);
    std::array<int, 3> side;
    for (int a = 0; a < 3; ++a) {
      const double u = double(pos[k][std::size_t(a)]) / h;
      side[std::size_t(a)] = (u - std::floor(u)) < 0.5 ? -1 : 1;
    }
    std::uint32_t best = ids[k], near = ids[k];  // near: the lowest earlier representative within tol
    for (int dz = 0; dz <= 1; ++dz)
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx)
          grid.for_each(Cell{c[0] + dx * side[0], c[1] + dy * side[1], c[2] + dz * side[2]}, [&](std::int32_t m) {
            const std::uint32_t j = ids[std::size_t(m)];
            if (j >= ids[k] || rep_of[j] != j) return;
            if (j < best && weld_compatible(o, in, L, attribute_tolerance, ids[k], j, pos[k].data(),
                                            pos[std::size_t(m)].data(), tol2))
              best = j;
            if (j < near && !same_region_copies(o, ids[k], j) &&
                squared_distance(pos[k].data(), pos[std::size_t(m)].data()) <= tol2)
              near = j;
          });
    if (best != ids[k]) {
      rep_of[ids[k]] = best;
      ++welded;
    } else if (near != ids[k]) {
      if (snap_to.empty()) snap_to = identity_map(nv);  // the first snap: every vertex its own so far
      snap_to[ids[k]] = snap_to[near];
      ++snapped;
    }
  }
  return rep_of;
}

}  // namespace restitch::detail
