// restitch/stitch/detail/cache.hpp - ClipStitcher's prepared cache: the labelling-independent part of stitching.
//
// For a (mesh, lattice): every vertex's canonical coordinates (snapped onto
// cell planes within the tolerance, stitch.hpp), the clamped cell range of
// every triangle with its overhang flags, and the triangles bucketed by input
// cell (CSR, ascending triangle order in each bucket). Built once by
// ClipStitcher::prepare, read by every stitch of a labelling.
//
// Cost O(#V + sum over triangles of the cells their canonical bounding box
// touches); memory 3 doubles per vertex, ~30 bytes per triangle and 4 bytes
// per (triangle, touched cell).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/mesh_boundary.hpp"
#include "restitch/stitch/detail/clip.hpp"

namespace restitch {

class ClipStitcher;

/// ClipStitcher's cache (ClipStitcher::cache_type). Treat as opaque: filled
/// by ClipStitcher::prepare. It refers to the mesh (not copied): the mesh must
/// outlive the cache and stay unchanged while the cache is used.
class ClipStitchCache {
 public:
  bool ready() const { return mesh_ != nullptr; }
  const Mesh* mesh() const { return mesh_; }
  const Lattice& lattice() const { return lattice_; }
  /// Snapping / sliver tolerance in model units.
  double tolerance() const { return tol_; }
  /// The input's bounding-box diagonal, model units.
  double diagonal() const { return diagonal_; }

  // Read by the stitcher's parts (stitch/detail/).
  double max_abs_coord() const { return max_abs_coord_; }
  /// Snapped canonical coordinates of vertex v (3 doubles).
  const double* canonical(std::size_t v) const { return canon_.data() + 3 * v; }
  /// Clamped cell range of triangle f: lo[3], hi[3].
  const std::int32_t* range(std::size_t f) const { return range_.data() + 6 * f; }
  /// Bit a: triangle f needs a cut at plane 0 of axis a; bit 3 + a: at plane cells[a].
  std::uint8_t overhang(std::size_t f) const { return overhang_[f]; }
  /// Vertex v lies on a plane c_a = k, 0 <= k <= cells[a].
  bool on_plane(std::size_t v) const { return on_plane_[v] != 0; }
  /// The input's edge between vertices a and b is open (used by one face, positions welded at the
  /// tolerance).
  bool input_edge_open(std::uint32_t a, std::uint32_t b) const {
    const std::uint64_t ra = weld_rep_[a], rb = weld_rep_[b];
    return std::binary_search(open_edges_.begin(), open_edges_.end(), (std::min(ra, rb) << 32) | std::max(ra, rb));
  }
  /// Triangles whose cell range includes input cell `cell`: [bucket_begin, bucket_end).
  const std::uint32_t* bucket_begin(int cell) const { return bucket_tri_.data() + bucket_start_[std::size_t(cell)]; }
  const std::uint32_t* bucket_end(int cell) const { return bucket_tri_.data() + bucket_start_[std::size_t(cell) + 1]; }

 private:
  friend class ClipStitcher;
  template <class = void>
  Status build(const Mesh& in, const Lattice& lattice, double tol, std::uint64_t max_bucket_entries);
  template <class = void>
  void canonical_coordinates(const Eigen::Matrix3d& a_inv);
  template <class = void>
  Status bucket_triangles(std::uint64_t max_bucket_entries);

