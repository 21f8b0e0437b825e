// restitch/retarget.hpp - resize a model along its repeats (docs/method.md sections 2 and 3).
//
//   Result<Analysis> a = restitch::analyze(mesh);
//   restitch::Retargeter<> r(mesh, *a);          // once per (mesh, analysis)
//   Result<RetargetResult> out = r.retarget({2, 0, 0});  // as often as you like
//
// A request is integer steps along the principal offsets (negative shrinks;
// dummy directions must stay 0), or a target bounding-box size turned into
// the nearest steps by `steps_for_size`. One call builds the labelling
// problem (restitch/energy/seam_energy.hpp), solves it with the solver
// policy (alpha-expansion over Boykov-Kolmogorov max-flow by default),
// and stitches the labelled cells into a triangle mesh (stitcher policy).
// Steps of zero return the input geometry unchanged (a copy of the mesh).
//
// Placement (restitch/placement.hpp, docs/method.md 2.7): the result is
// translated by whole periods so that the pivot of each world axis stays put
// (RetargetOptions::pivot, default the model's origin; `set_pivot` changes it
// between requests). The report says which pivot point and translation were
// used. `retarget_to_size` asks for a bounding-box size instead of steps: the
// nearest whole repeats, and with `exact` a scale along each asked axis about
// the pivot that brings the box to the size exactly (factors reported).
//
// Reuse: a Retargeter keeps everything that does not depend on the size:
// the label grid, the features grouped by cell with every cell-set distance
// computed so far, and the stitcher's prepared cache. That is what the live
// slider of the web demo calls. It refers to `mesh` and `analysis`, which
// must outlive it unchanged.
//
// Policies (each contract checked with a readable static_assert here):
//   LabelSpace  restitch/lattice/label_space.hpp (LatticeLabels, RegularLabels)
//   Solver      restitch/solver/mrf.hpp's graph-solver contract (AlphaExpansion<MaxFlow>)
//   Stitcher    restitch/stitch/stitch.hpp (ClipStitcher)
//
// Limits: a request whose nodes x labels exceed `max_problem_size` is refused
// with StatusCode::too_large and a message naming the option.
// Cost: O(nodes x labels x neighbours) per request for the tables, then the
// solver's cycles, then the stitch (linear in output triangles).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/detail/instantiation.hpp"
#include "restitch/energy/seam_energy.hpp"
#include "restitch/lattice/label_space.hpp"
#include "restitch/mesh_boundary.hpp"
#include "restitch/offsets/snap.hpp"
#include "restitch/placement.hpp"
#include "restitch/solver/alpha_expansion.hpp"
#include "restitch/stitch/stitch.hpp"

