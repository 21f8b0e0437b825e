// restitch/retarget/labelling.hpp - the labelling stage of a resize: the request planned, the problem built and solved (docs/method.md 2.1-2.5).
//
// `plan_request` checks a request against the label grid and gives the grid steps and output cells;
// `make_seam_problem` builds the labelling problem (restitch/energy/seam_energy.hpp) with the anchored
// ends; `solve_labelling` solves it from two starts with the solver policy.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/energy/seam_energy.hpp"
#include "restitch/energy/seam_geometry.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/progress.hpp"
#include "restitch/retarget/report.hpp"
#include "restitch/retarget/request.hpp"
#include "restitch/lattice/structure.hpp"
#include "restitch/solver/mrf.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// The parts that occur once (`structure`, null for none; docs/method.md 2.10) in a resize by grid steps k:
/// rep.parts gets each part along a resized axis with the shift that keeps it, rep.warnings a sentence for
/// a centred part the resize puts farther off the centre than it was (half a period), for an undecided
/// axis (CellStructure::undecided), for one read through an end around a gap (CellStructure::end_read) and
/// for one whose cells copied may be a gap in one part (CellStructure::gap_run).
/// Refused (invalid_argument): a shrink whose parts would not fit apart (parts_fit), saying how many steps
/// can be removed.
template <class = void>
Status plan_parts(const CellStructure* structure, const Eigen::Array3i& k, RetargetReport& rep) {
  if (!structure) return {};
  for (int a = 0; a < 3; ++a) {
    if (k[a] == 0) continue;
    const std::string axis = std::to_string(a + 1);
    if (structure->undecided[std::size_t(a)])
      rep.warnings.push_back({"undecided axis", "no two neighbouring cells along axis " + axis + " are copies of one another, so what "
                             "occurs once along it was not decided: look at the result (its period may be wrong: "
                             "give it with --offsets)"});
    if (structure->gap_run[std::size_t(a)])
      rep.warnings.push_back({"short repeat", "the cells a resize along axis " + axis + " copies lack, all along them, a wall "
                             "the model has on both sides of them, and nothing else repeats: they may be a gap in one part, like "
                             "a key notch over several pins, taken as repeating: look at the result"});
    if (structure->end_read[std::size_t(a)])
      rep.warnings.push_back({"short repeat", "the cells found to repeat along axis " + axis + " are copies only through an end cell "
                             "(no two whole cells are), and a surface both ends have is missing all along them: they may be a "
                             "gap in one part, like a key notch that reaches every cell, taken as repeating: look at the result"});
    if (k[a] < 0 && !parts_fit(*structure, a, k[a])) {
      int most = 0;
      while (most + 1 < structure->cells[a] && parts_fit(*structure, a, -(most + 1))) ++most;
      std::string list;
      for (const SingularPart& p : structure->parts)
        if (p.axis == a) list += (list.empty() ? "" : "; ") + describe_part(p);
      return error(StatusCode::invalid_argument,
                   "cannot shrink axis " + axis + " by " + std::to_string(-k[a]) +
                       " steps: its parts that occur once would not fit apart (" + list + "; at most " +
                       std::to_string(most) + " steps can be removed)");
    }
    for (const SingularPart& p : structure->parts) {
      if (p.axis != a) continue;
      const int d = CellStructure::shift_of(p, k[a]);
      rep.parts.push_back({p.axis, p.first, p.last, p.anchor, d});
      if (p.anchor == PartAnchor::centre && std::abs(CellStructure::offset_after(p, k[a])) > std::abs(p.offset) + 1e-9)
        rep.warnings.push_back({"part off centre", "the part at " + describe_part(p) + " is centred in the model; resized by " +
                               std::to_string(k[a]) + " steps it lies half a period off the centre (whole periods "
                               "cannot centre it)"});
    }
  }
  return {};
}

