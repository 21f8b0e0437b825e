// restitch/stitch/stitch.hpp - the stitcher: a labelled output lattice -> a real triangle mesh.
//
// method.md section 3. The solver gives every output cell x (linear index
// x = i + U_out * (j + V_out * k)) a label, a shift d = (du, dv, dw) in cells:
// output cell x copies input cell s = x - d, translated by A d (model units).
// For each *region* (a maximal 6-connected set of output cells sharing one
// label) the stitcher copies the input geometry of the source cells,
// translated by A d, and returns one triangle mesh.
//
// What happens to a triangle:
//   * wholly inside one region's source cells: copied UNTOUCHED (same
//     vertices, same attribute values bit for bit; positions translated).
//   * crossing a region boundary: clipped exactly against the cell planes
//     c_a = integer in canonical space (c = A^-1 (p - origin)), every vertex
//     attribute interpolated linearly at the cut points: normals and tangent
//     xyz re-normalised, tangent w = the sign of the interpolated w (so a
//     triangle whose corners agree keeps its w), UVs and colours linear. The
//     triangle is split only where needed (planes between cells in and out of
//     the region, chosen to lie on the region's boundary); each convex piece
//     inside the region is fanned into triangles with the input's winding.
//   * pieces and fan triangles whose area is below tolerance^2 (slivers) are
//     dropped. (Degenerate input triangles copied whole are kept as they are.)
//
// Cells and planes. Cell (i, j, k) is the half-open cube [i, i+1) x [j, j+1)
// x [k, k+1) in canonical space, so geometry with area lying on one side of a
// plane goes to that side, and a triangle lying IN a plane c_a = k goes to the
// high side (cell k). Canonical coordinates within the tolerance of an integer
// are snapped onto it first, so geometry meant to lie on a plane does.
// The input may overhang its grid (boundary features): canonical coordinates
// < 0 belong to cell 0 and >= cells[a] to the last cell, so no input is lost.
// Output cells are clamped the same way: output cell 0 and the last output
// cell along an axis include the overhang. The domain copied for output cell x
// from source cell s is the intersection of both: the overhang below plane 0
// is kept only when s_a == 0 AND x_a == 0 (that is, d_a == 0), the overhang
// beyond plane cells[a] only when s_a == U_in - 1 AND x_a == U_out - 1. An
// interior output cell that copies an end cell gets that cell without its
// overhang (cut at the outer plane).
//
// Labels pointing outside the input. A shift whose source x - d lies outside
// the input grid (a bad choice of the solver; the energy forbids it) leaves
// that output cell empty: no geometry, no region. Neighbouring regions are
// still clipped at its faces. A labelling with only such cells gives an empty
// mesh (status ok, report.triangles_* == 0).
//
// Welding. Output vertices on a seam (every cut vertex, and every vertex that
// lies on a cell plane) are welded to an earlier one when all of these hold:
// positions within the weld tolerance (Euclidean), the same group, and every
// attribute channel the group carries equal within `attribute_tolerance` per
// component (tangent w exactly). Otherwise they stay separate vertices at the
// same position, so texture seams and hard edges survive. Two untouched input
// vertices copied by the same region are never welded (the stitcher does not
// change the input's own topology). A face whose corners weld together is
// dropped. The tolerance is weld_tolerance (default 1e-6) times the input's
// bounding-box diagonal, but at least 8 float ulps of the largest output
// coordinate (positions are floats).
//
// Output. groups, materials and assets are copied from the input (same group
// indices); every channel the input has (N, T, UV sets, C) is present.
// Faces are ordered by group, then by region (regions are numbered by their
// first output cell in linear order), then by source face (the pieces of a
// clipped face in a fixed order). Vertices are compacted and numbered by first
// use. Same input, same output, bit for bit; no threads, no randomness.
//
// Cost. prepare: O(#V + sum over triangles of the cells their canonical
// bounding box touches). stitch: O(output triangles + output cells) for
// untouched copies, plus for each clipped triangle copy a split over the
// cells it touches, plus O(s log s) for s seam vertices. Measured on a
// 50k-triangle, 10 x 5 cell model (all channels) on a shared, loaded 2-core
// machine: prepare 8-16 ms native -O2, 24 ms WebAssembly -O3; stitch (best
// of 7) 1-5 ms native -O2 for outputs of 35k-100k triangles (up to 12 ms
// under heavy load), 1.5-13 ms WebAssembly -O3. Memory: the cache holds 3
// doubles per vertex, ~30 bytes per triangle and 4 bytes per (triangle,
// touched cell).
//
// The stitcher policy contract (the pipeline static_asserts
// is_stitcher_policy_v with a readable message):
//
//   struct MyStitcher {
//     // `in` is the input mesh (model units), `lattice` its lattice, `out_cells`
//     // the output grid (each >= 1), `cell_shift` one label per output cell in
//     // linear order (size U_out * V_out * W_out). Fills `out` (any previous
//     // content is replaced; `out` may not alias `in`) and `report`.
//     restitch::Status stitch(const restitch::Mesh& in, const restitch::Lattice& lattice,
//                             const Eigen::Array3i& out_cells,
//                             const std::vector<Eigen::Array3i>& cell_shift,
//                             restitch::Mesh& out, restitch::StitchReport& report) const;
//   };
//
// Optionally (checked by has_prepared_stitch_v), a policy that can reuse work
// across labellings (the web demo's live slider) offers
//
//     restitch::Status prepare(const Mesh& in, const Lattice& lattice, StitchCache& cache) const;
//     restitch::Status stitch(const StitchCache& cache, const Eigen::Array3i& out_cells,
//                             const std::vector<Eigen::Array3i>& cell_shift,
//                             Mesh& out, StitchReport& report) const;
//
// The cache refers to `in` (it is not copied): the mesh must outlive the
// cache and stay unchanged while the cache is used.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// What one stitch call did.
struct StitchReport {
  std::size_t regions = 0;               ///< regions with a valid source (empty cells are no region)
  std::size_t triangles_copied = 0;      ///< input triangles copied untouched (one per copy)
  std::size_t triangles_clipped = 0;     ///< input triangle copies that crossed a region boundary and were clipped
  std::size_t seam_vertices_welded = 0;  ///< output vertices removed by welding
  double ms = 0;                         ///< wall-clock time of the call (informative only)
};