namespace restitch {

struct RetargetOptions {
  Neighbourhood neighbourhood = Neighbourhood::n26;   ///< the paper's; n6 as an option
  SetDistance set_distance = SetDistance::hausdorff;  ///< the paper's; mean_nearest as an option
  /// The pairwise term solved (docs/method.md 2.4, 2.4b): the paper's descriptor sets of whole cells
  /// (default) or the geometry at the seam. The seams are measured on the geometry either way.
  /// Descriptor is the default because it was measured better on the real models (README, Seam energy):
  /// the geometric energy's first request of a new size costs more (up to 149 ms on the shared models in
  /// session 15, against 24 ms) and it shrinks some wrongly.
  SeamEnergy seam_energy = SeamEnergy::descriptor;
  /// A seam whose mismatch (model units) exceeds this is reported in RetargetReport::warnings.
  /// 0 (default): 3 x the sample spacing (CellSlabs::spacing), see docs/method.md 2.8.
  double seam_tolerance = 0;
  /// Refuse requests whose nodes x labels exceed this (memory and time grow with it).
  std::size_t max_problem_size = 2'000'000;
  /// Also report, for every output face, the index of the label of the cell it lies in (for display).
  bool face_labels = false;
  /// What stays put along each world axis x, y, z (restitch/placement.hpp): by default the model's origin.
  Pivots pivot{{Pivot::origin, Pivot::origin, Pivot::origin}};
  /// Count the boundary edges of the input (once, when the Retargeter is built) and of every output into
  /// the report (restitch/mesh_boundary.hpp). Off by default: counting the output costs O(#V + #F) with a
  /// hash look-up per vertex, several times the stitch itself (bench: 57 ms at 28k triangles on the
  /// loaded 2-core machine, against a 2 ms stitch), too slow for a live slider. The CLI turns it on.
  bool boundary_edges = false;
  /// Let a seam leave its cell plane (docs/method.md 2.9): after the labels are solved, each plane between
  /// output cells where copies meet moves, within half a cell, to where the two copies continue each other
  /// (when they do not at the cell plane), so a part longer than the cut's neighbourhood is not cut when
  /// an uncut position exists. Off: every seam on a cell plane, as in the paper.
  bool move_seams = true;
  /// Weld tolerance of the stitcher, relative to the input's bounding-box diagonal: seam vertices this
  /// close are merged and T-junctions this close split (restitch/stitch/stitch.hpp). 0 (default): the
  /// stitcher's own (ClipStitcher: 1e-6, exact copies only), raised to the copies' measured precision
  /// when measure_weld_tolerance is on. Real models' copies often differ by 1e-6 to 1e-4 of the diagonal,
  /// so their seams stay open at 1e-6 (README, Known limits); a larger value closes them and also snaps
  /// and drops slivers at that scale. Set on a stitcher with a `weld_tolerance` member; refused
  /// (invalid_argument) outside [0, 1e-2] or for a stitcher without one.
  double weld_tolerance = 0;
  /// With weld_tolerance 0: measure how closely the copies' vertices coincide along the principal
  /// offsets when the Retargeter is built (repeat_precision, restitch/offsets/snap.hpp; docs/method.md 3,
  /// "Measured weld tolerance"), and weld at that precision where it is coarser than the stitcher's own
  /// tolerance (at most 64 times it). Exact copies, and copies whose vertices do not pair, keep the
  /// stitcher's own.
  bool measure_weld_tolerance = true;
  /// Threads that propose the solver's expansion moves, set on a solver with a `threads` member
  /// (AlphaExpansion::threads; the result is bit-identical whatever the count): 1 (default) the calling
  /// thread, 0 every hardware thread; refused (invalid_argument) outside [0, 1024]. Used where the seam
  /// energy's terms are computed up front (the descriptor energy) and the problem is large enough.
  int threads = 1;
};

/// One seam of an output: two neighbouring output cells (sharing a face) with different labels, or an
/// output cell on a resized end whose label differs from its anchor (cell_b is then the virtual cell
/// just outside the output grid, label_b the anchor; docs/method.md 2.3).
struct SeamReport {
  Eigen::Array3i cell_a = Eigen::Array3i::Zero(), cell_b = Eigen::Array3i::Zero();    ///< output cells
  Eigen::Array3i label_a = Eigen::Array3i::Zero(), label_b = Eigen::Array3i::Zero();  ///< their shifts d
  double mismatch = 0;  ///< model units: min of the slab mismatches on either side (docs/method.md 2.8)
  bool outer = false;   ///< cell_b lies outside the output (an anchored end)
  double offset = 0;    ///< inner seams: where the cut lies, in cells from the face of cell_a toward cell_b (2.9)
};

struct RetargetReport {
  Eigen::Array3i steps = Eigen::Array3i::Zero();       ///< as requested, per lattice axis (dummies included; see lattice_steps_from_principal)
  Eigen::Array3i grid_steps = Eigen::Array3i::Zero();  ///< cells added per axis of the label grid
  Eigen::Array3i cells_in = Eigen::Array3i::Ones(), cells_out = Eigen::Array3i::Ones();
  int nodes = 0, labels = 0, edges = 0, cycles = 0;
  double energy = 0;
  bool non_metric = false;
  std::size_t triangles_in = 0, triangles_out = 0, vertices_out = 0, regions = 0;
  /// Boundary (open) edges of the input and of the output: positions welded over the whole mesh at the
  /// default weld tolerance (1e-6 of the bounding-box diagonal), attributes ignored, edges used by exactly
  /// one face (restitch/mesh_boundary.hpp). A closed input with exact repeats should give 0 out. Counted
  /// only with RetargetOptions::boundary_edges (then boundary_edges_counted is true; else both are 0).
  bool boundary_edges_counted = false;
  std::size_t boundary_edges_in = 0, boundary_edges_out = 0;
  /// The stitcher's weld tolerance as used, relative to the input's diagonal (0 for a stitcher without
  /// one), and whether it was measured from the copies (RetargetOptions::measure_weld_tolerance) rather
  /// than the stitcher's own or the one asked for.
  double weld_tolerance = 0;
  bool weld_tolerance_measured = false;
  Eigen::Vector3d size_in = Eigen::Vector3d::Zero(),
                  size_out = Eigen::Vector3d::Zero();  ///< bounding boxes, model units
  std::map<std::string, double> timings_ms;            ///< energy, solve, stitch, boundary (when counted), total (informative only)
  Placement placement;  ///< the pivot modes and point, and the translation applied (restitch/placement.hpp)
  /// retarget_to_size with exact: the scale applied per world axis about placement.pivot (1 = none), and
  /// the size of the nearest whole-repeat result before it.
  bool exact = false;
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  Eigen::Vector3d size_nearest = Eigen::Vector3d::Zero();
  /// The pairwise term solved, and every seam of the output measured on the geometry (model units).
  SeamEnergy seam_energy = SeamEnergy::descriptor;
  std::vector<SeamReport> seams;
  double max_seam_mismatch = 0;
  double seam_tolerance = 0;  ///< as used (RetargetOptions::seam_tolerance, or its default)
  double sample_spacing = 0;  ///< model units (CellSlabs::spacing)
  /// Seams over the tolerance, one sentence each ("seam between cells ... mismatches by ..."); empty when fine.
  std::vector<std::string> warnings;
  /// Where the planes between output cells lie (docs/method.md 2.9): plane_offsets[a][i], i = 0 ..
  /// cells_out[a], in cells from cell plane i along lattice axis a (0: on it; within +-1/2). Empty when
  /// no plane moved; seams_moved counts the planes that did.
  std::array<std::vector<double>, 3> plane_offsets;
  int seams_moved = 0;

  /// The plane between output cells i - 1 and i along lattice axis a as it lies (canonical units of the
  /// output grid: i plus its offset).
  template <class = void>
  double plane(int a, int i) const {
    const std::vector<double>& o = plane_offsets[std::size_t(a)];
    return double(i) + (o.empty() ? 0.0 : o[std::size_t(i)]);
  }
  /// The output cell holding canonical point t of the output grid (clamped into it), with the planes as
  /// they lie.
  template <class = void>
  Eigen::Array3i cell_of(const Eigen::Vector3d& t) const {
    Eigen::Array3i x;
    for (int a = 0; a < 3; ++a) {
      int i = std::clamp(int(std::floor(t[a])), 0, cells_out[a] - 1);
      if (i + 1 < cells_out[a] && t[a] >= plane(a, i + 1)) ++i;  // offsets lie within half a cell
      else if (i > 0 && t[a] < plane(a, i)) --i;
      x[a] = i;
    }
    return x;
  }
};

struct RetargetResult {
  Mesh mesh;
  RetargetReport report;
  Lattice grid;                        ///< the grid the labels live on, as placed in the output (model units)
  std::vector<Eigen::Array3i> labels;  ///< the label shifts, by label index
  std::vector<int> cell_labels;        ///< label index per output cell (linear order)
  std::vector<int> face_labels;        ///< label index per output face (when requested)
};

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
}  // namespace detail

namespace detail {
/// The planes between output cells as they lie after seams moved (docs/method.md 2.9): plane i along
/// axis a at i + j[a][i] / K, |j| < K / 2 (so a cell keeps at least 2 / K of its width), j[a] empty when
/// no plane of axis a moved.
struct MovedPlanes {
  static constexpr int K = 16;
  std::array<std::vector<int>, 3> j;

