// restitch/stitch/detail/tjunction.hpp - T-junction repair after welding.
//
// Two sides of a seam are cut from different copies, so one side may cut a
// seam segment into several edges where the other side has one edge: a
// T-junction. Welding cannot close it (the long edge has no vertex to weld
// to), so the output would have open edges along the seam.
//
// The repair, after welding (corners read through the weld map):
//   1. Boundary edges: an edge which exactly one face uses. Every face's
//      edges are counted: the long side of a T-junction need not touch the
//      seam. Where copies of one label meet across a cell plane inside a
//      region that is no box (an L of cells), a face clipped to the region's
//      boxes is cut on that plane while the next face of the same copy lies
//      whole in the region, so its edge crosses the plane with no seam
//      vertex at either end.
//   2. T-vertices: the seam corners (cut vertices, or copies of input
//      vertices on a cell plane) of boundary edges; only those: a vertex that
//      closes nothing on the other side is not a T-vertex, and a T-junction of
//      the input itself, away from every seam, is left as it was. A boundary
//      edge a -> b is split at every T-vertex v, other than a, b and the
//      face's third corner, that lies strictly inside it within the weld
//      tolerance: distance from the line <= tol, and more than tol from a and
//      from b. v may belong to another group (material): where two materials
//      meet, the input's faces share positions, not vertices, and one side's
//      cut vertex is the only vertex that closes the other side's edge; the
//      new corner is then a vertex of a's group at v's position (step 3).
//      T-vertices within tol of one another are one split point (several
//      vertices at one position: a texture seam on the other side).
//   3. Each split point gets a new corner with the T-vertex's position exactly
//      and attributes interpolated along a -> b with the clipping rules
//      (StitchOutput::interpolated_vertex). It then goes through the weld rule
//      (weld_compatible): it joins the first of the T-vertices at that point,
//      in vertex order, whose attributes agree, and stays a vertex of its own
//      otherwise (texture seams and hard edges stay split).
//   4. The face is fanned from the corner opposite the split edge over the
//      sorted split points, keeping its winding. A face with split points on
//      several edges is fanned edge by edge (the first and last triangles of a
//      fan keep the face's other two edges). An edge whose fan would make a
//      triangle of area below tol^2 (the clipper's sliver rule) is not split.
//   Faces keep their place in the face order (the triangles of a fanned face
//   follow one another where it was).
//
// Finding T-vertices: the T-vertices are chained in a hash grid of cells
// h = max(mean boundary edge length, 2 tol) wide. A boundary edge is sampled
// at spacing <= h; a point within tol of the edge is within h/2 + tol <= h of
// a sample, so it lies in the 27 cells around a sample's cell. Candidates are
// then sorted by (parameter, vertex id): the result does not depend on the
// hash order. Deterministic.
//
// Cost: O(#output vertices + #output faces) to count the edges (bucketed by
// their lower corner; each bucket, a vertex's few edges, sorted), plus
// O(27 (B + total boundary edge length / h)) = O(54 B) expected cell look-ups
// for B boundary edges, plus O(k log k) per edge for its k candidates, plus
// O(#faces) to rebuild the face list when something was split.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "restitch/detail/cell_hash.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"
#include "restitch/stitch/detail/cache.hpp"
#include "restitch/stitch/detail/output.hpp"
#include "restitch/stitch/detail/weld.hpp"

