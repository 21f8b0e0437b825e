// restitch/retarget/request.hpp - what a resize is asked: options, steps and sizes (docs/method.md 2.1, 2.7).
//
// A request is integer steps per lattice axis (`Retargeter::retarget`; a lattice axis is a principal
// offset or a dummy direction, in the order of Analysis::lattice), built from steps along the principal
// offsets in the order `analyze` reports them (`lattice_steps_from_principal`) or along the world axes
// x, y, z (`lattice_steps_from_world`), or a bounding-box size turned into the nearest steps
// (`steps_for_size`).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/energy/seam_energy.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/placement.hpp"
#include "restitch/status.hpp"

namespace restitch {

struct RetargetOptions {
  Neighbourhood neighbourhood = Neighbourhood::n26;   ///< the paper's; n6 as an option
  SetDistance set_distance = SetDistance::hausdorff;  ///< the paper's; mean_nearest as an option
  /// The pairwise term solved (docs/method.md 2.4, 2.4b): the paper's descriptor sets of whole cells
  /// (default) or the geometry at the seam. The seams are measured on the geometry either way.
  /// Descriptor is the default because it was measured better on the real models (docs/results.md,
  /// seam energies): the geometric energy's first request of a new size costs more (up to 149 ms on the
  /// shared models, against 24 ms) and it shrinks some wrongly.
  SeamEnergy seam_energy = SeamEnergy::descriptor;
  /// A seam whose mismatch (model units) exceeds this is over the tolerance (SeamReport::mismatch; the
  /// web page draws it red). 0 (default): 3 x the sample spacing (CellSlabs::spacing), see docs/method.md
  /// 2.8. An estimate from samples: the result check (`check`) says whether a seam is open.
  double seam_tolerance = 0;
  /// Refuse requests whose nodes x labels exceed this (memory and time grow with it).
  std::size_t max_problem_size = 2'000'000;
  /// Also report, for every output face, the index of the label of the cell it lies in (for display).
  bool face_labels = false;
  /// What stays put along each world axis x, y, z (restitch/placement.hpp): by default the model's origin.
  Pivots pivot{{Pivot::origin, Pivot::origin, Pivot::origin}};
  /// Check the result for what a modeller would reject (restitch/retarget/check.hpp, docs/method.md 2.11):
  /// open edges the input does not have, parts that occur once copied a wrong number of times, a size not
  /// the one asked, pieces left floating; each failed check adds a RetargetReport::warnings entry, and the
  /// report counts the boundary edges in, out and new. It costs O(#V + #F) per result with a hash look-up
  /// per vertex, several times the stitch (docs/benchmarks.md); a live slider may turn it off and check
  /// the size it settles on.
  bool check = true;
  /// Let a seam leave its cell plane (docs/method.md 2.9): after the labels are solved, each plane between
  /// output cells where copies meet moves, within half a cell, to where the two copies continue each other
  /// (when they do not at the cell plane), so a part longer than the cut's neighbourhood is not cut when
  /// an uncut position exists. Off: every seam on a cell plane, as in the paper.
  bool move_seams = true;
  /// Weld tolerance of the stitcher, relative to the input's bounding-box diagonal: seam vertices this
  /// close are merged and T-junctions this close split (restitch/stitch/stitch.hpp). 0 (default): the
  /// stitcher's own (ClipStitcher: 1e-6, exact copies only), raised to the copies' measured precision
  /// when measure_weld_tolerance is on. Real models' copies often differ by 1e-6 to 1e-4 of the diagonal,
  /// so their seams stay open at 1e-6 (docs/results.md, known limits); a larger value closes them and also snaps
  /// and drops slivers at that scale. Set on a stitcher with a `weld_tolerance` member; refused
  /// (invalid_argument) outside [0, 1e-2] or for a stitcher without one.
  double weld_tolerance = 0;
  /// With weld_tolerance 0: measure how closely the copies' vertices coincide along the principal
  /// offsets when the Retargeter is built (repeat_precision, restitch/offsets/snap.hpp; docs/method.md 3,
  /// "Measured weld tolerance"), and weld at that precision where it is coarser than the stitcher's own
  /// tolerance (at most 64 times it). Exact copies, and copies whose vertices do not pair, keep the
  /// stitcher's own.
  bool measure_weld_tolerance = true;
  /// Keep content that occurs once where it belongs (docs/method.md 2.10, restitch/lattice/structure.hpp):
  /// a slab along a resized axis that is a copy of neither neighbour (an end, a centred key, a valve, a tall
  /// drawer) is copied exactly once, at the same distance from the end it is near or at the centre, a shrink
  /// that cannot hold it is refused, and the origin's content stays put (restitch/placement.hpp). Off: the
  /// labelling as the paper's, with anchored ends only (docs/method.md 2.3).
  bool keep_parts = true;
  /// Threads that propose the solver's expansion moves, set on a solver with a `threads` member
  /// (AlphaExpansion::threads; the result is bit-identical whatever the count): 1 (default) the calling
  /// thread, 0 every hardware thread; refused (invalid_argument) outside [0, 1024]. Used where the seam
  /// energy's terms are computed up front (the descriptor energy) and the problem is large enough.
  int threads = 1;
};

namespace detail {
template <class = void>
std::string format_size(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}
template <class = void>
std::string format_point(const Eigen::Vector3d& p) {
  return "(" + format_size(p.x()) + ", " + format_size(p.y()) + ", " + format_size(p.z()) + ")";
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

namespace detail {
/// Whether `typed` is `size` written with as many significant digits as `typed` has (the fewest that
/// give `typed` back), when that is 3 or more: 10.361 and 10.4 are 10.3606 as a viewer shows it, 10.5 is
/// not, and 8 is not 8.04 (one digit is not a measurement).
template <class = void>
bool same_at_typed_precision(double typed, double size) {
  if (!std::isfinite(typed) || !std::isfinite(size) || typed <= 0 || size <= 0) return false;
  char a[40], b[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(a, sizeof a, "%.*g", digits, typed);
    if (std::strtod(a, nullptr) != typed) continue;
    if (digits < 3) return false;
    std::snprintf(b, sizeof b, "%.*g", digits, size);
    return std::strcmp(a, b) == 0;
  }
  return false;
}
}  // namespace detail

/// Per world axis: does `target` (0 keeps an axis) ask a model of bounding-box size `size` to change
/// along it? No change: within 1e-5 of the current size (relative, at least 1e-8 of the box diagonal),
/// or the current size rounded to the significant digits typed, 3 or more (detail::same_at_typed_precision),
/// so a size typed from a printed or displayed one is no change.
template <class = void>
std::array<bool, 3> size_changes(const Eigen::Vector3d& target, const Eigen::Vector3d& size) {
  std::array<bool, 3> out{{false, false, false}};
  for (int i = 0; i < 3; ++i)
    out[std::size_t(i)] = target[i] != 0 &&
                          !(std::abs(target[i] - size[i]) <= 1e-5 * std::max(size[i], 1e-3 * size.norm())) &&
                          !detail::same_at_typed_precision(target[i], size[i]);
  return out;
}

/// ok, or why `target` (model units, 0 keeps an axis) cannot be asked of a model of bounding-box size
/// `size_in` whose lattice is `L`: a negative or non-finite component, or a size change along a world
/// axis no principal offset runs along (world_axis_of), both invalid_argument naming the axis.
template <class = void>
Status check_size(const Lattice& L, const Eigen::Vector3d& size_in, const Eigen::Vector3d& target) {
  std::array<bool, 3> covered{{false, false, false}};
  for (int a = 0; a < 3; ++a)
    if (!L.dummy[a]) covered[std::size_t(world_axis_of(L.A.col(a)))] = true;
  RESTITCH_TRY(check_size_values(target));
  const std::array<bool, 3> change = size_changes(target, size_in);
  for (int i = 0; i < 3; ++i) {
    const std::string axis(1, "xyz"[i]);
    if (change[std::size_t(i)] && !covered[std::size_t(i)])
      return error(StatusCode::invalid_argument,
                   "no repeat runs along " + axis + ", so its size cannot change (asked " +
                       detail::format_size(target[i]) + ", the model is " + detail::format_size(size_in[i]) +
                       "); give 0 to keep " + axis);
  }
  return {};
}

/// The lattice steps whose result's bounding box is nearest to `target` (model units, 0 keeps an axis;
/// checked by check_size) for a model of size `size_in` whose lattice is `L`: every achievable step
/// count along each principal offset (at most `max_steps` added), the box growing by |v_a| per step.
/// Nearest by relative squared error; the first on a tie (lowest w, then v, then u).
template <class = void>
Result<Eigen::Array3i> nearest_steps(const Lattice& L, const Eigen::Vector3d& size_in, const Eigen::Vector3d& target,
                                     int max_steps) {
  RESTITCH_TRY(check_size(L, size_in, target));
  Eigen::Vector3d want = target;
  for (int i = 0; i < 3; ++i)
    if (!(want[i] > 0)) want[i] = size_in[i];
  Eigen::Array3i lo = Eigen::Array3i::Zero(), hi = Eigen::Array3i::Zero();
  for (int a = 0; a < 3; ++a)
    if (!L.dummy[a]) lo[a] = 1 - L.cells[a], hi[a] = max_steps;
  Eigen::Array3i best = Eigen::Array3i::Zero();
  double best_err = INFINITY;
  for (int w = lo[2]; w <= hi[2]; ++w)
    for (int v = lo[1]; v <= hi[1]; ++v)
      for (int u = lo[0]; u <= hi[0]; ++u) {
        // Each step along v_a moves the far end by v_a: the box grows by |v_a| per component.
        Eigen::Vector3d size = size_in;
        const Eigen::Array3i s(u, v, w);
        for (int a = 0; a < 3; ++a) size += L.A.col(a).cwiseAbs() * s[a];
        const double err = (size - want).cwiseQuotient(size_in.cwiseMax(1e-12)).squaredNorm();
        if (err < best_err - 1e-12) best_err = err, best = s;
      }
  return best;
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


/// Lattice steps from steps along the world axes x, y, z: each non-zero value goes to the lattice axis
/// that runs along that world axis (world_axis_of). A non-zero value along a world axis no principal
/// offset runs along is invalid_argument naming the axis (no_repetition when the model has none).
template <class = void>
Result<Eigen::Array3i> lattice_steps_from_world(const Analysis& analysis, const Eigen::Array3i& world_steps) {
  Eigen::Array3i out = Eigen::Array3i::Zero();
  const Lattice& L = analysis.lattice;
  for (int w = 0; w < 3; ++w) {
    if (world_steps[w] == 0) continue;
    int axis = -1;
    for (int a = 0; a < 3; ++a)
      if (!L.dummy[a] && world_axis_of(L.A.col(a)) == w) axis = a;
    if (axis < 0)
      return analysis.principal.empty()
                 ? error(StatusCode::no_repetition,
                         "no repetition was found in this model, so there is nothing to resize along")
                 : error(StatusCode::invalid_argument,
                         std::string("no repeat runs along ") + "xyz"[w] + ", so it cannot be resized along it");
    out[axis] = world_steps[w];
  }
  return out;
}

}  // namespace restitch