  bool moved(int a) const { return !j[std::size_t(a)].empty(); }
  bool any() const { return moved(0) || moved(1) || moved(2); }
  /// The same for the s-th K-th of a cell (s = 0 .. K cells - 1) along a moved axis.
  template <class = void>
  int cell_of_part(int a, int s, int cells) const {
    const std::vector<int>& J = j[std::size_t(a)];
    const int i = s / K;
    if (i + 1 < cells && s >= (i + 1) * K + J[std::size_t(i + 1)]) return i + 1;
    if (i > 0 && s < i * K + J[std::size_t(i)]) return i - 1;
    return i;
  }
};

template <class = void>
std::string format_size(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}
}  // namespace detail

/// ok when every component of a target size is finite and >= 0 (0 keeps an axis); else an
/// invalid_argument naming the first axis that is not.
template <class = void>
Status check_size_values(const Eigen::Vector3d& target) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(target[i]) || target[i] < 0) {
      const std::string axis(1, "xyz"[i]);
      return error(StatusCode::invalid_argument, "the size asked along " + axis + " (" +
                                                     detail::format_size(target[i]) +
                                                     ") is not a positive number; give 0 to keep " + axis);
    }
  return {};
}

/// Per world axis: does `target` (0 keeps an axis) ask a model of bounding-box size `size` to change
/// along it? Within 1e-5 of the current size (relative, at least 1e-8 of the box diagonal) is no change,
/// so a size typed from a printed one is no change.
template <class = void>
std::array<bool, 3> size_changes(const Eigen::Vector3d& target, const Eigen::Vector3d& size) {
  std::array<bool, 3> out{{false, false, false}};
  for (int i = 0; i < 3; ++i)
    out[std::size_t(i)] =
        target[i] != 0 && !(std::abs(target[i] - size[i]) <= 1e-5 * std::max(size[i], 1e-3 * size.norm()));
  return out;
}

namespace detail {
template <class S, class = void>
struct has_weld_tolerance : std::false_type {};
template <class S>
struct has_weld_tolerance<S, std::void_t<decltype(std::declval<S&>().weld_tolerance = 1.0)>> : std::true_type {};
template <class S>
inline constexpr bool has_weld_tolerance_v = has_weld_tolerance<S>::value;
}  // namespace detail

template <class LabelSpace = LatticeLabels, class Solver = AlphaExpansion<>, class Stitcher = ClipStitcher>
class Retargeter {
  static_assert(is_label_space_v<LabelSpace>,
                "restitch::Retargeter: the label space must provide `name`, `Status grid(const Mesh&, const Analysis&, "
                "Lattice&) const` and `Status grid_steps(const Analysis&, const Lattice&, const Eigen::Array3i&, "
                "Eigen::Array3i&) const` (see restitch/lattice/label_space.hpp)");
  static_assert(is_graph_solver_v<Solver, SeamMrf>,
                "restitch::Retargeter: the solver must provide `template <class P> Status solve(const P&, "
                "std::vector<int>&, SolveReport&, const Progress&) const` (see restitch/solver/mrf.hpp)");
  static_assert(is_stitcher_policy_v<Stitcher>,
                "restitch::Retargeter: the stitcher must provide `Status stitch(const Mesh&, const Lattice&, const "
                "Eigen::Array3i&, const std::vector<Eigen::Array3i>&, Mesh&, StitchReport&) const` "
                "(see restitch/stitch/stitch.hpp)");

 public:
  Retargeter(const Mesh& mesh, const Analysis& analysis, RetargetOptions options = {}, LabelSpace labels = {},
             Solver solver = {}, Stitcher stitcher = {});

  /// ok when the grid and caches were built; otherwise why not.
  const Status& status() const { return status_; }
  const Lattice& grid() const { return grid_; }
  static constexpr const char* label_space_name() { return LabelSpace::name; }
  /// The pivots of the following requests (RetargetOptions::pivot); nothing cached depends on them.
  void set_pivot(const Pivots& pivot) { options_.pivot = pivot; }
  const RetargetOptions& options() const { return options_; }

  /// Resizes by `steps` along the principal offsets (see the header comment).
  Result<RetargetResult> retarget(const Eigen::Array3i& steps, const Progress& progress = {});

  /// The labelling problem a request solves (for --dump-mrf and benchmarks).
  Result<SeamMrf> labelling_problem(const Eigen::Array3i& steps);

  /// The geometric seam measure this Retargeter reports with (and solves with, by default).
  CellSlabs& slabs() { return *slabs_; }

  /// The steps whose result's bounding box is nearest to `target` (model
  /// units; a component of 0 keeps that axis). Searches every achievable step
  /// count along each principal offset (at most `max_steps` added). Refused
  /// (invalid_argument, naming the axis): a negative or non-finite component,
  /// and a size change along a world axis no principal offset runs along
  /// (world_axis_of). A component equal to the current size (within 1e-5 of
  /// it, relative) is no change.
  Result<Eigen::Array3i> steps_for_size(const Eigen::Vector3d& target, int max_steps = 64) const;

  /// Resizes to the bounding-box size `target` (model units, 0 keeps an axis): the nearest whole repeats
  /// (steps_for_size), placed about the pivot. With `exact`, the result is then scaled along every world
  /// axis asked for (component > 0) about the pivot point, by target / size, so its box is `target`
  /// exactly (to float rounding); the report gives the factors and the size before scaling.
  Result<RetargetResult> retarget_to_size(const Eigen::Vector3d& target, bool exact, const Progress& progress = {});

  /// ok, or why `target` cannot be asked for (see steps_for_size).
  Status check_size(const Eigen::Vector3d& target) const;

