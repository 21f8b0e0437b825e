// restitch/stitch/detail/zipper.hpp - closing seams whose two sides do not quite meet: a strip of
// triangles between the two cut lines, in the seam plane.
//
// Where two copies meet at a seam, the stitcher cuts both at the same plane, so each side's cut line lies
// in that plane. Welding (weld.hpp) joins the vertices that coincide and the T-junction repair
// (tjunction.hpp) splits the edges that another side's vertex lies on; what stays open is where the two
// cut lines are not the same line: copies that differ slightly (a modeller's repeats are exact to 1e-5 or
// 1e-4 of the model, beyond the weld tolerance) or that are tessellated differently on a curved surface
// (two polygons inscribed in the same circle with their corners in different places). Moving either
// side's vertices onto the other's, or splitting its edges at them, tilts its faces (a split point off
// the face's plane folds the fan; an earlier zipper did that and drew crease lines on the models). This
// one moves nothing: it adds triangles between the two cut lines, whose corners are those lines' own
// vertices, all in the seam plane. The strip is as wide as the two lines are apart.
//
//   1. Open seam edges: edges of the faces, with both corners seam vertices (cut vertices, or copies of
//      input vertices on a cell plane), used by exactly one face, directed as that face runs them.
//   2. Chains: the open seam edges followed head to tail through positions with one open edge in and one
//      out (any other position ends the chains through it), open or closed. A chain with no cut vertex
//      whose every edge is a copy of one the input has open is the input's own open edge (left open).
//   3. Partners: a chain and another, of the same group, running the other way (open chains: each one's
//      start within the gap of the other's end; closed ones: their vector areas point opposite ways), with
//      every vertex of each within the gap of the other's polyline. The nearest such chain (by that
//      Hausdorff distance; the first in chain order on a tie) that is not taken yet.
//      Where the two sides touch (the weld joined a vertex of each, or a short edge joins them), they run
//      as one chain, out along one side and back along the other: a slit. A chain left without a partner
//      is cut at its tips (the point farthest from its start, or a closed chain's farthest pair of
//      points) and its two halves are partners if they pass the same test.
//   4. The strip: the two lines walked together from a matched start (open chains: their ends; closed:
//      the other's vertex nearest the first's first vertex), each step advancing the line whose next
//      vertex makes the shorter diagonal (the classic contour-stitching rule). Each triangle runs the
//      line's edge the other way from its face, so the surface stays consistently oriented. Triangles
//      with a repeated corner (two lines that share a vertex) are left out; their edge is the diagonal.
// Gap: 1e-3 of the input's bounding-box diagonal, the tolerance at which restitch/lattice/structure.hpp
// calls two slabs copies: wider apart, the sides are not copies of each other and the seam stays open
// (the result check, restitch/retarget/check.hpp, says so).
//
// Cost: O(s log s) for the s edges of faces with two seam corners, then per chain a sweep over the
// chains sorted by their boxes (a partner's box is within the gap of its own) and O(n m) distance tests
// for chains of n and m vertices whose boxes agree.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "restitch/detail/triangle_surface.hpp"
#include "restitch/mesh.hpp"
#include "restitch/stitch/detail/cache.hpp"
#include "restitch/stitch/detail/output.hpp"

