// restitch/stitch/stitch.hpp - the stitcher: a labelled output lattice -> a real triangle mesh.
//
// docs/method.md section 3. The solver gives every output cell x (linear index
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
// overhang (cut at the outer plane). An end cell x whose source is not the
// input's end cell along a gets an END CAP instead: the input's end from the
// end plane outward (Lattice::end_low / end_high: the cell plane, so the
// overhang, unless the input's end cell is not full), taken from the end cell
// s' (s with s'_a = 0 or U_in - 1) and translated with the anchored shift;
// x's own copy is cut at the same plane (stitch/detail/regions.hpp). Ends are
// therefore always kept, and an output one cell long carries both
// (docs/method.md section 3).
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
// across labellings (the web demo's live slider) names its own cache type and
// offers
//
//     using cache_type = ...;   // default-constructible, movable
//     restitch::Status prepare(const Mesh& in, const Lattice& lattice, cache_type& cache) const;
//     restitch::Status stitch(const cache_type& cache, const Eigen::Array3i& out_cells,
//                             const std::vector<Eigen::Array3i>& cell_shift,
//                             Mesh& out, StitchReport& report) const;
//
// ClipStitcher's cache (ClipStitchCache) refers to `in` (it is not copied):
// the mesh must outlive the cache and stay unchanged while the cache is used.
//
// Parts (stitch/detail/): clip.hpp (polygon clipping against cell planes),
// cache.hpp (the prepared cache), regions.hpp (regions of a labelling),
// region_clip.hpp (one triangle into one region), output.hpp (the output
// being built and its assembly), weld.hpp (welding), tjunction.hpp (the
// T-junction repair), zipper.hpp (strips between cut lines that do not quite
// meet: after welding and the T-junction repair, seams whose two cut lines lie
// within 1e-3 of the diagonal of each other are closed by triangles in the
// seam plane between them; ClipStitcher::zip_seams).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"
#include "restitch/stitch/detail/cache.hpp"
#include "restitch/stitch/detail/output.hpp"
#include "restitch/stitch/detail/region_clip.hpp"
#include "restitch/stitch/detail/regions.hpp"
#include "restitch/stitch/detail/tjunction.hpp"
#include "restitch/stitch/detail/zipper.hpp"
#include "restitch/stitch/detail/weld.hpp"

namespace restitch {

/// What one stitch call did.
struct StitchReport {
  std::size_t regions = 0;               ///< regions with a valid source (empty cells are no region)
  std::size_t triangles_copied = 0;      ///< input triangles copied untouched (one per copy)
  std::size_t triangles_clipped = 0;     ///< input triangle copies that crossed a region boundary and were clipped
  std::size_t seam_vertices_welded = 0;  ///< output vertices removed by welding
  /// seam vertices moved onto an earlier one within the tolerance that they may not join (another
  /// group, or attributes that differ): the surface closes, the attribute seam stays
  std::size_t seam_vertices_snapped = 0;
  std::size_t t_junction_edges_split = 0;  ///< boundary seam edges split at T-vertices (stitch/detail/tjunction.hpp)
  std::size_t zip_triangles = 0;  ///< triangles added between the sides of seams that do not quite meet (zipper.hpp)
  std::size_t end_caps = 0;  ///< overhangs copied onto ends whose region is not anchored there (file comment)
  double ms = 0;                         ///< wall-clock time of the call (informative only)
};

/// The default stitcher: exact clipping against cell planes, attribute
/// interpolation, seam welding. See the file comment for the full contract.
class ClipStitcher {
 public:
  using cache_type = ClipStitchCache;

  double weld_tolerance = 1e-6;       ///< relative to the input's bounding-box diagonal
  double attribute_tolerance = 1e-4;  ///< per component, for welding (normals, tangents, UVs, colours)
  bool weld = true;                   ///< weld coincident seam vertices
  bool repair_t_junctions = true;     ///< after welding, split boundary seam edges at T-vertices (needs weld)
  /// then close what stays open where the two sides' cut lines lie within 1e-3 of the diagonal of each
  /// other with a strip of triangles in the seam plane (stitch/detail/zipper.hpp; needs weld)
  bool zip_seams = true;

  /// Largest grid (input or output) accepted, in cells.
  static constexpr std::int64_t max_cells = std::int64_t(1) << 24;
  /// Most (triangle, touched cell) pairs in the cache.
  static constexpr std::uint64_t max_bucket_entries = std::uint64_t(1) << 30;