 private:
  // Checks a request and fills the size-independent part of the report.
  Status plan(const Eigen::Array3i& steps, RetargetReport& rep) const {
    rep.steps = steps;
    rep.cells_in = grid_.cells;
    rep.triangles_in = mesh_->triangle_count();
    rep.boundary_edges_counted = options_.boundary_edges;
    rep.boundary_edges_in = boundary_edges_in_;
    if constexpr (detail::has_weld_tolerance_v<Stitcher>) rep.weld_tolerance = stitcher_.weld_tolerance;
    rep.weld_tolerance_measured = weld_measured_;
    rep.size_in = size_in_;
    if ((steps != 0).any() && analysis_->principal.empty())
      return error(StatusCode::no_repetition,
                   "no repetition was found in this model, so there is nothing to resize along");
    RESTITCH_TRY(space_.grid_steps(*analysis_, grid_, steps, rep.grid_steps));
    const Eigen::Array3i k = rep.grid_steps;
    for (int a = 0; a < 3; ++a)
      if (grid_.cells[a] + k[a] < 1)
        return error(StatusCode::invalid_argument, "cannot shrink axis " + std::to_string(a + 1) + " by " +
                                                       std::to_string(-steps[a]) + " steps: the model has " +
                                                       std::to_string(grid_.cells[a]) + " cells along it (at most " +
                                                       std::to_string(grid_.cells[a] - 1) + " steps can be removed)");
    // Down to one cell: its two ends must fit in it. The first cell's own end reaches to end_low and the
    // last cell's starts at end_high (Lattice, lattice/fit.hpp); when they overlap, one cell would cut one
    // of them (a garage door whose jambs each take most of a cell).
    for (int a = 0; a < 3; ++a)
      if (k[a] != 0 && grid_.cells[a] + k[a] == 1 && grid_.end_low[a] > grid_.end_high[a])
        return error(StatusCode::invalid_argument,
                     "cannot shrink axis " + std::to_string(a + 1) + " to one cell: the model's two ends take more " +
                         "than one cell along it and would be cut (at most " + std::to_string(grid_.cells[a] - 2) +
                         " steps can be removed)");
    rep.cells_out = grid_.cells + k;
    const double nodes = double(rep.cells_out.prod());
    const double labels = double((k.abs() + 1).prod());
    if (nodes * labels > double(options_.max_problem_size))
      return error(StatusCode::too_large,
                   "this request needs " + std::to_string(std::int64_t(nodes)) + " nodes x " +
                       std::to_string(std::int64_t(labels)) + " labels, more than the limit of " +
                       std::to_string(options_.max_problem_size) +
                       " (RetargetOptions::max_problem_size; --max-problem on the command line): ask for fewer steps "
                       "or raise the limit");
    return {};
  }

  // The second start's dynamic programme is skipped above this many pairwise terms (about 10 ms here;
  // docs/method.md 2.5): a cost limit, so large step counts keep the slider's pace.
  static constexpr double separable_budget = double(1 << 20);

  SeamMrf make_problem(const Eigen::Array3i& k) {
    SeamMrf problem = options_.seam_energy == SeamEnergy::geometry ? SeamMrf(*slabs_, k, options_.neighbourhood)
                                                                   : SeamMrf(*cells_, k, options_.neighbourhood);
    problem.penalise_inner_ends(grid_.end_low, grid_.end_high);
    return problem;
  }

  // RetargetOptions::weld_tolerance onto the stitcher.
  Status set_weld_tolerance() {
    const double w = options_.weld_tolerance;
    if (!(w >= 0 && w <= 1e-2))
      return error(StatusCode::invalid_argument, "the weld tolerance " + format_size(w) +
                                                     " is outside [0, 0.01] (a fraction of the bounding-box diagonal)");
    if (w == 0) return {};
    if constexpr (detail::has_weld_tolerance_v<Stitcher>) {
      stitcher_.weld_tolerance = w;
      return {};
    } else {
      return error(StatusCode::invalid_argument, "this stitcher has no weld tolerance to set");
    }
  }