namespace restitch::detail {

/// x . y summed in a fixed order, the same on every platform (no vectorised reduction): which T-vertices
/// split an edge must not depend on the build.
inline double dot3(const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
}

/// Splits boundary seam edges at T-vertices (see the file comment). `rep_of`
/// is the weld map; it grows by one entry per new vertex. `tol` is the weld
/// tolerance used. Returns how many edges were split.
template <class = void>
std::size_t repair_t_junctions(StitchOutput& o, const Mesh& in, const ClipStitchCache& cache,
                                      const VertexLayout& L, float attribute_tolerance, double tol,
                                      std::vector<std::uint32_t>& rep_of) {
  const std::size_t nf = o.face_count();
  auto seam = [&](std::uint32_t v) { return o.is_cut(v) || cache.on_plane(o.source(v)); };
  auto corners = [&](std::size_t f, std::uint32_t* c) {
    const std::uint32_t* r = o.face(f);
    for (int k = 0; k < 3; ++k) c[k] = rep_of[r[k]];
    return c[0] != c[1] && c[1] != c[2] && c[2] != c[0];
  };
  // 1. Every face's edges, bucketed by their lower corner (a counting sort), each bucket (a vertex's few
  //    edges) sorted by (upper corner, face * 3 + edge); an upper corner that occurs once in its bucket is
  //    a boundary edge.
  const std::size_t nv0 = o.vertex_count();
  auto each_edge = [&](auto&& visit) {
    for (std::size_t f = 0; f < nf; ++f) {
      std::uint32_t c[3];
      if (!corners(f, c)) continue;
      for (int k = 0; k < 3; ++k) {
        const int n = (k + 1) % 3;
        visit(std::min(c[k], c[n]), std::max(c[k], c[n]), 3 * std::uint64_t(f) + std::uint64_t(k));
      }
    }
  };
  std::vector<std::uint32_t> bucket(nv0 + 1, 0);
  each_edge([&](std::uint32_t a, std::uint32_t, std::uint64_t) { ++bucket[a + 1]; });
  for (std::size_t v = 0; v < nv0; ++v) bucket[v + 1] += bucket[v];
  std::vector<std::pair<std::uint32_t, std::uint64_t>> uses(bucket[nv0]);  // (upper corner, face * 3 + edge)
  {
    std::vector<std::uint32_t> fill(bucket.begin(), bucket.end() - 1);
    each_edge([&](std::uint32_t a, std::uint32_t b, std::uint64_t at) { uses[fill[a]++] = {b, at}; });
  }
  std::vector<std::uint64_t> open;  // face * 3 + edge, ascending
  for (std::size_t v = 0; v < nv0; ++v) {
    auto* b = uses.data() + bucket[v];
    auto* e = uses.data() + bucket[v + 1];
    if (e - b > 1) std::sort(b, e);
    for (auto* i = b; i != e;) {
      auto* j = i + 1;
      while (j != e && j->first == i->first) ++j;
      if (j - i == 1) open.push_back(i->second);
      i = j;
    }
  }
  if (open.empty()) return 0;
  std::sort(open.begin(), open.end());

  // 2. T-vertices: the seam corners of boundary edges, in a hash grid.
  auto pos = [&](std::uint32_t v) {
    float p[3] = {0, 0, 0};  // filled by position()
    o.position(v, p);
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  std::vector<std::uint32_t> tv;
  double total_length = 0;
  for (const std::uint64_t e : open) {
    std::uint32_t c[3];
    corners(std::size_t(e / 3), c);
    const int k = int(e % 3);
    for (const std::uint32_t v : {c[k], c[(k + 1) % 3]})
      if (seam(v)) tv.push_back(v);
    total_length += (pos(c[k]) - pos(c[(k + 1) % 3])).norm();
  }
  if (tv.empty()) return 0;
  std::sort(tv.begin(), tv.end());
  tv.erase(std::unique(tv.begin(), tv.end()), tv.end());
  const double h = std::max(total_length / double(open.size()), 2.0 * tol);
  const auto cell_of = [h](const Eigen::Vector3d& p) {
    return Cell{cell_index(p.x(), h), cell_index(p.y(), h), cell_index(p.z(), h)};
  };
  std::vector<Eigen::Vector3d> tpos(tv.size());
  CellChains grid(tv.size());
  for (std::size_t i = 0; i < tv.size(); ++i) {
    tpos[i] = pos(tv[i]);
    grid.insert(cell_of(tpos[i]), std::int32_t(i));
  }

  // 3. Split points per boundary edge: the corner to put there, ascending along the edge.
  std::vector<std::uint32_t> split_start(open.size() + 1, 0), split_vertex;
  std::vector<std::int32_t> found;
  struct Candidate {
    double t;
    std::uint32_t v;  // index into tv
    bool operator<(const Candidate& o) const { return t != o.t ? t < o.t : v < o.v; }
  };
  std::vector<Candidate> cand;
  const double tol2 = tol * tol;
  for (std::size_t e = 0; e < open.size(); ++e) {
    split_start[e] = std::uint32_t(split_vertex.size());
    std::uint32_t c[3];
    corners(std::size_t(open[e] / 3), c);
    const int k = int(open[e] % 3);
    const std::uint32_t a = c[k], b = c[(k + 1) % 3], opp = c[(k + 2) % 3];
    const Eigen::Vector3d pa = pos(a), pb = pos(b), d = pb - pa;
    const double len2 = dot3(d, d), len = std::sqrt(len2);
    if (!(len > 2.0 * tol)) continue;
    found.clear();
    const int samples = int(std::ceil(len / h)) + 1;
    for (int i = 0; i < samples; ++i) {
      const Cell s = cell_of(pa + d * (double(i) / double(samples - 1)));
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            grid.for_each(Cell{s[0] + dx, s[1] + dy, s[2] + dz}, [&](std::int32_t m) { found.push_back(m); });
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    cand.clear();
    for (const std::int32_t m : found) {
      const std::uint32_t v = tv[std::size_t(m)];
      if (v == a || v == b || v == opp) continue;
      const Eigen::Vector3d q = tpos[std::size_t(m)] - pa;
      const double t = dot3(q, d) / len2;
      if (!(t * len > tol && (1.0 - t) * len > tol)) continue;
      const Eigen::Vector3d off = q - t * d;
      if (dot3(off, off) > tol2) continue;
      cand.push_back({t, std::uint32_t(m)});
    }
    if (cand.empty()) continue;
    std::sort(cand.begin(), cand.end());
    for (std::size_t i = 0; i < cand.size();) {
      // One split point: the first candidate and those within tol of it.
      const Eigen::Vector3d& p0 = tpos[cand[i].v];
      std::size_t j = i + 1;
      while (j < cand.size() && (tpos[cand[j].v] - p0).squaredNorm() <= tol2) ++j;
      float p[3] = {0, 0, 0}, fa[3] = {0, 0, 0}, fb[3] = {0, 0, 0};
      o.position(tv[cand[i].v], p);
      // The new corner's parameter from the stored (float) positions, each term in a fixed order, so that
      // its attributes come out the same bytes on every platform.
      o.position(a, fa);
      o.position(b, fb);
      double num = 0, den = 0;
      for (int x = 0; x < 3; ++x) {
        const double dx = double(fb[x]) - double(fa[x]);
        num += (double(p[x]) - double(fa[x])) * dx;
        den += dx * dx;
      }
      const std::uint32_t nv = o.interpolated_vertex(a, b, num / den, p);
      RESTITCH_ASSERT(nv == rep_of.size(), "repair_t_junctions: the weld map must cover every output vertex");
      // The weld rule: join the first compatible T-vertex at this point, in vertex order.
      std::uint32_t joined = nv;
      for (std::size_t m = i; m < j; ++m) {
        const std::uint32_t v = tv[cand[m].v];
        float q[3] = {0, 0, 0};
        o.position(v, q);
        if (v < joined && weld_compatible(o, in, L, attribute_tolerance, nv, v, p, q, tol2)) joined = v;
      }
      rep_of.push_back(joined);
      split_vertex.push_back(joined);
      i = j;
    }
  }
  split_start[open.size()] = std::uint32_t(split_vertex.size());
  if (split_vertex.empty()) return 0;

  // 4. Rebuild the face list, fanning faces with split edges in place.
  std::vector<std::uint32_t> faces, groups;
  faces.reserve(3 * (nf + split_vertex.size()));
  groups.reserve(nf + split_vertex.size());
  std::size_t split_edges = 0;
  auto area = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return 0.5 * (pos(y) - pos(x)).cross(pos(z) - pos(x)).norm();
  };
  using Span = std::array<std::uint32_t, 2>;  // [begin, end) into split_vertex
  // Emits triangle (v0, v1, v2) whose edge k (v_k -> v_{k+1}) carries split points s[k].
  auto emit = [&](auto&& self, std::array<std::uint32_t, 3> v, std::array<Span, 3> s, std::uint32_t g) -> void {
    for (int k = 0; k < 3; ++k) {
      if (s[std::size_t(k)][0] == s[std::size_t(k)][1]) continue;
      const std::uint32_t a = v[std::size_t(k)], b = v[std::size_t((k + 1) % 3)], opp = v[std::size_t((k + 2) % 3)];
      std::vector<std::uint32_t> chain{a};
      for (std::uint32_t i = s[std::size_t(k)][0]; i < s[std::size_t(k)][1]; ++i) chain.push_back(split_vertex[i]);
      chain.push_back(b);
      bool sliver = false;
      for (std::size_t i = 0; i + 1 < chain.size() && !sliver; ++i)
        sliver = area(chain[i], chain[i + 1], opp) < tol2;
      if (sliver) {
        s[std::size_t(k)] = {0, 0};
        continue;
      }
      ++split_edges;
      const Span none{0, 0};
      // First triangle keeps edge opp -> a, last keeps b -> opp; the others are plain.
      self(self, {chain[0], chain[1], opp}, {none, none, s[std::size_t((k + 2) % 3)]}, g);
      for (std::size_t i = 1; i + 2 < chain.size(); ++i) {
        faces.insert(faces.end(), {chain[i], chain[i + 1], opp});
        groups.push_back(g);
      }
      self(self, {chain[chain.size() - 2], b, opp}, {none, s[std::size_t((k + 1) % 3)], none}, g);
      return;
    }
    faces.insert(faces.end(), {v[0], v[1], v[2]});
    groups.push_back(g);
  };
  std::size_t e = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    std::array<Span, 3> s{};
    std::uint32_t c[3];
    const bool kept = corners(f, c);
    while (e < open.size() && open[e] / 3 == f) {
      s[std::size_t(open[e] % 3)] = {split_start[e], split_start[e + 1]};
      ++e;
    }
    if (!kept || (s[0][0] == s[0][1] && s[1][0] == s[1][1] && s[2][0] == s[2][1])) {
      const std::uint32_t* r = o.face(f);
      faces.insert(faces.end(), {r[0], r[1], r[2]});
      groups.push_back(o.face_group(f));
      continue;
    }
    emit(emit, {c[0], c[1], c[2]}, s, o.face_group(f));
  }
  o.replace_faces(std::move(faces), std::move(groups));
  return split_edges;
}

}  // namespace restitch::detail