/// The labelling-independent part of stitching a (mesh, lattice): canonical
/// coordinates, the cell range of every triangle and triangles bucketed by
/// source cell. Built by ClipStitcher::prepare; treat as opaque.
class StitchCache {
 public:
  bool ready() const { return mesh_ != nullptr; }
  const Mesh* mesh() const { return mesh_; }
  const Lattice& lattice() const { return lattice_; }
  /// Snapping / sliver tolerance in model units.
  double tolerance() const { return tol_; }

 private:
  friend class ClipStitcher;
  const Mesh* mesh_ = nullptr;
  Lattice lattice_;
  double tol_ = 0;
  double max_abs_coord_ = 0;
  std::vector<double> canon_;           // 3 per vertex, snapped canonical coordinates
  std::vector<std::int32_t> range_;     // 6 per triangle: lo[3], hi[3], clamped cell range
  std::vector<std::uint8_t> overhang_;  // per triangle: bit a = needs a cut at plane 0, bit 3+a = at plane cells[a]
  std::vector<std::uint8_t> on_plane_;  // per vertex: lies on a plane c_a = k, 0 <= k <= cells[a]
  std::vector<std::uint32_t> bucket_start_;  // per input cell + 1
  std::vector<std::uint32_t> bucket_tri_;    // triangles whose cell range includes the cell, ascending
};

namespace detail {

/// Cell index of a canonical interval [m, M] along an axis with n cells (half-open cells, clamped ends).
inline void cell_range(double m, double M, int n, std::int32_t& lo, std::int32_t& hi) {
  const double top = double(n - 1);
  double l = std::floor(m), h = (M > m) ? std::ceil(M) - 1.0 : l;
  l = std::min(std::max(l, 0.0), top);
  h = std::min(std::max(h, 0.0), top);
  lo = std::int32_t(l);
  hi = std::int32_t(h);
}

/// A convex polygon during clipping: n vertices of `stride` doubles each
/// (canonical xyz, model xyz, then the attribute channels), and for each
/// vertex the input vertex it is an untouched copy of (-1 for a cut point).
struct ClipPolygon {
  std::vector<double> d;
  std::vector<std::int64_t> src;
  int n = 0;
  void clear() { n = 0; }
  void reserve_for(int count, int stride) {
    if (int(src.size()) < count) {
      src.resize(std::size_t(count));
      d.resize(std::size_t(count) * std::size_t(stride));
    }
  }
  void push(const double* v, std::int64_t s, int stride) {
    reserve_for(n + 1, stride);
    std::copy(v, v + stride, d.data() + std::size_t(n) * std::size_t(stride));
    src[std::size_t(n)] = s;
    ++n;
  }
  const double* vertex(int i, int stride) const { return d.data() + std::size_t(i) * std::size_t(stride); }
};

/// Splits `in` by the plane c_axis = k. Half-open rule: a polygon entirely
/// at or above k (including one lying in the plane) goes to `high`, one
/// entirely at or below k (and not in the plane) to `low`; otherwise vertices
/// on the plane go to both and edges crossing it strictly are cut. The cut
/// point is interpolated from the edge's lower end, so the two triangles
/// sharing an edge compute the same bits.
inline void split_polygon(const ClipPolygon& in, int axis, double k, int stride, ClipPolygon& low, ClipPolygon& high) {
  low.clear();
  high.clear();
  bool all_ge = true, all_le = true;
  for (int i = 0; i < in.n; ++i) {
    const double v = in.vertex(i, stride)[axis];
    all_ge = all_ge && v >= k;
    all_le = all_le && v <= k;
  }
  if (all_ge || all_le) {
    ClipPolygon& dst = all_ge ? high : low;
    for (int i = 0; i < in.n; ++i) dst.push(in.vertex(i, stride), in.src[std::size_t(i)], stride);
    return;
  }
  double cut[64];
  RESTITCH_ASSERT(stride <= 64, "too many attribute channels for the clipper");
  for (int i = 0; i < in.n; ++i) {
    const int j = (i + 1 == in.n) ? 0 : i + 1;
    const double* p = in.vertex(i, stride);
    const double* q = in.vertex(j, stride);
    const double vp = p[axis], vq = q[axis];
    if (vp <= k) low.push(p, in.src[std::size_t(i)], stride);
    if (vp >= k) high.push(p, in.src[std::size_t(i)], stride);
    if ((vp < k && vq > k) || (vp > k && vq < k)) {
      const double* a = vp < vq ? p : q;  // lower end
      const double* b = vp < vq ? q : p;
      const double t = (k - a[axis]) / (b[axis] - a[axis]);
      for (int c = 0; c < stride; ++c) cut[c] = a[c] + t * (b[c] - a[c]);
      cut[axis] = k;
      low.push(cut, -1, stride);
      high.push(cut, -1, stride);
    }
  }
}

/// The output being built. An output vertex is a recipe: an input vertex
/// copied by a region (its values are read from the input when the mesh is
/// written), or a cut vertex whose values sit in `cut` (position already
/// translated, then the attribute channels, `cut_stride` floats each).
struct StitchOutput {
  static constexpr std::uint32_t cut_bit = 0x80000000u;
  std::vector<std::uint32_t> vsrc;    // input vertex, or cut index | cut_bit
  std::vector<std::int32_t> vregion;  // the region that made the vertex
  std::vector<std::uint32_t> vgroup;  // the group of the faces using it
  std::vector<float> cut;
  std::vector<std::uint32_t> faces;  // 3 per face
  std::vector<std::uint32_t> fgroup;
};

}  // namespace detail

/// The default stitcher: exact clipping against cell planes, attribute
/// interpolation, seam welding. See the file comment for the full contract.
class ClipStitcher {
 public:
  double weld_tolerance = 1e-6;       ///< relative to the input's bounding-box diagonal
  double attribute_tolerance = 1e-4;  ///< per component, for welding (normals, tangents, UVs, colours)
  bool weld = true;                   ///< weld coincident seam vertices