  // RetargetOptions::measure_weld_tolerance: the stitcher's tolerance raised to the precision at which the
  // copies' vertices repeat along the principal offsets.
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
        if (used[std::size_t(v)]) points.row(row++) = mesh.V.row(v).cast<double>();
      const double base = stitcher_.weld_tolerance;
      const RepeatPrecision p = repeat_precision(points, offsets, bounding_box(mesh).size().norm(), base);
      if (p.tolerance > base) stitcher_.weld_tolerance = p.tolerance, weld_measured_ = true;
    }
  }

  // Every seam of a labelling, measured on the geometry (docs/method.md 2.8): face neighbours with
  // different labels, and end cells whose label differs from their anchor. The mismatch of a seam
  // between x (label di) and x' = x + e (label dj): the sources x - di and x - dj compared at their
  // plane toward e (CellSlabs::plane_mismatch, either side of it), or x' - di and x' - dj at theirs
  // toward -e when that is smaller (the same plane; it matters where one pair has a cell outside). An end cell x with label d
  // and anchor d' (outer seam, where the stitcher puts an end cap): the cells x - d and x - d' compared
  // on either side of the end plane (Lattice::end_low / end_high; CellSlabs::plane_mismatch).
  void measure_seams(const Eigen::Array3i& k, const Eigen::Array3i& cells_out, const std::vector<Eigen::Array3i>& shift,
                     const detail::MovedPlanes& planes, RetargetReport& rep) {
    const CellGrid out(cells_out);
    rep.seam_energy = options_.seam_energy;
    rep.sample_spacing = slabs_->spacing();
    rep.seam_tolerance = options_.seam_tolerance > 0 ? options_.seam_tolerance : 3 * slabs_->spacing();
    auto measure = [&](const Eigen::Array3i& x, const Eigen::Array3i& y, const Eigen::Array3i& di,
                       const Eigen::Array3i& dj, bool outer) {
      const Eigen::Array3i e = y - x;
      SeamReport seam{x, y, di, dj, 0.0, outer};
      // An end faces nothing in the output, whatever the labels: only its own side counts.
      if (outer) {
        const int a = e[0] != 0 ? 0 : e[1] != 0 ? 1 : 2;  // an end differs from its anchor along one axis
        const double f = e[a] < 0 ? grid_.end_low[a] : grid_.end_high[a];
        seam.mismatch = slabs_->plane_mismatch(x - di, x - dj, a, f);
      } else {  // the plane between x and y, seen from either pair of sources
        const int a = e[0] != 0 ? 0 : e[1] != 0 ? 1 : 2;
        const int j = planes.moved(a) ? planes.j[std::size_t(a)][std::size_t(y[a])] : 0;
        seam.offset = double(j) / planes.K;
        const auto between = [&](const Eigen::Array3i& d1, const Eigen::Array3i& d2, int c, double lo, double hi) {
          if ((d1 == d2).all()) return 0.0;
          if (j == 0)
            return std::min(slabs_->plane_mismatch(x - d1, x - d2, a, 1.0, c, lo, hi),
                            slabs_->plane_mismatch(y - d1, y - d2, a, 0.0, c, lo, hi));
          // the cut lies inside y (j > 0) or inside x (j < 0): that cell's two sources there
          return j > 0 ? slabs_->plane_mismatch(y - d1, y - d2, a, seam.offset, c, lo, hi)
                       : slabs_->plane_mismatch(x - d1, x - d2, a, 1.0 + seam.offset, c, lo, hi);
        };
        // On an output end face along another resized axis c, a label not anchored to that end gets an
        // end cap (restitch/stitch/detail/regions.hpp): beyond the end plane (Lattice end_low / end_high,
        // inside the cell or at its plane) and in the overhang past the cell, the anchored copy holds the
        // face; only between the end planes do the labels' own copies meet. So the seam is measured in
        // parts along c, the end's part between the anchored labels (overhang included), the rest between
        // di and dj (overhang excluded); the largest counts (docs/method.md 2.8). On an output one cell
        // long along c both ends' caps meet in the cell.
        int c = -1;
        bool low = false, high = false;
        for (int b = 0; b < 3 && c < 0; ++b) {
          if (b == a || k[b] == 0) continue;
          low = x[b] == 0;
          high = x[b] == cells_out[b] - 1;
          if ((low && (di[b] != 0 || dj[b] != 0)) || (high && (di[b] != k[b] || dj[b] != k[b]))) c = b;
        }
        if (c < 0) {
          seam.mismatch = between(di, dj, -1, 0.0, 1.0);
        } else {
          const auto anchored = [&](const Eigen::Array3i& d, int anchor) {  // the label a cap copies with
            Eigen::Array3i v = d;
            v[c] = anchor;
            return v;
          };
          double lo = 0.0, hi = 1.0;  // the part of the face the labels' own copies hold, along c
          if (low) {
            lo = grid_.end_low[c];
            seam.mismatch = between(anchored(di, 0), anchored(dj, 0), c, -INFINITY, lo);
          }
          if (high) {
            hi = grid_.end_high[c];
            seam.mismatch = std::max(seam.mismatch, between(anchored(di, k[c]), anchored(dj, k[c]), c, hi, INFINITY));
          }
          if (lo < hi) seam.mismatch = std::max(seam.mismatch, between(di, dj, c, lo, hi));
        }
      }
      rep.max_seam_mismatch = std::max(rep.max_seam_mismatch, seam.mismatch);
      rep.seams.push_back(seam);
    };
    for (std::int64_t xi = 0; xi < out.size(); ++xi) {
      const Eigen::Array3i x = out.cell(xi), di = shift[std::size_t(xi)];
      for (int a = 0; a < 3; ++a) {
        Eigen::Array3i y = x;
        y[a] += 1;
        if (out.inside(y)) {
          const Eigen::Array3i& dj = shift[std::size_t(out.index(y))];
          if ((di != dj).any()) measure(x, y, di, dj, false);
        }
        if (k[a] == 0) continue;
        for (int side = 0; side < 2; ++side) {  // anchored ends
          if (side == 0 ? x[a] != 0 : x[a] != out.dims[a] - 1) continue;
          Eigen::Array3i anchor = di, outside = x;
          anchor[a] = side == 0 ? 0 : k[a];
          outside[a] += side == 0 ? -1 : 1;
          if ((anchor != di).any()) measure(x, outside, di, anchor, true);
        }
      }
    }
    for (const SeamReport& seam : rep.seams)
      if (seam.mismatch > rep.seam_tolerance) rep.warnings.push_back(seam_warning(seam, rep.seam_tolerance));
  }

  static std::string seam_warning(const SeamReport& s, double tolerance) {
    auto cell = [](const Eigen::Array3i& c) {
      return "(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
    };
    return (s.outer ? "seam between cell " + cell(s.cell_a) + " and the end of the model outside it"
                    : "seam between cells " + cell(s.cell_a) + " and " + cell(s.cell_b)) +
           " mismatches by " + format_size(s.mismatch) + " model units (tolerance " + format_size(tolerance) + ")";
  }

  // The label of the output cell each face's centroid lies in (with the planes as they lie).
  std::vector<int> face_labels(const Mesh& m, const RetargetReport& rep, const std::vector<int>& labelling) const {
    const CellGrid out(rep.cells_out);
    std::vector<int> fl(m.triangle_count(), 0);
    const Eigen::Matrix3d Ainv = grid_.A.inverse();
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int corner = 0; corner < 3; ++corner)
        for (int i = 0; i < 3; ++i) c[i] += double(m.V(m.F(f, corner), i)) / 3.0;
      fl[std::size_t(f)] = labelling[std::size_t(out.index(rep.cell_of(Ainv * (c - grid_.origin))))];
    }
    return fl;
  }

  // Where the seams go (docs/method.md 2.9). Per plane i (1 .. cells_out[a] - 1) of each axis a where
  // output cells with different labels meet: the seams across it ask CellSlabs::seam_positions for
  // every position within half a cell; the plane stays on the cell plane when no sample there fails to
  // continue, and otherwise moves to the valid position with the fewest such samples (then the fewest
  // samples cut, then the nearest the cell plane, then the lower), only when that is fewer than on the
  // cell plane. A plane stays put when a cell on either side of it meets a different label along
  // another axis (moving it would change those seams, which were not measured), and every plane stays
  // when an output end is copied from elsewhere (its end cap is cut at the lattice's end plane, in
  // whole cells).
  detail::MovedPlanes move_seams(const Eigen::Array3i& k, const Eigen::Array3i& cells_out,
                                 const std::vector<Eigen::Array3i>& shift) {
    detail::MovedPlanes planes;
    if (!options_.move_seams) return planes;
    const CellGrid out(cells_out);
    const auto label = [&](const Eigen::Array3i& x) -> const Eigen::Array3i& { return shift[std::size_t(out.index(x))]; };
    for (std::int64_t xi = 0; xi < out.size(); ++xi) {  // an end copied from elsewhere: end caps, keep cells
      const Eigen::Array3i x = out.cell(xi);
      for (int a = 0; a < 3; ++a) {
        if (x[a] == 0 && shift[std::size_t(xi)][a] != 0) return planes;
        if (x[a] == out.dims[a] - 1 && shift[std::size_t(xi)][a] != k[a]) return planes;
      }
    }
    constexpr int K = detail::MovedPlanes::K, H = K / 2 - 1;
    for (int a = 0; a < 3; ++a)
      for (int i = 1; i < cells_out[a]; ++i) {
        std::vector<std::int64_t> fail(2 * H + 1, 0), cut(2 * H + 1, 0);
        std::vector<char> valid(2 * H + 1, 1);
        bool seam = false, blocked = false;
        for (std::int64_t xi = 0; xi < out.size() && !blocked; ++xi) {
          const Eigen::Array3i x = out.cell(xi);
          if (x[a] != i - 1) continue;
          Eigen::Array3i y = x;
          y[a] = i;
          for (const Eigen::Array3i& z : {x, y})
            for (int b = 0; b < 3; ++b)
              for (const int step : {-1, 1}) {
                Eigen::Array3i n = z;
                n[b] += step;
                if (b != a && out.inside(n) && (label(n) != label(z)).any()) blocked = true;
              }
          const Eigen::Array3i &di = label(x), &dj = label(y);
          if ((di == dj).all()) continue;
          seam = true;
          const CellSlabs::SeamPositions& p = slabs_->seam_positions(x - di, a, dj - di, K);
          for (std::size_t q = 0; q < valid.size(); ++q) {
            fail[q] += p.fail[q];
            cut[q] += p.cut[q];
            valid[q] = char(valid[q] && p.valid[q]);
          }
        }
        if (!seam || blocked || !valid[H] || fail[H] == 0) continue;
        int best = H;
        const auto key = [&](int q) { return std::make_tuple(fail[std::size_t(q)], cut[std::size_t(q)], std::abs(q - H), q); };
        for (int q = 0; q <= 2 * H; ++q)
          if (valid[std::size_t(q)] && fail[std::size_t(q)] < fail[H] && key(q) < key(best)) best = q;
        if (best == H) continue;
        if (!planes.moved(a)) planes.j[std::size_t(a)].assign(std::size_t(cells_out[a]) + 1, 0);
        planes.j[std::size_t(a)][std::size_t(i)] = best - H;
      }
    return planes;
  }

  // Stitches a labelling whose planes moved: on the grid K times finer along the moved axes (each
  // K-th of a cell takes the label of the output cell it now lies in, shifts scaled by K), so the
  // stitcher cuts at the moved planes. Its prepared cache is built once per set of moved axes. A grid
  // past the stitcher's limits (too_large) makes the caller stitch on the cell planes instead.
  Status stitch_moved(const Eigen::Array3i& cells_out, const std::vector<Eigen::Array3i>& shift,
                      const detail::MovedPlanes& planes, Mesh& mesh, StitchReport& st) {
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

  const Mesh* mesh_;
  const Analysis* analysis_;
  RetargetOptions options_;
  LabelSpace space_;
  Solver solver_;
  Stitcher stitcher_;
  Status status_;
  Lattice grid_;
  std::unique_ptr<CellDescriptors> cells_;
  std::unique_ptr<CellSlabs> slabs_;
  detail::stitch_cache_t<Stitcher> cache_;  // the stitcher's prepared cache, when it has one
  std::map<int, detail::stitch_cache_t<Stitcher>> fine_caches_;  // the same K times finer, per mask of moved axes
  Eigen::Vector3d size_in_ = Eigen::Vector3d::Zero();
  BoundingBox box_in_;
  std::size_t boundary_edges_in_ = 0;
  bool weld_measured_ = false;  // RetargetOptions::measure_weld_tolerance raised the stitcher's

  static std::string format_size(double x) { return detail::format_size(x); }
};

