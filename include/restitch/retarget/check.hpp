// restitch/retarget/check.hpp - the result check: what a modeller would reject in a resize (docs/method.md 2.11).
//
// A resize that keeps the model's content adds or removes whole copies and nothing else. The check looks
// at the output for what breaks that, and says so in RetargetReport::warnings (one sentence each, named
// by its check):
//   * "open seam": an open edge of the output that is no copy of an open edge of the input (an output
//     boundary edge whose corners, moved back by the shift of a label or an anchored end, or by one of
//     those and half a period for a centred part moved alone, lie on one boundary edge of the input).
//     Where two copies meet at a seam and continue each other, the stitcher welds them shut; a new open
//     edge is a cut that the other side does not continue (half a pin, a wall cut with nothing beyond it)
//     or a crack the stitcher could not close. The input's own open
//     edges (sheets, touching boxes) and their copies are not counted.
//   * "unmatched seam": a seam where one copy has surface near the cut and the other none within the seam
//     measure's band (the measure's empty value, restitch/energy/seam_geometry.hpp): copies with nothing
//     in common glued together, such as two end caps face to face, which close every edge.
//   * "part count": a part that occurs once (restitch/lattice/structure.hpp) copied more than once,
//     not at all, or only in part, read from the labels: the shifts of the output cells whose source
//     lies in the part's slabs; and, whatever the slabs were read as, what the input's surface holds once
//     along a resized axis (CellStructure::once) held by the output at more than one place along it, or
//     whole at none.
//   * "size": an output box that is not the input's grown by the whole periods asked for; and, for a
//     request by size without the exact scale (check_size_asked), one that is not the size asked.
//   * "floating piece": a group of touching pieces of the output whose box is no input group's box
//     grown by whole periods along the resized axes (a fragment cut off, a copy left in the air).
//   * "side by side": the input is held together by one group over its whole box and the output by
//     none: copies of the whole model placed next to each other (a 2-pin package grown into two
//     packages end to end, each a group the floating-piece test knows), not one model resized.
// Tolerances: positions at twice the stitcher's weld tolerance (a cut point lies on its input edge to
// float rounding; twice, because both ends of an edge are compared); sizes and contact at 1e-3 of the
// bounding-box diagonal, the tolerance at which restitch/lattice/structure.hpp calls two slabs copies
// (below any part a modeller places on purpose).
//
// Cost: the output's boundary edges (O(#V + #F), restitch/mesh_boundary.hpp), a hash-grid look-up per
// output boundary edge and candidate shift, a union-find over the faces and a sweep over the pieces'
// boxes; where something occurs once along a resized axis, a tree over the output's triangles
// (O(#F log #F)) and up to CellStructure::once_samples bounded point-to-surface queries per group and
// candidate shift. What depends on the input alone (`InputShape`) is built once per Retargeter.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "restitch/detail/cell_hash.hpp"
#include "restitch/detail/disjoint_sets.hpp"
#include "restitch/detail/triangle_surface.hpp"
#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/lattice/structure.hpp"
#include "restitch/mesh.hpp"
#include "restitch/mesh_boundary.hpp"
#include "restitch/retarget/report.hpp"
#include "restitch/retarget/request.hpp"