  /// Builds the labelling-independent cache. Validates the mesh and lattice.
  /// Cost O(#V + bucketed triangle-cells).
  Status prepare(const Mesh& in, const Lattice& lattice, StitchCache& cache) const {
    cache = StitchCache();
    RESTITCH_TRY(validate(in));
    if (in.UV.size() > max_uv_sets)
      return error(StatusCode::unsupported, "the mesh has " + std::to_string(in.UV.size()) +
                                                " texture coordinate sets; the stitcher carries at most " +
                                                std::to_string(max_uv_sets));
    if (!lattice.A.allFinite() || !lattice.origin.allFinite())
      return error(StatusCode::invalid_argument, "the lattice has a non-finite offset or origin");
    if ((lattice.cells < 1).any())
      return error(StatusCode::invalid_argument, "the lattice must have at least one input cell along each axis");
    const double cells_in = double(lattice.cells(0)) * lattice.cells(1) * lattice.cells(2);
    if (cells_in > double(max_cells))
      return error(StatusCode::too_large, "the input lattice has more than " + std::to_string(max_cells) + " cells");
    const double scale = lattice.A.colwise().norm().prod();
    const double det = lattice.A.determinant();
    if (!(std::abs(det) > 1e-9 * scale) || !(scale > 0))
      return error(StatusCode::invalid_argument, "the lattice offsets are (nearly) linearly dependent");

    const Eigen::Matrix3d a_inv = lattice.A.inverse();
    const BoundingBox box = bounding_box(in);
    double max_abs = 0;
    for (Eigen::Index i = 0; i < in.V.size(); ++i) max_abs = std::max(max_abs, double(std::abs(in.V.data()[i])));
    const double tol = std::max(weld_tolerance * box.size().norm(), 8.0 * double(FLT_EPSILON) * max_abs);
    cache.tol_ = tol;
    cache.max_abs_coord_ = max_abs;
    cache.lattice_ = lattice;

    // Canonical coordinates, snapped onto planes within the tolerance.
    const std::size_t nv = in.vertex_count(), nf = in.triangle_count();
    std::array<double, 3> snap;
    for (int a = 0; a < 3; ++a) snap[std::size_t(a)] = tol * a_inv.row(a).norm();
    cache.canon_.resize(nv * 3);
    cache.on_plane_.assign(nv, 0);
    for (std::size_t v = 0; v < nv; ++v) {
      const Eigen::Vector3d p = in.V.row(Eigen::Index(v)).cast<double>().transpose();
      const Eigen::Vector3d c = a_inv * (p - lattice.origin);
      for (int a = 0; a < 3; ++a) {
        double x = c(a);
        const double r = std::nearbyint(x);
        if (std::abs(x - r) <= snap[std::size_t(a)]) {
          x = r;
          if (r >= 0 && r <= double(lattice.cells(a))) cache.on_plane_[v] = 1;
        }
        cache.canon_[3 * v + std::size_t(a)] = x;
      }
    }

    // Cell range and overhang flags of every triangle, then buckets (CSR).
    cache.range_.resize(nf * 6);
    cache.overhang_.assign(nf, 0);
    const int ncell = lattice.cells.prod();
    std::uint64_t entries = 0;
    std::vector<std::uint32_t> count(std::size_t(ncell) + 1, 0);
    for (std::size_t f = 0; f < nf; ++f) {
      std::int32_t* r = &cache.range_[6 * f];
      std::uint8_t flags = 0;
      for (int a = 0; a < 3; ++a) {
        double m = INFINITY, M = -INFINITY;
        for (int k = 0; k < 3; ++k) {
          const double x = cache.canon_[3 * std::size_t(in.F(Eigen::Index(f), k)) + std::size_t(a)];
          m = std::min(m, x);
          M = std::max(M, x);
        }
        detail::cell_range(m, M, lattice.cells(a), r[a], r[3 + a]);
        const double n = double(lattice.cells(a));
        if (m < 0) flags |= std::uint8_t(1u << a);                        // not all >= 0
        if (M > n || (m == n && M == n)) flags |= std::uint8_t(8u << a);  // not wholly below n
      }
      cache.overhang_[f] = flags;
      entries += std::uint64_t(r[3] - r[0] + 1) * std::uint64_t(r[4] - r[1] + 1) * std::uint64_t(r[5] - r[2] + 1);
    }
    if (entries > max_bucket_entries)
      return error(StatusCode::too_large, "the triangles touch too many cells in total (" + std::to_string(entries) +
                                              "); use fewer cells or split very large triangles");
    for (std::size_t f = 0; f < nf; ++f) {
      const std::int32_t* r = &cache.range_[6 * f];
      for (int k = r[2]; k <= r[5]; ++k)
        for (int j = r[1]; j <= r[4]; ++j)
          for (int i = r[0]; i <= r[3]; ++i) ++count[std::size_t(cell_index(lattice.cells, i, j, k)) + 1];
    }
    for (std::size_t c = 0; c < std::size_t(ncell); ++c) count[c + 1] += count[c];
    cache.bucket_start_ = count;
    cache.bucket_tri_.resize(count.back());
    for (std::size_t f = 0; f < nf; ++f) {
      const std::int32_t* r = &cache.range_[6 * f];
      for (int k = r[2]; k <= r[5]; ++k)
        for (int j = r[1]; j <= r[4]; ++j)
          for (int i = r[0]; i <= r[3]; ++i)
            cache.bucket_tri_[count[std::size_t(cell_index(lattice.cells, i, j, k))]++] = std::uint32_t(f);
    }
    cache.mesh_ = &in;
    return {};
  }

  /// Stitches one labelling with a prepared cache. See the file comment.
  Status stitch(const StitchCache& cache, const Eigen::Array3i& out_cells,
                const std::vector<Eigen::Array3i>& cell_shift, Mesh& out, StitchReport& report) const {
    const auto t0 = std::chrono::steady_clock::now();
    report = StitchReport();
    if (!cache.ready()) return error(StatusCode::invalid_argument, "the stitch cache was not prepared");
    if ((out_cells < 1).any())
      return error(StatusCode::invalid_argument, "the output grid must have at least one cell along each axis");
    const double n_out = double(out_cells(0)) * out_cells(1) * out_cells(2);
    if (n_out > double(max_cells))
      return error(StatusCode::too_large, "the output grid has more than " + std::to_string(max_cells) + " cells");
    if (double(cell_shift.size()) != n_out)
      return error(StatusCode::invalid_argument, "the labelling has " + std::to_string(cell_shift.size()) +
                                                     " entries but the output grid has " +
                                                     std::to_string(std::size_t(n_out)) + " cells");
    if (cache.mesh() == &out) return error(StatusCode::invalid_argument, "the output mesh must not be the input mesh");
    Run run(*this, cache, out_cells, cell_shift);
    run.execute(out, report);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return {};
  }