template <class LabelSpace, class Solver, class Stitcher>
Retargeter<LabelSpace, Solver, Stitcher>::Retargeter(const Mesh& mesh, const Analysis& analysis, RetargetOptions options,
                                                     LabelSpace labels, Solver solver, Stitcher stitcher)
    : mesh_(&mesh), analysis_(&analysis), options_(options), space_(labels), solver_(solver), stitcher_(stitcher) {
  status_ = detail::guarded("Retargeter", [&]() -> Status {
    if (options_.threads < 0 || options_.threads > 1024)
      return error(StatusCode::invalid_argument,
                   "threads must be 0 (every hardware thread) to 1024, not " + std::to_string(options_.threads));
    detail::set_policy_threads(solver_, options_.threads, 0);
    RESTITCH_TRY(set_weld_tolerance());
    if (options_.weld_tolerance == 0 && options_.measure_weld_tolerance) measure_weld_tolerance(mesh, analysis);
    RESTITCH_TRY(space_.grid(mesh, analysis, grid_));
    if (std::int64_t(grid_.cells.prod()) > std::int64_t(options_.max_problem_size))
      return error(StatusCode::too_large, "the label grid has " + std::to_string(grid_.cells.prod()) +
                                              " cells, more than max_problem_size (" +
                                              std::to_string(options_.max_problem_size) + ")");
    cells_ = std::make_unique<CellDescriptors>(analysis, grid_, options_.set_distance);
    slabs_ = std::make_unique<CellSlabs>(analysis, grid_);
    if constexpr (has_prepared_stitch_v<Stitcher>) RESTITCH_TRY(stitcher_.prepare(mesh, grid_, cache_));
    box_in_ = bounding_box(mesh);
    size_in_ = box_in_.size();
    if (options_.boundary_edges) boundary_edges_in_ = boundary_edge_count(mesh);
    return {};
  });
}