namespace restitch {

namespace detail {

/// The boxes of the groups of touching pieces of m: pieces are the faces connected through welded corners
/// (weld tolerance `weld`); two pieces touch when their boxes, grown by `contact`, overlap. Sorted.
template <class = void>
std::vector<BoundingBox> touching_groups(const Mesh& m, double weld, double contact) {
  const std::vector<std::uint32_t> rep = weld_positions(m, weld);
  DisjointSets corners(m.vertex_count());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int c = 1; c < 3; ++c) corners.join(rep[m.F(f, 0)], rep[m.F(f, c)]);
  std::vector<int> piece(m.vertex_count(), -1);
  std::vector<BoundingBox> boxes;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t r = corners.find(rep[m.F(f, c)]);
      if (piece[r] < 0) piece[r] = int(boxes.size()), boxes.emplace_back();
      boxes[std::size_t(piece[r])].extend(m.V.row(m.F(f, c)).template cast<double>().transpose());
    }
  // Pieces whose grown boxes overlap: a sweep along x over the boxes sorted by their low x.
  std::vector<std::uint32_t> order(boxes.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return boxes[a].min.x() < boxes[b].min.x() || (boxes[a].min.x() == boxes[b].min.x() && a < b);
  });
  DisjointSets groups(boxes.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const BoundingBox& a = boxes[order[i]];
    for (std::size_t j = i + 1; j < order.size(); ++j) {
      const BoundingBox& b = boxes[order[j]];
      if (b.min.x() > a.max.x() + 2 * contact) break;
      if (((b.min.array() - contact) <= (a.max.array() + contact)).all() &&
          ((a.min.array() - contact) <= (b.max.array() + contact)).all())
        groups.join(order[i], order[j]);
    }
  }
  std::vector<BoundingBox> out(boxes.size());
  std::vector<char> used(boxes.size(), 0);
  for (std::size_t p = 0; p < boxes.size(); ++p) {
    const std::uint32_t g = groups.find(std::uint32_t(p));
    used[g] = 1;
    out[g].extend(boxes[p].min), out[g].extend(boxes[p].max);
  }
  std::vector<BoundingBox> result;
  for (std::size_t g = 0; g < out.size(); ++g)
    if (used[g]) result.push_back(out[g]);
  return result;
}


/// How n periods along each lattice axis change a box: by |A_a n_a| per world axis, with n_a's sign.
template <class = void>
Eigen::Vector3d box_change(const Lattice& grid, const Eigen::Array3i& n) {
  Eigen::Vector3d change = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) change += (grid.A.col(a) * double(n[a])).cwiseAbs() * (n[a] < 0 ? -1.0 : 1.0);
  return change;
}

}  // namespace detail

/// What the check needs of the input, built once: its open edges in a hash grid, its groups of touching
/// pieces, and its tolerances (see the file comment).
struct InputShape {
  std::vector<Eigen::Vector3d> edge_a, edge_b;  // the input's boundary edges
  double cell = 1;                              // the hash grid's cell, model units
  detail::CellHashMap<std::vector<std::uint32_t>> grid;
  std::vector<BoundingBox> groups;
  double weld = 0, contact = 0;  // the stitcher's weld tolerance and the contact tolerance, model units

  InputShape() = default;
  /// `relative_weld`: the stitcher's weld tolerance, relative to the diagonal (RetargetReport::weld_tolerance).
  template <class = void>
  InputShape(const Mesh& in, double relative_weld) {
    const double diagonal = bounding_box(in).size().norm();
    weld = weld_tolerance_of(in, std::max(relative_weld, 1e-6));
    contact = 1e-3 * diagonal;
    groups = detail::touching_groups(in, weld, contact);
    const std::vector<BoundaryEdge> open = boundary_edges_at(in, weld_tolerance_of(in));
    double length = 0;
    for (const BoundaryEdge& e : open) {
      edge_a.push_back(in.V.row(e.a).cast<double>().transpose());
      edge_b.push_back(in.V.row(e.b).cast<double>().transpose());
      length += (edge_b.back() - edge_a.back()).norm();
    }
    // Cells about the mean edge long (at least 8 tolerances): a few cells per edge, a few edges per cell.
    cell = std::max(open.empty() ? diagonal : length / double(open.size()), 8 * check_tolerance());
    if (!(cell > 0)) cell = 1;
    // Each edge goes into the cells of points along it at most half a cell apart, so a point within the
    // tolerance of the edge lies in such a cell or a neighbour of it.
    for (std::uint32_t i = 0; i < edge_a.size(); ++i) {
      const int n = 1 + int(std::ceil(2 * (edge_b[i] - edge_a[i]).norm() / cell));
      detail::Cell last{{INT64_MIN, 0, 0}};
      for (int s = 0; s <= n; ++s) {
        const Eigen::Vector3d p = edge_a[i] + (edge_b[i] - edge_a[i]) * (double(s) / n);
        const detail::Cell c{detail::cell_index(p.x(), cell), detail::cell_index(p.y(), cell),
                             detail::cell_index(p.z(), cell)};
        if (c == last) continue;
        last = c;
        std::vector<std::uint32_t>& list = *grid.get(c).first;
        if (list.empty() || list.back() != i) list.push_back(i);
      }
    }
  }

  double check_tolerance() const { return 2 * weld; }