  /// Prepares and stitches in one call (the policy contract). `report.ms` includes the preparation.
  Status stitch(const Mesh& in, const Lattice& lattice, const Eigen::Array3i& out_cells,
                const std::vector<Eigen::Array3i>& cell_shift, Mesh& out, StitchReport& report) const {
    const auto t0 = std::chrono::steady_clock::now();
    report = StitchReport();
    if (&in == &out) return error(StatusCode::invalid_argument, "the output mesh must not be the input mesh");
    StitchCache cache;
    RESTITCH_TRY(prepare(in, lattice, cache));
    RESTITCH_TRY(stitch(cache, out_cells, cell_shift, out, report));
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return {};
  }

  /// Largest grid (input or output) accepted, in cells.
  static constexpr std::int64_t max_cells = std::int64_t(1) << 24;
  /// Most texture coordinate sets carried (a clip vertex holds at most 64 numbers).
  static constexpr std::size_t max_uv_sets = 16;
  /// Most (triangle, touched cell) pairs in the cache.
  static constexpr std::uint64_t max_bucket_entries = std::uint64_t(1) << 30;

 private:
  static int cell_index(const Eigen::Array3i& cells, int i, int j, int k) { return i + cells(0) * (j + cells(1) * k); }

  // One stitch call: all working state.
  struct Run {
    const ClipStitcher& self;
    const StitchCache& cache;
    const Mesh& in;
    const Lattice& lat;
    Eigen::Array3i out_cells;
    const std::vector<Eigen::Array3i>& shift;

    // Layout of a clip vertex.
    int stride = 6, off_n = -1, off_t = -1, off_uv = -1, off_c = -1, uv_sets = 0;
    bool has_n = false, has_t = false, has_c = false;
    int cut_stride = 3, cut_n = 0, cut_t = 0, cut_uv = 0, cut_c = 0;  // offsets unused when a channel is absent

    // Regions.
    std::vector<std::int32_t> region_of;  // per output cell, -1 = empty
    std::vector<Eigen::Array3i> region_shift;
    std::vector<Eigen::Vector3d> region_t;  // A d of each region, model units
    std::vector<std::uint32_t> region_start, region_cells;

    // Current region.
    std::int32_t cur = -1;
    Eigen::Array3i cur_d;
    Eigen::Vector3d cur_t;
    std::array<bool, 3> keep_low{}, keep_high{};
    std::uint8_t cut_mask = 0;  // overhang flags that force a cut in this region

    std::vector<std::int32_t> vstamp, tstamp;
    std::vector<std::uint32_t> vmap;
    std::vector<std::uint32_t> gathered;
    std::vector<detail::ClipPolygon> work, spare;  // BSP polygons per depth
    std::vector<double> vbuf;
    std::vector<std::uint32_t> ids;
    detail::StitchOutput o;
    StitchReport rep;

    Run(const ClipStitcher& s, const StitchCache& c, const Eigen::Array3i& oc, const std::vector<Eigen::Array3i>& sh)
        : self(s), cache(c), in(*c.mesh()), lat(c.lattice()), out_cells(oc), shift(sh) {
      has_n = in.N.rows() > 0;
      has_t = in.T.rows() > 0;
      has_c = in.C.rows() > 0;
      uv_sets = int(in.UV.size());
      if (has_n) off_n = stride, stride += 3;
      if (has_t) off_t = stride, stride += 4;
      if (uv_sets) off_uv = stride, stride += 2 * uv_sets;
      if (has_c) off_c = stride, stride += 4;
      // A cut vertex keeps the same channels as floats, without the canonical coordinates.
      cut_n = 3 + (off_n - 6);
      cut_t = 3 + (off_t - 6);
      cut_uv = 3 + (off_uv - 6);
      cut_c = 3 + (off_c - 6);
      cut_stride = stride - 3;
      vbuf.resize(std::size_t(stride));
    }

    void build_regions() {
      const std::size_t n = shift.size();
      region_of.assign(n, -1);
      std::vector<std::uint8_t> valid(n, 0);
      for (std::size_t x = 0; x < n; ++x) {
        const int i = int(x % std::size_t(out_cells(0)));
        const int j = int((x / std::size_t(out_cells(0))) % std::size_t(out_cells(1)));
        const int k = int(x / (std::size_t(out_cells(0)) * std::size_t(out_cells(1))));
        const Eigen::Array<std::int64_t, 3, 1> s(std::int64_t(i) - shift[x](0), std::int64_t(j) - shift[x](1),
                                                 std::int64_t(k) - shift[x](2));
        valid[x] = (s >= 0).all() && (s < lat.cells.cast<std::int64_t>()).all();
      }
      std::vector<std::uint32_t> queue;
      region_start.assign(1, 0);
      region_cells.clear();
      for (std::size_t seed = 0; seed < n; ++seed) {
        if (!valid[seed] || region_of[seed] >= 0) continue;
        const std::int32_t r = std::int32_t(region_shift.size());
        region_shift.push_back(shift[seed]);
        queue.assign(1, std::uint32_t(seed));
        region_of[seed] = r;
        for (std::size_t q = 0; q < queue.size(); ++q) {
          const std::uint32_t x = queue[q];
          const int i = int(x % std::uint32_t(out_cells(0)));
          const int j = int((x / std::uint32_t(out_cells(0))) % std::uint32_t(out_cells(1)));
          const int k = int(x / (std::uint32_t(out_cells(0)) * std::uint32_t(out_cells(1))));
          const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                                {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
          for (const auto& c : nb) {
            if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= out_cells(0) || c[1] >= out_cells(1) ||
                c[2] >= out_cells(2))
              continue;
            const std::size_t y = std::size_t(c[0] + out_cells(0) * (c[1] + out_cells(1) * c[2]));
            if (valid[y] && region_of[y] < 0 && (shift[y] == shift[seed]).all()) {
              region_of[y] = r;
              queue.push_back(std::uint32_t(y));
            }
          }
        }
        std::sort(queue.begin(), queue.end());
        region_cells.insert(region_cells.end(), queue.begin(), queue.end());
        region_start.push_back(std::uint32_t(region_cells.size()));
      }
    }

