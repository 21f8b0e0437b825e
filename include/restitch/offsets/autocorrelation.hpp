// restitch/offsets/autocorrelation.hpp - the translational symmetry transform S_T by FFT, an offset detector built
// on it, and S_T as a structure score of a mesh.
//
// docs/method.md 1.9. Kim, Lipman, Funkhouser 2012 ("Symmetry-guided texture
// synthesis", Eq. 2) describe the translational structure of a function f by
// its normalised autocorrelation
//
//   S_T(f)(t) = sum_x f(x) f(x + t) / ||f||^2.
//
// Here f is the surface of a model, voxelised from its dense samples, and the
// peaks of S_T are the model's dominant offsets, found without descriptors or
// matches.
//
// The field (`symmetry_transform`):
//  * Voxel edge h = `voxel_factor` (2) x the dense spacing s (0.02, so
//    h = 0.04 normalized units). Two spacings because (a) the dense samples
//    hold only about 0.5 points per s^2, so voxels of one spacing that a face
//    crosses are often empty and the field is speckled, while a near-maximal
//    sample (every surface point within s of a sample) puts at least one
//    sample into every 2s x 2s patch of a face; (b) a peak is then known to
//    half a voxel diagonal, 0.035, inside the 0.043 (half a histogram bin
//    diagonal) the ICP's first stage was designed to capture
//    (offsets/refine.hpp); (c) the longest side spans 50 voxels, so a grid is
//    at most about 108^3 cells after padding, which the FFT does in a
//    fraction of a second.
//  * Trilinear splatting: each sample adds its trilinear weights (summing to
//    1) to the 8 voxels around it. This is the "mild blur": a face whose
//    translate falls between voxel layers still correlates with its copy (at
//    half a voxel off, 72% of the value in a voxel-aligned position, against
//    0% to 100% for nearest-voxel counting), so near-coincident surfaces count
//    and a peak depends little on where the voxel grid falls.
//  * The grid starts at floor(min / h) * h (the points' coordinates, per
//    axis), so two point sets in the same frame are voxelised on the same
//    grid. n_a = floor((max_a - origin_a) / h) + 2 voxels per axis.
//  * Zero padding: a linear (not circular) autocorrelation over the offsets
//    |t_a| <= n_a - 1 needs FFTs of N_a >= 2 n_a - 1 points (offsets t and
//    t - N_a must not alias); N_a is the smallest such size with no prime
//    factor above 5 (kissfft's fast radices).
//  * Limit: the padded grid may hold at most `max_cells` (2^22, 64 MiB of
//    complex doubles) cells. A larger grid is never allocated: the voxel edge
//    grows (by the cube root of the excess, at least 5% a step) until the
//    grid fits, and `SymmetryTransform::voxel` reports the edge used. The
//    default analysis never needs it (at most 108^3 = 1.26M cells).
//
// S_T (`autocorrelate`): R = IFFT(|FFT(f)|^2) with Eigen's FFT module
// (unsupported/Eigen/FFT, kissfft), 3-D as 1-D transforms along x, y, z.
// Lines that are all zero (the padding) are skipped going forward, and lines
// whose results are not needed are skipped going back. S_T(t) = R(t) / R(0),
// R(0) = ||f||^2 = sum_x f(x)^2, exactly: S_T(0) = 1 (to rounding), S_T(t) =
// S_T(-t), and since f >= 0, 0 <= S_T(t) <= 1 (Cauchy-Schwarz). For a voxel
// offset t, S_T(t) is the share of the surface's squared field that lands on
// the surface under t: about the share of the surface that maps onto itself
// (n copies of a module, shifted by the period: (n-1)/n of them), somewhat
// less for a sampled surface (copies are sampled independently) and less
// again for a period that falls between voxels.
// The paper further standardises S_T to mean 0, variance 1; restitch keeps
// the plain ratio because it is a share, comparable between models and with
// the overlap thresholds of the refinement.
//
// Peaks (`symmetry_peaks`): t and -t are the same offset, so only the half of
// the grid after its centre in memory order is searched: t_z > 0, or t_z = 0
// and t_y > 0, or t_z = t_y = 0 and t_x > 0. S_T itself is a poor peak
// signal: a plate or a wall sliding along itself makes S_T fall linearly
// from 1, and a period on it (the facade's windows) is a shoulder of that
// slope, not a local maximum. So peaks are taken on the radial contrast
//   K(t) = S_T(t) - (S_T(t - d u) + S_T(t + d u)) / 2,  u = t / |t|,
// d = `contrast_distance` (2 voxels; S_T interpolated trilinearly), the
// second difference the significance test applies to the overlap: about 0
// on a slide, positive at a period. A peak is a voxel offset longer than
// tau whose K is at least every one of its 26 neighbours' (strictly above
// those earlier in memory order, so a plateau gives one peak), with
// K >= `min_contrast` (0.002) and S_T >= `min_value`. Peaks are ranked by
// S_T (ties: memory order) and thinned by non-maximum suppression: one within
// `suppression_radius` (0.15, as the histogram's) of a stronger kept peak or
// of its negative is dropped. Each peak's position is refined per axis by
// the vertex of the parabola through K at t - e, t, t + e (clamped to half a
// voxel).
//
// AutocorrelationOffsetDetector (a policy of offsets/detector.hpp):
//  1. S_T of the dense samples (evidence.dense, normalized), peaks with
//     S_T >= `min_strength` (0.1) and K >= `min_peak_contrast` (0.002), the
//     `max_peaks` (20) strongest. min_strength is well under the overlap
//     test's 1/3, because S_T underestimates the overlap (sampling, voxel
//     phase); it only keeps noise out of the refinement. The contrast
//     threshold is low because the facade's window periods reach only
//     0.01-0.02 on a wall that dominates S_T; a sampled plate's slide stays
//     below it, and chance coincidences that pass it are the refinement's
//     to reject.
//  2. The histogram detector's refinement and significance tests
//     (refine_and_test, offsets/detector.hpp), started from the peaks, so
//     its DominantOffsets mean the same: ICP from the peak, overlap >= 1/3, a
//     peak and not a slide, a pattern and not a pair. `votes` (and
//     `bin_votes`) = round(S_T(peak) x #dense samples): the number of dense
//     samples S_T says land on the surface. The mass test is replaced by
//     min_strength (min_votes = 0 in the shared tests). One test is added
//     (SignificanceOptions::axis_contrast): the contrast must also hold at
//     2t along each world axis. S_T sees combinations the histogram's
//     shortest-offset votes never propose: on the fence sample a picket
//     period plus the gap between the two rails, which maps one rail onto
//     the other while the pickets slide along themselves, is a strict
//     maximum at t and keeps overlap at 2t through the sliding pickets; at
//     2t the rails no longer meet, so along y it is a pure slide.
//  It ignores features and matches (`uses_matches = false`, so analyze()
//  skips the matching stage), reports progress and timings under
//  "autocorrelation" and "refinement", and leaves the sparsity at 0 (it has
//  no histogram). OffsetDetection::peaks counts the peaks after suppression,
//  before the max_peaks cap.
//
// Structure score (`structure_score`, `structure_at`): S_T of a mesh's
// surface, sampled like the analysis (Poisson-disk, spacing 0.02, seed 1,
// normalized units). `structure_score(mesh)` is the strongest translational
// symmetry of the mesh in its own normalization: the largest S_T over its 8
// strongest peaks longer than tau (0.15; no minimum S_T), each measured at its
// sub-voxel position (see `symmetry_at`); 0 without a peak. Sliding large
// faces count too (the samples score 0.77-0.84, random boxes 0.43-0.69). `structure_at(mesh, offsets, reference)`
// measures S_T of `mesh` at given offsets (model units) in a *reference*
// normalization (e.g. the input's Analysis::normalization) so that an input
// and its resized results are sampled and voxelised on the same grid:
// S_T at the input's principal offsets is how much of the input's
// translational structure a result keeps (a perfect resize by k modules of
// n gives about (n+k-1)/(n+k) of the repeated part).
// `symmetry_at(points, transform, t)` evaluates S_T at any offset t:
// sum_x f(x) g_t(x) / ||f||^2 with g_t the splat of the samples moved by t.
// At a voxel offset that is exactly the FFT's S_T (to rounding); between
// voxels the moved samples are splatted again instead of interpolating S_T,
// so a period's value does not depend on how it falls on the grid.
//
// Units: those of the points (normalized in the analysis). Deterministic (no
// threads, no randomness; kissfft's plans depend only on the sizes). Never
// throws (allocation failure aside, as everywhere in restitch).
// Cost: splatting O(#points); FFT O(N log N) for N = N_x N_y N_z padded
// cells (at most `max_cells`), two complex doubles per cell of memory; peaks
// O(N); refinement as in offsets/detector.hpp.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unsupported/Eigen/FFT>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/mesh.hpp"
#include "restitch/normalization.hpp"
#include "restitch/offsets/detector.hpp"
#include "restitch/progress.hpp"
#include "restitch/sampling/poisson_disk.hpp"
#include "restitch/status.hpp"
#include "restitch/offsets/symmetry_transform.hpp"

