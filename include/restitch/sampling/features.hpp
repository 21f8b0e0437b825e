// restitch/sampling/features.hpp - mesh vertices as features, and joining point sets.
//
// docs/method.md 1.1: "All mesh vertices are features too, but cap them: above a
// limit (default 20 000) subsample vertices to the dense spacing." The
// analysis uses features = concat(poisson_disk_sample(..., 0.06, ...),
// vertex_features(...)).
//
//   Result<PointSet> vertex_features(mesh, norm, cap, subsample_spacing, seed, keep_flat = false)
//   PointSet concat(a, b)
//
// vertex_features contract:
//   * Only vertices referenced by some triangle are used (any triangle, also
//     a zero-area one). Vertices at identical positions (exact float equality
//     of x, y and z; flat shading and UV seams duplicate them) are merged
//     into one feature, represented by the lowest vertex index. Features come
//     in increasing order of that index.
//   * Positions in NORMALIZED units (`norm.to_normalized`).
//   * Normal: the sum over every triangle touching the position (through any
//     of the merged vertices) of (b - a) x (c - a), i.e. area-weighted face
//     normals, normalized. The mesh's N channel is not used. Fallback when
//     that sum has zero length (e.g. two coincident faces of opposite
//     orientation): the unit normal of the largest-area incident triangle
//     (lowest face index on equal areas); when every incident triangle has
//     zero area: +Z (0, 0, 1). Normals are never NaN.
//   * Shape-neutral vertices are not features (unless `keep_flat`): a merged
//     vertex inside a flat region (every incident triangle with the same unit
//     normal, within 1e-4, and every edge shared by two of them), inside two
//     coincident flat regions facing opposite ways (a board resting on
//     another with vertices at the same positions: normals u and -u, every
//     edge either inside one of them or shared by two faces along u and two
//     along -u, one of each pair on either side of the edge), or inside a
//     straight crease or straight open edge (two normals at most, and exactly
//     two such feature edges, collinear and opposite); moving it along its
//     region or line changes nothing a modeller made. Such vertices exist only
//     because of how the region was tessellated (a wall or a board meshed
//     every few centimetres), their descriptors are those of a plane or a
//     straight edge wherever they are, and their matches vote for the
//     tessellation's own lattice: a facade meshed finely was analysed along
//     (3.2, 0.2, 0), a wall-grid shift, instead of its bays, and a fence's
//     pickets meshed along their height gave a false repeat along y. Vertices
//     with a zero-area incident triangle are kept.
//   * cap: when more than `cap` merged vertices remain, they are thinned by
//     Poisson-disk elimination at `subsample_spacing`: visited in a seeded
//     random order (std::mt19937_64(seed), raw output, Fisher-Yates), a
//     vertex is kept when no kept vertex is closer than the spacing. If more
//     than `cap` are still kept, an evenly strided subset of exactly `cap` of
//     them (in vertex order: the k-th kept is floor(k * kept / cap)) remains.
//     cap == 0 returns an empty set (vertex features off).
//   * Deterministic; the output is sized by the call.
//   * Errors: invalid_mesh (no triangles, index out of range, a non-finite
//     referenced position), invalid_argument (subsample_spacing not finite
//     and > 0), too_large (spacing too small for the grid, see poisson_disk.hpp).
//
// Cost: O(#F + #V log #V) (a sort to merge positions); the thinning adds
// O(#V) expected grid tests. Memory O(#V + #F).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/mesh.hpp"
#include "restitch/normalization.hpp"
#include "restitch/sampling/poisson_disk.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// The rows of `a` followed by the rows of `b`. Cost O(#a + #b).
template <class = void>
PointSet concat(const PointSet& a, const PointSet& b) {
  RESTITCH_ASSERT(a.points.rows() == a.normals.rows() && b.points.rows() == b.normals.rows(),
                  "a PointSet needs one normal per point");
  PointSet out;
  out.points.resize(a.size() + b.size(), 3);
  out.normals.resize(a.size() + b.size(), 3);
  out.points.topRows(a.size()) = a.points;
  out.points.bottomRows(b.size()) = b.points;
  out.normals.topRows(a.size()) = a.normals;
  out.normals.bottomRows(b.size()) = b.normals;
  return out;
}

