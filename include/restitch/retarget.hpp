// restitch/retarget.hpp - resize a model along its repeats (docs/method.md sections 2 and 3).
//
//   Result<Analysis> a = restitch::analyze(mesh);
//   restitch::Retargeter<> r(mesh, *a);          // once per (mesh, analysis)
//   Result<RetargetResult> out = r.retarget({2, 0, 0});  // as often as you like
//
// A request is integer steps per LATTICE axis (negative shrinks; dummy
// directions must stay 0): lattice_steps_from_principal and
// lattice_steps_from_world (restitch/retarget/request.hpp) make them from
// steps along the principal offsets in the order `analyze` reports them or
// along x, y, z. Or a target bounding-box size, turned into the nearest
// steps by `steps_for_size`. One call runs the stages, each in its header:
//   plan, labelling problem, solve    restitch/retarget/labelling.hpp
//   seams off the cell planes         restitch/retarget/seams.hpp
//   stitch                            restitch/retarget/stitching.hpp
//   centred part moved half a period  restitch/retarget/centring.hpp
//   seam report                       restitch/retarget/seams.hpp
//   place                             restitch/placement.hpp
// The solver policy defaults to alpha-expansion over push-relabel max-flow
// (restitch/solver/). Steps of zero return the input geometry unchanged (a
// copy of the mesh). What a request returns: restitch/retarget/report.hpp.
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
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/detail/instantiation.hpp"
#include "restitch/energy/seam_energy.hpp"
#include "restitch/energy/seam_geometry.hpp"
#include "restitch/lattice/grid.hpp"
#include "restitch/lattice/label_space.hpp"
#include "restitch/mesh_boundary.hpp"
#include "restitch/placement.hpp"
#include "restitch/retarget/centring.hpp"
#include "restitch/retarget/check.hpp"
#include "restitch/retarget/labelling.hpp"
#include "restitch/retarget/report.hpp"
#include "restitch/retarget/request.hpp"
#include "restitch/retarget/seams.hpp"
#include "restitch/retarget/stitching.hpp"
#include "restitch/lattice/structure.hpp"
#include "restitch/solver/alpha_expansion.hpp"
#include "restitch/stitch/stitch.hpp"

namespace restitch {

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

  /// Resizes by `steps`, one per lattice axis (see the header comment).
  Result<RetargetResult> retarget(const Eigen::Array3i& steps, const Progress& progress = {});

  /// The labelling problem a request solves (for --dump-mrf and benchmarks).
  Result<SeamMrf> labelling_problem(const Eigen::Array3i& steps);

  /// The geometric seam measure this Retargeter reports with (and solves with, by default).
  CellSlabs& slabs() { return *slabs_; }
  /// What repeats along each axis of the label grid and what occurs once (restitch/lattice/structure.hpp);
  /// null with RetargetOptions::keep_parts off, for a label grid that is not the analysis lattice (the
  /// regular baseline), or before the grid was built.
  const CellStructure* structure() const { return structure_.get(); }

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
  // The centred parts of rep.parts that a resize by k grid steps leaves half a period off the centre
  // (centring_move), each moved alone the rest of the way in `mesh` where it can be (centre_part); the
  // planned "part off centre" warning of a part so moved is taken back.
  Status centre_parts(const Eigen::Array3i& k, RetargetReport& rep, Mesh& mesh) const {
    if (!structure_) return {};
    for (PartReport& pr : rep.parts) {
      const SingularPart* p = structure_->part_of(pr.axis, pr.first);
      const int move = p ? centring_move(*p, k[pr.axis]) : 0;
      if (move == 0) continue;
      CentringOptions co;
      co.tolerance = structure_->tolerance;
      co.spacing = structure_->spacing[pr.axis] * grid_.A.col(pr.axis).norm();
      co.weld = stitch_.weld_tolerance();
      Mesh centred;
      bool moved = false;
      RESTITCH_TRY(centre_part(
          mesh, grid_, rep.cells_out, *p, pr.shift, move, co,
          [this](const Mesh& m, const Lattice& l, const Eigen::Array3i& c, const std::vector<Eigen::Array3i>& s,
                 Mesh& o, StitchReport& r) { return stitch_.stitch_mesh(m, l, c, s, o, r); },
          centred, moved));
      if (!moved) continue;
      mesh = std::move(centred);
      pr.half = move;
      const std::string where = describe_part(*p);
      rep.warnings.erase(std::remove_if(rep.warnings.begin(), rep.warnings.end(),
                                        [&](const ResultWarning& w) {
                                          return w.check == "part off centre" &&
                                                 w.message.find(where) != std::string::npos;
                                        }),
                         rep.warnings.end());
    }
    return {};
  }