/// Checks lattice `steps` (one per axis of `grid`, the label grid of `space`) and fills
/// rep.grid_steps and rep.cells_out (and the parts, plan_parts; a warning "pair" for a resized axis whose
/// repeat is a pair candidate promoted on request, unless `structure` finds three slabs or more along it that
/// are copies, else "two copies" where it finds exactly two): refused when the model has no repeat,
/// when an axis would shrink below one cell or to one cell that cannot hold both ends, when the parts
/// that occur once do not allow it (plan_parts), and when nodes x labels exceed options.max_problem_size
/// (too_large, naming the option).
template <class LabelSpace>
Status plan_request(const LabelSpace& space, const Analysis& analysis, const Lattice& grid,
                    const RetargetOptions& options, const CellStructure* structure, const Eigen::Array3i& steps,
                    RetargetReport& rep) {
  if ((steps != 0).any() && analysis.principal.empty())
    return error(StatusCode::no_repetition, "no repetition was found in this model, so there is nothing to resize along");
  RESTITCH_TRY(space.grid_steps(analysis, grid, steps, rep.grid_steps));
  const Eigen::Array3i k = rep.grid_steps;
  for (int a = 0; a < 3; ++a)
    if (grid.cells[a] + k[a] < 1)
      return error(StatusCode::invalid_argument, "cannot shrink axis " + std::to_string(a + 1) + " by " +
                                                     std::to_string(-steps[a]) + " steps: the model has " +
                                                     std::to_string(grid.cells[a]) + " cells along it (at most " +
                                                     std::to_string(grid.cells[a] - 1) + " steps can be removed)");
  // Down to one cell: its two ends must fit in it. The first cell's own end reaches to end_low and the
  // last cell's starts at end_high (Lattice, lattice/fit.hpp); when they overlap, one cell would cut one
  // of them (a garage door whose jambs each take most of a cell).
  for (int a = 0; a < 3; ++a)
    if (k[a] != 0 && grid.cells[a] + k[a] == 1 && grid.end_low[a] > grid.end_high[a])
      return error(StatusCode::invalid_argument,
                   "cannot shrink axis " + std::to_string(a + 1) + " to one cell: the model's two ends take more " +
                       "than one cell along it and would be cut (at most " + std::to_string(grid.cells[a] - 2) +
                       " steps can be removed)");
  rep.cells_out = grid.cells + k;
  RESTITCH_TRY(plan_parts(structure, k, rep));
  // A repeat of two copies that make up less than half of the model (a pair candidate, promoted on request:
  // docs/method.md 1.10, 1.13) is a detail of a larger whole: what each copy holds is repeated with it and
  // the rest is kept at the ends, which the model may not mean (a 2-column box header's key notch, whose
  // edges lie in the ends, widens with the pins). Unless the structure finds three slabs or more along the
  // axis that are copies (docs/method.md 2.11): then the repeat is no pair, whatever its pattern test said
  // (a 3-column facade whose ends hold most of it).
  for (int a = 0; a < analysis.axes.real_count; ++a) {
    const int i = analysis.axes.source[std::size_t(a)];
    if (steps[a] == 0) continue;
    const DominantOffset* d =
        i >= 0 && i < int(analysis.dominant.size()) ? &analysis.dominant[std::size_t(i)] : nullptr;
    int copies = 0, first = -1, last = -1;  // the slabs that are copies: how many, the first and the last
    if (structure) {
      const std::vector<int>& copy_of = structure->copy_of[std::size_t(a)];
      for (int c = 0; c < int(copy_of.size()); ++c)
        if (copy_of[std::size_t(c)] >= 0) ++copies, last = c, first = first < 0 ? c : first;
    }
    if (d && d->promoted && !d->significant && d->is_pair() && copies < 3)
      rep.warnings.push_back({"pair", "the repeat along axis " + std::to_string(a + 1) +
                                          " is two copies that make up less than half of the model (a candidate, "
                                          "resized along on request): what each copy holds is repeated with it and "
                                          "the rest kept at the ends; look at the result"});
    // A repeat found in two exact copies (1.13) whose slabs are the only two copies, side by side, each next
    // to an end (a 2-pin connector: its two pins' cells between the end walls): content in both (a slot next
    // to each end) may belong to the ends or to every copy, and nothing in the model tells which. It is
    // repeated with every copy. From three copies on, or with a slab between a copy and its end that is no
    // copy (a 4-pin connector's end pins, whose slots make them parts), the model decides.
    else if (d && d->exact_pair() && structure && !structure->undecided[std::size_t(a)] && copies == 2 &&
             last == first + 1 && first <= 1 && last >= grid.cells[a] - 2)
      rep.warnings.push_back({"two copies", "the repeat along axis " + std::to_string(a + 1) +
                                                " has two copies, each next to an end: what both hold may belong "
                                                "to the ends (a slot next to each end) rather than to every copy, "
                                                "and was repeated with every copy; look at the result"});
  }
  const double nodes = double(rep.cells_out.prod());
  const double labels = double((k.abs() + 1).prod());
  if (nodes * labels > double(options.max_problem_size))
    return error(StatusCode::too_large,
                 "this request needs " + std::to_string(std::int64_t(nodes)) + " nodes x " +
                     std::to_string(std::int64_t(labels)) + " labels, more than the limit of " +
                     std::to_string(options.max_problem_size) +
                     " (RetargetOptions::max_problem_size; --max-problem on the command line): ask for fewer steps "
                     "or raise the limit");
  return {};
}