  const Mesh* mesh_ = nullptr;
  Lattice lattice_;
  double tol_ = 0;
  double diagonal_ = 0;
  double max_abs_coord_ = 0;
  std::vector<double> canon_;
  std::vector<std::int32_t> range_;
  std::vector<std::uint8_t> overhang_;
  std::vector<std::uint8_t> on_plane_;
  std::vector<std::uint32_t> weld_rep_;    // per vertex, its position's representative at tol_
  std::vector<std::uint64_t> open_edges_;  // the input's open edges, (lower rep << 32) | higher rep, sorted
  std::vector<std::uint32_t> bucket_start_;  // per input cell + 1
  std::vector<std::uint32_t> bucket_tri_;
};

/// Fills the cache for a validated mesh and lattice; `tol` in model units.
template <class>
Status ClipStitchCache::build(const Mesh& in, const Lattice& lattice, double tol,
                                     std::uint64_t max_bucket_entries) {
  mesh_ = &in;  // read by the helpers below; reset on failure
  lattice_ = lattice;
  tol_ = tol;
  diagonal_ = bounding_box(in).size().norm();
  max_abs_coord_ = max_abs_coordinate(in);
  canonical_coordinates(lattice.A.inverse());
  weld_rep_ = weld_positions(in, tol);
  open_edges_.clear();
  for (const BoundaryEdge& e : boundary_edges_welded(in, weld_rep_)) open_edges_.push_back((std::uint64_t(e.a) << 32) | e.b);
  const Status s = bucket_triangles(max_bucket_entries);
  if (!s) mesh_ = nullptr;
  return s;
}

// Canonical coordinates, snapped onto planes within the tolerance.
template <class>
void ClipStitchCache::canonical_coordinates(const Eigen::Matrix3d& a_inv) {
  const Mesh& in = *mesh_;
  const std::size_t nv = in.vertex_count();
  std::array<double, 3> snap;
  for (int a = 0; a < 3; ++a) snap[std::size_t(a)] = tol_ * a_inv.row(a).norm();
  canon_.resize(nv * 3);
  on_plane_.assign(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = in.V.row(Eigen::Index(v)).cast<double>().transpose();
    const Eigen::Vector3d c = a_inv * (p - lattice_.origin);
    for (int a = 0; a < 3; ++a) {
      double x = c(a);
      const double r = std::nearbyint(x);
      if (std::abs(x - r) <= snap[std::size_t(a)]) {
        x = r;
        if (r >= 0 && r <= double(lattice_.cells(a))) on_plane_[v] = 1;
      }
      canon_[3 * v + std::size_t(a)] = x;
    }
  }
}

// Cell range and overhang flags of every triangle, then buckets (CSR).
template <class>
Status ClipStitchCache::bucket_triangles(std::uint64_t max_bucket_entries) {
  const Mesh& in = *mesh_;
  const std::size_t nf = in.triangle_count();
  const CellGrid grid(lattice_.cells);
  range_.resize(nf * 6);
  overhang_.assign(nf, 0);
  std::uint64_t entries = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    std::int32_t* r = &range_[6 * f];
    std::uint8_t flags = 0;
    for (int a = 0; a < 3; ++a) {
      double m = INFINITY, M = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const double x = canon_[3 * std::size_t(in.F(Eigen::Index(f), k)) + std::size_t(a)];
        m = std::min(m, x);
        M = std::max(M, x);
      }
      detail::cell_range(m, M, lattice_.cells(a), r[a], r[3 + a]);
      const double n = double(lattice_.cells(a));
      if (m < 0) flags |= std::uint8_t(1u << a);                        // not all >= 0
      if (M > n || (m == n && M == n)) flags |= std::uint8_t(8u << a);  // not wholly below n
    }
    overhang_[f] = flags;
    entries += std::uint64_t(r[3] - r[0] + 1) * std::uint64_t(r[4] - r[1] + 1) * std::uint64_t(r[5] - r[2] + 1);
  }
  if (entries > max_bucket_entries)
    return error(StatusCode::too_large, "the triangles touch too many cells in total (" + std::to_string(entries) +
                                            "); use fewer cells or split very large triangles");
  // Two passes over every (triangle, touched cell): count, then place.
  const auto for_each_entry = [&](auto&& visit) {
    for (std::size_t f = 0; f < nf; ++f) {
      const std::int32_t* r = &range_[6 * f];
      for (int k = r[2]; k <= r[5]; ++k)
        for (int j = r[1]; j <= r[4]; ++j)
          for (int i = r[0]; i <= r[3]; ++i) visit(std::size_t(grid.index(i, j, k)), std::uint32_t(f));
    }
  };
  std::vector<std::uint32_t> count(std::size_t(grid.size()) + 1, 0);
  for_each_entry([&](std::size_t cell, std::uint32_t) { ++count[cell + 1]; });
  for (std::size_t c = 0; c + 1 < count.size(); ++c) count[c + 1] += count[c];
  bucket_start_ = count;
  bucket_tri_.resize(count.back());
  for_each_entry([&](std::size_t cell, std::uint32_t f) { bucket_tri_[count[cell]++] = f; });
  return {};
}

}  // namespace restitch