template <class LabelSpace, class Solver, class Stitcher>
Result<RetargetResult> Retargeter<LabelSpace, Solver, Stitcher>::retarget(const Eigen::Array3i& steps,
                                                                          const Progress& progress) {
  return detail::guarded("retarget", [&]() -> Result<RetargetResult> {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    auto ms_since = [](clock::time_point t) {
      return std::chrono::duration<double, std::milli>(clock::now() - t).count();
    };
    RESTITCH_TRY(status_);
    RetargetResult out;
    RetargetReport& rep = out.report;
    RESTITCH_TRY(plan(steps, rep));
    out.grid = grid_;
    const Eigen::Array3i k = rep.grid_steps;
    const double nodes = double(rep.cells_out.prod());

    if ((k == 0).all()) {  // nothing to do: the input, unchanged
      out.mesh = *mesh_;
      rep.nodes = int(nodes), rep.labels = 1, rep.regions = 1;
      rep.triangles_out = rep.triangles_in;
      rep.vertices_out = out.mesh.vertex_count();
      rep.boundary_edges_out = rep.boundary_edges_in;
      rep.size_out = size_in_;
      rep.placement = place(analysis_->lattice, box_in_, Eigen::Array3i::Zero(), options_.pivot);  // not moved
      rep.size_nearest = size_in_;
      out.labels = {Eigen::Array3i::Zero()};
      out.cell_labels.assign(std::size_t(nodes), 0);
      if (options_.face_labels) out.face_labels.assign(out.mesh.triangle_count(), 0);
      rep.timings_ms["total"] = ms_since(t0);
      return out;
    }

    if (!progress.report("energy", 0.0)) return error(StatusCode::cancelled, "cancelled");
    auto t = clock::now();
    SeamMrf problem = make_problem(k);
    rep.timings_ms["energy"] = ms_since(t);
    rep.nodes = problem.node_count();
    rep.labels = problem.label_count();
    rep.edges = problem.edge_count();

    t = clock::now();
    // Two starts (docs/method.md 2.5): the input stretched, and, where it beats that solve's result, the
    // best labelling with straight seams; the lower energy wins, the first on a tie. Each solve reports
    // half of the progress.
    std::vector<int> labelling = problem.initial_labels();
    SolveReport solve;
    const auto half = [&progress](double base) {
      return Progress([&progress, base](std::string_view stage, double f) {
        return progress.report(stage, base + 0.5 * f);
      });
    };
    RESTITCH_TRY(solver_.solve(problem, labelling, solve, half(0.0)));
    if (problem.separable_terms() > separable_budget) {
      // the second start is skipped on very large requests (its cost; docs/method.md 2.5)
    } else if (std::vector<int> straight = problem.separable_labels(); energy(problem, straight) < solve.energy) {
      SolveReport second;
      RESTITCH_TRY(solver_.solve(problem, straight, second, half(0.5)));
      if (second.energy < solve.energy) labelling.swap(straight), solve = second;
    }
    rep.timings_ms["solve"] = ms_since(t);
    rep.cycles = solve.cycles;
    rep.energy = solve.energy;
    rep.non_metric = solve.non_metric_detected;

    out.labels = problem.labels();
    out.cell_labels = labelling;
    std::vector<Eigen::Array3i> shift(labelling.size());
    for (std::size_t x = 0; x < labelling.size(); ++x) shift[x] = out.labels[std::size_t(labelling[x])];

    if (!progress.report("stitching", 0.0)) return error(StatusCode::cancelled, "cancelled");
    t = clock::now();
    detail::MovedPlanes planes = move_seams(k, rep.cells_out, shift);
    rep.timings_ms["seam planes"] = ms_since(t);
    t = clock::now();
    StitchReport st;
    if (planes.any()) {
      const Status moved = stitch_moved(rep.cells_out, shift, planes, out.mesh, st);
      if (moved.code() == StatusCode::too_large) {  // the finer grid is past the stitcher's limits: seams stay
        planes = detail::MovedPlanes();
        out.mesh = Mesh();
        st = StitchReport();
      } else {
        RESTITCH_TRY(moved);
      }
    }
    if (!planes.any()) {
      if constexpr (has_prepared_stitch_v<Stitcher>) {
        RESTITCH_TRY(stitcher_.stitch(cache_, rep.cells_out, shift, out.mesh, st));
      } else {
        RESTITCH_TRY(stitcher_.stitch(*mesh_, grid_, rep.cells_out, shift, out.mesh, st));
      }
    }
    rep.timings_ms["stitch"] = ms_since(t);
    for (int a = 0; a < 3; ++a)
      if (planes.moved(a)) {
        rep.plane_offsets[std::size_t(a)].clear();
        for (const int j : planes.j[std::size_t(a)]) {
          rep.plane_offsets[std::size_t(a)].push_back(double(j) / planes.K);
          rep.seams_moved += j != 0;
        }
      }
    t = clock::now();
    measure_seams(k, rep.cells_out, shift, planes, rep);
    rep.timings_ms["seams"] = ms_since(t);
    rep.regions = st.regions;
    rep.triangles_out = out.mesh.triangle_count();
    rep.vertices_out = out.mesh.vertex_count();
    if (options_.boundary_edges) {
      t = clock::now();
      rep.boundary_edges_out = boundary_edge_count(out.mesh);
      rep.timings_ms["boundary"] = ms_since(t);
    }
    if (options_.face_labels) out.face_labels = face_labels(out.mesh, rep, labelling);
    // Placement: whole periods, so that the pivot stays put (placement.hpp).
    rep.placement = place(analysis_->lattice, box_in_, rep.steps, options_.pivot);
    translate(out.mesh, rep.placement.translation);
    out.grid.origin += rep.placement.translation;
    rep.size_out = out.mesh.empty() ? Eigen::Vector3d::Zero() : bounding_box(out.mesh).size();
    rep.size_nearest = rep.size_out;
    rep.timings_ms["total"] = ms_since(t0);
    progress.report("stitching", 1.0);
    if (out.mesh.empty())
      return error(StatusCode::internal, "the labelling left every output cell empty; please report this model");
    return out;
  });
}

template <class LabelSpace, class Solver, class Stitcher>
Result<SeamMrf> Retargeter<LabelSpace, Solver, Stitcher>::labelling_problem(const Eigen::Array3i& steps) {
  return detail::guarded("labelling_problem", [&]() -> Result<SeamMrf> {
    RESTITCH_TRY(status_);
    RetargetReport rep;
    RESTITCH_TRY(plan(steps, rep));
    return make_problem(rep.grid_steps);
  });
}