/// The mesh vertices as features (see the top of this header).
namespace detail {

/// Representative of each referenced vertex position: equal positions map to
/// their lowest index (rep), `order` lists the referenced vertices sorted by
/// (x, y, z, index). Fails on a non-finite referenced vertex.
template <class = void>
Status merge_equal_positions(const Mesh& mesh, std::vector<std::uint32_t>& rep,
                                    std::vector<std::uint32_t>& order) {
  const Eigen::Index nv = mesh.V.rows();
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[mesh.F(f, k)] = 1;
  order.clear();
  for (Eigen::Index i = 0; i < nv; ++i) {
    if (!used[static_cast<std::size_t>(i)]) continue;
    if (!mesh.V.row(i).allFinite())
      return error(StatusCode::invalid_mesh,
                   "vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or infinity)");
    order.push_back(static_cast<std::uint32_t>(i));
  }
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    for (int k = 0; k < 3; ++k) {
      const float pa = mesh.V(a, k), pb = mesh.V(b, k);
      if (pa < pb) return true;
      if (pb < pa) return false;
    }
    return a < b;
  });
  rep.assign(static_cast<std::size_t>(nv), 0);
  for (std::size_t k = 0; k < order.size();) {
    std::size_t e = k + 1;
    while (e < order.size() && mesh.V(order[e], 0) == mesh.V(order[k], 0) &&
           mesh.V(order[e], 1) == mesh.V(order[k], 1) && mesh.V(order[e], 2) == mesh.V(order[k], 2))
      ++e;
    for (std::size_t j = k; j < e; ++j) rep[order[j]] = order[k];
    k = e;
  }
  return {};
}

/// Area-weighted normal sums per representative (`sum`), and the normal of
/// each one's largest face as the fallback for a zero sum (`best_normal`).
template <class = void>
void representative_normals(const Mesh& mesh, const std::vector<std::uint32_t>& rep,
                                   std::vector<Eigen::Vector3d>& sum, std::vector<Eigen::Vector3d>& best_normal) {
  const std::size_t nv = static_cast<std::size_t>(mesh.V.rows());
  sum.assign(nv, Eigen::Vector3d::Zero());
  best_normal.assign(nv, Eigen::Vector3d(0, 0, 1));
  std::vector<double> best_area(nv, 0.0);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)).transpose().template cast<double>();
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1)).transpose().template cast<double>();
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2)).transpose().template cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    std::uint32_t seen[3];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t r = rep[mesh.F(f, k)];
      seen[k] = r;
      if ((k > 0 && seen[0] == r) || (k > 1 && seen[1] == r)) continue;  // a face counts once per position
      sum[r] += n;
      if (len > best_area[r]) best_area[r] = len, best_normal[r] = n / len;
    }
  }
}