namespace restitch {

/// The shared significance tests as the autocorrelation detector runs them (see the header comment).
template <class = void>
SignificanceOptions autocorrelation_significance() {
  SignificanceOptions s;
  s.min_votes = 0;
  s.axis_contrast = true;
  s.part.enabled = false;
  return s;
}

/// The autocorrelation offset detector (see the header comment; the policy contract is in offsets/detector.hpp).
struct AutocorrelationOffsetDetector {
  static constexpr const char* name = "autocorrelation";
  static constexpr bool uses_matches = false;  ///< analyze() skips the matching stage

  SymmetryFieldOptions field{};      ///< voxel edge 2 x the dense spacing, at most 2^22 padded cells
  double min_strength = 0.1;         ///< S_T at a peak at least this to be refined
  double min_peak_contrast = 0.002;  ///< the radial contrast of S_T at a peak at least this
  double contrast_distance = 2;      ///< d of the radial contrast, in voxels
  double suppression_radius = 0.15;
  std::size_t max_peaks = 20;
  /// The significance tests, for refine_and_test: no mass test (min_strength filters first), the
  /// contrast along each world axis at 2t (see the header comment), and no part test (no votes).
  SignificanceOptions significance = autocorrelation_significance();

  template <class = void>
  Status detect(const OffsetEvidence& ev, OffsetDetection& out, const Progress& progress) const {
    return detail::guarded("AutocorrelationOffsetDetector::detect", [&]() -> Status {
      out = OffsetDetection{};
      if (ev.dense.normals.rows() != ev.dense.points.rows())
        return error(StatusCode::invalid_argument, "the dense samples need one normal per point");
      if (!(ev.dense_spacing > 0) || !std::isfinite(ev.dense_spacing) || !(ev.tau >= 0) || !std::isfinite(ev.tau))
        return error(StatusCode::invalid_argument, "the dense spacing must be positive and tau non-negative");
      if (!(max_peaks >= 1 && significance.valid() && suppression_radius >= 0 && std::isfinite(suppression_radius) &&
            min_strength >= 0 && min_strength <= 1 && std::isfinite(min_peak_contrast) && contrast_distance > 0 &&
            std::isfinite(contrast_distance)))
        return error(StatusCode::invalid_argument, "AutocorrelationOffsetDetector parameters out of range");

      // 1. S_T and its peaks.
      auto t0 = std::chrono::steady_clock::now();
      SymmetryTransform st;
      RESTITCH_TRY(symmetry_transform(ev.dense.points, ev.dense_spacing, field, st, progress, "autocorrelation"));
      SymmetryPeakOptions po;
      po.tau = ev.tau;
      po.min_value = min_strength;
      po.min_contrast = min_peak_contrast;
      po.contrast_distance = contrast_distance;
      po.suppression_radius = suppression_radius;
      const std::vector<SymmetryPeak> peaks = symmetry_peaks(st, po);
      out.peaks = peaks.size();
      out.timings_ms["autocorrelation"] = detail::elapsed_ms(t0);
      if (!progress.report("autocorrelation", 1))
        return error(StatusCode::cancelled, "cancelled during the autocorrelation");

      // 2. Refinement and significance, shared with the histogram detector.
      t0 = std::chrono::steady_clock::now();
      std::vector<OffsetCandidate> todo;
      const double dense = double(ev.dense.size());
      for (std::size_t k = 0; k < peaks.size() && k < max_peaks; ++k) {
        const auto votes = std::size_t(std::llround(peaks[k].value * dense));
        todo.push_back({peaks[k].offset, votes, votes, {}});
      }
      RESTITCH_TRY(refine_and_test(ev, todo, significance, progress, out.dominant));
      out.timings_ms["refinement"] = detail::elapsed_ms(t0);
      if (!progress.report("refinement", 1)) return error(StatusCode::cancelled, "cancelled during offset refinement");
      return {};
    });
  }
};

/// How a mesh is sampled and voxelised for a structure score (normalized units).
struct StructureScoreOptions {
  double spacing = 0.02;  ///< Poisson-disk spacing of the samples (the analysis' dense spacing)
  std::uint64_t seed = 1;
  double tau = 0.15;  ///< structure_score: only offsets longer than this count
  SymmetryFieldOptions field{};
};

/// S_T of several offsets of one mesh, and the voxel edge it was measured with (normalized units).
struct StructureValues {
  std::vector<double> values;  ///< S_T at each offset, in order
  double voxel = 0;            ///< voxel edge used (grows beyond 2 x spacing only for very large meshes)
};

namespace detail {
template <class = void>
Status sample_for_structure(const Mesh& mesh, const Normalization& norm, const StructureScoreOptions& o,
                                   const Progress& progress, PointSet& samples) {
  RESTITCH_TRY(validate(mesh));
  Result<PointSet> s = poisson_disk_sample(mesh, norm, o.spacing, o.seed, progress);
  if (!s) return s.status();
  samples = std::move(*s);
  return {};
}
}  // namespace detail

/// The strongest translational symmetry of a mesh (see the header comment): in [0, 1], 0 without a peak.
template <class = void>
Result<double> structure_score(const Mesh& mesh, const StructureScoreOptions& options = {},
                                      const Progress& progress = {}) {
  return detail::guarded("structure_score", [&]() -> Result<double> {
    PointSet samples;
    RESTITCH_TRY(detail::sample_for_structure(mesh, Normalization::of(bounding_box(mesh)), options, progress, samples));
    SymmetryTransform st;
    RESTITCH_TRY(symmetry_transform(samples.points, options.spacing, options.field, st, progress, "structure"));
    // The 8 strongest peaks (suppression as in the detector), each measured at its sub-voxel position.
    double best = 0;
    SymmetryPeakOptions po;
    po.tau = options.tau;
    po.min_value = 0;
    po.max_count = 8;
    for (const SymmetryPeak& p : symmetry_peaks(st, po))
      best = std::max(best, symmetry_at(samples.points, st, p.offset));
    return std::min(best, 1.0);
  });
}

/// S_T of `mesh` at each of `offsets` (model units), sampled and voxelised in the `reference` normalization
/// (e.g. the input's Analysis::normalization; see the header comment).
template <class = void>
Result<StructureValues> structure_at(const Mesh& mesh, const std::vector<Eigen::Vector3d>& offsets,
                                            const Normalization& reference, const StructureScoreOptions& options = {},
                                            const Progress& progress = {}) {
  return detail::guarded("structure_at", [&]() -> Result<StructureValues> {
    if (!(reference.scale > 0) || !std::isfinite(reference.scale) || !reference.center.allFinite())
      return error(StatusCode::invalid_argument, "the reference normalization must be finite with a positive scale");
    for (const Eigen::Vector3d& v : offsets)
      if (!v.allFinite()) return error(StatusCode::invalid_argument, "the offsets must be finite");
    PointSet samples;
    RESTITCH_TRY(detail::sample_for_structure(mesh, reference, options, progress, samples));
    SymmetryTransform st;
    RESTITCH_TRY(symmetry_transform(samples.points, options.spacing, options.field, st, progress, "structure"));
    StructureValues out;
    out.voxel = st.voxel;
    for (const Eigen::Vector3d& v : offsets)
      out.values.push_back(symmetry_at(samples.points, st, reference.to_normalized_offset(v)));
    return out;
  });
}

}  // namespace restitch

