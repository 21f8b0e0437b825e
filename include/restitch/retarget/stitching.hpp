// restitch/retarget/stitching.hpp - the stitch stage of a resize: the stitcher, its caches and its weld tolerance (docs/method.md 3).
//
// `StitchStage<Stitcher>` holds the stitcher policy with what it prepares once per (mesh, grid): its
// cache (when it offers the prepared stitch), the same K times finer per set of moved axes (seams off
// the cell planes, 2.9), and the weld tolerance as set or measured from the copies (3, "Measured weld
// tolerance"). `stitch` turns a labelling into a mesh.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <map>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/offsets/snap.hpp"
#include "restitch/retarget/request.hpp"
#include "restitch/retarget/seams.hpp"
#include "restitch/stitch/stitch.hpp"

namespace restitch {

namespace detail {
/// The stitcher's `cache_type` when it offers the prepared stitch, else an empty placeholder.
template <class S, bool = has_prepared_stitch_v<S>>
struct stitch_cache {
  struct type {};
};
template <class S>
struct stitch_cache<S, true> {
  using type = typename S::cache_type;
};
template <class S>
using stitch_cache_t = typename stitch_cache<S>::type;

template <class S, class = void>
struct has_weld_tolerance : std::false_type {};
template <class S>
struct has_weld_tolerance<S, std::void_t<decltype(std::declval<S&>().weld_tolerance = 1.0)>> : std::true_type {};
template <class S>
inline constexpr bool has_weld_tolerance_v = has_weld_tolerance<S>::value;
}  // namespace detail

template <class Stitcher>
class StitchStage {
 public:
  explicit StitchStage(Stitcher stitcher = {}) : stitcher_(std::move(stitcher)) {}

  /// RetargetOptions::weld_tolerance onto the stitcher: 0 keeps the stitcher's own; outside [0, 1e-2], or
  /// non-zero for a stitcher without one, is invalid_argument.
  template <class = void>
  Status set_weld_tolerance(double w) {
    if (!(w >= 0 && w <= 1e-2))
      return error(StatusCode::invalid_argument, "the weld tolerance " + detail::format_size(w) +
                                                     " is outside [0, 0.01] (a fraction of the bounding-box diagonal)");
    if (w == 0) return {};
    if constexpr (detail::has_weld_tolerance_v<Stitcher>) {
      stitcher_.weld_tolerance = w;
      return {};
    } else {
      return error(StatusCode::invalid_argument, "this stitcher has no weld tolerance to set");
    }
  }

  /// RetargetOptions::measure_weld_tolerance: the stitcher's tolerance raised to the precision at which the
  /// copies' vertices repeat along the principal offsets.
  template <class = void>
  void measure_weld_tolerance(const Mesh& mesh, const Analysis& analysis) {
    if constexpr (detail::has_weld_tolerance_v<Stitcher>) {
      const std::vector<Eigen::Vector3d> offsets = analysis.principal_model_units();
      if (offsets.empty()) return;
      // The vertices the faces use (one that no face uses is not geometry), in index order; a position
      // shared by several vertices (split normals or UVs) counts once per vertex, in every rung alike.
      std::vector<char> used(std::size_t(mesh.V.rows()), 0);
      for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
        for (int c = 0; c < 3; ++c) used[std::size_t(mesh.F(f, c))] = 1;
      Eigen::Matrix<double, Eigen::Dynamic, 3> points(Eigen::Index(std::count(used.begin(), used.end(), 1)), 3);
      Eigen::Index row = 0;
      for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
        if (used[std::size_t(v)]) points.row(row++) = mesh.V.row(v).template cast<double>();
      const double base = stitcher_.weld_tolerance;
      const RepeatPrecision p = repeat_precision(points, offsets, bounding_box(mesh).size().norm(), base);
      if (p.tolerance > base) stitcher_.weld_tolerance = p.tolerance, weld_measured_ = true;
    }
  }

  /// The stitcher's weld tolerance as it stands (0 for a stitcher without one), and whether it was measured.
  double weld_tolerance() const {
    if constexpr (detail::has_weld_tolerance_v<Stitcher>) return stitcher_.weld_tolerance;
    return 0;
  }
  bool weld_measured() const { return weld_measured_; }

  /// Prepares the stitch of `mesh` on `grid` (both must outlive this object unchanged).
  template <class = void>
  Status prepare(const Mesh& mesh, const Lattice& grid) {
    mesh_ = &mesh;
    grid_ = grid;
    if constexpr (has_prepared_stitch_v<Stitcher>) RESTITCH_TRY(stitcher_.prepare(mesh, grid_, cache_));
    return {};
  }