    // ---- output vertices -------------------------------------------------
    std::uint32_t copy_vertex(std::uint32_t v, std::uint32_t group) {
      if (vstamp[v] == cur) return vmap[v];
      const std::uint32_t id = std::uint32_t(o.vsrc.size());
      vstamp[v] = cur;
      vmap[v] = id;
      o.vsrc.push_back(v);
      o.vregion.push_back(cur);
      o.vgroup.push_back(group);
      return id;
    }

    std::uint32_t cut_vertex(const double* x, std::uint32_t group) {
      const std::uint32_t id = std::uint32_t(o.vsrc.size());
      o.vsrc.push_back(std::uint32_t(o.cut.size() / std::size_t(cut_stride)) | detail::StitchOutput::cut_bit);
      o.vregion.push_back(cur);
      o.vgroup.push_back(group);
      for (int a = 0; a < 3; ++a) o.cut.push_back(float(x[3 + a] + cur_t(a)));
      if (has_n) {
        const double* n = x + off_n;
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double s = len > 0 ? 1.0 / len : 1.0;
        for (int a = 0; a < 3; ++a) o.cut.push_back(float(n[a] * s));
      }
      if (has_t) {
        const double* t = x + off_t;
        const double len = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        const double s = len > 0 ? 1.0 / len : 1.0;
        for (int a = 0; a < 3; ++a) o.cut.push_back(float(t[a] * s));
        o.cut.push_back(t[3] >= 0 ? 1.0f : -1.0f);
      }
      for (int a = 0; a < 2 * uv_sets; ++a) o.cut.push_back(float(x[off_uv + a]));
      if (has_c)
        for (int a = 0; a < 4; ++a) o.cut.push_back(float(x[off_c + a]));
      return id;
    }

    // Values of output vertex i: position (translated) and attribute channels.
    bool is_cut(std::uint32_t i) const { return (o.vsrc[i] & detail::StitchOutput::cut_bit) != 0; }
    const float* cut_data(std::uint32_t i) const {
      return o.cut.data() + std::size_t(o.vsrc[i] & ~detail::StitchOutput::cut_bit) * std::size_t(cut_stride);
    }
    void position(std::uint32_t i, float* p) const {
      if (is_cut(i)) {
        std::copy(cut_data(i), cut_data(i) + 3, p);
        return;
      }
      const Eigen::Vector3d& t = region_t[std::size_t(o.vregion[i])];
      for (int a = 0; a < 3; ++a) p[a] = float(double(in.V(Eigen::Index(o.vsrc[i]), a)) + t(a));
    }
    const float* normal(std::uint32_t i) const {
      return is_cut(i) ? cut_data(i) + cut_n : in.N.data() + 3 * std::size_t(o.vsrc[i]);
    }
    const float* tangent(std::uint32_t i) const {
      return is_cut(i) ? cut_data(i) + cut_t : in.T.data() + 4 * std::size_t(o.vsrc[i]);
    }
    const float* texcoord(std::uint32_t i, int set) const {
      return is_cut(i) ? cut_data(i) + cut_uv + 2 * set : in.UV[std::size_t(set)].data() + 2 * std::size_t(o.vsrc[i]);
    }
    const float* color(std::uint32_t i) const {
      return is_cut(i) ? cut_data(i) + cut_c : in.C.data() + 4 * std::size_t(o.vsrc[i]);
    }
    bool weld_candidate(std::uint32_t i) const { return is_cut(i) || cache.on_plane_[o.vsrc[i]]; }

    void load_vertex(std::uint32_t v, double* x) const {
      for (int a = 0; a < 3; ++a) x[a] = cache.canon_[3 * std::size_t(v) + std::size_t(a)];
      for (int a = 0; a < 3; ++a) x[3 + a] = in.V(Eigen::Index(v), a);
      if (has_n)
        for (int a = 0; a < 3; ++a) x[off_n + a] = in.N(Eigen::Index(v), a);
      if (has_t)
        for (int a = 0; a < 4; ++a) x[off_t + a] = in.T(Eigen::Index(v), a);
      for (int s = 0; s < uv_sets; ++s)
        for (int a = 0; a < 2; ++a) x[off_uv + 2 * s + a] = in.UV[std::size_t(s)](Eigen::Index(v), a);
      if (has_c)
        for (int a = 0; a < 4; ++a) x[off_c + a] = in.C(Eigen::Index(v), a);
    }

    // ---- one input triangle in the current region -------------------------
    // Does input cell (i, j, k), moved by the current shift, fall in the current region?
    bool cell_in_region(int i, int j, int k) const {
      const std::int64_t x = std::int64_t(i) + cur_d(0), y = std::int64_t(j) + cur_d(1), z = std::int64_t(k) + cur_d(2);
      if (x < 0 || y < 0 || z < 0 || x >= out_cells(0) || y >= out_cells(1) || z >= out_cells(2)) return false;
      return region_of[std::size_t(x + out_cells(0) * (y + std::int64_t(out_cells(1)) * z))] == cur;
    }

    void process_triangle(std::uint32_t f) {
      const std::int32_t* r = &cache.range_[6 * std::size_t(f)];
      const std::uint8_t flags = cache.overhang_[f];
      // Whole: no overhang cut needed, and every cell of its range in the region
      // (a one-cell triangle came from that cell's bucket, so its cell is in).
      bool whole = (flags & cut_mask) == 0;
      if (whole && (r[0] != r[3] || r[1] != r[4] || r[2] != r[5]))
        for (int k = r[2]; k <= r[5] && whole; ++k)
          for (int j = r[1]; j <= r[4] && whole; ++j)
            for (int i = r[0]; i <= r[3] && whole; ++i) whole = cell_in_region(i, j, k);
      const std::uint32_t g = in.FG(Eigen::Index(f));
      if (whole) {
        const std::uint32_t a = copy_vertex(in.F(Eigen::Index(f), 0), g);
        const std::uint32_t b = copy_vertex(in.F(Eigen::Index(f), 1), g);
        const std::uint32_t c = copy_vertex(in.F(Eigen::Index(f), 2), g);
        o.faces.push_back(a);
        o.faces.push_back(b);
        o.faces.push_back(c);
        o.fgroup.push_back(g);
        ++rep.triangles_copied;
        return;
      }
      ++rep.triangles_clipped;
      // The triangle as a polygon in work[0]; overhang cuts first.
      if (work.size() < 2) work.resize(2), spare.resize(2);
      work[0].clear();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = in.F(Eigen::Index(f), k);
        load_vertex(v, vbuf.data());
        work[0].push(vbuf.data(), v, stride);
      }
      for (int a = 0; a < 3; ++a) {
        if (!keep_low[std::size_t(a)] && (flags & (1u << a))) {  // keep c_a >= 0
          detail::split_polygon(work[0], a, 0.0, stride, work[1], spare[1]);
          std::swap(work[0], spare[1]);
        }
        if (!keep_high[std::size_t(a)] && (flags & (8u << a))) {  // keep c_a < cells[a]
          detail::split_polygon(work[0], a, double(lat.cells(a)), stride, work[1], spare[1]);
          std::swap(work[0], work[1]);
        }
        if (work[0].n < 3) return;
      }
      std::array<int, 3> lo{{r[0], r[1], r[2]}}, hi{{r[3], r[4], r[5]}};
      bsp(0, lo, hi, g);
    }