  /// Builds the labelling-independent cache. Validates the mesh and lattice.
  /// Cost O(#V + bucketed triangle-cells).
  template <class = void>
  Status prepare(const Mesh& in, const Lattice& lattice, cache_type& cache) const {
    return detail::guarded("ClipStitcher::prepare", [&]() -> Status {
      cache = cache_type();
      RESTITCH_TRY(validate(in));
      if (in.UV.size() > max_uv_sets)
        return error(StatusCode::unsupported, "the mesh has " + std::to_string(in.UV.size()) +
                                                  " texture coordinate sets; the stitcher carries at most " +
                                                  std::to_string(max_uv_sets));
      if (!lattice.A.allFinite() || !lattice.origin.allFinite())
        return error(StatusCode::invalid_argument, "the lattice has a non-finite offset or origin");
      if ((lattice.cells < 1).any())
        return error(StatusCode::invalid_argument, "the lattice must have at least one input cell along each axis");
      if (CellGrid(lattice.cells).size() > max_cells)
        return error(StatusCode::too_large, "the input lattice has more than " + std::to_string(max_cells) + " cells");
      const double scale = lattice.A.colwise().norm().prod();
      const double det = lattice.A.determinant();
      if (!(std::abs(det) > 1e-9 * scale) || !(scale > 0))
        return error(StatusCode::invalid_argument, "the lattice offsets are (nearly) linearly dependent");
      const double tol =
          std::max(weld_tolerance * bounding_box(in).size().norm(), 8.0 * double(FLT_EPSILON) * max_abs_coordinate(in));
      return cache.build(in, lattice, tol, max_bucket_entries);
    });
  }

  /// Stitches one labelling with a prepared cache. See the file comment.
  template <class = void>
  Status stitch(const cache_type& cache, const Eigen::Array3i& out_cells,
                const std::vector<Eigen::Array3i>& cell_shift, Mesh& out, StitchReport& report) const {
    return detail::guarded("ClipStitcher::stitch", [&]() -> Status {
      const auto t0 = std::chrono::steady_clock::now();
      report = StitchReport();
      if (!cache.ready()) return error(StatusCode::invalid_argument, "the stitch cache was not prepared");
      if ((out_cells < 1).any())
        return error(StatusCode::invalid_argument, "the output grid must have at least one cell along each axis");
      const CellGrid out_grid(out_cells);
      if (out_grid.size() > max_cells)
        return error(StatusCode::too_large, "the output grid has more than " + std::to_string(max_cells) + " cells");
      if (std::int64_t(cell_shift.size()) != out_grid.size())
        return error(StatusCode::invalid_argument, "the labelling has " + std::to_string(cell_shift.size()) +
                                                       " entries but the output grid has " +
                                                       std::to_string(out_grid.size()) + " cells");
      if (cache.mesh() == &out)
        return error(StatusCode::invalid_argument, "the output mesh must not be the input mesh");
      run(cache, out_grid, cell_shift, out, report);
      report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      return {};
    });
  }

  /// Prepares and stitches in one call (the policy contract). `report.ms` includes the preparation.
  template <class = void>
  Status stitch(const Mesh& in, const Lattice& lattice, const Eigen::Array3i& out_cells,
                const std::vector<Eigen::Array3i>& cell_shift, Mesh& out, StitchReport& report) const {
    return detail::guarded("ClipStitcher::stitch", [&]() -> Status {
      const auto t0 = std::chrono::steady_clock::now();
      report = StitchReport();
      if (&in == &out) return error(StatusCode::invalid_argument, "the output mesh must not be the input mesh");
      cache_type cache;
      RESTITCH_TRY(prepare(in, lattice, cache));
      RESTITCH_TRY(stitch(cache, out_cells, cell_shift, out, report));
      report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      return {};
    });
  }