  /// Stitches the output cells `cells_out` with label shifts `shift` (linear cell order) into `out`. With
  /// moved planes, on the grid K times finer along the moved axes; where that grid is past the stitcher's
  /// limits (too_large) the planes are reset and the seams stay on the cell planes.
  template <class = void>
  Status stitch(const Eigen::Array3i& cells_out, const std::vector<Eigen::Array3i>& shift, MovedPlanes& planes,
                Mesh& out, StitchReport& st) {
    if (planes.any()) {
      const Status moved = stitch_moved(cells_out, shift, planes, out, st);
      if (moved.code() == StatusCode::too_large) {  // the finer grid is past the stitcher's limits: seams stay
        planes = MovedPlanes();
        out = Mesh();
        st = StitchReport();
      } else {
        RESTITCH_TRY(moved);
      }
    }
    if (!planes.any()) {
      if constexpr (has_prepared_stitch_v<Stitcher>) {
        RESTITCH_TRY(stitcher_.stitch(cache_, cells_out, shift, out, st));
      } else {
        RESTITCH_TRY(stitcher_.stitch(*mesh_, grid_, cells_out, shift, out, st));
      }
    }
    return {};
  }

  /// Stitches `mesh` (any mesh, not the prepared one) on `lattice` with the stitcher's plain call and its
  /// weld tolerance: a centred part moved alone (restitch/retarget/centring.hpp).
  template <class = void>
  Status stitch_mesh(const Mesh& mesh, const Lattice& lattice, const Eigen::Array3i& cells_out,
                     const std::vector<Eigen::Array3i>& shift, Mesh& out, StitchReport& st) const {
    return stitcher_.stitch(mesh, lattice, cells_out, shift, out, st);
  }

 private:
  // Stitches a labelling whose planes moved: on the grid K times finer along the moved axes (each
  // K-th of a cell takes the label of the output cell it now lies in, shifts scaled by K), so the
  // stitcher cuts at the moved planes. Its prepared cache is built once per set of moved axes. A grid
  // past the stitcher's limits (too_large) makes the caller stitch on the cell planes instead.
  template <class = void>
  Status stitch_moved(const Eigen::Array3i& cells_out, const std::vector<Eigen::Array3i>& shift,
                      const MovedPlanes& planes, Mesh& mesh, StitchReport& st) {
    Eigen::Array3i f = Eigen::Array3i::Ones();
    int mask = 0;
    for (int a = 0; a < 3; ++a)
      if (planes.moved(a)) f[a] = planes.K, mask |= 1 << a;
    Lattice fine = grid_;
    for (int a = 0; a < 3; ++a)
      if (f[a] > 1) {
        fine.A.col(a) /= f[a];
        fine.cells[a] *= f[a];
        fine.end_low[a] = 0, fine.end_high[a] = 1;  // no end caps here (move_seams)
      }
    const CellGrid out(cells_out), parts(cells_out * f);
    std::vector<Eigen::Array3i> fine_shift(std::size_t(parts.size()));
    for (std::int64_t q = 0; q < parts.size(); ++q) {
      const Eigen::Array3i c = parts.cell(q);
      Eigen::Array3i x;
      for (int a = 0; a < 3; ++a) x[a] = f[a] > 1 ? planes.cell_of_part(a, c[a], cells_out[a]) : c[a];
      fine_shift[std::size_t(q)] = shift[std::size_t(out.index(x))] * f;
    }
    if constexpr (has_prepared_stitch_v<Stitcher>) {
      auto it = fine_caches_.find(mask);
      if (it == fine_caches_.end()) {
        detail::stitch_cache_t<Stitcher> cache;
        RESTITCH_TRY(stitcher_.prepare(*mesh_, fine, cache));
        it = fine_caches_.emplace(mask, std::move(cache)).first;
      }
      return stitcher_.stitch(it->second, parts.dims, fine_shift, mesh, st);
    } else {
      return stitcher_.stitch(*mesh_, fine, parts.dims, fine_shift, mesh, st);
    }
  }

  Stitcher stitcher_;
  const Mesh* mesh_ = nullptr;
  Lattice grid_;
  detail::stitch_cache_t<Stitcher> cache_;  // the stitcher's prepared cache, when it has one
  std::map<int, detail::stitch_cache_t<Stitcher>> fine_caches_;  // the same K times finer, per mask of moved axes
  bool weld_measured_ = false;  // measure_weld_tolerance raised the stitcher's
};

}  // namespace restitch