    // Tight clamped cell range of a polygon.
    void polygon_range(const detail::ClipPolygon& p, std::array<int, 3>& lo, std::array<int, 3>& hi) const {
      for (int a = 0; a < 3; ++a) {
        double m = INFINITY, M = -INFINITY;
        for (int i = 0; i < p.n; ++i) {
          const double v = p.vertex(i, stride)[a];
          m = std::min(m, v);
          M = std::max(M, v);
        }
        std::int32_t l, h;
        detail::cell_range(m, M, lat.cells(a), l, h);
        lo[std::size_t(a)] = std::max(lo[std::size_t(a)], int(l));
        hi[std::size_t(a)] = std::min(hi[std::size_t(a)], int(h));
      }
    }

    // Counts the cells of a box that belong to the current region.
    std::int64_t count_in(const std::array<int, 3>& lo, const std::array<int, 3>& hi) const {
      std::int64_t c = 0;
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int i = lo[0]; i <= hi[0]; ++i) c += cell_in_region(i, j, k);
      return c;
    }

    // Recursively splits work[depth] until each piece lies in cells that are
    // all in, or all out of, the current region; emits the pieces that are in.
    // Level L splits work[L] into work[L + 1] (low) and spare[L + 1] (high);
    // deeper levels never touch spare[L + 1], so the high piece waits there.
    void bsp(std::size_t depth, std::array<int, 3> lo, std::array<int, 3> hi, std::uint32_t group) {
      if (work.size() < depth + 2) work.resize(depth + 2), spare.resize(depth + 2);
      polygon_range(work[depth], lo, hi);
      for (int a = 0; a < 3; ++a)
        if (lo[std::size_t(a)] > hi[std::size_t(a)]) return;
      const std::int64_t total = std::int64_t(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
      const std::int64_t in_count = count_in(lo, hi);
      if (in_count == 0) return;
      if (in_count == total) {
        emit(work[depth], group);
        return;
      }
      // The plane: best one that separates cells in the region from cells
      // out of it (both sides uniform), else one with a side all out (it is
      // dropped at once), else one with a side all in; ties go to the first,
      // axis by axis, low to high. So cuts fall on the region's boundary.
      int axis = -1, plane = 0, score = 0;
      for (int a = 0; a < 3; ++a) {
        const std::size_t ua = std::size_t(a);
        for (int k = lo[ua] + 1; k <= hi[ua]; ++k) {
          std::array<int, 3> h1 = hi;
          h1[ua] = k - 1;
          const std::int64_t c1 = count_in(lo, h1), c2 = in_count - c1;
          const std::int64_t n1 = total / (hi[ua] - lo[ua] + 1) * (k - lo[ua]), n2 = total - n1;
          const bool u1 = c1 == 0 || c1 == n1, u2 = c2 == 0 || c2 == n2;
          const int sc = (u1 && u2) ? 3 : (c1 == 0 || c2 == 0) ? 2 : (u1 || u2) ? 1 : 0;
          if (sc > score) score = sc, axis = a, plane = k;
        }
      }
      if (axis < 0) {
        int best = -1;
        for (int a = 0; a < 3; ++a)
          if (hi[std::size_t(a)] - lo[std::size_t(a)] > best) best = hi[std::size_t(a)] - lo[std::size_t(a)], axis = a;
        plane = (lo[std::size_t(axis)] + hi[std::size_t(axis)] + 1) / 2;
      }
      detail::split_polygon(work[depth], axis, double(plane), stride, work[depth + 1], spare[depth + 1]);
      std::array<int, 3> h1 = hi, l2 = lo;
      h1[std::size_t(axis)] = plane - 1;
      l2[std::size_t(axis)] = plane;
      if (work[depth + 1].n >= 3) bsp(depth + 1, lo, h1, group);
      if (spare[depth + 1].n >= 3) {
        std::swap(work[depth + 1], spare[depth + 1]);
        bsp(depth + 1, l2, hi, group);
      }
    }

    void emit(const detail::ClipPolygon& p, std::uint32_t group) {
      if (p.n < 3) return;
      const double tol2 = cache.tol_ * cache.tol_;
      auto model = [&](int i) {
        const double* x = p.vertex(i, stride);
        return Eigen::Vector3d(x[3], x[4], x[5]);
      };
      const Eigen::Vector3d p0 = model(0);
      double area = 0;
      for (int i = 1; i + 1 < p.n; ++i) area += 0.5 * (model(i) - p0).cross(model(i + 1) - p0).norm();
      if (area < tol2) return;
      ids.resize(std::size_t(p.n));
      for (int i = 0; i < p.n; ++i) {
        const std::int64_t s = p.src[std::size_t(i)];
        ids[std::size_t(i)] = s >= 0 ? copy_vertex(std::uint32_t(s), group) : cut_vertex(p.vertex(i, stride), group);
      }
      for (int i = 1; i + 1 < p.n; ++i) {
        if (0.5 * (model(i) - p0).cross(model(i + 1) - p0).norm() < tol2) continue;
        o.faces.push_back(ids[0]);
        o.faces.push_back(ids[std::size_t(i)]);
        o.faces.push_back(ids[std::size_t(i) + 1]);
        o.fgroup.push_back(group);
      }
    }

    // ---- welding, ordering, output ----------------------------------------
    bool compatible(std::uint32_t i, std::uint32_t j, const float* pi, const float* pj, double tol2) const {
      if (o.vgroup[i] != o.vgroup[j]) return false;
      if (!is_cut(i) && !is_cut(j) && o.vregion[i] == o.vregion[j]) return false;
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double d = double(pi[a]) - double(pj[a]);
        d2 += d * d;
      }
      if (d2 > tol2) return false;
      const AttributeSet& at = in.groups[o.vgroup[i]].attributes;
      const float e = float(self.attribute_tolerance);
      auto close = [e](const float* x, const float* y, int n) {
        for (int k = 0; k < n; ++k)
          if (!(std::abs(x[k] - y[k]) <= e)) return false;
        return true;
      };
      if (has_n && at.normals && !close(normal(i), normal(j), 3)) return false;
      if (has_t && at.tangents && (!close(tangent(i), tangent(j), 3) || tangent(i)[3] != tangent(j)[3])) return false;
      for (int s = 0; s < std::min(uv_sets, at.uv_sets); ++s)
        if (!close(texcoord(i, s), texcoord(j, s), 2)) return false;
      if (has_c && at.color_components > 0 && !close(color(i), color(j), std::min(at.color_components, 4)))
        return false;
      return true;
    }

    // Representative of every output vertex after welding (itself when not welded).
    std::vector<std::uint32_t> weld_map() {
      const std::size_t nv = o.vsrc.size();
      std::vector<std::uint32_t> rep_of(nv);
      for (std::size_t i = 0; i < nv; ++i) rep_of[i] = std::uint32_t(i);
      if (!self.weld) return rep_of;
      struct Key {
        std::int64_t x, y, z;
        std::uint32_t id;
        float p[3];
      };
      std::vector<Key> keys;
      double max_abs = cache.max_abs_coord_;
      for (std::size_t i = 0; i < nv; ++i)
        if (weld_candidate(std::uint32_t(i))) {
          Key k{0, 0, 0, std::uint32_t(i), {0, 0, 0}};
          position(std::uint32_t(i), k.p);
          for (int a = 0; a < 3; ++a) max_abs = std::max(max_abs, double(std::abs(k.p[a])));
          keys.push_back(k);
        }
      if (keys.size() < 2) return rep_of;
      const double tol = std::max(cache.tol_, 8.0 * double(FLT_EPSILON) * max_abs);
      const double tol2 = tol * tol, h = 2.0 * tol;
      for (Key& k : keys) {
        k.x = std::int64_t(std::floor(k.p[0] / h));
        k.y = std::int64_t(std::floor(k.p[1] / h));
        k.z = std::int64_t(std::floor(k.p[2] / h));
      }
      auto less = [](const Key& a, const Key& b) {
        if (a.x != b.x) return a.x < b.x;
        if (a.y != b.y) return a.y < b.y;
        if (a.z != b.z) return a.z < b.z;
        return a.id < b.id;
      };
      std::vector<Key> order = keys;  // in vertex order
      std::sort(keys.begin(), keys.end(), less);
      // Each candidate, in vertex order, joins the lowest earlier representative it is compatible with.
      // A partner is at most tol = h / 2 away, so along each axis it lies in
      // this bin or in the neighbour on the side of the nearer bin face: 8 bins.
      for (const Key& k : order) {
        std::uint32_t best = k.id;
        std::array<int, 3> side;
        for (int a = 0; a < 3; ++a) {
          const double u = double(k.p[a]) / h;
          side[std::size_t(a)] = (u - std::floor(u)) < 0.5 ? -1 : 1;
        }
        for (int dz = 0; dz <= 1; ++dz)
          for (int dy = 0; dy <= 1; ++dy)
            for (int dx = 0; dx <= 1; ++dx) {
              const Key probe{k.x + dx * side[0], k.y + dy * side[1], k.z + dz * side[2], 0, {0, 0, 0}};
              for (auto it = std::lower_bound(keys.begin(), keys.end(), probe, less);
                   it != keys.end() && it->x == probe.x && it->y == probe.y && it->z == probe.z && it->id < best; ++it)
                if (rep_of[it->id] == it->id && compatible(k.id, it->id, k.p, it->p, tol2)) best = it->id;
            }
        if (best != k.id) {
          rep_of[k.id] = best;
          ++rep.seam_vertices_welded;
        }
      }
      return rep_of;
    }

    void finish(Mesh& out) {
      const std::vector<std::uint32_t> rep_of = weld_map();
      // Faces: remap, drop collapsed ones, stable counting sort by group.
      const std::size_t nf = o.fgroup.size(), ng = in.groups.size();
      std::vector<std::uint32_t> gstart(ng + 1, 0);
      for (std::size_t f = 0; f < nf; ++f) {
        std::uint32_t* c = &o.faces[3 * f];
        for (int k = 0; k < 3; ++k) c[k] = rep_of[c[k]];
        if (c[0] != c[1] && c[1] != c[2] && c[2] != c[0])
          ++gstart[o.fgroup[f] + 1];
        else
          o.fgroup[f] = std::uint32_t(ng);  // dropped
      }
      for (std::size_t g = 0; g < ng; ++g) gstart[g + 1] += gstart[g];
      const std::size_t kept = gstart[ng];
      std::vector<std::uint32_t> order(kept);
      for (std::size_t f = 0; f < nf; ++f)
        if (o.fgroup[f] < ng) order[gstart[o.fgroup[f]]++] = std::uint32_t(f);
      // Vertices: numbered by first use.
      const std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
      std::vector<std::uint32_t> newid(o.vsrc.size(), none), old;
      old.reserve(o.vsrc.size());
      Mesh m;
      m.F.resize(Eigen::Index(kept), 3);
      m.FG.resize(Eigen::Index(kept));
      std::uint32_t* F = m.F.data();
      for (std::size_t r = 0; r < kept; ++r) {
        const std::size_t f = order[r];
        for (std::size_t k = 0; k < 3; ++k) {
          const std::uint32_t src = o.faces[3 * f + k];
          std::uint32_t& id = newid[src];
          if (id == none) {
            id = std::uint32_t(old.size());
            old.push_back(src);
          }
          F[3 * r + k] = id;
        }
        m.FG(Eigen::Index(r)) = o.fgroup[f];
      }
      const Eigen::Index nv = Eigen::Index(old.size());
      m.V.resize(nv, 3);
      if (has_n) m.N.resize(nv, 3);
      if (has_t) m.T.resize(nv, 4);
      if (has_c) m.C.resize(nv, 4);
      m.UV.assign(std::size_t(uv_sets), MatrixX2f(nv, 2));
      for (std::size_t v = 0; v < std::size_t(nv); ++v) {
        const std::uint32_t s = old[v];
        position(s, m.V.data() + 3 * v);
        if (has_n) std::copy(normal(s), normal(s) + 3, m.N.data() + 3 * v);
        if (has_t) std::copy(tangent(s), tangent(s) + 4, m.T.data() + 4 * v);
        for (int u = 0; u < uv_sets; ++u)
          std::copy(texcoord(s, u), texcoord(s, u) + 2, m.UV[std::size_t(u)].data() + 2 * v);
        if (has_c) std::copy(color(s), color(s) + 4, m.C.data() + 4 * v);
      }
      m.groups = in.groups;
      m.materials = in.materials;
      m.assets = in.assets;
      out = std::move(m);
    }

    void execute(Mesh& out, StitchReport& report) {
      build_regions();
      rep.regions = region_shift.size();
      const std::size_t nv = in.vertex_count(), nf = in.triangle_count();
      vstamp.assign(nv, -1);
      vmap.assign(nv, 0);
      tstamp.assign(nf, -1);
      const double growth = std::max(1.0, double(shift.size()) / double(lat.cells.prod()));
      o.faces.reserve(std::size_t(double(nf) * 3 * std::min(growth, 8.0)) + 64);
      o.fgroup.reserve(o.faces.capacity() / 3);
      o.vsrc.reserve(std::size_t(double(nv) * std::min(growth, 8.0)) + 64);
      o.vregion.reserve(o.vsrc.capacity());
      o.vgroup.reserve(o.vsrc.capacity());
      for (const Eigen::Array3i& d : region_shift) region_t.push_back(lat.shift(d));
      for (std::size_t r = 0; r < region_shift.size(); ++r) {
        cur = std::int32_t(r);
        cur_d = region_shift[r];
        cur_t = region_t[r];
        cut_mask = 0;
        for (int a = 0; a < 3; ++a) {
          keep_low[std::size_t(a)] = cur_d(a) == 0;
          keep_high[std::size_t(a)] = cur_d(a) == out_cells(a) - lat.cells(a);
          if (!keep_low[std::size_t(a)]) cut_mask |= std::uint8_t(1u << a);
          if (!keep_high[std::size_t(a)]) cut_mask |= std::uint8_t(8u << a);
        }
        // Gather the triangles of the region's source cells, in face order.
        gathered.clear();
        std::uint32_t tmin = std::numeric_limits<std::uint32_t>::max(), tmax = 0;
        for (std::uint32_t q = region_start[r]; q < region_start[r + 1]; ++q) {
          const std::uint32_t x = region_cells[q];
          const int i = int(x % std::uint32_t(out_cells(0)));
          const int j = int((x / std::uint32_t(out_cells(0))) % std::uint32_t(out_cells(1)));
          const int k = int(x / (std::uint32_t(out_cells(0)) * std::uint32_t(out_cells(1))));
          const int s = cell_index(lat.cells, i - cur_d(0), j - cur_d(1), k - cur_d(2));
          for (std::uint32_t b = cache.bucket_start_[std::size_t(s)]; b < cache.bucket_start_[std::size_t(s) + 1];
               ++b) {
            const std::uint32_t t = cache.bucket_tri_[b];
            if (tstamp[t] == cur) continue;
            tstamp[t] = cur;
            gathered.push_back(t);
            tmin = std::min(tmin, t);
            tmax = std::max(tmax, t);
          }
        }
        if (gathered.empty()) continue;
        const double span = double(tmax - tmin) + 1.0;
        if (double(gathered.size()) * 16.0 >= span) {
          for (std::uint32_t t = tmin; t <= tmax; ++t)
            if (tstamp[t] == cur) process_triangle(t);
        } else {
          std::sort(gathered.begin(), gathered.end());
          for (std::uint32_t t : gathered) process_triangle(t);
        }
      }
      finish(out);
      report = rep;
    }
  };
};

