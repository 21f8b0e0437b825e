// restitch/analysis.hpp - the analysis driver: offset statistics, principal offsets and the lattice of a mesh.
//
// `restitch::analyze(mesh, options, progress)` runs method.md section 1 end to
// end and returns an `Analysis`: everything the retarget step needs, so
// nothing is computed twice.
//
//   1. normalization  centre the model, scale its longest side to [-1, 1]
//   2. sampling       dense Poisson-disk samples (0.02) = the descriptor
//                     support; features = Poisson-disk samples (0.06) followed
//                     by the mesh vertices (merged, capped at 20 000)
//   3. descriptors    one descriptor row per feature (policy, default SHOT)
//   4. matching       per feature the most similar feature beyond tau = 0.15
//                     (policy, default exact brute force)
//   5. histogram,     the offset detector (policy, default the paper's
//      refinement     histogram + NMS + ICP + significance test; the mesh
//                     vertices serve as exact ICP anchors)
//   6. lattice        significant dominant offsets reduced to fundamentals
//                     (an offset that is k >= 2 times a shorter one becomes
//                     that one), greedy principal offsets, dummy directions,
//                     grid phase, input cells (offsets/principal.hpp,
//                     lattice/fit.hpp)
//
// Policies are passed as objects inside `AnalysisOptions` (their run-time
// parameters, e.g. the descriptor radius, are members). Each one's contract
// is checked at compile time here with a readable message:
// is_descriptor_policy_v (descriptor/descriptor.hpp), is_matcher_policy_v
// (matcher/matcher.hpp), is_offset_detector_v (offsets/detector.hpp).
//
// Policy names (Analysis::descriptor_name etc.): a policy's
// `static constexpr const char* name` if it has one, else a `name()` member,
// else `policy_name_of<T>` (specialised below for the shipped policies:
// "shot", "fpfh", "brute_force", "reduced"; "custom" otherwise). A user's
// policy should simply declare `static constexpr const char* name = "...";`.
//
// Seeds: the dense sampling uses `seed`, the feature sampling `seed + 1` and
// the vertex thinning `seed + 2`, so the two Poisson-disk samples are
// independent and the whole analysis is a function of (mesh, options).
//
// Contract: `mesh` is checked by restitch::validate and its Status returned
// on bad input. A model without repetition is not an error: it yields zero
// principal offsets and a lattice of three dummy axes (the retarget step
// reports StatusCode::no_repetition when asked to resize along nothing).
// Progress: the stages report under the names "sampling", "descriptors",
// "matching", "histogram", "refinement", "lattice"; a callback returning false
// cancels (StatusCode::cancelled). Never throws; deterministic; no threads.
// Units: everything in Analysis is normalized except `lattice` (model units)
// and `principal_model_units()`.
//
// Cost (the defaults, measured on the sample models, see
// tests/analysis_test.cpp): dominated by the descriptors, O(#features * k)
// with k ~ 100-300 support points per feature, and by exact matching,
// O(#features^2 * D); the rest is O(#dense log #dense).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/descriptor/fpfh.hpp"
#include "restitch/descriptor/shot.hpp"
#include "restitch/lattice/fit.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/matcher/brute_force.hpp"
#include "restitch/matcher/matcher.hpp"
#include "restitch/matcher/reduced.hpp"
#include "restitch/mesh.hpp"
#include "restitch/normalization.hpp"
#include "restitch/offsets/detector.hpp"
#include "restitch/offsets/histogram.hpp"
#include "restitch/offsets/principal.hpp"
#include "restitch/offsets/snap.hpp"
#include "restitch/progress.hpp"
#include "restitch/sampling/features.hpp"
#include "restitch/sampling/poisson_disk.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// Name of a policy type that has neither `name` nor `name()`: specialise for your type, or give it a `name`.
template <class T>
struct policy_name_of {
  static const char* get() { return "custom"; }
};
template <>
struct policy_name_of<ShotDescriptor> {
  static const char* get() { return "shot"; }
};
template <>
struct policy_name_of<FpfhDescriptor> {
  static const char* get() { return "fpfh"; }
};
template <>
struct policy_name_of<BruteForceMatcher> {
  static const char* get() { return "brute_force"; }
};
template <>
struct policy_name_of<ReducedMatcher> {
  static const char* get() { return "reduced"; }
};