/// Marks the shape-neutral representatives (see the top of this header). A vertex's feature edges are
/// its edges not shared by exactly two triangles of the same unit normal (within `tolerance`), nor by
/// four, two along some u and two along -u with one of each pair on either side of the edge (two
/// coincident sheets passing through it): open, non-manifold and crease edges.
/// Neutral: no zero-area incident triangle, at most two distinct incident normals, and either no feature
/// edge (inside a flat region: one normal, or two opposite ones) or exactly two, collinear and opposite
/// (inside a straight crease or a straight open edge).
template <class = void>
std::vector<char> shape_neutral(const Mesh& mesh, const std::vector<std::uint32_t>& rep,
                                       double tolerance = 1e-4) {
  const std::size_t nv = static_cast<std::size_t>(mesh.V.rows());
  std::vector<char> neutral(nv, 1), normals(nv, 0);  // normals: distinct incident normals seen (capped at 3)
  std::vector<Eigen::Vector3d> n1(nv, Eigen::Vector3d::Zero()), n2(nv, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> unit(static_cast<std::size_t>(mesh.F.rows()), Eigen::Vector3d::Zero());
  struct Side {
    std::uint32_t a, b;  // a < b
    std::uint32_t face;
    bool operator<(const Side& o) const { return a != o.a ? a < o.a : b != o.b ? b < o.b : face < o.face; }
  };
  std::vector<Side> sides;
  sides.reserve(3 * static_cast<std::size_t>(mesh.F.rows()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    std::uint32_t r[3];
    for (int k = 0; k < 3; ++k) r[k] = rep[mesh.F(f, k)];
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)).transpose().template cast<double>();
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1)).transpose().template cast<double>();
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2)).transpose().template cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0) || r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) {
      for (int k = 0; k < 3; ++k) neutral[r[k]] = 0;
      continue;
    }
    const Eigen::Vector3d u = n / len;
    unit[std::size_t(f)] = u;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = r[k];
      if (normals[v] == 0)
        normals[v] = 1, n1[v] = u;
      else if ((u - n1[v]).norm() > tolerance) {
        if (normals[v] == 1)
          normals[v] = 2, n2[v] = u;
        else if (normals[v] == 2 && (u - n2[v]).norm() > tolerance)
          normals[v] = 3;
      }
      sides.push_back(Side{std::min(r[k], r[(k + 1) % 3]), std::max(r[k], r[(k + 1) % 3]), std::uint32_t(f)});
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<char> feature_edges(nv, 0);  // capped at 3
  std::vector<Eigen::Vector3d> dir1(nv, Eigen::Vector3d::Zero()), dir2(nv, Eigen::Vector3d::Zero());
  auto position = [&](std::uint32_t v) { return Eigen::Vector3d(mesh.V.row(v).transpose().cast<double>()); };
  auto add_feature = [&](std::uint32_t v, std::uint32_t w) {
    const Eigen::Vector3d d = (position(w) - position(v)).normalized();
    if (feature_edges[v] == 0) dir1[v] = d;
    if (feature_edges[v] == 1) dir2[v] = d;
    if (feature_edges[v] < 3) ++feature_edges[v];
  };
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t e = i + 1;
    while (e < sides.size() && sides[e].a == sides[i].a && sides[e].b == sides[i].b) ++e;
    bool smooth = false;
    if (e - i == 2) {
      smooth = (unit[sides[i].face] - unit[sides[i + 1].face]).norm() <= tolerance;
    } else if (e - i == 4) {
      // Two coincident sheets facing opposite ways pass through the edge: two faces along u and two along
      // -u, and of each pair one on either side of the edge (a stack of cards ending at the edge, or a
      // sheet folded back onto itself, has all four on one side).
      const Eigen::Vector3d& u = unit[sides[i].face];
      const Eigen::Vector3d pa = position(sides[i].a), across = u.cross(position(sides[i].b) - pa);
      int along[2] = {0, 0}, against[2] = {0, 0};  // by side of the edge
      for (std::size_t k = i; k < e; ++k) {
        const std::size_t f = sides[k].face;
        std::uint32_t third = 0;
        for (int c = 0; c < 3; ++c)
          if (rep[mesh.F(Eigen::Index(f), c)] != sides[i].a && rep[mesh.F(Eigen::Index(f), c)] != sides[i].b)
            third = mesh.F(Eigen::Index(f), c);
        const int side = (position(third) - pa).dot(across) > 0 ? 1 : 0;
        const Eigen::Vector3d& w = unit[f];
        if ((w - u).norm() <= tolerance) ++along[side];
        if ((w + u).norm() <= tolerance) ++against[side];
      }
      smooth = along[0] == 1 && along[1] == 1 && against[0] == 1 && against[1] == 1;
    }
    if (!smooth) add_feature(sides[i].a, sides[i].b), add_feature(sides[i].b, sides[i].a);
    i = e;
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (!neutral[v]) continue;
    if (normals[v] == 0 || normals[v] > 2)
      neutral[v] = 0;
    else if (feature_edges[v] == 0)  // one sheet, or two coincident ones facing opposite ways
      neutral[v] = normals[v] == 1 || (n1[v] + n2[v]).norm() <= tolerance;
    else
      neutral[v] = feature_edges[v] == 2 && dir1[v].dot(dir2[v]) < -1 + 0.5 * tolerance * tolerance;
  }
  return neutral;
}