namespace detail {
template <class T, class = void>
struct is_stitcher_policy : std::false_type {};
template <class T>
struct is_stitcher_policy<
    T, std::void_t<decltype(std::declval<const T&>().stitch(
           std::declval<const Mesh&>(), std::declval<const Lattice&>(), std::declval<const Eigen::Array3i&>(),
           std::declval<const std::vector<Eigen::Array3i>&>(), std::declval<Mesh&>(), std::declval<StitchReport&>()))>>
    : std::is_same<decltype(std::declval<const T&>().stitch(std::declval<const Mesh&>(), std::declval<const Lattice&>(),
                                                            std::declval<const Eigen::Array3i&>(),
                                                            std::declval<const std::vector<Eigen::Array3i>&>(),
                                                            std::declval<Mesh&>(), std::declval<StitchReport&>())),
                   Status> {};

template <class T, class = void>
struct has_prepared_stitch : std::false_type {};
template <class T>
struct has_prepared_stitch<
    T, std::void_t<decltype(std::declval<const T&>().prepare(
                       std::declval<const Mesh&>(), std::declval<const Lattice&>(), std::declval<StitchCache&>())),
                   decltype(std::declval<const T&>().stitch(
                       std::declval<const StitchCache&>(), std::declval<const Eigen::Array3i&>(),
                       std::declval<const std::vector<Eigen::Array3i>&>(), std::declval<Mesh&>(),
                       std::declval<StitchReport&>()))>> : std::true_type {};
}  // namespace detail

/// True when T satisfies the stitcher policy contract (see the file comment).
template <class T>
inline constexpr bool is_stitcher_policy_v = detail::is_stitcher_policy<T>::value;

/// True when T also offers prepare(in, lattice, cache) + stitch(cache, ...).
template <class T>
inline constexpr bool has_prepared_stitch_v = detail::has_prepared_stitch<T>::value;

static_assert(is_stitcher_policy_v<ClipStitcher>, "ClipStitcher must satisfy the stitcher policy contract");
static_assert(has_prepared_stitch_v<ClipStitcher>, "ClipStitcher must offer the prepared stitch");

}  // namespace restitch