namespace detail {
template <class T, class = void>
struct has_static_name : std::false_type {};
template <class T>
struct has_static_name<T, std::void_t<decltype(T::name)>> : std::is_convertible<decltype(T::name), const char*> {};
template <class T, class = void>
struct has_name_function : std::false_type {};
template <class T>
struct has_name_function<T, std::void_t<decltype(std::declval<const T&>().name())>>
    : std::is_convertible<decltype(std::declval<const T&>().name()), std::string> {};
}  // namespace detail

/// A policy's name for reports (see the header comment).
template <class T>
std::string policy_name(const T& policy) {
  if constexpr (detail::has_static_name<T>::value) {
    (void)policy;
    return T::name;
  } else if constexpr (detail::has_name_function<T>::value) {
    return policy.name();
  } else {
    (void)policy;
    return policy_name_of<T>::get();
  }
}

/// Options of `analyze`. Lengths are normalized (the model's longest side spans 2).
template <class Descriptor = ShotDescriptor, class Matcher = BruteForceMatcher,
          class Detector = HistogramOffsetDetector>
struct AnalysisOptions {
  Descriptor descriptor{};
  Matcher matcher{};
  Detector detector{};
  double dense_spacing = 0.02;                    ///< dense Poisson-disk spacing: the descriptor support
  double feature_spacing = 0.06;                  ///< feature Poisson-disk spacing
  std::size_t vertex_cap = 20000;                 ///< at most this many mesh vertices become features (0: none)
  float tau = 0.15f;                              ///< matches must be farther apart than this
  std::uint64_t seed = 1;                         ///< see the header comment
  double min_angle = 3.14159265358979323846 / 3;  ///< between principal offsets
  double dummy_length = 0.2;                      ///< length of dummy directions
  LatticeFitOptions lattice{};                    ///< grid phase and end slivers
  /// Refine each principal offset onto the mesh's own vertices (offsets/snap.hpp),
  /// so exactly copied geometry gives exact offsets; kept only where supported.
  bool snap_to_vertices = true;
  SnapOptions snap{};
};

/// Everything the analysis found (see the header comment for units).
struct Analysis {
  Normalization normalization;
  PointSet dense;                          ///< dense samples, normalized
  PointSet features;                       ///< Poisson features, then vertex features; normalized
  std::size_t sampled_features = 0;        ///< features [0, sampled_features) are Poisson samples, the rest vertices
  DescriptorMatrix descriptors;            ///< #features by D
  std::vector<Match> matches;              ///< one per feature
  std::vector<DominantOffset> dominant;    ///< ranked by votes; refined offsets, normalized
  std::vector<Eigen::Vector3d> principal;  ///< the real principal offsets only, normalized, in selection order
  PrincipalOffsets axes;                   ///< principal offsets completed by dummies, normalized
  Lattice lattice;                         ///< model units, dummies included
  Eigen::Matrix3d A_normalized = Eigen::Matrix3d::Identity();   ///< lattice axes, normalized
  Eigen::Vector3d origin_normalized = Eigen::Vector3d::Zero();  ///< lattice origin, normalized space
  Eigen::Array3d phase = Eigen::Array3d::Zero();                ///< chosen grid phase per axis
  Sparsity sparsity;                                            ///< top7, top20 (the paper's Fig. 5)
  std::size_t histogram_peaks = 0;                              ///< peaks found by non-maximum suppression
  std::map<std::string, double> timings_ms;  ///< sampling, descriptors, matching, histogram, refinement, lattice
  std::string descriptor_name, matcher_name, detector_name;