  /// Whether the segment p-q lies on one of the input's open edges (both ends within the tolerance of it).
  template <class = void>
  bool on_open_edge(const Eigen::Vector3d& p, const Eigen::Vector3d& q) const {
    const Eigen::Vector3d m = 0.5 * (p + q);
    const detail::Cell c{detail::cell_index(m.x(), cell), detail::cell_index(m.y(), cell),
                         detail::cell_index(m.z(), cell)};
    const double tol = check_tolerance();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::vector<std::uint32_t>* list = grid.find(detail::Cell{{c[0] + dx, c[1] + dy, c[2] + dz}});
          if (!list) continue;
          for (const std::uint32_t i : *list)
            if ((detail::closest_point_on_segment(p, edge_a[i], edge_b[i]) - p).norm() <= tol &&
                (detail::closest_point_on_segment(q, edge_a[i], edge_b[i]) - q).norm() <= tol)
              return true;
        }
    return false;
  }
};

/// The result check (see the file comment) of `out`, stitched on `grid` (input space; the output was then
/// moved by rep.placement.translation) from the shifts `shift` (one per output cell, linear order) with the
/// grid steps rep.grid_steps; `structure` (null for none) is what occurs once. Fills rep.boundary_edges_out,
/// and rep.open_edges, and appends a warning per failed check.
///
/// `empty_mismatch` (0: not checked) is the seam measure's value for a seam where one copy has surface near the
/// cut and the other has none (CellSlabs::empty_mismatch); rep.seams must be measured.
template <class = void>
void check_result(const InputShape& input, const Mesh& out, const Lattice& grid, const std::vector<Eigen::Array3i>& shift,
                  const CellStructure* structure, RetargetReport& rep, double empty_mismatch = 0) {
  const Eigen::Array3i k = rep.grid_steps;
  rep.checked = true;

  // Open seams. The candidate shifts: per axis, every label's component and the anchored ends' (0, k), and a
  // centred part's moved a further half period alone (restitch/retarget/centring.hpp).
  std::array<std::vector<double>, 3> along;
  for (int a = 0; a < 3; ++a) {
    std::set<double> s{0.0, double(k[a])};
    for (const Eigen::Array3i& d : shift) s.insert(d[a]);
    const std::set<double> whole = s;  // the region moved with the part copies R, whose cells have any of them
    for (const PartReport& p : rep.parts)
      if (p.axis == a && p.half != 0)
        for (const double d : whole) s.insert(d + 0.5 * p.half);
    along[std::size_t(a)].assign(s.begin(), s.end());
  }
  std::vector<Eigen::Vector3d> moves, move_cells;  // model units; the same in periods, before the placement
  for (const double x : along[0])
    for (const double y : along[1])
      for (const double z : along[2]) {
        move_cells.emplace_back(x, y, z);
        moves.push_back(grid.A * move_cells.back() + rep.placement.translation);
      }
  const std::vector<BoundaryEdge> open = boundary_edges_at(out, weld_tolerance_of(out, 1e-6));
  rep.boundary_edges_out = open.size();
  rep.open_edges.clear();
  for (const BoundaryEdge& e : open) {
    const Eigen::Vector3d p = out.V.row(e.a).cast<double>().transpose(), q = out.V.row(e.b).cast<double>().transpose();
    bool own = false;
    for (std::size_t i = 0; i < moves.size() && !own; ++i) own = input.on_open_edge(p - moves[i], q - moves[i]);
    if (own) continue;
    rep.open_edges.push_back({p.cast<float>(), q.cast<float>()});
  }
  if (rep.boundary_edges_new() > 0) {
    const Eigen::Vector3d at = 0.5 * (rep.open_edges[0][0] + rep.open_edges[0][1]).cast<double>();
    rep.warnings.push_back({"open seam", std::to_string(rep.boundary_edges_new()) +
                                             " edge(s) of the output are open where the input is closed (the copies "
                                             "meeting at a seam do not continue each other), the first near " +
                                             detail::format_point(at)});
  }

  // Unmatched seams: surface that reaches the cut on one side and nothing on the other within the slab
  // band. Closed surfaces there (two end caps glued face to face, a part that ends at the cut) open no
  // edge, so the open-seam check cannot see them. Only seams across a resized axis: there the two copies
  // are consecutive along the repeat. Across another axis a seam lies where the labels step, and the
  // measure gives an end cell the overhang past the input grid, which the stitcher keeps only at the
  // output's ends: an exact result can measure empty there (docs/method.md 2.11).
  if (empty_mismatch > 0) {
    std::size_t unmatched = 0;
    const SeamReport* first = nullptr;
    for (const SeamReport& s : rep.seams) {
      bool across_resized = false;
      for (int a = 0; a < 3; ++a) across_resized |= s.cell_a[a] != s.cell_b[a] && k[a] != 0;
      if (across_resized && s.mismatch >= empty_mismatch && unmatched++ == 0) first = &s;
    }
    if (first) {
      auto cell = [](const Eigen::Array3i& c) {
        return "(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
      };
      rep.warnings.push_back({"unmatched seam", std::to_string(unmatched) +
                                                    " seam(s) join surface on one side to none on the other (the "
                                                    "copies meeting there have nothing in common), the first "
                                                    "between output cells " +
                                                    cell(first->cell_a) + " and " + cell(first->cell_b)});
    }
  }

  // Parts copied once: the shifts along the part's axis of the cells whose source lies in its slabs. A part
  // that holds an end slab is kept by the end caps too (restitch/stitch/stitch.hpp), so only another copy of
  // it counts against it there.
  if (structure) {
    const CellGrid cells(rep.cells_out);
    for (const PartReport& p : rep.parts) {
      const bool end = p.first == 0 || p.last == rep.cells_in[p.axis] - 1;
      std::set<int> copies;
      bool whole = true;
      for (std::int64_t x = 0; x < cells.size(); ++x) {
        const Eigen::Array3i c = cells.cell(x);
        const int d = shift[std::size_t(x)][p.axis], source = c[p.axis] - d;
        if (source >= p.first && source <= p.last) copies.insert(d);
        if (c[p.axis] >= p.first + p.shift && c[p.axis] <= p.last + p.shift && d != p.shift) whole = false;
      }
      if (end) copies.insert(p.shift), whole = true;
      const std::string name = "the part at cells " + std::to_string(p.first + 1) + "-" + std::to_string(p.last + 1) +
                               " along axis " + std::to_string(p.axis + 1);
      if (copies.size() != 1)
        rep.warnings.push_back({"part count", name + " occurs once in the input and " +
                                                  std::to_string(copies.size()) + " times in the output"});
      else if (!whole || *copies.begin() != p.shift)
        rep.warnings.push_back({"part count", name + " is not copied whole to its place"});
    }
  }

  // What occurs once, found from the surface alone (CellStructure::once): each group must be held by the output
  // at one place along its axis (one of the moves above: a label's shift, an anchored end's, or a centred
  // part's moved alone), not more, and not nowhere (cut, or lost).
  if (structure) {
    std::unique_ptr<detail::TriangleSurface> surface;
    for (int a = 0; a < 3; ++a) {
      if (k[a] == 0 || structure->once[std::size_t(a)].empty()) continue;
      if (!surface) surface = std::make_unique<detail::TriangleSurface>(out);
      std::size_t wrong = 0, first_count = 0;
      const std::vector<Eigen::Vector3d>* first = nullptr;
      for (const std::vector<Eigen::Vector3d>& g : structure->once[std::size_t(a)]) {
        std::set<double> at;  // the moves along a that hold it
        for (std::size_t i = 0; i < moves.size(); ++i)
          if (!at.count(move_cells[i][a]) && detail::held_at(*surface, g, moves[i], structure->tolerance))
            at.insert(move_cells[i][a]);
        if (at.size() == 1) continue;
        if (wrong++ == 0) first = &g, first_count = at.size();
      }
      if (!first) continue;
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& q : *first) centre += q / double(first->size());
      rep.warnings.push_back(
          {"part count", "what the input holds once near " + detail::format_point(centre) + " (along axis " +
                             std::to_string(a + 1) + ", moved a period either way it is not there) " +
                             (first_count == 0 ? std::string("is not whole in the output")
                                               : "occurs " + std::to_string(first_count) + " times in the output") +
                             (wrong > 1 ? ", and " + std::to_string(wrong - 1) + " more such content is not once" : "")});
    }
  }

  // Size: the input's box grown by the whole periods asked for.
  const double diagonal = rep.size_in.norm(), tol = 1e-3 * diagonal;
  const Eigen::Vector3d grown = detail::box_change(grid, k);
  for (int w = 0; w < 3; ++w)
    if (std::abs(rep.size_out[w] - (rep.size_in[w] + grown[w])) > tol) {
      rep.warnings.push_back({"size", std::string("the output is ") + detail::format_size(rep.size_out[w]) + " along " +
                                          "xyz"[w] + ", not the " + detail::format_size(rep.size_in[w] + grown[w]) +
                                          " that the whole periods asked for give"});
      break;
    }

  // Floating pieces: every group of touching pieces is an input group grown by whole periods.
  const std::vector<BoundingBox> groups = detail::touching_groups(out, input.weld, input.contact);
  for (const BoundingBox& g : groups) {
    bool known = false;
    for (const BoundingBox& h : input.groups) {
      for (int n0 = std::min(0, k[0]); n0 <= std::max(0, k[0]) && !known; ++n0)
        for (int n1 = std::min(0, k[1]); n1 <= std::max(0, k[1]) && !known; ++n1)
          for (int n2 = std::min(0, k[2]); n2 <= std::max(0, k[2]) && !known; ++n2) {
            const Eigen::Vector3d change = detail::box_change(grid, Eigen::Array3i(n0, n1, n2));
            known = (g.size() - h.size() - change).cwiseAbs().maxCoeff() <= input.contact;
          }
      if (known) break;
    }
    if (!known) {
      rep.warnings.push_back({"floating piece", "a piece of the output (" + detail::format_size(g.size().norm()) +
                                                    " across, near " + detail::format_point(g.center()) +
                                                    ") touches nothing else and is no piece of the input"});
      break;
    }
  }

  // Side by side: an input that one group spans whole gives an output that one group spans whole.
  const auto spans = [&](const BoundingBox& g, const Eigen::Vector3d& size) {
    return (g.size() - size).cwiseAbs().maxCoeff() <= input.contact;
  };
  bool one_piece = false, still = false;
  for (const BoundingBox& h : input.groups) one_piece = one_piece || spans(h, rep.size_in);
  const BoundingBox* largest = nullptr;
  for (const BoundingBox& g : groups) {
    still = still || spans(g, rep.size_out);
    if (!largest || g.size().norm() > largest->size().norm()) largest = &g;
  }
  if (one_piece && !still && largest)
    rep.warnings.push_back({"side by side", "the input is one piece over its whole box and the output is not (its largest "
                                            "piece is " + detail::format_size(largest->size().norm()) + " across of " +
                                            detail::format_size(rep.size_out.norm()) +
                                            "): copies of the model side by side, not one model resized"});
}