/// The second start's dynamic programme is skipped above this many pairwise terms (about 10 ms here;
/// docs/method.md 2.5): a cost limit, so large step counts keep the slider's pace.
inline constexpr double separable_budget = double(1 << 20);

/// The labelling problem of grid steps `k` with the seam energy options.seam_energy (`cells` for the
/// descriptor energy, `slabs` for the geometric one), end cells kept out of the middle (2.3), and the parts
/// of `structure` (null: none) kept once (2.10): every slab of a part along a resized axis is copied only
/// with the part's shift (CellStructure::shift_of), and placed there, an end slab too (the anchored ends
/// only pull toward it, and an end cap starts at an end plane that a thin part can lie beyond), except on
/// an output one cell long, where both ends' caps meet in that cell; the other slabs between two parts are
/// copied only between those parts' places (SeamMrf::keep_runs).
template <class = void>
SeamMrf make_seam_problem(CellDescriptors& cells, CellSlabs& slabs, const Lattice& grid, const RetargetOptions& options,
                          const CellStructure* structure, const Eigen::Array3i& k) {
  SeamMrf problem = options.seam_energy == SeamEnergy::geometry ? SeamMrf(slabs, k, options.neighbourhood)
                                                                : SeamMrf(cells, k, options.neighbourhood);
  problem.penalise_inner_ends(grid.end_low, grid.end_high);
  if (structure)
    for (const SingularPart& p : structure->parts) {
      const int a = p.axis;
      if (k[a] == 0) continue;
      const int d = CellStructure::shift_of(p, k[a]);
      const bool one_cell = grid.cells[a] + k[a] == 1;  // both ends' caps meet in the one output cell
      for (int j = p.first; j <= p.last; ++j) problem.pin_slab(a, j, d, !one_cell);
    }
  // Runs keep their side (2.10): the slabs between two parts are copied only between those parts' places.
  if (structure)
    for (int a = 0; a < 3; ++a) {
      if (k[a] == 0) continue;
      std::vector<const SingularPart*> along;
      for (const SingularPart& p : structure->parts)
        if (p.axis == a) along.push_back(&p);
      if (along.empty()) continue;
      std::sort(along.begin(), along.end(), [](const SingularPart* x, const SingularPart* y) { return x->first < y->first; });
      const int in_n = grid.cells[a], out_n = grid.cells[a] + k[a];
      if (out_n <= 0) continue;
      std::vector<int> input_run(std::size_t(in_n), 0), output_run(std::size_t(out_n), 0);
      const auto runs = [&](std::vector<int>& run, bool output) {
        for (int x = 0; x < int(run.size()); ++x) {
          int r = 0;
          for (const SingularPart* p : along) {
            const int d = output ? CellStructure::shift_of(*p, k[a]) : 0;
            if (x >= p->first + d && x <= p->last + d) r = -1;
            if (r >= 0 && x > p->last + d) ++r;
          }
          run[std::size_t(x)] = r;
        }
      };
      runs(input_run, false), runs(output_run, true);
      problem.keep_runs(a, input_run, output_run);
    }
  return problem;
}

/// Solves `problem` with `solver` from two starts (docs/method.md 2.5): the input stretched, and, where
/// it beats that solve's result, the best labelling with straight seams; the lower energy wins, the first
/// on a tie. Each solve reports half of the progress.
template <class Solver>
Status solve_labelling(const Solver& solver, const SeamMrf& problem, const Progress& progress,
                       std::vector<int>& labelling, SolveReport& solve) {
  labelling = problem.initial_labels();
  const auto half = [&progress](double base) {
    return Progress([&progress, base](std::string_view stage, double f) {
      return progress.report(stage, base + 0.5 * f);
    });
  };
  RESTITCH_TRY(solver.solve(problem, labelling, solve, half(0.0)));
  if (problem.separable_terms() > separable_budget) {
    // the second start is skipped on very large requests (its cost; docs/method.md 2.5)
  } else if (std::vector<int> straight = problem.separable_labels(); energy(problem, straight) < solve.energy) {
    SolveReport second;
    RESTITCH_TRY(solver.solve(problem, straight, second, half(0.5)));
    if (second.energy < solve.energy) labelling.swap(straight), solve = second;
  }
  return {};
}

}  // namespace restitch