  // The part of the report that does not depend on the request's size.
  void fill_input_report(const Eigen::Array3i& steps, RetargetReport& rep) const {
    rep.steps = steps;
    rep.cells_in = grid_.cells;
    rep.triangles_in = mesh_->triangle_count();
    rep.boundary_edges_in = input_shape_ ? input_shape_->edge_a.size() : 0;
    rep.weld_tolerance = stitch_.weld_tolerance();
    rep.weld_tolerance_measured = stitch_.weld_measured();
    rep.size_in = size_in_;
  }

  const Mesh* mesh_;
  const Analysis* analysis_;
  RetargetOptions options_;
  LabelSpace space_;
  Solver solver_;
  StitchStage<Stitcher> stitch_;
  Status status_;
  Lattice grid_;
  std::unique_ptr<CellDescriptors> cells_;
  std::unique_ptr<CellSlabs> slabs_;
  std::unique_ptr<CellStructure> structure_;  // with RetargetOptions::keep_parts
  Eigen::Vector3d size_in_ = Eigen::Vector3d::Zero();
  BoundingBox box_in_;
  std::unique_ptr<InputShape> input_shape_;  // with RetargetOptions::check
};

template <class LabelSpace, class Solver, class Stitcher>
Retargeter<LabelSpace, Solver, Stitcher>::Retargeter(const Mesh& mesh, const Analysis& analysis, RetargetOptions options,
                                                     LabelSpace labels, Solver solver, Stitcher stitcher)
    : mesh_(&mesh), analysis_(&analysis), options_(options), space_(labels), solver_(solver), stitch_(stitcher) {
  status_ = detail::guarded("Retargeter", [&]() -> Status {
    if (options_.threads < 0 || options_.threads > 1024)
      return error(StatusCode::invalid_argument,
                   "threads must be 0 (every hardware thread) to 1024, not " + std::to_string(options_.threads));
    detail::set_policy_threads(solver_, options_.threads, 0);
    RESTITCH_TRY(stitch_.set_weld_tolerance(options_.weld_tolerance));
    if (options_.weld_tolerance == 0 && options_.measure_weld_tolerance) stitch_.measure_weld_tolerance(mesh, analysis);
    RESTITCH_TRY(space_.grid(mesh, analysis, grid_));
    if (std::int64_t(grid_.cells.prod()) > std::int64_t(options_.max_problem_size))
      return error(StatusCode::too_large, "the label grid has " + std::to_string(grid_.cells.prod()) +
                                              " cells, more than max_problem_size (" +
                                              std::to_string(options_.max_problem_size) + ")");
    cells_ = std::make_unique<CellDescriptors>(analysis, grid_, options_.set_distance);
    box_in_ = bounding_box(mesh);
    size_in_ = box_in_.size();
    slabs_ = std::make_unique<CellSlabs>(analysis, grid_);
    // Seams move to where the stitcher can close them (docs/method.md 2.9): the copies' surfaces within its
    // zipper's gap.
    slabs_->set_surface(mesh, detail::zip_gap_of_diagonal * size_in_.norm());
    // Parts that occur once are found on the lattice's own cells (one period each); a label space with
    // other cells (the regular baseline) keeps the paper's labelling.
    const Lattice& L = analysis.lattice;
    if (options_.keep_parts && (grid_.cells == L.cells).all() && grid_.A == L.A && grid_.origin == L.origin)
      structure_ = std::make_unique<CellStructure>(cell_structure(mesh, analysis, grid_));
    RESTITCH_TRY(stitch_.prepare(mesh, grid_));
    if (options_.check) input_shape_ = std::make_unique<InputShape>(mesh, stitch_.weld_tolerance());
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
    fill_input_report(steps, rep);
    RESTITCH_TRY(plan_request(space_, *analysis_, grid_, options_, structure_.get(), steps, rep));
    out.grid = grid_;
    const Eigen::Array3i k = rep.grid_steps;
    const double nodes = double(rep.cells_out.prod());

    if ((k == 0).all()) {  // nothing to do: the input, unchanged
      out.mesh = *mesh_;
      rep.nodes = int(nodes), rep.labels = 1, rep.regions = 1;
      rep.triangles_out = rep.triangles_in;
      rep.vertices_out = out.mesh.vertex_count();
      rep.boundary_edges_out = rep.boundary_edges_in;
      rep.checked = bool(input_shape_);
      rep.size_out = size_in_;
      rep.placement = place(analysis_->lattice, box_in_, Eigen::Array3i::Zero(), options_.pivot, structure_.get());
      rep.size_nearest = size_in_;
      out.labels = {Eigen::Array3i::Zero()};
      out.cell_labels.assign(std::size_t(nodes), 0);
      if (options_.face_labels) out.face_labels.assign(out.mesh.triangle_count(), 0);
      rep.timings_ms["total"] = ms_since(t0);
      return out;
    }

    // Labelling problem and solve.
    if (!progress.report("energy", 0.0)) return error(StatusCode::cancelled, "cancelled");
    auto t = clock::now();
    SeamMrf problem = make_seam_problem(*cells_, *slabs_, grid_, options_, structure_.get(), k);
    rep.timings_ms["energy"] = ms_since(t);
    rep.nodes = problem.node_count();
    rep.labels = problem.label_count();
    rep.edges = problem.edge_count();
    t = clock::now();
    std::vector<int> labelling;
    SolveReport solve;
    RESTITCH_TRY(solve_labelling(solver_, problem, progress, labelling, solve));
    rep.timings_ms["solve"] = ms_since(t);
    rep.cycles = solve.cycles;
    rep.energy = solve.energy;
    rep.non_metric = solve.non_metric_detected;
    out.labels = problem.labels();
    out.cell_labels = labelling;
    std::vector<Eigen::Array3i> shift(labelling.size());
    for (std::size_t x = 0; x < labelling.size(); ++x) shift[x] = out.labels[std::size_t(labelling[x])];

    // Seams off the cell planes, then the stitch.
    if (!progress.report("stitching", 0.0)) return error(StatusCode::cancelled, "cancelled");
    t = clock::now();
    MovedPlanes planes;
    if (options_.move_seams) planes = move_seams(*slabs_, k, rep.cells_out, shift);
    rep.timings_ms["seam planes"] = ms_since(t);
    t = clock::now();
    StitchReport st;
    RESTITCH_TRY(stitch_.stitch(rep.cells_out, shift, planes, out.mesh, st));
    rep.timings_ms["stitch"] = ms_since(t);
    for (int a = 0; a < 3; ++a)
      if (planes.moved(a)) {
        rep.plane_offsets[std::size_t(a)].clear();
        for (const int j : planes.j[std::size_t(a)]) {
          rep.plane_offsets[std::size_t(a)].push_back(double(j) / planes.K);
          rep.seams_moved += j != 0;
        }
      }

    // A centred part that whole periods leave half a period off the centre, moved the rest alone (2.10).
    t = clock::now();
    RESTITCH_TRY(centre_parts(k, rep, out.mesh));
    rep.timings_ms["centring"] = ms_since(t);

    // Seam report.
    t = clock::now();
    measure_seams(*slabs_, grid_, options_, k, rep.cells_out, shift, planes, rep);
    rep.timings_ms["seams"] = ms_since(t);
    rep.regions = st.regions;
    rep.triangles_out = out.mesh.triangle_count();
    rep.vertices_out = out.mesh.vertex_count();
    if (options_.face_labels) out.face_labels = face_labels(grid_, out.mesh, rep, labelling);

    // Placement: whole periods, so that the pivot stays put (placement.hpp).
    rep.placement = place(analysis_->lattice, box_in_, rep.steps, options_.pivot, structure_.get());
    translate(out.mesh, rep.placement.translation);
    out.grid.origin += rep.placement.translation;
    rep.size_out = out.mesh.empty() ? Eigen::Vector3d::Zero() : bounding_box(out.mesh).size();
    rep.size_nearest = rep.size_out;
    if (input_shape_ && !out.mesh.empty()) {
      t = clock::now();
      check_result(*input_shape_, out.mesh, grid_, shift, structure_.get(), rep, slabs_->empty_mismatch());
      rep.timings_ms["check"] = ms_since(t);
    }
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
    fill_input_report(steps, rep);
    RESTITCH_TRY(plan_request(space_, *analysis_, grid_, options_, structure_.get(), steps, rep));
    return make_seam_problem(*cells_, *slabs_, grid_, options_, structure_.get(), rep.grid_steps);
  });
}

template <class LabelSpace, class Solver, class Stitcher>
Result<Eigen::Array3i> Retargeter<LabelSpace, Solver, Stitcher>::steps_for_size(const Eigen::Vector3d& target,
                                                                                int max_steps) const {
  return detail::guarded("steps_for_size", [&]() -> Result<Eigen::Array3i> {
    RESTITCH_TRY(status_);
    return nearest_steps(analysis_->lattice, size_in_, target, max_steps);
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
    if (!exact) {
      if (rep.checked) check_size_asked(target, analysis_->lattice, rep);
      return out;
    }
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
  return restitch::check_size(analysis_->lattice, size_in_, target);
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