template <class LabelSpace, class Solver, class Stitcher>
Result<Eigen::Array3i> Retargeter<LabelSpace, Solver, Stitcher>::steps_for_size(const Eigen::Vector3d& target,
                                                                                int max_steps) const {
  return detail::guarded("steps_for_size", [&]() -> Result<Eigen::Array3i> {
    RESTITCH_TRY(status_);
    RESTITCH_TRY(check_size(target));
    const Lattice& L = analysis_->lattice;
    Eigen::Vector3d want = target;
    for (int i = 0; i < 3; ++i)
      if (!(want[i] > 0)) want[i] = size_in_[i];
    Eigen::Array3i lo = Eigen::Array3i::Zero(), hi = Eigen::Array3i::Zero();
    for (int a = 0; a < 3; ++a)
      if (!L.dummy[a]) lo[a] = 1 - L.cells[a], hi[a] = max_steps;
    Eigen::Array3i best = Eigen::Array3i::Zero();
    double best_err = INFINITY;
    for (int w = lo[2]; w <= hi[2]; ++w)
      for (int v = lo[1]; v <= hi[1]; ++v)
        for (int u = lo[0]; u <= hi[0]; ++u) {
          // Each step along v_a moves the far end by v_a: the box grows by |v_a| per component.
          Eigen::Vector3d size = size_in_;
          const Eigen::Array3i s(u, v, w);
          for (int a = 0; a < 3; ++a) size += L.A.col(a).cwiseAbs() * s[a];
          const double err = (size - want).cwiseQuotient(size_in_.cwiseMax(1e-12)).squaredNorm();
          if (err < best_err - 1e-12) best_err = err, best = s;
        }
    return best;
  });
}

template <class LabelSpace, class Solver, class Stitcher>
Result<RetargetResult> Retargeter<LabelSpace, Solver, Stitcher>::retarget_to_size(const Eigen::Vector3d& target, bool exact,
                                                                                  const Progress& progress) {
  return detail::guarded("retarget_to_size", [&]() -> Result<RetargetResult> {
    Result<Eigen::Array3i> steps = steps_for_size(target);
    RESTITCH_TRY(steps.status());
    Result<RetargetResult> out = retarget(*steps, progress);
    RESTITCH_TRY(out.status());
    RetargetReport& rep = out->report;
    if (!exact) return out;
    rep.exact = true;
    for (int i = 0; i < 3; ++i)
      if (target[i] > 0 && rep.size_out[i] > 0) rep.scale[i] = target[i] / rep.size_out[i];
    if (rep.scale != Eigen::Vector3d::Ones()) {
      const Eigen::Vector3d& p = rep.placement.pivot;
      scale_about(out->mesh, rep.scale, p);
      out->grid.A = rep.scale.asDiagonal() * out->grid.A;
      out->grid.origin = p + rep.scale.asDiagonal() * (out->grid.origin - p);
      rep.size_out = bounding_box(out->mesh).size();
    }
    return out;
  });
}

template <class LabelSpace, class Solver, class Stitcher>
Status Retargeter<LabelSpace, Solver, Stitcher>::check_size(const Eigen::Vector3d& target) const {
  const Lattice& L = analysis_->lattice;
  std::array<bool, 3> covered{{false, false, false}};
  for (int a = 0; a < 3; ++a)
    if (!L.dummy[a]) covered[std::size_t(world_axis_of(L.A.col(a)))] = true;
  RESTITCH_TRY(check_size_values(target));
  const std::array<bool, 3> change = size_changes(target, size_in_);
  for (int i = 0; i < 3; ++i) {
    const std::string axis(1, "xyz"[i]);
    if (change[std::size_t(i)] && !covered[std::size_t(i)])
      return error(StatusCode::invalid_argument,
                   "no repeat runs along " + axis + ", so its size cannot change (asked " +
                       format_size(target[i]) + ", the model is " + format_size(size_in_[i]) +
                       "); give 0 to keep " + axis);
  }
  return {};
}


/// Lattice steps from steps along the principal offsets in order (the i-th
/// value goes to the i-th non-dummy lattice axis), as a user states them.
/// More non-zero values than principal offsets is an error saying how many
/// the model has.
template <class = void>
Result<Eigen::Array3i> lattice_steps_from_principal(const Analysis& analysis, const std::vector<int>& steps) {
  Eigen::Array3i out = Eigen::Array3i::Zero();
  std::size_t next = 0;
  for (int a = 0; a < 3; ++a)
    if (!analysis.lattice.dummy[a] && next < steps.size()) out[a] = steps[next++];
  for (std::size_t i = next; i < steps.size(); ++i)
    if (steps[i] != 0)
      return analysis.principal.empty()
                 ? error(StatusCode::no_repetition,
                         "no repetition was found in this model, so there is nothing to resize along")
                 : error(StatusCode::invalid_argument,
                         "the model has " + std::to_string(analysis.principal.size()) +
                             " principal offset(s), so at most that many steps can be non-zero");
  return out;
}

/// The inverse of lattice_steps_from_principal: the steps along each principal offset, in order.
template <class = void>
std::vector<int> principal_steps_from_lattice(const Analysis& analysis, const Eigen::Array3i& lattice_steps) {
  std::vector<int> out;
  for (int a = 0; a < 3; ++a)
    if (!analysis.lattice.dummy[a]) out.push_back(lattice_steps[a]);
  return out;
}

/// One-shot convenience: builds a Retargeter and resizes once.
template <class LabelSpace = LatticeLabels, class Solver = AlphaExpansion<>, class Stitcher = ClipStitcher>
Result<RetargetResult> retarget(const Mesh& mesh, const Analysis& analysis, const Eigen::Array3i& steps,
                                const RetargetOptions& options = {}, const Progress& progress = {}) {
  Retargeter<LabelSpace, Solver, Stitcher> r(mesh, analysis, options);
  return r.retarget(steps, progress);
}

// The compiled mode (restitch/detail/instantiation.hpp): both label spaces with the default solver and stitcher.
RESTITCH_INSTANTIATE(class Retargeter<LatticeLabels>)
RESTITCH_INSTANTIATE(class Retargeter<RegularLabels>)
RESTITCH_INSTANTIATE(Result<RetargetResult> retarget<>(const Mesh&, const Analysis&, const Eigen::Array3i&,
                                                       const RetargetOptions&, const Progress&))

}  // namespace restitch