/// The result check's "size asked" (docs/method.md 2.11), for a request by size without the exact scale:
/// along each world axis asked to change (size_changes), the output's size `rep.size_out` must be the
/// asked size within 1e-3 of the input's diagonal (the "size" check's tolerance). The nearest whole periods
/// miss it when the asked size is no whole number of periods away: a size typed between two counts, or a
/// period found at a multiple or a fraction of the one the user counts in (a run of slats with its rail
/// taken for the period: every size between two of its copies is missed). Appends a warning saying the
/// size asked, the size given and the period along that axis.
template <class = void>
void check_size_asked(const Eigen::Vector3d& target, const Lattice& L, RetargetReport& rep) {
  const double tol = 1e-3 * rep.size_in.norm();
  const std::array<bool, 3> asked = size_changes(target, rep.size_in);
  for (int w = 0; w < 3; ++w) {
    if (!asked[std::size_t(w)] || std::abs(rep.size_out[w] - target[w]) <= tol) continue;
    if (!size_changes(target, rep.size_out)[std::size_t(w)]) continue;  // the output, as typed
    std::string periods;
    for (int a = 0; a < 3; ++a)
      if (!L.dummy[a] && world_axis_of(L.A.col(a)) == w)
        periods += (periods.empty() ? "" : ", ") + detail::format_size(std::abs(L.A(w, a)));
    const std::string axis(1, "xyz"[w]);
    rep.warnings.push_back({"size", "asked " + detail::format_size(target[w]) + " along " + axis + "; the output is " +
                                        detail::format_size(rep.size_out[w]) + ", the nearest size whole periods (" +
                                        periods + " along " + axis + ") reach from " +
                                        detail::format_size(rep.size_in[w])});
    return;
  }
}

}  // namespace restitch