  /// The real principal offsets in model units.
  std::vector<Eigen::Vector3d> principal_model_units() const {
    std::vector<Eigen::Vector3d> out;
    for (const Eigen::Vector3d& v : principal) out.push_back(normalization.to_model_offset(v));
    return out;
  }
};

/// Runs the analysis (see the header comment).
template <class D = ShotDescriptor, class M = BruteForceMatcher, class Det = HistogramOffsetDetector>
Result<Analysis> analyze(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options = {},
                         const Progress& progress = {}) {
  static_assert(is_descriptor_policy_v<D>,
                "restitch::analyze: the descriptor policy must provide `int dimension() const` and `Status "
                "compute(const PointSet&, const PointSet&, DescriptorMatrix&, const Progress&) const` "
                "(see restitch/descriptor/descriptor.hpp)");
  static_assert(is_matcher_policy_v<M>,
                "restitch::analyze: the matcher policy must provide `Status match(const PointSet&, const "
                "DescriptorMatrix&, float, std::vector<Match>&, const Progress&) const` "
                "(see restitch/matcher/matcher.hpp)");
  static_assert(is_offset_detector_v<Det>,
                "restitch::analyze: the offset detector policy must provide `static constexpr const char* name` "
                "and `Status detect(const OffsetEvidence&, OffsetDetection&, const Progress&) const` "
                "(see restitch/offsets/detector.hpp)");
  using clock = std::chrono::steady_clock;
  const auto finite_positive = [](double x) { return x > 0 && std::isfinite(x); };
  if (!finite_positive(options.dense_spacing) || !finite_positive(options.feature_spacing))
    return error(StatusCode::invalid_argument, "the sampling spacings must be positive finite lengths");
  if (!(options.tau >= 0) || !std::isfinite(options.tau))
    return error(StatusCode::invalid_argument, "tau must be a non-negative finite length");
  if (!(options.min_angle > 0 && options.min_angle <= 3.14159265358979323846 / 2))
    return error(StatusCode::invalid_argument, "the minimum angle between principal offsets must be in (0, pi/2]");
  if (!finite_positive(options.dummy_length))
    return error(StatusCode::invalid_argument, "the dummy direction length must be a positive finite length");
  RESTITCH_TRY(validate(mesh));
  const auto cancelled = [](const char* stage) {
    return error(StatusCode::cancelled, std::string("analysis cancelled during ") + stage);
  };

  Analysis a;
  a.descriptor_name = policy_name(options.descriptor);
  a.matcher_name = policy_name(options.matcher);
  a.detector_name = policy_name(options.detector);
  a.normalization = Normalization::of(bounding_box(mesh));

  // Sampling.
  PointSet anchors;  // the vertex features, for the offset refinement
  auto t0 = clock::now();
  if (!progress.report("sampling", 0)) return cancelled("sampling");
  {
    Result<PointSet> dense = poisson_disk_sample(mesh, a.normalization, options.dense_spacing, options.seed, progress);
    if (!dense) return dense.status();
    Result<PointSet> sampled =
        poisson_disk_sample(mesh, a.normalization, options.feature_spacing, options.seed + 1, progress);
    if (!sampled) return sampled.status();
    Result<PointSet> vertices =
        vertex_features(mesh, a.normalization, options.vertex_cap, options.dense_spacing, options.seed + 2);
    if (!vertices) return vertices.status();
    a.dense = std::move(*dense);
    a.sampled_features = std::size_t(sampled->size());
    a.features = concat(*sampled, *vertices);
    anchors = std::move(*vertices);
  }
  a.timings_ms["sampling"] = detail::elapsed_ms(t0);
  if (!progress.report("sampling", 1)) return cancelled("sampling");

  // Descriptors.
  t0 = clock::now();
  if (!progress.report("descriptors", 0)) return cancelled("descriptors");
  RESTITCH_TRY(options.descriptor.compute(a.dense, a.features, a.descriptors, progress));
  if (a.descriptors.rows() != a.features.size())
    return error(StatusCode::internal, "the descriptor policy returned a wrong number of rows");
  a.timings_ms["descriptors"] = detail::elapsed_ms(t0);
  if (!progress.report("descriptors", 1)) return cancelled("descriptors");

  // Matching.
  t0 = clock::now();
  if (!progress.report("matching", 0)) return cancelled("matching");
  RESTITCH_TRY(options.matcher.match(a.features, a.descriptors, options.tau, a.matches, progress));
  if (a.matches.size() != std::size_t(a.features.size()))
    return error(StatusCode::internal, "the matcher policy returned a wrong number of matches");
  a.timings_ms["matching"] = detail::elapsed_ms(t0);
  if (!progress.report("matching", 1)) return cancelled("matching");

  // Offset detection (histogram, refinement).
  {
    OffsetDetection det;
    const OffsetEvidence evidence{a.dense, a.features, a.matches, options.dense_spacing, double(options.tau), &anchors};
    RESTITCH_TRY(options.detector.detect(evidence, det, progress));
    a.dominant = std::move(det.dominant);
    a.sparsity = det.sparsity;
    a.histogram_peaks = det.peaks;
    for (const auto& kv : det.timings_ms) a.timings_ms[kv.first] = kv.second;
  }

  // Principal offsets and lattice.
  t0 = clock::now();
  if (!progress.report("lattice", 0)) return cancelled("lattice");
  std::vector<Eigen::Vector3d> significant;
  std::vector<int> where;  // index in a.dominant of each significant offset
  for (std::size_t i = 0; i < a.dominant.size(); ++i)
    if (a.dominant[i].significant) significant.push_back(a.dominant[i].offset), where.push_back(int(i));
  a.axes = select_principal_offsets(reduce_to_fundamentals(significant, options.dense_spacing), options.min_angle,
                                    options.dummy_length);
  for (int& s : a.axes.source)
    if (s >= 0) s = where[std::size_t(s)];  // PrincipalOffsets::source indexes Analysis::dominant
  if (options.snap_to_vertices && a.axes.real_count > 0) {
    // Unique vertex positions, normalized, in a fixed order (offsets/snap.hpp).
    std::vector<std::array<float, 3>> unique(std::size_t(mesh.V.rows()));
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
      unique[std::size_t(i)] = {mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2)};
    std::sort(unique.begin(), unique.end());
    unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
    Eigen::Matrix<double, Eigen::Dynamic, 3> P(Eigen::Index(unique.size()), 3);
    for (std::size_t i = 0; i < unique.size(); ++i)
      P.row(Eigen::Index(i)) =
          a.normalization.to_normalized(Eigen::Vector3d(unique[i][0], unique[i][1], unique[i][2])).transpose();
    for (int k = 0; k < a.axes.real_count; ++k) {
      const SnapResult snapped = snap_offset(P, a.axes.axes[std::size_t(k)], options.snap);
      if (snapped.snapped) a.axes.axes[std::size_t(k)] = snapped.offset;
    }
  }
  for (int k = 0; k < a.axes.real_count; ++k) a.principal.push_back(a.axes.axes[std::size_t(k)]);
  {
    Result<LatticeFit> fit = fit_lattice(mesh, a.normalization, a.dense, a.axes, options.lattice);
    if (!fit) return fit.status();
    a.lattice = fit->lattice;
    a.A_normalized = fit->A_normalized;
    a.origin_normalized = fit->origin_normalized;
    a.phase = fit->phase;
  }
  a.timings_ms["lattice"] = detail::elapsed_ms(t0);
  if (!progress.report("lattice", 1)) return cancelled("lattice");
  return a;
}

}  // namespace restitch