/// Thins `reps` (ascending) to at most `cap`: a Poisson-disk pass at `spacing`
/// in a seeded random order, then an even stride if still over the cap.
template <class Position>
Status thin_vertices(std::vector<std::uint32_t>& reps, std::size_t cap, double spacing, std::uint64_t seed,
                     const Position& position) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (std::uint32_t v : reps) {
    const Eigen::Vector3d p = position(v);
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  RESTITCH_TRY(check_grid_range(lo, hi, spacing));
  std::vector<std::uint32_t> visit = reps;
  std::mt19937_64 rng(seed);
  for (std::size_t i = visit.size(); i > 1; --i) std::swap(visit[i - 1], visit[bounded_index(rng, i)]);
  PointGrid grid(spacing, lo, hi, reps.size());
  std::vector<std::uint32_t> kept;
  for (std::uint32_t v : visit) {
    const Eigen::Vector3d p = position(v).template cast<float>().template cast<double>();
    if (!grid.far_from_all(p)) continue;
    grid.insert(p);
    kept.push_back(v);
  }
  std::sort(kept.begin(), kept.end());
  if (kept.size() > cap) {
    std::vector<std::uint32_t> strided(cap);
    for (std::size_t k = 0; k < cap; ++k)
      strided[k] = kept[static_cast<std::size_t>((static_cast<unsigned long long>(k) * kept.size()) /
                                                 cap)];  // k * kept < 2^64 for any real mesh
    kept.swap(strided);
  }
  reps.swap(kept);
  return {};
}

/// The representatives that shape the model (rep[v] == v, in `order`), without the shape-neutral ones
/// (inside a flat region or a straight crease) unless `keep_flat`: where they repeat, the model does, and not
/// only its tessellation.
template <class = void>
std::vector<std::uint32_t> shaping_representatives(const Mesh& mesh, const std::vector<std::uint32_t>& rep,
                                                   const std::vector<std::uint32_t>& order, bool keep_flat) {
  std::vector<char> neutral;
  if (!keep_flat) neutral = shape_neutral(mesh, rep);
  std::vector<std::uint32_t> reps;
  for (const std::uint32_t v : order)
    if (rep[v] == v && (keep_flat || !neutral[v])) reps.push_back(v);
  return reps;
}

}  // namespace detail

template <class = void>
Result<PointSet> vertex_features(const Mesh& mesh, const Normalization& norm, std::size_t cap = 20000,
                                        double subsample_spacing = 0.02, std::uint64_t seed = 1,
                                        bool keep_flat = false) {
  if (!(subsample_spacing > 0) || !std::isfinite(subsample_spacing))
    return error(StatusCode::invalid_argument, "the vertex subsampling spacing must be a positive finite number");
  if (mesh.F.rows() == 0) return error(StatusCode::invalid_mesh, "the mesh has no triangles");
  const Eigen::Index nv = mesh.V.rows();
  if (mesh.F.maxCoeff() >= static_cast<std::uint32_t>(nv))
    return error(StatusCode::invalid_mesh, "a triangle refers to a vertex index past the end of the vertex list");
  if (cap == 0) return PointSet{};

  std::vector<std::uint32_t> rep, order;
  RESTITCH_TRY(detail::merge_equal_positions(mesh, rep, order));
  std::vector<Eigen::Vector3d> sum, best_normal;
  detail::representative_normals(mesh, rep, sum, best_normal);
  std::vector<std::uint32_t> reps = detail::shaping_representatives(mesh, rep, order, keep_flat);
  std::sort(reps.begin(), reps.end());

  auto position = [&](std::uint32_t v) { return norm.to_normalized(mesh.V.row(v).transpose().cast<double>()); };
  if (reps.size() > cap) RESTITCH_TRY(detail::thin_vertices(reps, cap, subsample_spacing, seed, position));

  PointSet out;
  out.points.resize(static_cast<Eigen::Index>(reps.size()), 3);
  out.normals.resize(static_cast<Eigen::Index>(reps.size()), 3);
  for (std::size_t i = 0; i < reps.size(); ++i) {
    const std::uint32_t v = reps[i];
    const double len = sum[v].norm();
    const Eigen::Vector3d n = (len > 0 && std::isfinite(len)) ? Eigen::Vector3d(sum[v] / len) : best_normal[v];
    out.points.row(static_cast<Eigen::Index>(i)) = position(v).template cast<float>().transpose();
    out.normals.row(static_cast<Eigen::Index>(i)) = n.cast<float>().transpose();
  }
  return out;
}

}  // namespace restitch