 private:
  // One stitch of a checked labelling: regions, then each region's source
  // triangles in face order (copied or clipped), then welding and assembly.
  template <class = void>
  void run(const cache_type& cache, const CellGrid& out_grid, const std::vector<Eigen::Array3i>& cell_shift,
           Mesh& out, StitchReport& report) const {
    const Mesh& in = *cache.mesh();
    const Lattice& lat = cache.lattice();
    const detail::StitchRegions regions = detail::build_regions(lat, out_grid, cell_shift);
    report.regions = regions.size();
    const detail::VertexLayout layout(in);
    detail::StitchOutput output(in, layout, regions.translation);
    const double growth = std::min(std::max(1.0, double(cell_shift.size()) / double(lat.cells.prod())), 8.0);
    output.reserve(std::size_t(double(in.triangle_count()) * growth) + 22,
                   std::size_t(double(in.vertex_count()) * growth) + 64);
    detail::RegionClipper clipper(in, cache, layout, out_grid, regions, output);
    std::vector<std::int32_t> stamp(in.triangle_count(), -1);  // per input triangle: the last region that gathered it
    std::vector<std::uint32_t> gathered;
    std::size_t cap = 0;
    for (std::int32_t r = 0; r < std::int32_t(regions.size()); ++r) {
      const detail::Region region(regions, r, out_grid, lat.cells);
      gather_triangles(cache, out_grid, regions, region, stamp, gathered);
      for (std::uint32_t t : gathered) {
        if (clipper.add_triangle(region, t))
          ++report.triangles_clipped;
        else
          ++report.triangles_copied;
      }
      for (; cap < regions.caps.size() && regions.caps[cap].owner == r; ++cap) {  // its end caps
        const detail::Region end(regions, cap, out_grid, lat.cells);
        gather_triangles(cache, out_grid, regions, end, stamp, gathered);
        const bool at_cell_plane = !regions.caps[cap].cuts_owner;  // the outer cell plane: only overhangs
        for (std::uint32_t t : gathered)
          if (!at_cell_plane || (cache.overhang(t) & end.cap_flag())) {
            clipper.add_triangle(end, t);
            ++report.triangles_clipped;
          }
      }
    }
    report.end_caps = regions.caps.size();
    double tol = cache.tolerance();
    std::vector<std::uint32_t> snap_to;
    std::vector<std::uint32_t> rep_of =
        weld ? detail::weld_map(output, in, cache, layout, float(attribute_tolerance), report.seam_vertices_welded,
                                snap_to, report.seam_vertices_snapped, &tol)
             : detail::identity_map(output.vertex_count());
    if (weld) output.snap_positions(std::move(snap_to));
    if (weld && repair_t_junctions)
      report.t_junction_edges_split =
          detail::repair_t_junctions(output, in, cache, layout, float(attribute_tolerance), tol, rep_of);
    if (weld && zip_seams)
      report.zip_triangles = detail::zip_seams(output, cache, detail::zip_gap_of_diagonal * cache.diagonal(), rep_of);
    output.assemble(rep_of, out);
  }

  // The triangles of a region's source cells, once each, in ascending face order.
  template <class = void>
  static void gather_triangles(const cache_type& cache, const CellGrid& out_grid,
                               const detail::StitchRegions& regions, const detail::Region& region,
                               std::vector<std::int32_t>& stamp, std::vector<std::uint32_t>& gathered) {
    const CellGrid in_grid(cache.lattice().cells);
    gathered.clear();
    std::uint32_t tmin = std::numeric_limits<std::uint32_t>::max(), tmax = 0;
    const std::size_t owner = std::size_t(region.owner);
    for (std::uint32_t q = regions.start[owner]; q < regions.start[owner + 1]; ++q) {
      const Eigen::Array3i x = out_grid.cell(regions.cells[q]);
      if (region.cap_axis >= 0 && x(region.cap_axis) != region.cap_face) continue;
      const int s = in_grid.index(x - region.d);
      for (const std::uint32_t* t = cache.bucket_begin(s); t != cache.bucket_end(s); ++t) {
        if (stamp[*t] == region.id) continue;
        stamp[*t] = region.id;
        gathered.push_back(*t);
        tmin = std::min(tmin, *t);
        tmax = std::max(tmax, *t);
      }
    }
    if (gathered.empty()) return;
    // Dense ranges are listed by a scan of the stamps, sparse ones sorted.
    if (double(gathered.size()) * 16.0 >= double(tmax - tmin) + 1.0) {
      gathered.clear();
      for (std::uint32_t t = tmin; t <= tmax; ++t)
        if (stamp[t] == region.id) gathered.push_back(t);
    } else {
      std::sort(gathered.begin(), gathered.end());
    }
  }
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
    T, std::void_t<typename T::cache_type,
                   decltype(std::declval<const T&>().prepare(std::declval<const Mesh&>(), std::declval<const Lattice&>(),
                                                             std::declval<typename T::cache_type&>())),
                   decltype(std::declval<const T&>().stitch(
                       std::declval<const typename T::cache_type&>(), std::declval<const Eigen::Array3i&>(),
                       std::declval<const std::vector<Eigen::Array3i>&>(), std::declval<Mesh&>(),
                       std::declval<StitchReport&>()))>> : std::true_type {};
}  // namespace detail

/// True when T satisfies the stitcher policy contract (see the file comment).
template <class T>
inline constexpr bool is_stitcher_policy_v = detail::is_stitcher_policy<T>::value;

/// True when T also names a `cache_type` and offers prepare(in, lattice, cache) + stitch(cache, ...).
template <class T>
inline constexpr bool has_prepared_stitch_v = detail::has_prepared_stitch<T>::value;

static_assert(is_stitcher_policy_v<ClipStitcher>, "ClipStitcher must satisfy the stitcher policy contract");
static_assert(has_prepared_stitch_v<ClipStitcher>, "ClipStitcher must offer the prepared stitch");

}  // namespace restitch