namespace restitch::detail {

/// The zipper's gap as a fraction of the input's bounding-box diagonal (see the file comment). The seam
/// mover judges continuation at the same gap (restitch/energy/seam_geometry.hpp, CellSlabs::set_surface).
inline constexpr double zip_gap_of_diagonal = 1e-3;

/// Closes seams whose sides lie within `gap` (model units) of each other with strips of triangles (see the
/// file comment). `rep_of` is the weld map. Returns how many triangles were added.
template <class = void>
std::size_t zip_seams(StitchOutput& o, const ClipStitchCache& cache, double gap, const std::vector<std::uint32_t>& rep_of) {
  const std::size_t nf = o.face_count();
  auto seam = [&](std::uint32_t v) { return o.is_cut(v) || cache.on_plane(o.source(v)); };
  auto pos = [&](std::uint32_t v) {
    float p[3] = {0, 0, 0};
    o.position(v, p);
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  // Positions: the weld's geometric part leaves coincident seam vertices at one exact position, but keeps
  // them apart where their attributes differ (hard edges, texture seams). Edges and chains are followed
  // by position (`pid`); the triangles use the vertices of the edges they close.
  std::vector<std::uint32_t> pid(o.vertex_count(), 0);
  {
    std::vector<std::pair<std::array<float, 3>, std::uint32_t>> at;
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = rep_of[o.face(f)[k]];
        if (!seam(v)) continue;
        float p[3] = {0, 0, 0};
        o.position(v, p);
        at.push_back({{p[0], p[1], p[2]}, v});
      }
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < at.size(); ++i) {
      if (i > 0 && at[i].first != at[i - 1].first) ++id;
      pid[at[i].second] = id;
    }
  }
  // 1. Open seam edges (by position), directed as their face runs them.
  struct Use {
    std::uint32_t lo, hi, from, to, group;  // lo, hi: positions; from, to: vertices
  };
  std::vector<Use> uses;
  for (std::size_t f = 0; f < nf; ++f) {
    const std::uint32_t* r = o.face(f);
    const std::uint32_t c[3] = {rep_of[r[0]], rep_of[r[1]], rep_of[r[2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = c[k], b = c[(k + 1) % 3];
      if (seam(a) && seam(b) && pid[a] != pid[b])
        uses.push_back({std::min(pid[a], pid[b]), std::max(pid[a], pid[b]), a, b, o.face_group(f)});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.from != y.from ? x.from < y.from : x.to < y.to;
  });
  std::vector<Use> open;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    if (j - i == 1) open.push_back(uses[i]);
    i = j;
  }
  if (open.size() < 2) return 0;

  // 2. Chains over positions.
  std::vector<std::uint32_t> ids;  // the positions the open edges use, dense
  for (const Use& e : open) ids.push_back(pid[e.from]), ids.push_back(pid[e.to]);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  auto id = [&](std::uint32_t v) { return std::uint32_t(std::lower_bound(ids.begin(), ids.end(), pid[v]) - ids.begin()); };
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> edge_at(ids.size(), none);  // the open edge leaving a position
  std::vector<int> out_degree(ids.size(), 0), in_degree(ids.size(), 0);
  for (std::uint32_t e = 0; e < open.size(); ++e) {
    const std::uint32_t a = id(open[e].from), b = id(open[e].to);
    edge_at[a] = e;
    ++out_degree[a], ++in_degree[b];
  }
  struct Chain {
    std::vector<std::uint32_t> from, to;  // per edge, its face's vertices, in order along the chain
    bool closed = false;
    std::uint32_t group = 0;
    Eigen::Vector3d lo, hi, area;  // box, and vector area (closed chains)
    std::size_t points() const { return closed ? from.size() : from.size() + 1; }
    std::uint32_t point(std::size_t k) const {  // a vertex at point k (k == points() wraps on a closed chain)
      if (k < from.size()) return from[k];
      return closed ? from[k - from.size()] : to.back();
    }
  };
  std::vector<Chain> chains;
  // A position with one open edge in and one out continues a chain; any other ends the chains through it
  // (where the two sides of a slit touch, two edges go in and two out).
  auto simple = [&](std::uint32_t a) { return out_degree[a] == 1 && in_degree[a] == 1; };
  std::vector<char> taken(open.size(), 0);
  auto walk = [&](std::uint32_t first) {
    Chain c;
    c.group = open[first].group;
    const std::uint32_t start = id(open[first].from);
    bool clean = true;
    for (std::uint32_t e = first;;) {
      if (taken[e] || open[e].group != c.group) {
        clean = false;
        break;
      }
      taken[e] = 1;
      c.from.push_back(open[e].from), c.to.push_back(open[e].to);
      const std::uint32_t b = id(open[e].to);
      if (!simple(b)) break;  // the end of an open chain
      if (b == start) {
        c.closed = true;
        break;
      }
      e = edge_at[b];
    }
    if (clean && c.from.size() >= (c.closed ? 3u : 1u)) chains.push_back(std::move(c));
  };
  for (std::uint32_t e = 0; e < open.size(); ++e)
    if (!taken[e] && !simple(id(open[e].from))) walk(e);  // open chains, from their starts
  for (std::uint32_t e = 0; e < open.size(); ++e)
    if (!taken[e]) walk(e);  // what is left: closed chains
  auto bound = [&](Chain& c) {  // its box, and its vector area if closed
    c.lo = c.hi = pos(c.point(0));
    c.area.setZero();
    for (std::size_t k = 0; k < c.points(); ++k) {
      const Eigen::Vector3d p = pos(c.point(k));
      c.lo = c.lo.cwiseMin(p), c.hi = c.hi.cwiseMax(p);
      if (c.closed) c.area += p.cross(pos(c.point(k + 1)));
    }
  };
  std::vector<Chain> cut;  // only chains a seam made: with a cut vertex, or an edge the input has closed
  for (Chain& c : chains) {
    bool made = false;
    for (std::size_t k = 0; k < c.from.size() && !made; ++k)
      made = o.is_cut(c.from[k]) || o.is_cut(c.to[k]) || !cache.input_edge_open(o.source(c.from[k]), o.source(c.to[k]));
    if (!made) continue;
    bound(c);
    cut.push_back(std::move(c));
  }
  if (cut.empty()) return 0;

  // 3. Partners.
  auto polyline_distance = [&](const Eigen::Vector3d& p, const Chain& c) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < c.from.size(); ++i)
      best = std::min(best, (closest_point_on_segment(p, pos(c.from[i]), pos(c.to[i])) - p).norm());
    return best;
  };
  auto hausdorff = [&](const Chain& a, const Chain& b) {
    double h = 0;
    for (std::size_t k = 0; k < a.points(); ++k) h = std::max(h, polyline_distance(pos(a.point(k)), b));
    for (std::size_t k = 0; k < b.points(); ++k) h = std::max(h, polyline_distance(pos(b.point(k)), a));
    return h;
  };
  std::vector<std::uint32_t> order(cut.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return cut[a].lo.x() < cut[b].lo.x() || (cut[a].lo.x() == cut[b].lo.x() && a < b);
  });
  std::vector<std::uint32_t> partner(cut.size(), none);
  for (std::size_t oi = 0; oi < order.size(); ++oi) {
    const std::uint32_t i = order[oi];
    if (partner[i] != none) continue;
    const Chain& a = cut[i];
    std::uint32_t best = none;
    double best_h = gap;
    for (std::size_t oj = oi + 1; oj < order.size(); ++oj) {
      const std::uint32_t j = order[oj];
      const Chain& b = cut[j];
      if (b.lo.x() > a.lo.x() + gap) break;
      if (partner[j] != none || b.closed != a.closed || b.group != a.group) continue;
      if ((a.lo - b.lo).cwiseAbs().maxCoeff() > gap || (a.hi - b.hi).cwiseAbs().maxCoeff() > gap) continue;
      if (a.closed) {
        if (!(a.area.dot(b.area) < 0)) continue;
      } else if ((pos(a.point(0)) - pos(b.point(b.points() - 1))).norm() > gap ||
                 (pos(a.point(a.points() - 1)) - pos(b.point(0))).norm() > gap) {
        continue;
      }
      const double h = hausdorff(a, b);
      if (h <= best_h && (best == none || h < best_h)) best = j, best_h = h;
    }
    if (best != none) partner[i] = best, partner[best] = i;
  }
  // 3b. Slits (file comment, step 3): a chain without a partner, cut at its tips into two halves that may be.
  const std::size_t unsplit = cut.size();
  for (std::uint32_t i = 0; i < unsplit; ++i) {
    if (partner[i] != none || cut[i].from.size() < 2) continue;
    const Chain& c = cut[i];
    const std::size_t n = c.points();
    if (!c.closed && (pos(c.point(0)) - pos(c.point(n - 1))).norm() > gap) continue;
    std::size_t tip_a = 0, tip_b = 0;
    double far = -1;
    for (std::size_t a = 0; a < (c.closed ? n : 1); ++a)
      for (std::size_t b = a + 1; b < n; ++b) {
        const double d = (pos(c.point(a)) - pos(c.point(b))).squaredNorm();
        if (d > far) far = d, tip_a = a, tip_b = b;
      }
    auto half = [&](std::size_t first_edge, std::size_t edges) {  // edges from first_edge on, around a closed chain
      Chain h;
      h.group = c.group;
      for (std::size_t k = 0; k < edges; ++k) {
        const std::size_t e = (first_edge + k) % c.from.size();
        h.from.push_back(c.from[e]), h.to.push_back(c.to[e]);
      }
      if (edges > 0) bound(h);
      return h;
    };
    Chain first = half(tip_a, tip_b - tip_a);
    Chain second = half(tip_b, c.from.size() - (tip_b - tip_a));
    if (first.from.empty() || second.from.empty() || hausdorff(first, second) > gap) continue;
    const std::uint32_t j = std::uint32_t(cut.size());
    cut.push_back(std::move(first));
    cut.push_back(std::move(second));
    partner.push_back(j + 1), partner.push_back(j);
  }

  // 4. The strips.
  std::vector<std::uint32_t> faces(o.face(0), o.face(0) + 3 * nf), groups(nf);
  for (std::size_t f = 0; f < nf; ++f) groups[f] = o.face_group(f);
  std::size_t added = 0;
  auto emit = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint32_t g) {
    if (pid[x] == pid[y] || pid[y] == pid[z] || pid[z] == pid[x]) return;
    faces.insert(faces.end(), {x, y, z});
    groups.push_back(g);
    ++added;
  };
  for (std::uint32_t i = 0; i < cut.size(); ++i) {
    if (partner[i] == none || partner[i] < i) continue;
    const Chain& c = cut[i];
    const Chain& d = cut[partner[i]];
    // d walked backwards from point s: its point k is d's point (s - k), its edge k is d's edge
    // (s - k - 1), which its face runs from point k + 1 to point k.
    const std::size_t n = c.from.size(), m = d.from.size(), dp = d.points();
    std::size_t s = dp - 1;  // open: d's last point meets c's first
    if (c.closed) {
      const Eigen::Vector3d p0 = pos(c.point(0));
      s = 0;
      for (std::size_t k = 1; k < dp; ++k)
        if ((pos(d.point(k)) - p0).squaredNorm() < (pos(d.point(s)) - p0).squaredNorm()) s = k;
    }
    auto d_point = [&](std::size_t k) { return d.point(c.closed ? (s + dp - k % dp) % dp : s - k); };
    auto d_edge = [&](std::size_t k) { return c.closed ? (s + 2 * m - k - 1) % m : s - k - 1; };
    std::size_t a = 0, b = 0;
    while (a < n || b < m) {
      const bool advance_c =
          b == m || (a < n && (pos(c.point(a + 1)) - pos(d_point(b))).squaredNorm() <=
                                  (pos(c.point(a)) - pos(d_point(b + 1))).squaredNorm());
      if (advance_c) {  // c's edge a, the other way round
        emit(c.to[a], c.from[a], d_point(b), c.group);
        ++a;
      } else {  // d's edge, the other way round
        const std::size_t e = d_edge(b);
        emit(c.point(a), d.to[e], d.from[e], c.group);
        ++b;
      }
    }
  }
  if (added > 0) o.replace_faces(std::move(faces), std::move(groups));
  return added;
}

}  // namespace restitch::detail
