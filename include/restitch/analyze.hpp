// restitch/analyze.hpp - the analysis driver: offset statistics, principal offsets and the lattice of a mesh.
//
// `restitch::analyze(mesh, options, progress)` runs docs/method.md section 1 end to
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
//                     vertices serve as exact ICP anchors). The
//                     alternative AutocorrelationOffsetDetector
//                     (offsets/autocorrelation.hpp) reports
//                     "autocorrelation" instead of "histogram" and, since it
//                     ignores matches, step 4 is skipped (Analysis::matches
//                     stays empty, no "matching" timing)
//   6. lattice        each significant dominant offset replaced by its
//                     fundamental period when it is k >= 2 periods long
//                     (tested on the geometry: offsets/fundamental.hpp), then
//                     reduced to fundamentals among themselves (an offset
//                     that is k >= 2 times a shorter one of the list becomes
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
// "matching", "histogram", "refinement", "lattice" (with the autocorrelation
// detector: no "matching", "autocorrelation" for "histogram"); a callback returning false
// cancels (StatusCode::cancelled). Never throws; deterministic: the same Analysis bit for bit whatever
// AnalysisOptions::threads (1, the default, starts no thread).
// Units: everything in Analysis is normalized except `lattice` (model units)
// and `principal_model_units()`.
//
// Cost (the defaults, measured on the sample models, see
// tests/analysis_test.cpp): dominated by the descriptors, O(#features * k)
// with k ~ 100-300 support points per feature, and by exact matching,
// O(#features^2 * D); the rest is O(#dense log #dense).
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/analysis.hpp"
#include "restitch/descriptor/descriptor.hpp"
#include "restitch/detail/instantiation.hpp"
#include "restitch/detail/parallel.hpp"
#include "restitch/descriptor/fpfh.hpp"
#include "restitch/descriptor/shot.hpp"
#include "restitch/lattice/fit.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/lattice/structure.hpp"
#include "restitch/matcher/brute_force.hpp"
#include "restitch/matcher/matcher.hpp"
#include "restitch/matcher/reduced.hpp"
#include "restitch/mesh.hpp"
#include "restitch/normalization.hpp"
#include "restitch/offsets/detector.hpp"
#include "restitch/offsets/fundamental.hpp"
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
  bool flat_vertex_features = false;  ///< also vertices inside flat regions (shape-neutral; sampling/features.hpp)
  float tau = 0.15f;                              ///< matches must be farther apart than this
  std::uint64_t seed = 1;                         ///< see the header comment
  double min_angle = 3.14159265358979323846 / 3;  ///< between principal offsets
  double dummy_length = 0.2;                      ///< length of dummy directions
  LatticeFitOptions lattice{};                    ///< grid phase and end slivers
  /// Refine each principal offset onto the mesh's own vertices (offsets/snap.hpp),
  /// so exactly copied geometry gives exact offsets; kept only where supported.
  bool snap_to_vertices = true;
  SnapOptions snap{};
  /// Replace each significant dominant offset that is k >= 2 periods long by
  /// its fundamental period (offsets/fundamental.hpp).
  bool find_fundamentals = true;
  FundamentalOptions fundamental{};
  /// Look for periods shorter than the dense samples resolve (3 dense spacings) inside the pairs
  /// (docs/method.md 1.6.1), on samples `fine_spacing_ratio` times as far apart.
  bool find_short_periods = true;
  double fine_spacing_ratio = 0.5;
  /// Check each principal offset against the model's structure (docs/method.md 1.12,
  /// restitch/lattice/structure.hpp) and take a divisor of it, or a multiple of it, where that describes
  /// the model better: the shortest t / m (m up to fundamental.max_divisor) whose copies pair vertex for
  /// vertex and repeat as much of the model as t, or, where no two neighbouring cells of t are copies
  /// (modules of two alternating parts), the shortest m t (m up to 4) at which some are.
  bool verify_periods = true;
  /// Along each world axis no principal offset runs along, the shifts at which the vertices that shape the
  /// model repeat, checked against its structure: the shortest whose neighbouring cells are copies over at
  /// least half of what lies between the end slabs is a repeat the matching cast no vote for (three pickets
  /// between two posts; the pitch of a long model, too short for the matching's scales): a principal offset
  /// where the surface is a pattern at it, else a candidate of reason "vertices", which a size asked along
  /// that axis then uses (docs/method.md 1.14).
  bool vertex_repeats = true;
  /// Where a principal axis is undecided on the cheapest grid phase, up to this many other phases at local
  /// minima of the cut cost are tried, cheapest first, and the first on which the axis is decided is taken
  /// (docs/method.md 1.7, Phase by structure; 0: off). Each costs a lattice fit and a one-axis structure,
  /// 50 to 100 ms on a 10k-triangle connector: 8 keep the worst case within about the time the analysis
  /// takes on such a model.
  int max_phases_by_structure = 8;
  /// Make a pair (two copies: a candidate of reason "pair") significant when its copies are exact and make up
  /// at least half of the model: a quarter of the vertices pair, and a quarter of the surface area is
  /// triangles whose corners, moved by it, land on vertices (docs/method.md 1.13). As certain a repeat as a
  /// pattern of five.
  bool exact_pairs = true;
  /// Workers for the descriptors, the matching and the offset refinement (detail/parallel.hpp): 1
  /// runs on the calling thread alone, 0 on every hardware thread. analyze() gives this number to
  /// every policy that has a `threads` member (or a `significance.threads`, the shipped detectors),
  /// overriding theirs. The analysis is bit-identical whatever the number.
  int threads = 1;
};

namespace detail {

/// Runs one named stage of the analysis: reports progress 0 and 1 around
/// `body` (a cancel at either gives StatusCode::cancelled naming the stage)
/// and records its wall-clock time in `timings` under the stage's name.
template <class Body>
Status analysis_stage(const char* stage, const Progress& progress, std::map<std::string, double>& timings,
                      Body&& body) {
  const auto cancelled = [stage] {
    return error(StatusCode::cancelled, std::string("analysis cancelled during ") + stage);
  };
  const auto t0 = std::chrono::steady_clock::now();
  if (!progress.report(stage, 0)) return cancelled();
  RESTITCH_TRY(body());
  timings[stage] = elapsed_ms(t0);
  if (!progress.report(stage, 1)) return cancelled();
  return {};
}

/// The unique positions of the vertices the faces use, normalized, in a fixed (sorted) order: the
/// points offsets are snapped onto (offsets/snap.hpp). A vertex no face uses is not geometry (and may
/// lie anywhere: it would be far outside the normalized box).
template <class = void>
Eigen::Matrix<double, Eigen::Dynamic, 3> unique_normalized_vertices(const Mesh& mesh,
                                                                           const Normalization& normalization) {
  std::vector<std::array<float, 3>> unique;
  unique.reserve(std::size_t(mesh.F.size()));
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Index i = mesh.F(f, k);
      unique.push_back({mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2)});
    }
  std::sort(unique.begin(), unique.end());
  unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
  Eigen::Matrix<double, Eigen::Dynamic, 3> P(Eigen::Index(unique.size()), 3);
  for (std::size_t i = 0; i < unique.size(); ++i)
    P.row(Eigen::Index(i)) =
        normalization.to_normalized(Eigen::Vector3d(unique[i][0], unique[i][1], unique[i][2])).transpose();
  return P;
}

/// Checks the run-time parameters of AnalysisOptions (not the policies').
template <class D, class M, class Det>
Status check_analysis_options(const AnalysisOptions<D, M, Det>& options) {
  const auto finite_positive = [](double x) { return x > 0 && std::isfinite(x); };
  if (!finite_positive(options.dense_spacing) || !finite_positive(options.feature_spacing))
    return error(StatusCode::invalid_argument, "the sampling spacings must be positive finite lengths");
  if (!(options.tau >= 0) || !std::isfinite(options.tau))
    return error(StatusCode::invalid_argument, "tau must be a non-negative finite length");
  if (!(options.min_angle > 0 && options.min_angle <= 3.14159265358979323846 / 2))
    return error(StatusCode::invalid_argument, "the minimum angle between principal offsets must be in (0, pi/2]");
  if (!finite_positive(options.dummy_length))
    return error(StatusCode::invalid_argument, "the dummy direction length must be a positive finite length");
  if (!(options.fine_spacing_ratio > 0 && options.fine_spacing_ratio <= 1))
    return error(StatusCode::invalid_argument, "the fine spacing ratio must be in (0, 1]");
  if (options.threads < 0 || options.threads > 1024)
    return error(StatusCode::invalid_argument, "the number of threads must be in [0, 1024] (0: every hardware thread)");
  return {};
}

/// Stage "sampling": dense samples, then the features (Poisson samples followed
/// by the vertex features, which are also returned as the ICP anchors).
template <class D, class M, class Det>
Status sample_features(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options, const Progress& progress,
                       Analysis& a, PointSet& anchors) {
  Result<PointSet> dense = poisson_disk_sample(mesh, a.normalization, options.dense_spacing, options.seed, progress);
  if (!dense) return dense.status();
  Result<PointSet> sampled =
      poisson_disk_sample(mesh, a.normalization, options.feature_spacing, options.seed + 1, progress);
  if (!sampled) return sampled.status();
  Result<PointSet> vertices =
      vertex_features(mesh, a.normalization, options.vertex_cap, options.dense_spacing, options.seed + 2,
                      options.flat_vertex_features);
  if (!vertices) return vertices.status();
  a.dense = std::move(*dense);
  a.sampled_features = std::size_t(sampled->size());
  a.features = concat(*sampled, *vertices);
  anchors = std::move(*vertices);
  return {};
}

/// Each significant dominant offset replaced by its fundamental period (offsets/fundamental.hpp).
/// `vertices`: the unique vertex positions (normalized), or null when offsets are not snapped.
template <class D, class M, class Det>
void reduce_to_fundamental_periods(const AnalysisOptions<D, M, Det>& options,
                                   const Eigen::Matrix<double, Eigen::Dynamic, 3>* vertices, Analysis& a) {
  if (!options.find_fundamentals || a.dense.size() == 0) return;
  IcpOptions icp;
  icp.spacing = options.dense_spacing;
  std::unique_ptr<SelfAligner> aligner;  // built on the first significant offset only
  FundamentalOptions fo = options.fundamental;
  fo.snap = options.snap;
  for (DominantOffset& d : a.dominant) {
    if (!d.significant) continue;
    if (!aligner) aligner = std::make_unique<SelfAligner>(a.dense, icp);
    const FundamentalPeriod f = fundamental_period(*aligner, d.offset, d.overlap, d.contrast, fo, vertices);
    d.offset = f.offset;
    d.divisor = f.divisor;
  }
}

/// docs/method.md 1.6.1: the periods shorter than the dense samples resolve (3 dense spacings h).
/// A pair t (1.6 never divides pairs), or a significant t so short that 1.6 could not try t / 2
/// (|t| / 2 < 3 h), may be k periods p with |p| = |t| / k under 3 h, where 1.6 cannot look. (A longer
/// significant t is not searched: on most models some t / k passes the screen below, the overlap
/// being blurred over 1.5 h, and the fine samples would cost every model.) For each divisor k with
/// 3 h' <= |t| / k < 3 h, with
/// h' = fine_spacing_ratio x h, a screen on the dense samples first asks what every period has,
/// overlap(t / k) >= overlap(t) - overlap_slack (1.6); the divisors that pass are searched on finer
/// samples at h': for k from the largest down, ICP from t / k on the fine samples gives p; p is kept
/// when t is nearer a multiple m p, m >= 2, than any other (|t - m p| <= |p| / 2: a pair refined on a
/// slide, as the blinds' tilted slats, is a multiple plus part of the slide) and p passes every
/// significance test of offsets/detector.hpp on the fine samples. The first (shortest) kept p
/// replaces t, significant, with its divisor multiplied by m. The fine samples are drawn only when a
/// divisor passes the screen, so most models pay a few overlaps.
template <class D, class M, class Det>
Status find_short_periods(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options,
                          const Eigen::Matrix<double, Eigen::Dynamic, 3>* vertices, Analysis& a) {
  if (!options.find_fundamentals || !options.find_short_periods || a.dense.size() == 0) return {};
  const double h = options.dense_spacing, hf = h * options.fine_spacing_ratio;
  const double coarse_min = options.fundamental.min_length * h, fine_min = options.fundamental.min_length * hf;
  SignificanceOptions tests;
  tests.icp.spacing = h;
  tests.threads = options.threads;
  std::unique_ptr<SelfAligner> coarse;  // built when some offset has a short divisor
  std::vector<std::pair<std::size_t, std::vector<int>>> todo;  // (dominant, divisors that pass the screen)
  const std::vector<Eigen::Vector3d> basis = significant_basis(a.dominant, tests.icp.overlap_radius());
  for (std::size_t i = 0; i < a.dominant.size(); ++i) {
    const DominantOffset& d = a.dominant[i];
    const double len = d.offset.norm();
    if (!d.is_pair() && !(d.significant && len / 2 < coarse_min)) continue;
    // A pair that is an integer combination of significant offsets is searched through them.
    if (d.is_pair() && is_lattice_vector(d.offset, basis, nullptr, tests.icp.overlap_radius())) continue;
    std::vector<int> ks;
    SnapResult exact;  // t's vertex pairs (computed once a divisor passes the overlap screen)
    bool snapped = false;
    for (int k = options.fundamental.max_divisor; k >= 2; --k) {
      if (!(len / k >= fine_min && len / k < coarse_min)) continue;
      if (!coarse) coarse = std::make_unique<SelfAligner>(a.dense, tests.icp);
      if (coarse->overlap(d.offset / double(k)) < coarse->overlap(d.offset) - options.fundamental.overlap_slack)
        continue;
      // Exact copies (offsets/fundamental.hpp): where t's vertices repeat, a period's repeat too, with
      // at least as many pairs; a t / k whose vertices do not is no period, and needs no fine samples.
      if (vertices && !snapped) exact = snap_offset(*vertices, d.offset, options.snap), snapped = true;
      if (exact.snapped) {
        const SnapResult s = snap_offset(*vertices, d.offset / double(k), options.snap);
        if (!s.snapped || s.pairs < exact.pairs) continue;
      }
      ks.push_back(k);
    }
    if (!ks.empty()) todo.emplace_back(i, std::move(ks));
  }
  if (todo.empty()) return {};
  const auto t0 = std::chrono::steady_clock::now();
  Result<PointSet> fine = poisson_disk_sample(mesh, a.normalization, hf, options.seed + 3, {});
  if (!fine) return fine.status();
  a.timings_ms["fine sampling"] = elapsed_ms(t0);  // part of "lattice"; present only when drawn
  tests.icp.spacing = hf;
  const SelfAligner aligner(*fine, tests.icp);
  const double radius = tests.icp.overlap_radius();
  const PointSet no_features;
  const std::vector<Match> no_matches;
  const OffsetEvidence evidence{*fine, no_features, no_matches, hf, fine_min, nullptr};
  std::vector<Eigen::Vector3d> found;  // short periods kept so far: their multiples need no search
  for (const auto& [i, ks] : todo) {
    DominantOffset& d = a.dominant[i];
    bool known = false;
    for (const Eigen::Vector3d& p : found) known = known || is_lattice_vector(d.offset, {}, &p, radius);
    if (known) continue;
    for (const int k : ks) {  // largest divisor first: the shortest period wins
      const Eigen::Vector3d p = aligner.refine(d.offset / double(k)).offset;
      const double m = std::round(d.offset.dot(p) / std::max(p.squaredNorm(), 1e-300));
      if (!(p.norm() >= fine_min) || m < 2 || (d.offset - m * p).norm() > 0.5 * p.norm()) continue;
      std::vector<DominantOffset> tested;
      RESTITCH_TRY(refine_and_test(evidence, {OffsetCandidate{p, d.votes, d.bin_votes, {}}}, tests, {}, tested));
      if (tested.empty() || !tested.front().significant) continue;
      DominantOffset s = std::move(tested.front());
      s.bin_center = d.bin_center;
      s.divisor = d.divisor * int(m);
      std::vector<OffsetTest> record = std::move(d.tests);
      record_test(record, "fine_divisor", m, 2);
      for (OffsetTest& t : s.tests) t.name = "fine_" + t.name, record.push_back(t);
      s.tests = std::move(record);
      d = std::move(s);
      found.push_back(d.offset);
      break;
    }
  }
  return {};
}

/// Analysis::candidates (docs/method.md 1.10): pairs, then significant offsets that are not
/// principal, each skipped when it is an integer combination of the principal offsets or a multiple of
/// an earlier candidate. Ranked as Analysis::dominant. Offsets as refined, not snapped: snapping costs
/// O(#vertices) per offset, and a promoted candidate is snapped as a principal offset anyway.
template <class = void>
void collect_candidates(double tolerance, Analysis& a) {
  a.candidates.clear();
  std::vector<Eigen::Vector3d> taken;  // the candidates so far
  for (const int kind : {0, 1, 2})  // pairs, parallel, vertices
    for (std::size_t i = 0; i < a.dominant.size(); ++i) {
      const DominantOffset& d = a.dominant[i];
      if (d.promoted || !(kind == 0 ? d.is_pair() : kind == 1 ? d.significant : d.from_vertices())) continue;
      const Eigen::Vector3d v = d.offset;
      bool known = is_lattice_vector(v, a.principal, nullptr, tolerance);
      for (const Eigen::Vector3d& e : taken) known = known || is_lattice_vector(v, {}, &e, tolerance);
      if (known) continue;
      taken.push_back(v);
      RepeatCandidate c;
      c.offset = canonical_sign(v);
      c.dominant = int(i);
      c.reason = kind == 0 ? "pair" : kind == 1 ? "parallel" : "vertices";
      // n copies give overlap(2t) / overlap(t) = (n - 2) / (n - 1), so n = (2 - r) / (1 - r).
      const double r = d.overlap > 0 ? std::clamp(d.overlap_double / d.overlap, 0.0, 0.99) : 0.0;
      c.copies = kind == 0 ? 2 : kind == 1 ? std::max(3, int(std::lround((2 - r) / (1 - r)))) : d.copies;
      a.candidates.push_back(c);
    }
  // A multiple of a shorter candidate is no repeat of its own: a pair of eight pins on a 32-pin connector,
  // whose pitch the vertices repeat at (1.14), listed after it.
  std::vector<RepeatCandidate> kept;
  for (const RepeatCandidate& c : a.candidates) {
    bool multiple = false;
    for (const RepeatCandidate& e : a.candidates)
      multiple = multiple || (e.offset.norm() < c.offset.norm() - tolerance &&
                              is_lattice_vector(c.offset, {}, &e.offset, tolerance));
    if (!multiple) kept.push_back(c);
  }
  a.candidates = std::move(kept);
}

/// docs/method.md 1.13: whether a shift snapped onto the vertices moves two exact copies that make up half
/// of the model: at least a quarter of the (queried) vertices pair, at least a quarter of the surface area is
/// triangles whose three corners, moved by it, land on vertices (within the snap's end radius), and of that
/// area at most a quarter lands on vertices again at twice the shift. A quarter: with two copies of area A_m
/// each and the rest A_e, the share is A_m / (2 A_m + A_e), at least 1/4 exactly when the copies make up half
/// of the surface. The tests are recorded ("pair_exact_vertices", "pair_exact_area", "pair_third_copy"). The
/// vertices' grid is built on the first shift that gets that far.
class ExactPairs {
public:
  ExactPairs(const Mesh& mesh, const Normalization& norm, const Eigen::Matrix<double, Eigen::Dynamic, 3>& vertices,
             const SnapOptions& snap)
      : mesh_(mesh), norm_(norm), vertices_(vertices), snap_(snap) {}

  /// `inside`: where not null, only the triangles whose centroid lies between the end slabs of that lattice
  /// along `axis` count towards the area (cells 1 to cells - 2: the model's ends aside).
  bool two_copies(const SnapResult& snapped, std::vector<OffsetTest>& tests, const Lattice* inside = nullptr,
                  int axis = 0) {
    if (vertices_.rows() == 0 || mesh_.F.rows() == 0) return false;
    const double queries = double(snap_.max_queries > 0
                                      ? std::min<std::size_t>(std::size_t(vertices_.rows()), snap_.max_queries)
                                      : std::size_t(vertices_.rows()));
    if (!record_test(tests, "pair_exact_vertices", double(snapped.pairs) / queries, 0.25)) return false;
    if (!grid_) {
      grid_ = std::make_unique<CellChains>(std::size_t(vertices_.rows()));
      for (Eigen::Index v = 0; v < vertices_.rows(); ++v) grid_->insert(cell(vertices_.row(v).transpose()), std::int32_t(v));
    }
    double paired = 0, third = 0, total = 0;
    const Eigen::Vector3d t = snapped.offset;
    const Eigen::Matrix3d to_cells = inside ? inside->A_inverse() : Eigen::Matrix3d::Identity();
    for (Eigen::Index f = 0; f < mesh_.F.rows(); ++f) {
      Eigen::Vector3d c[3];
      for (int k = 0; k < 3; ++k) c[k] = norm_.to_normalized(mesh_.V.row(mesh_.F(f, k)).template cast<double>().transpose());
      if (inside) {
        const double u = (to_cells * (norm_.to_model((c[0] + c[1] + c[2]) / 3) - inside->origin))[axis];
        if (!(u >= 1 && u <= inside->cells[axis] - 1)) continue;
      }
      const double area = (c[1] - c[0]).cross(c[2] - c[0]).norm();
      total += area;
      if (!(lands(c[0] + t) && lands(c[1] + t) && lands(c[2] + t))) continue;
      paired += area;
      if (lands(c[0] + 2 * t) && lands(c[1] + 2 * t) && lands(c[2] + 2 * t)) third += area;
    }
    if (!record_test(tests, "pair_exact_area", total > 0 ? paired / total : 0.0, 0.25)) return false;
    // Two copies: what lands at t does not land again at 2 t (0 but by chance). A pattern of n >= 3 copies
    // lands (n - 2) / (n - 1) >= 1/2 of it there, a slide along a surface tessellated in k equal rows
    // (k - 2) / (k - 1); at most 1/4, halfway.
    return record_test(tests, "pair_third_copy", paired > 0 ? third / paired : 0.0, 0.25, true);
  }

private:
  Cell cell(const Eigen::Vector3d& p) const {
    return Cell{cell_index(p.x(), h()), cell_index(p.y(), h()), cell_index(p.z(), h())};
  }
  double h() const { return 4 * snap_.end_radius; }  // grid cell; a partner lies within end_radius
  bool lands(const Eigen::Vector3d& q) const {
    const double r2 = snap_.end_radius * snap_.end_radius;
    bool hit = false;
    grid_->for_each_in(cell((q.array() - h()).matrix()), cell((q.array() + h()).matrix()), [&](std::int32_t v) {
      hit = hit || (vertices_.row(v).transpose() - q).squaredNorm() <= r2;
    });
    return hit;
  }

  const Mesh& mesh_;
  const Normalization& norm_;
  const Eigen::Matrix<double, Eigen::Dynamic, 3>& vertices_;
  const SnapOptions& snap_;
  std::unique_ptr<CellChains> grid_;  // the unique vertices by cell
};

/// The normalized positions of the vertices that shape the model (detail::shaping_representatives, equal
/// positions once); empty when a referenced vertex is not finite.
template <class = void>
Eigen::Matrix<double, Eigen::Dynamic, 3> shape_vertices(const Mesh& mesh, const Normalization& norm, bool keep_flat) {
  std::vector<std::uint32_t> rep, order;
  Eigen::Matrix<double, Eigen::Dynamic, 3> P(0, 3);
  if (!detail::merge_equal_positions(mesh, rep, order).ok()) return P;
  const std::vector<std::uint32_t> reps = detail::shaping_representatives(mesh, rep, order, keep_flat);
  P.resize(Eigen::Index(reps.size()), 3);
  for (std::size_t i = 0; i < reps.size(); ++i)
    P.row(Eigen::Index(i)) = norm.to_normalized(mesh.V.row(reps[i]).transpose().template cast<double>()).transpose();
  return P;
}

/// shape_vertices of one mesh and normalization, gathered on first use and kept: the snap of the principal
/// offsets, the shorter repeats of 1.12 and the vertex repeats of 1.14 all read them.
class ShapingVertices {
 public:
  ShapingVertices(const Mesh& mesh, const Normalization& norm, bool keep_flat)
      : mesh_(mesh), norm_(norm), keep_flat_(keep_flat) {}
  const Eigen::Matrix<double, Eigen::Dynamic, 3>& get() {
    if (!done_) points_ = shape_vertices(mesh_, norm_, keep_flat_), done_ = true;
    return points_;
  }

 private:
  const Mesh& mesh_;
  const Normalization& norm_;
  bool keep_flat_;
  bool done_ = false;
  Eigen::Matrix<double, Eigen::Dynamic, 3> points_{0, 3};
};

/// The greedy principal offsets over the promoted offsets (first, in request order) and the
/// significant ones reduced to fundamentals among themselves, vertex snapping, the lattice fit, and
/// the candidates. `vertices`: the unique vertex positions (normalized), or null when offsets are not
/// snapped; `shaping`: the vertices that shape the model, in the same normalization.
template <class D, class M, class Det>
Status select_and_fit(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options,
                      const Eigen::Matrix<double, Eigen::Dynamic, 3>* vertices, ShapingVertices& shaping,
                      Analysis& a) {
  std::vector<Eigen::Vector3d> promoted, significant;
  std::vector<int> where;  // index in a.dominant of each listed offset
  for (int i : a.promoted) promoted.push_back(a.dominant[std::size_t(i)].offset), where.push_back(i);
  for (std::size_t i = 0; i < a.dominant.size(); ++i)
    if (a.dominant[i].significant && !a.dominant[i].promoted)
      significant.push_back(a.dominant[i].offset), where.push_back(int(i));
  // Two copies (docs/method.md 1.13): a pair whose copies are exact and make up half of the model is as
  // certain as a pattern; after the patterns, and not when the significant offsets span it.
  if (vertices && options.exact_pairs) {
    const std::vector<Eigen::Vector3d> basis = independent_offsets(significant, options.dense_spacing);
    ExactPairs pairs(mesh, a.normalization, *vertices, options.snap);
    for (std::size_t i = 0; i < a.dominant.size(); ++i) {
      DominantOffset& d = a.dominant[i];
      if (d.promoted || !d.is_pair() || is_lattice_vector(d.offset, basis, nullptr, options.dense_spacing)) continue;
      const SnapResult snapped = snap_offset(*vertices, d.offset, options.snap);
      if (!snapped.snapped || !pairs.two_copies(snapped, d.tests)) continue;
      d.offset = snapped.offset;
      d.significant = true;
      significant.push_back(d.offset), where.push_back(int(i));
    }
  }
  for (const Eigen::Vector3d& v : reduce_to_fundamentals(significant, options.dense_spacing)) promoted.push_back(v);
  a.axes = select_principal_offsets(promoted, options.min_angle, options.dummy_length);
  for (int& s : a.axes.source)
    if (s >= 0) s = where[std::size_t(s)];  // PrincipalOffsets::source indexes Analysis::dominant
  a.principal.clear();
  for (int k = 0; k < a.axes.real_count; ++k) {
    Eigen::Vector3d& axis = a.axes.axes[std::size_t(k)];
    if (!vertices) {
      a.principal.push_back(axis);
      continue;
    }
    // Snapped onto the vertices; where the vertices that shape the model (not those inside flat regions or
    // straight creases, 1.1) pair at another shift, or pair where all the vertices do not, theirs: a face
    // tessellated evenly over a housing's whole length repeats at its own step, and a few steps near the
    // pitch pair more of its vertices than the pins do (0.0067 mm per pin off), or its vertices within a
    // start radius pull the mean off every pair (0.003 mm per pin off; both under the size check's
    // tolerance: docs/method.md 1.6, Vertex snapping).
    const SnapResult all = snap_offset(*vertices, axis, options.snap);
    const SnapResult shape =
        shaping.get().rows() > 1 ? snap_offset(shaping.get(), axis, options.snap) : SnapResult{};
    if (shape.snapped && (!all.snapped || (shape.offset - all.offset).norm() > 2 * options.snap.end_radius))
      axis = shape.offset;
    else if (all.snapped)
      axis = all.offset;
    a.principal.push_back(axis);
  }
  complete_with_dummies(a.axes, options.dummy_length);  // orthogonal to the snapped axes
  Result<LatticeFit> fit = fit_lattice(mesh, a.normalization, a.dense, a.axes, options.lattice);
  if (!fit) return fit.status();
  a.lattice = fit->lattice;
  a.A_normalized = fit->A_normalized;
  a.origin_normalized = fit->origin_normalized;
  a.phase = fit->phase;
  collect_candidates(options.dense_spacing, a);
  return {};
}

/// The model length the repeating slabs along lattice axis a cover (slabs x |v_a|), or -1 when the axis is
/// undecided (restitch/lattice/structure.hpp).
template <class = void>
double repeated_length(const CellStructure& s, const Lattice& L, int a) {
  if (s.undecided[std::size_t(a)]) return -1;
  int repeating = 0;
  for (int i = 0; i < L.cells[a]; ++i) repeating += s.repeats(a, i);
  return repeating * L.A.col(a).norm();
}

/// The parts along lattice axis a inside the model (holding no end slab).
template <class = void>
std::ptrdiff_t inner_parts(const CellStructure& s, int a) {
  return std::count_if(s.parts.begin(), s.parts.end(), [&](const SingularPart& p) {
    return p.axis == a && p.first > 0 && p.last < s.cells[a] - 1;
  });
}

/// The snap for a shorter repeat proposed to replace a period (docs/method.md 1.12): from two end radii, so it
/// averages the repeat's own exact pairs. From the detector's start radius it can slide to another lag nearby
/// with more pairs (a housing tessellated evenly every 0.973 over its length: three steps, 2.918, lie 0.418
/// from a 2.5 pitch, 0.039 normalized), and the repeat would be lost.
template <class = void>
SnapOptions lag_snap(SnapOptions snap) {
  snap.start_radius = std::min(snap.start_radius, 2 * snap.end_radius);
  return snap;
}

/// Whether some slab along lattice axis a is a copy of a slab a number of cells away that is no multiple of m:
/// copies a divisor t / m of the period t proves (1.12). Copies only at multiples of m cells are t's own
/// copies on a finer grid (a box header's two plain columns around its notch, four pitches apart, are so
/// eight half pitches apart), no sign that t / m repeats.
template <class = void>
bool copies_off_multiple(const CellStructure& s, int a, int m) {
  const std::vector<int>& c = s.copy_of[std::size_t(a)];
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c[i] >= 0 && (c[i] - int(i)) % m != 0) return true;
  return false;
}

/// Whether two neighbouring slabs along lattice axis a are copies, not read through an end (CellStructure::
/// end_read: the model's end lacking all along a wall its other end has): a repeat next door.
template <class = void>
bool copies_next_door(const CellStructure& s, int a) {
  const std::vector<int>& c = s.copy_of[std::size_t(a)];
  if (s.end_read[std::size_t(a)]) return false;
  for (int i = 0; i + 1 < int(c.size()); ++i)
    if (c[std::size_t(i)] == i + 1 || c[std::size_t(i + 1)] == i) return true;
  return false;
}

/// Whether a part along lattice axis a inside the model (holding no end slab) is a copy of another part
/// (SingularPart::repeated): content that recurs, which a period that makes it a part has missed (1.12).
template <class = void>
bool repeated_inner_part(const CellStructure& s, int a) {
  return std::any_of(s.parts.begin(), s.parts.end(), [&](const SingularPart& p) {
    return p.axis == a && p.repeated && p.first > 0 && p.last < s.cells[a] - 1;
  });
}

/// The slabs the parts along lattice axis a take, in all.
template <class = void>
int part_slabs(const CellStructure& s, int a) {
  int n = 0;
  for (const SingularPart& p : s.parts)
    if (p.axis == a) n += p.last - p.first + 1;
  return n;
}

/// part_slabs where some part along lattice axis a kept at an end takes more than one slab, else -1
/// (docs/method.md 1.7, An end part cut by a plane).
template <class = void>
int split_part_slabs(const CellStructure& s, int a) {
  const bool split = std::any_of(s.parts.begin(), s.parts.end(), [&](const SingularPart& p) {
    return p.axis == a && p.anchor != PartAnchor::centre && p.last > p.first;
  });
  return split ? part_slabs(s, a) : -1;
}

/// The fewest slabs the parts along lattice axis a of `s` (read on `grid`) can take with the cell planes moved
/// by `shift` periods, in all, as their own content (SingularPart::content: where each differs from the
/// surface a period either side) tells: one slab more than the planes strictly inside a part's content (one
/// for a part with no content). Not from the model's end: on another phase an end slab may be read over its
/// periodic part, as a copy, and the part then holds no end slab. docs/method.md 1.7, An end part cut by a
/// plane: a phase whose count is no lower than the parts' slabs now cannot hold them in fewer, and is not read.
template <class = void>
int part_slabs_moved(const CellStructure& s, const Lattice& grid, int a, double shift) {
  const Eigen::RowVector3d row = grid.A_inverse().row(a);
  int n = 0;
  for (const SingularPart& p : s.parts) {
    if (p.axis != a) continue;
    if (p.content.empty()) {  // one slab at least
      ++n;
      continue;
    }
    double c0 = INFINITY, c1 = -INFINITY;
    for (const Eigen::Vector3d& x : p.content) {
      const double t = row.dot(x - grid.origin);
      c0 = std::min(c0, t), c1 = std::max(c1, t);
    }
    // Planes m + shift strictly inside (c0, c1).
    const double lo = std::floor(c0 - shift) + 1, hi = std::ceil(c1 - shift) - 1;
    n += 1 + std::max(0, int(hi - lo) + 1);
  }
  return n;
}

/// Whether two structures have the same parts along lattice axis a: as many, in order, each with the same
/// anchor.
template <class = void>
bool same_parts(const CellStructure& s, const CellStructure& t, int a) {
  std::vector<PartAnchor> x, y;
  for (const SingularPart& p : s.parts)
    if (p.axis == a) x.push_back(p.anchor);
  for (const SingularPart& p : t.parts)
    if (p.axis == a) y.push_back(p.anchor);
  return x == y;
}

/// Why the structure along lattice axis a cannot be read on its grid phase (docs/method.md 1.7, Phase by
/// structure): `undecided_axis` where no two slabs tell what occurs once, `nothing_repeats` where the axis
/// has three cells or more and no slab repeats at all (a plane through a part that occurs once, a pin-1
/// marker, leaves every cell different from every other), `gap_run` where what repeats may be a gap in one
/// part and nothing else repeats (CellStructure::gap_run, with some slab repeating), `read` otherwise.
enum class Unread { read = 0, undecided_axis = 1, nothing_repeats = 2, gap_run = 3 };

template <class = void>
Unread structure_unread(const CellStructure& s, int a) {
  if (s.undecided[std::size_t(a)]) return Unread::undecided_axis;
  const std::vector<int>& c = s.copy_of[std::size_t(a)];
  if (s.cells[a] >= 3 && !c.empty() && std::count(c.begin(), c.end(), -1) == int(c.size()))
    return Unread::nothing_repeats;
  return s.gap_run[std::size_t(a)] ? Unread::gap_run : Unread::read;
}

/// What the analysis knows of each axis's structure on the lattice as it is (docs/method.md 1.7, 1.12): the
/// Unread found (as an int; -1 where not known) and, where read, split_part_slabs (-2 where not known).
struct AxisReadings {
  std::array<int, 3> unread{{-1, -1, -1}};
  std::array<int, 3> split{{-2, -2, -2}};
  /// Records the structure `s` read along axis k as the retargeter reads it (end slabs over their periodic
  /// parts): its Unread and split_part_slabs.
  void read(const CellStructure& s, int k) {
    unread[std::size_t(k)] = int(structure_unread(s, k));
    split[std::size_t(k)] = split_part_slabs(s, k);
  }
};

/// The lattice of `a`'s principal offsets with axis k's period replaced by `period` (written to `axes`, the
/// dummy directions completed).
template <class D, class M, class Det>
Result<LatticeFit> fit_with_period(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options, const Analysis& a,
                                   int k, const Eigen::Vector3d& period, PrincipalOffsets& axes) {
  axes = a.axes;
  axes.axes[std::size_t(k)] = period;
  complete_with_dummies(axes, options.dummy_length);
  return fit_lattice(mesh, a.normalization, a.dense, axes, options.lattice);
}

/// Replaces principal axis k's period by `period` (snapped; `f`: the factor it is of the old one, m > 0 a
/// multiple, -m a divisor, 0 another repeat) on the lattice `fit` of `axes` (which holds it), and records
/// the factor (and `tests`) on the dominant offset the axis came from.
template <class = void>
void take_period(Analysis& a, const PrincipalOffsets& axes, int k, const Eigen::Vector3d& period,
                 const LatticeFit& fit, int f, const std::vector<OffsetTest>& tests) {
  const double before = a.axes.axes[std::size_t(k)].norm();
  a.axes = axes;
  a.principal[std::size_t(k)] = period;
  a.lattice = fit.lattice;
  a.A_normalized = fit.A_normalized;
  a.origin_normalized = fit.origin_normalized;
  a.phase = fit.phase;
  if (const int i = a.axes.source[std::size_t(k)]; i >= 0) {
    DominantOffset& d = a.dominant[std::size_t(i)];
    d.offset = period;
    if (f == 0)
      record_test(d.tests, "structure_shorter", before / period.norm(), 1);
    else
      record_test(d.tests, f > 0 ? "structure_multiple" : "structure_divisor", std::abs(f), 2);
    d.tests.insert(d.tests.end(), tests.begin(), tests.end());
    d.divisor = f >= 0 ? d.divisor : d.divisor * -f;
  }
}

/// docs/method.md 1.12: each principal offset t checked against the structure of the model on its
/// lattice. Where no two neighbouring cells are copies (the axis is undecided, or decided by copies farther
/// apart only), the shortest m t, m = 2..4, at which some are, with at least two cells; otherwise the
/// shortest t / m, m = max_divisor..2, at least one dense spacing long, whose copies pair vertex for vertex
/// (snap_offset), some of whose cells are copies at a shift t does not make, whose repeating cells cover at
/// least as much of the model as t's, one period of t aside (the ends' slabs fall differently), and which has
/// no more parts that occur once inside the model (not at an end) than t; then the shorter repeats along t that
/// divide nothing (the run of slats with its rail). The first that qualifies replaces t (snapped), and the
/// dominant offset it came from gets its divisor (or multiple) and a test record "structure_divisor" /
/// "structure_multiple" / "structure_shorter". `vertices`: the unique vertex positions (normalized);
/// nothing is done without them; `shaping`: those that shape the model (the lags of the shorter repeats).
template <class D, class M, class Det>
Status verify_periods(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options,
                      const Eigen::Matrix<double, Eigen::Dynamic, 3>* vertices, ShapingVertices& shaping,
                      std::unique_ptr<TriangleSurface>& surface, Analysis& a, AxisReadings& known) {
  if (!options.verify_periods || !vertices || a.axes.real_count == 0 || a.dense.size() == 0) return {};
  bool changed = false;
  for (int k = 0; k < a.axes.real_count; ++k) {
    if (!surface) surface = std::make_unique<TriangleSurface>(mesh);
    const CellStructure st = cell_structure(mesh, a, a.lattice, 0, surface.get(), true, k);
    known.read(st, k);  // unless a period below replaces t
    const double have = repeated_length(st, a.lattice, k);
    const Eigen::Vector3d t = a.axes.axes[std::size_t(k)];
    const double extent = a.lattice.cells[k] * t.norm();  // the model's length along t, about
    // What is tried, in order: multiples (f > 0) or divisors (f < 0) of t, then the shorter repeats along t
    // that are no divisor of it (f = 0; `from`: the dominant offset it is, -1 for a lag of the vertices),
    // shortest first.
    struct Guess {
      Eigen::Vector3d offset;
      int f = 0;
      int from = -1;
    };
    std::vector<Guess> guesses;
    if (st.undecided[std::size_t(k)] || st.far_copies[std::size_t(k)]) {
      for (int m = 2; m <= 4; ++m)
        if (2 * m * t.norm() <= extent + 1e-9) guesses.push_back({t * double(m), m, -1});
    }
    // Copies farther apart decide an axis a multiple of the period may have decided as well: five pitches of a
    // 24-column box header make the cells plain, notch edge, notch, notch edge, plain, whose two plain
    // cells are copies; the pitch itself is a divisor, tried after the multiples.
    // t's slabs compared and none alike, next door or farther: t is no repeat the structure shows (an even
    // tessellation's step near the pitch, three cuts of a long wall), and a shorter repeat that has copies
    // is tried whatever the number of t's copies.
    const bool alike_nowhere = structure_unread(st, k) == Unread::nothing_repeats ||
                               (st.undecided[std::size_t(k)] && !st.far_copies[std::size_t(k)] && st.cells[k] >= 3);
    if (!st.undecided[std::size_t(k)] || alike_nowhere) {
      for (int m = options.fundamental.max_divisor; m >= 2 && !st.undecided[std::size_t(k)]; --m)
        // At least one dense spacing: a slab that thin still holds samples of every surface crossing it (they
        // lie a spacing apart), which the copy test needs; the overlap's bound (fundamental.min_length) is for
        // tests on overlaps, and this one is exact.
        if (t.norm() / m >= options.dense_spacing) guesses.push_back({t / double(m), -m, -1});
      // A shorter repeat along t that whole divisions of t do not reach: slats in two equal runs split by a
      // rail, where the run with its rail is t (two copies, or a weak pattern) and the slat pitch is no
      // divisor of it. Parallel: off t's line by less than one dense spacing. Only where t occurs at most
      // twice (the model spans less than three periods): each boundary between copies of t breaks the
      // shorter repeat's phase and becomes a part of it, and it may add one part at most (below); or where
      // t's slabs are alike nowhere, which makes no copies of t.
      std::vector<Guess> shorter;
      const Eigen::Vector3d dir = t.normalized();
      const bool shorter_too = st.extent_high[k] - st.extent_low[k] < 3 || alike_nowhere;
      const auto propose = [&](const Eigen::Vector3d& u, int from) {
        const int m = int(std::lround(t.norm() / u.norm()));
        if (m >= 2 && m <= options.fundamental.max_divisor &&
            (u - t / double(m)).norm() <= (m + 1) * options.snap.end_radius)
          return;  // a divisor: tried as one
        for (const Guess& g : shorter)
          if ((g.offset - u).norm() <= options.dense_spacing) return;
        shorter.push_back({u, 0, from});
      };
      for (std::size_t i = 0; shorter_too && i < a.dominant.size(); ++i) {
        const DominantOffset& d = a.dominant[i];
        const Eigen::Vector3d u = d.offset.dot(dir) < 0 ? Eigen::Vector3d(-d.offset) : d.offset;
        const bool pair = std::any_of(d.tests.begin(), d.tests.end(),
                                      [](const OffsetTest& x) { return x.name == "pair_third_copy"; });
        if (!d.significant || pair || u.norm() < options.dense_spacing ||
            u.norm() >= t.norm() - options.dense_spacing || (u - u.dot(dir) * dir).norm() > options.dense_spacing)
          continue;
        propose(u, int(i));
      }
      // And the shifts along t at which the vertices that shape the model repeat (on lines parallel to t; not
      // those inside flat regions or straight creases, which a fine tessellation repeats at its own step, as
      // for the features, 1.1): a slat pitch the matching did not vote for (three slats a run: their pairs
      // are outvoted by the runs'). The four most paired, with as many pairs as a snap needs: each costs a
      // lattice fit and a structure, and the structure's exact test below decides.
      for (const Eigen::Vector3d& u : shorter_too ? vertex_lags(shaping.get(), t, options.snap.end_radius, options.dense_spacing,
                                                          options.snap.min_pairs, 4)
                                            : std::vector<Eigen::Vector3d>{})
        propose(u, -1);
      std::stable_sort(shorter.begin(), shorter.end(),
                       [](const Guess& x, const Guess& y) { return x.offset.norm() < y.offset.norm(); });
      guesses.insert(guesses.end(), shorter.begin(), shorter.end());
    }
    for (const Guess& g : guesses) {
      const int f = g.f;
      const Eigen::Vector3d guess = g.offset;
      SnapResult snapped = snap_offset(*vertices, guess, f == 0 && g.from < 0 ? lag_snap(options.snap) : options.snap);
      // A shorter repeat the matching found, snapped from the detector's start radius, may slide to another lag
      // with more pairs (lag_snap); from two end radii it keeps its own pairs, if it has them.
      if (f == 0 && g.from >= 0 && (snapped.offset - guess).norm() > options.dense_spacing)
        snapped = snap_offset(*vertices, guess, lag_snap(options.snap));
      // Exactly m t or t / m: t is exact to the snap's end radius, so its multiple or divisor is to (m + 1)
      // of them; the snap's start radius would take whatever pairs nearby (a pin's edge near half a pitch).
      // A shorter repeat the matching found is refined to within a dense spacing (ICP on the samples), one
      // from the vertices' lags to the end radius (exact pairs, averaged); either stays on t's line (within
      // two end radii) once snapped, or it is another repeat than the one proposed.
      const double moved = (snapped.offset - guess).norm();
      const Eigen::Vector3d across = snapped.offset - snapped.offset.dot(t.normalized()) * t.normalized();
      if (!snapped.snapped || (f != 0 && moved > (std::abs(f) + 1) * options.snap.end_radius) ||
          (f == 0 && (moved > (g.from >= 0 ? options.dense_spacing : 2 * options.snap.end_radius) ||
                      across.norm() > 2 * options.snap.end_radius)))
        continue;
      PrincipalOffsets axes;
      Result<LatticeFit> fit = fit_with_period(mesh, options, a, k, snapped.offset, axes);
      if (!fit) return fit.status();
      // A divisor or a multiple is a guess, taken on proof: its slabs are compared whole. An end slab
      // compared over its periodic part (2.10) matches its neighbour there by construction, which proves no
      // division (half a bookshelf's column: the side panel's cell, panel aside, is the next half column)
      // and no multiple (of a connector's three modules slot, plain, slot, the pair of the last two, its end
      // past its periodic part, against the first two).
      const CellStructure there = cell_structure(mesh, a, fit->lattice, 0, surface.get(), f == 0, k);
      const double got = repeated_length(there, fit->lattice, k);
      // The parts along k are counted inside the model (not holding an end slab: how the ends fall differs
      // between lattices, a shutter's bottom rail takes two cells of its slat pitch and one of six pitches).
      // Either must make some neighbouring cells copies (an axis too short to compare any is no answer).
      // A divisor explains as much of the model as t did, one period aside (the end slabs fall differently),
      // with some copies at a shift t does not make (copies_off_multiple), and no more parts inside it (a
      // third of a pitch over a wall subdivided in thirds repeats the wall but makes every pin a part of its
      // own; a quarter of a bookshelf's column every divider).
      // A shorter repeat found on its own (the matching voted for it, or the shaping vertices repeat at it)
      // is another repeat, not t cut finer, so no end falls differently: it covers at least what t's copies
      // did, and where t's cells are no copies (t is two copies: each whole slab is an end) at least half of
      // the length t's lattice spans, as two copies must make up half the model (1.13); but where t's slabs
      // were compared and none is a copy (nothing repeats along t), t covers nothing, and neighbouring
      // copies are more (a 5-slat shutter read as two slats with the rail, three cells all
      // different); copies farther apart are not (a lag of a rail's height, or of a pin's width, makes two
      // cells alike far apart, each a rail's or a pin's edges: no repeat of what lies between). It may make
      // a part of the one boundary between t's two copies (the rail between two runs), no more; and no part
      // may occur twice: from three copies of t on, what lies between them recurs and t is the module (so too
      // a tessellation's step across a bookshelf's columns, whose dividers fall at a different phase in each
      // of its cells and are no copies slab for slab, which the count catches).
      const bool covers = got >= have - t.norm() / a.normalization.scale;
      const double spans = a.lattice.cells[k] * t.norm() / a.normalization.scale;
      const bool compared = alike_nowhere;  // t's slabs compared, none alike
      const bool covers_more = have > 0 ? got >= have : compared ? copies_next_door(there, k) : got >= 0.5 * spans;
      if (!(got > 0) ||
          (f < 0 && (!covers || !copies_off_multiple(there, k, -f) || inner_parts(there, k) > inner_parts(st, k))) ||
          (f == 0 && (!covers_more || repeated_inner_part(there, k) || inner_parts(there, k) > inner_parts(st, k) + 1)))
        continue;
      if (f == 0 && g.from >= 0) axes.source[std::size_t(k)] = g.from;  // else t's dominant now reads s
      take_period(a, axes, k, snapped.offset, *fit, f, {});
      // The refit moves every axis's planes (A changed): the axes before are not known any more.
      for (int i = 0; i < k; ++i) known.unread[std::size_t(i)] = -1, known.split[std::size_t(i)] = -2;
      known.unread[std::size_t(k)] = int(structure_unread(there, k));
      known.split[std::size_t(k)] = f == 0 ? split_part_slabs(there, k) : -2;  // f != 0: its end slabs whole
      changed = true;
      break;
    }
  }
  if (changed) collect_candidates(options.dense_spacing, a);
  return {};
}

/// The vertex features of an analysis (features [sampled_features, end)): the ICP anchors.
template <class = void>
PointSet vertex_anchors(const Analysis& a) {
  PointSet v;
  const Eigen::Index first = Eigen::Index(a.sampled_features), n = a.features.size() - first;
  if (n <= 0) return v;
  v.points = a.features.points.bottomRows(n);
  v.normals = a.features.normals.bottomRows(n);
  return v;
}

/// Whether the exact shift u (normalized) passes the whole-surface significance tests of 1.5 (overlap,
/// contrast, the pattern at 2u, slides; the votes aside: u comes from the vertices, whose pairs are its
/// evidence) on samples fine enough for its length: the dense ones where the contrast's probes, two overlap
/// radii either side, lie within half a period (|u| >= 2 fundamental.min_length h), else the fine ones of
/// 1.6.1 (drawn once into `fine`). ICP from u, trimmed at the overlap radius from the start, must stay
/// within that radius of it. The tests are appended to `record`, named "pattern_...".
template <class D, class M, class Det>
Result<bool> vertex_pattern(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options, const Analysis& a,
                            const Eigen::Vector3d& u, std::unique_ptr<PointSet>& fine,
                            std::vector<OffsetTest>& record) {
  const double h = options.dense_spacing;
  const bool coarse = u.norm() >= 2 * options.fundamental.min_length * h;
  const double spacing = coarse ? h : h * options.fine_spacing_ratio;
  if (!coarse && !fine) {
    Result<PointSet> drawn = poisson_disk_sample(mesh, a.normalization, spacing, options.seed + 3, {});
    if (!drawn) return drawn.status();
    fine = std::make_unique<PointSet>(std::move(*drawn));
  }
  SignificanceOptions tests;
  tests.min_votes = 0;
  tests.icp.spacing = spacing;
  // u is exact (snapped onto the vertices), not a bin centre: the first stage needs no reach past the
  // second's, and a reach of two bins pulls every vertex whose copy is missing (a divider's top) onto itself
  // when the period is shorter than that.
  tests.icp.start_trim = tests.icp.overlap_radius();
  tests.threads = options.threads;
  const PointSet anchors = vertex_anchors(a), no_features;
  const std::vector<Match> no_matches;
  const OffsetEvidence evidence{coarse ? a.dense : *fine, no_features, no_matches, spacing,
                                options.fundamental.min_length * spacing, &anchors};
  std::vector<DominantOffset> tested;
  RESTITCH_TRY(refine_and_test(evidence, {OffsetCandidate{u, 0, 0, {}}}, tests, {}, tested));
  if (tested.empty()) return false;
  for (OffsetTest t : tested.front().tests)
    if (t.name != "votes") t.name = "pattern_" + t.name, record.push_back(t);
  return tested.front().significant &&
         record_test(record, "pattern_stays", (tested.front().offset - u).norm() / tests.icp.overlap_radius(), 1, true);
}

/// docs/method.md 1.14: along each world axis w that no principal offset runs along, the shifts at which
/// the vertices that shape the model repeat (vertex_lags over shape_vertices, the four most paired),
/// shortest first; the first that snaps onto the vertices along w, whose lattice (the principal offsets and
/// it) has neighbouring cells along it that are copies, covering at least half of the slabs between the two
/// end slabs, with no part that occurs twice inside the model, is added to the dominant offsets (votes 0,
/// test records "vertex_lag", "vertex_copies", "vertex_structure"; DominantOffset::from_vertices). Where it
/// also passes the whole-surface tests of 1.5 (vertex_pattern: the matching cast no vote for a pattern it
/// would have found, its period too short for the matching's scales) it is significant and a principal
/// offset, after the others; else a candidate of reason "vertices", where a candidate that is a multiple of
/// it no longer is one (collect_candidates). `vertices`: the unique vertex positions (normalized); nothing
/// is done without them; `shaping`: those that shape the model (whose lags are tried).
template <class D, class M, class Det>
Status find_vertex_repeats(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options,
                           const Eigen::Matrix<double, Eigen::Dynamic, 3>* vertices, ShapingVertices& shaping,
                           std::unique_ptr<TriangleSurface>& surface, Analysis& a) {
  if (!options.vertex_repeats || !vertices || vertices->rows() < 2 || a.axes.real_count >= 3 || a.dense.size() == 0)
    return {};
  std::array<bool, 3> covered{{false, false, false}};
  for (const Eigen::Vector3d& p : a.principal) covered[std::size_t(world_axis_of(p))] = true;
  std::unique_ptr<PointSet> fine;  // vertex_pattern's fine samples, drawn once needed
  bool added = false;
  for (int w = 0; w < 3; ++w) {
    if (covered[std::size_t(w)] || a.axes.real_count >= 3) continue;
    const double length = vertices->col(w).maxCoeff() - vertices->col(w).minCoeff();
    const Eigen::Vector3d along = Eigen::Vector3d::Unit(w);
    std::vector<Eigen::Vector3d> lags =
        vertex_lags(shaping.get(), length * along, options.snap.end_radius, options.dense_spacing, options.snap.min_pairs, 4);
    std::stable_sort(lags.begin(), lags.end(),
                     [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) { return x.norm() < y.norm(); });
    for (const Eigen::Vector3d& u : lags) {
      // Exact pairs, averaged: the snap stays within two end radii of the lag, and on w's line.
      const SnapResult snapped = snap_offset(*vertices, u, options.snap);
      const Eigen::Vector3d across = snapped.offset - snapped.offset[w] * along;
      if (!snapped.snapped || (snapped.offset - u).norm() > 2 * options.snap.end_radius ||
          across.norm() > 2 * options.snap.end_radius)
        continue;
      std::vector<Eigen::Vector3d> list(a.principal.begin(), a.principal.end());
      list.push_back(snapped.offset);
      PrincipalOffsets axes = select_principal_offsets(list, options.min_angle, options.dummy_length);
      if (axes.real_count != int(list.size())) continue;
      Result<LatticeFit> fit = fit_lattice(mesh, a.normalization, a.dense, axes, options.lattice);
      if (!fit) return fit.status();
      const int k = axes.real_count - 1;
      if (!surface) surface = std::make_unique<TriangleSurface>(mesh);
      const CellStructure st = cell_structure(mesh, a, fit->lattice, 0, surface.get(), true, k);
      const double got = repeated_length(st, fit->lattice, k);
      // Half of what lies between the end slabs (they hold the model's ends: posts, a housing's walls): the
      // repeat is the model's content along w, not a detail of one part (a handle's grooves), which a size
      // asked along w must not multiply.
      const double between = std::max(fit->lattice.cells[k] - 2, 1) * fit->lattice.A.col(k).norm();
      // Copies next door: a slab and its neighbour, the lag's own evidence. Slabs alike only far apart are
      // what any lag finds on a plain stretch (a housing's wall at a pin's width, copies of an end slab's
      // periodic part), not a repeat of the model's content.
      if (!(got > 0) || repeated_inner_part(st, k) || !copies_next_door(st, k)) continue;
      DominantOffset d;
      d.offset = d.bin_center = d.unslid = snapped.offset;
      record_test(d.tests, "vertex_lag", double(snapped.pairs), double(options.snap.min_pairs));
      for (int i = 0; i < fit->lattice.cells[k]; ++i) d.copies += st.repeats(k, i);
      // A repeat is two slabs at least, a slab and its copy (a lag as long as the model, a box's depth, gives
      // an axis of one cell, which has no structure and counts its one slab as repeating).
      if (!record_test(d.tests, "vertex_copies", d.copies, 2) ||
          !record_test(d.tests, "vertex_structure", got / between, 0.5))
        continue;
      Result<bool> pattern = vertex_pattern(mesh, options, a, snapped.offset, fine, d.tests);
      if (!pattern) return pattern.status();
      d.significant = *pattern;
      a.dominant.push_back(d);
      added = true;
      if (d.significant) {  // a principal offset, after the others (the selection keeps the list's order)
        for (int i = 0; i < k; ++i) axes.source[std::size_t(i)] = a.axes.source[std::size_t(i)];
        a.axes = axes;
        a.axes.source[std::size_t(k)] = int(a.dominant.size()) - 1;
        a.principal.push_back(a.axes.axes[std::size_t(k)]);
        a.lattice = fit->lattice;
        a.A_normalized = fit->A_normalized;
        a.origin_normalized = fit->origin_normalized;
        a.phase = fit->phase;
      }
      break;
    }
  }
  if (added) collect_candidates(options.dense_spacing, a);
  return {};
}

/// docs/method.md 1.7, Phase by structure: along each principal axis k whose structure on the chosen phase
/// is undecided (no two neighbouring slabs, nor two farther apart around content that occurs once, are
/// copies: restitch/lattice/structure.hpp) or where nothing repeats at all (structure_unread), the other
/// phases at which the cut cost has a local minimum (lattice/fit.hpp, phase_minima: the middle of each gap
/// the planes can sit in), cheapest first, at most `max_phases_by_structure`; the first on which the axis
/// is decided, some slabs repeat and no part inside is a copy of another replaces the phase along k (refit
/// along k alone). For an undecided axis, with its end slabs compared whole and some part inside the model;
/// where nothing repeated, as the retargeter reads it (end slabs over their periodic parts). Also along an
/// axis that is read where a part kept at an end takes two slabs or more (split_part_slabs; An end part cut
/// by a plane): the first phase that reads the same cells and parts (same_parts) in fewer slabs. The cut cost is
/// what the phase is chosen by where the structure says nothing; where the cheapest phase cuts the content
/// that occurs once into the cells of what repeats (a notch edge in a plain column's cell) the structure
/// cannot be read there, and the seams on exact copies are exact at any phase (the stitcher clips,
/// docs/method.md 3). `known`: what the caller found on the lattice as it is; updated with what is found here
/// (read, where another phase is taken).
template <class D, class M, class Det>
Status phase_by_structure(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options,
                          std::unique_ptr<TriangleSurface>& surface, Analysis& a, AxisReadings& known) {
  if (options.max_phases_by_structure <= 0 || a.dense.size() == 0) return {};
  std::array<int, 3>& unread = known.unread;
  for (int k = 0; k < a.axes.real_count; ++k) {
    if (a.lattice.cells[k] < 3) continue;  // fewer cells are read as they are
    if (!surface) surface = std::make_unique<TriangleSurface>(mesh);
    std::optional<CellStructure> now;  // the structure on the chosen phase, as the retargeter reads it
    const auto read_now = [&]() -> const CellStructure& {
      return now ? *now : now.emplace(cell_structure(mesh, a, a.lattice, 0, surface.get(), true, k));
    };
    const Unread why =
        unread[std::size_t(k)] >= 0 ? Unread(unread[std::size_t(k)]) : structure_unread(read_now(), k);
    unread[std::size_t(k)] = int(why);
    // Read: searched only where a part kept at an end takes more than one slab (a plane through a pin-1
    // marker puts its tail in the next pin's cell), for the same parts in fewer slabs.
    const int split = why != Unread::read          ? -1
                      : known.split[std::size_t(k)] != -2 ? known.split[std::size_t(k)]
                                                           : split_part_slabs(read_now(), k);
    if (why == Unread::read && split < 0) continue;
    if (split >= 0) read_now();  // its parts, compared below (before the tasks, which only read it)
    LatticeFit from;  // the lattice as fitted, and the cost of each phase along k
    from.lattice = a.lattice, from.A_normalized = a.A_normalized, from.origin_normalized = a.origin_normalized;
    from.phase = a.phase;
    Result<LatticeFit> base = refit_axis(mesh, a.normalization, a.dense, a.axes, options.lattice, from, k);
    if (!base) return base.status();
    const int K = options.lattice.phase_candidates;
    const int chosen = int(std::lround(a.phase[k] * K)) % K;
    std::vector<int> phases;  // the phases to try, in order
    int minima = 0;  // of the cheapest max_phases_by_structure minima, those that could qualify
    for (const int j : phase_minima(base->phase_cost[std::size_t(k)])) {
      if (j == chosen || minima++ >= options.max_phases_by_structure) continue;
      // An end part cut by a plane: only a phase whose planes could hold the parts in fewer slabs is read.
      if (split >= 0 && part_slabs_moved(*now, a.lattice, k, double(((j - chosen) % K + K) % K) / K) >= split)
        continue;
      phases.push_back(j);
    }
    // Tried a batch of `threads` at a time, each independent; the first in order that qualifies is taken, so
    // the lattice is the same whatever the number of threads.
    const std::size_t batch = std::size_t(resolve_threads(options.threads));
    bool taken = false;
    for (std::size_t from = 0; from < phases.size() && !taken; from += batch) {
      const std::size_t n = std::min(batch, phases.size() - from);
      std::vector<Result<LatticeFit>> fits(n, error(StatusCode::internal, "not tried"));
      std::vector<char> good(n, 0);
      detail::parallel_tasks(
          int(n), n,
          [&](std::size_t t, int) {
            LatticeFitOptions forced = options.lattice;
            forced.phase[std::size_t(k)] = phases[from + t];
            fits[t] = refit_axis(mesh, a.normalization, a.dense, a.axes, forced, *base, k);
            if (!fits[t]) return;
            // Another phase is a guess, taken on proof, as 1.12's periods are: end slabs compared whole (over
            // its periodic part an end slab matches its neighbour by construction; so a 3-column box header,
            // whose notch reaches every column, read its open front as what repeats, and grew it). And it
            // must keep inside the model what made the cheapest phase undecided: there two whole cells
            // inside the model differ, so a reading with no part inside has moved that content into the
            // ends, which the cheapest phase refused (a 3-column box header whose notch reaches past its
            // outer pins: every column an open front, the notch's edges in the end parts, and the notch grew
            // with the pins). Unless it is read as three modules A B A whose middle repeats: each A holds what
            // B lacks, in a slab of its own, kept once (a 3-pin connector whose wall is longer than its pitch:
            // the cheapest phase cuts each end cap inside a module's cell, another reads slot, plain, slot).
            // Where nothing repeated, no content was kept inside: a phase that keeps the part whole is read as
            // the retargeter reads it, end slabs over their periodic parts (a 3-pin package whose pin-1 marker
            // the cheapest phase cut has one whole cell, the second pin's, and its third pin in the end cell).
            const bool whole_ends = why == Unread::undecided_axis || why == Unread::gap_run;
            const CellStructure st = cell_structure(mesh, a, fits[t]->lattice, 0, surface.get(), !whole_ends, k);
            if (split >= 0) {  // the same reading, its parts cut by fewer planes
              good[t] = fits[t]->lattice.cells[k] == a.lattice.cells[k] && structure_unread(st, k) == Unread::read &&
                        repeated_length(st, fits[t]->lattice, k) > 0 && !repeated_inner_part(st, k) &&
                        same_parts(*now, st, k) && part_slabs(st, k) < split;
              return;
            }
            const bool kept_inside = inner_parts(st, k) > 0 || st.plain_middle[std::size_t(k)];
            good[t] = structure_unread(st, k) == Unread::read && (kept_inside || !whole_ends) &&
                      repeated_length(st, fits[t]->lattice, k) > 0 && !repeated_inner_part(st, k);
          },
          [](std::size_t) { return true; });
      for (std::size_t t = 0; t < n && !taken; ++t) {
        if (!fits[t]) return fits[t].status();
        if (!good[t]) continue;
        a.lattice = fits[t]->lattice;
        a.A_normalized = fits[t]->A_normalized;
        a.origin_normalized = fits[t]->origin_normalized;
        a.phase = fits[t]->phase;
        unread[std::size_t(k)] = int(Unread::read);
        known.split[std::size_t(k)] = -2;
        taken = true;
      }
    }
  }
  return {};
}

/// docs/method.md 1.12, Two copies of a multiple: along each principal axis k still undecided on every phase
/// tried (phase_by_structure), the shortest m t, m = 2..4, with at least two periods along the model,
/// snapped within (m + 1) snap end radii of m t, that moves two exact copies making up half of what lies
/// between t's end slabs (ExactPairs, its area counted there: the ends are the part's end structure) and
/// reads the axis on its lattice (end slabs over their periodic parts, as the retargeter reads them) with no
/// part inside the model (two copies between the ends, nothing else): a
/// railing of two modules of two alternating balusters between its posts, whose half module the rails and
/// bars repeat. `vertices`: the unique vertex positions (normalized); nothing is done without them.
/// `known`: what was found on the lattice as it is (AxisReadings).
template <class D, class M, class Det>
Status two_copy_periods(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options,
                        const Eigen::Matrix<double, Eigen::Dynamic, 3>* vertices,
                        std::unique_ptr<TriangleSurface>& surface, Analysis& a, const AxisReadings& known) {
  if (!options.verify_periods || !options.exact_pairs || !vertices || a.axes.real_count == 0 || a.dense.size() == 0)
    return {};
  std::optional<ExactPairs> pairs;  // the vertices' grid, once a multiple needs it
  bool changed = false;
  for (int k = 0; k < a.axes.real_count; ++k) {
    if (!surface) surface = std::make_unique<TriangleSurface>(mesh);
    const int why = known.unread[std::size_t(k)];
    if (why >= 0 ? why != int(Unread::undecided_axis)
                 : !cell_structure(mesh, a, a.lattice, 0, surface.get(), true, k).undecided[std::size_t(k)])
      continue;
    const Eigen::Vector3d t = a.axes.axes[std::size_t(k)];
    const double extent = a.lattice.cells[k] * t.norm();  // the model's length along t, about
    for (int m = 2; m <= 4 && 2 * m * t.norm() <= extent + 1e-9; ++m) {
      const SnapResult snapped = snap_offset(*vertices, t * double(m), options.snap);
      if (!snapped.snapped || (snapped.offset - t * double(m)).norm() > (m + 1) * options.snap.end_radius) continue;
      std::vector<OffsetTest> tests;
      if (!(pairs ? *pairs : pairs.emplace(mesh, a.normalization, *vertices, options.snap))
               .two_copies(snapped, tests, &a.lattice, k))
        continue;
      PrincipalOffsets axes;
      Result<LatticeFit> fit = fit_with_period(mesh, options, a, k, snapped.offset, axes);
      if (!fit) return fit.status();
      // Two copies between the model's ends, and nothing else: its slabs are copies (not only some of their
      // triangles: posts alike under caps that all differ pair their bodies three posts apart), and no part
      // lies inside the model along k.
      const CellStructure there = cell_structure(mesh, a, fit->lattice, 0, surface.get(), true, k);
      if (structure_unread(there, k) != Unread::read || !(repeated_length(there, fit->lattice, k) > 0) ||
          inner_parts(there, k) > 0)
        continue;
      take_period(a, axes, k, snapped.offset, *fit, m, tests);
      changed = true;
      break;
    }
  }
  if (changed) collect_candidates(options.dense_spacing, a);
  return {};
}

/// Stage "lattice": significant dominant offsets reduced to their fundamental periods, then select_and_fit.
template <class D, class M, class Det>
Status fit_principal_lattice(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options, Analysis& a) {
  Eigen::Matrix<double, Eigen::Dynamic, 3> P;  // unique vertex positions, normalized (offsets/snap.hpp)
  if (options.snap_to_vertices) P = unique_normalized_vertices(mesh, a.normalization);
  reduce_to_fundamental_periods(options, options.snap_to_vertices ? &P : nullptr, a);
  RESTITCH_TRY(find_short_periods(mesh, options, options.snap_to_vertices ? &P : nullptr, a));
  ShapingVertices shaping(mesh, a.normalization, options.flat_vertex_features);
  RESTITCH_TRY(select_and_fit(mesh, options, options.snap_to_vertices ? &P : nullptr, shaping, a));
  std::unique_ptr<TriangleSurface> surface;  // the mesh's triangles for the structures, built once needed
  AxisReadings known;  // per axis, as verify_periods found it
  RESTITCH_TRY(verify_periods(mesh, options, options.snap_to_vertices ? &P : nullptr, shaping, surface, a, known));
  RESTITCH_TRY(phase_by_structure(mesh, options, surface, a, known));
  RESTITCH_TRY(two_copy_periods(mesh, options, options.snap_to_vertices ? &P : nullptr, surface, a, known));
  return find_vertex_repeats(mesh, options, options.snap_to_vertices ? &P : nullptr, shaping, surface, a);
}


}  // namespace detail

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
  return detail::guarded("analyze", [&]() -> Result<Analysis> {
    RESTITCH_TRY(detail::check_analysis_options(options));
    RESTITCH_TRY(validate(mesh));

    Analysis a;
    a.descriptor_name = policy_name(options.descriptor);
    a.matcher_name = policy_name(options.matcher);
    a.detector_name = policy_name(options.detector);
    a.normalization = Normalization::of(bounding_box(mesh));
    std::map<std::string, double>& timings = a.timings_ms;

    PointSet anchors;  // the vertex features, for the offset refinement
    RESTITCH_TRY(detail::analysis_stage("sampling", progress, timings,
                                        [&] { return detail::sample_features(mesh, options, progress, a, anchors); }));
    RESTITCH_TRY(detail::analysis_stage("descriptors", progress, timings, [&]() -> Status {
      D descriptor = options.descriptor;
      detail::set_policy_threads(descriptor, options.threads, 0);
      RESTITCH_TRY(descriptor.compute(a.dense, a.features, a.descriptors, progress));
      if (a.descriptors.rows() != a.features.size())
        return error(StatusCode::internal, "the descriptor policy returned a wrong number of rows");
      return {};
    }));
    if constexpr (detector_uses_matches_v<Det>)  // a detector that ignores matches (autocorrelation) skips the stage
      RESTITCH_TRY(detail::analysis_stage("matching", progress, timings, [&]() -> Status {
        M matcher = options.matcher;
        detail::set_policy_threads(matcher, options.threads, 0);
        RESTITCH_TRY(matcher.match(a.features, a.descriptors, options.tau, a.matches, progress));
        if (a.matches.size() != std::size_t(a.features.size()))
          return error(StatusCode::internal, "the matcher policy returned a wrong number of matches");
        return {};
      }));
    {  // Offset detection: the detector reports its own stages ("histogram" or "autocorrelation", "refinement").
      OffsetDetection det;
      const OffsetEvidence evidence{a.dense, a.features, a.matches, options.dense_spacing, double(options.tau),
                                    &anchors};
      Det detector = options.detector;
      detail::set_policy_threads(detector, options.threads, 0);
      RESTITCH_TRY(detector.detect(evidence, det, progress));
      a.dominant = std::move(det.dominant);
      a.sparsity = det.sparsity;
      a.histogram_peaks = det.peaks;
      for (const auto& kv : det.timings_ms) timings[kv.first] = kv.second;
    }
    RESTITCH_TRY(detail::analysis_stage("lattice", progress, timings,
                                        [&] { return detail::fit_principal_lattice(mesh, options, a); }));
    return a;
  });
}

/// Makes `offsets` (model units, at most three, pairwise at least `options.min_angle` apart) the first
/// principal offsets of `a`, which `analyze(mesh, options)` computed, and refits the lattice
/// (docs/method.md 1.10). Each offset is refined by the same ICP as a dominant offset, starting from the
/// value given, so it need not be typed exactly; a refined offset that lands within the overlap radius
/// of a dominant offset (or of its negative) promotes that one, any other is added to
/// `Analysis::dominant` with its tests run, for the report. The promoted offsets are resized along
/// whatever their tests say: promotion is the user's decision. Errors (invalid_argument, `a` unchanged):
/// more than three offsets, a zero or non-finite one, two closer than min_angle, or one whose
/// refinement slides onto the trivial self-match (no repeat there). Replaces an earlier promotion.
/// Cost: one ICP refinement and test run per offset, plus the lattice fit.
template <class D, class M, class Det>
Status promote_offsets(const Mesh& mesh, const AnalysisOptions<D, M, Det>& options,
                       const std::vector<Eigen::Vector3d>& offsets, Analysis& a) {
  return detail::guarded("promote_offsets", [&]() -> Status {
    RESTITCH_TRY(detail::check_analysis_options(options));
    if (offsets.size() > 3) return error(StatusCode::invalid_argument, "at most three offsets can be made principal");
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      if (!offsets[i].allFinite() || !(offsets[i].norm() > 0))
        return error(StatusCode::invalid_argument, "offset " + std::to_string(i + 1) + " is zero or not finite");
      for (std::size_t j = 0; j < i; ++j)
        if (!far_enough_apart(offsets[i], offsets[j], options.min_angle))
          return error(StatusCode::invalid_argument, "offsets " + std::to_string(j + 1) + " and " +
                                                         std::to_string(i + 1) + " are too close in direction");
    }
    if (a.dense.size() == 0) return error(StatusCode::invalid_argument, "the analysis has no samples");
    Analysis b = a;
    for (const int i : b.promoted) b.dominant[std::size_t(i)].promoted = false;
    b.promoted.clear();
    IcpOptions icp = SignificanceOptions{}.icp;
    icp.spacing = options.dense_spacing;
    const PointSet anchors = detail::vertex_anchors(b);
    const SelfAligner aligner(b.dense, icp, anchors.size() ? &anchors : nullptr);
    const double radius = icp.overlap_radius();
    Eigen::Matrix<double, Eigen::Dynamic, 3> P;
    if (options.snap_to_vertices) P = detail::unique_normalized_vertices(mesh, b.normalization);
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      const Eigen::Vector3d typed = b.normalization.to_normalized_offset(offsets[i]);
      Eigen::Vector3d t = aligner.refine(typed).offset;
      bool kept = false;  // the value typed, snapped, rather than ICP's
      if (options.snap_to_vertices) {  // the value typed stands where it repeats more vertices (docs/method.md 1.10)
        const SnapResult at_typed = snap_offset(P, typed, options.snap);
        // So too where ICP slid onto the model itself (a flat box pulls it there) but the value typed maps
        // vertex pairs: a repeat of the vertices (1.14) the surface alone does not hold.
        if (at_typed.snapped && (!(t.norm() > radius) || at_typed.pairs > snap_offset(P, t, options.snap).pairs))
          t = at_typed.offset, kept = true;
      }
      if (!(t.norm() > radius))
        return error(StatusCode::invalid_argument,
                     "offset " + std::to_string(i + 1) + " is no repeat: refined, it slides onto the model itself");
      // A dominant offset within the overlap radius is the same repeat; where the value typed stood (an exact
      // repeat of the vertices), only one that snaps to it: ICP's result lies within a sample spacing of the
      // repeat it found, so one farther off is another repeat nearby (3 pickets between posts: 0.17 typed, the
      // pickets' pitch, and 0.154, from a picket to a post, 0.026 of the normalized length apart).
      const auto same = [&](const Eigen::Vector3d& o) {
        if ((o - t).norm() > radius) return false;
        if (!kept) return true;
        const SnapResult there = snap_offset(P, o, options.snap);
        return there.snapped && (there.offset - t).norm() <= 2 * options.snap.end_radius;
      };
      int found = -1;
      for (std::size_t k = 0; k < b.dominant.size() && found < 0; ++k)
        if (same(b.dominant[k].offset) || same(Eigen::Vector3d(-b.dominant[k].offset))) found = int(k);
      if (found < 0) {  // a new dominant offset, tested like the detector's
        const PointSet no_features;
        const std::vector<Match> no_matches;
        const OffsetEvidence evidence{
            b.dense, no_features, no_matches, options.dense_spacing, 0.0, anchors.size() ? &anchors : nullptr};
        std::vector<DominantOffset> added;
        RESTITCH_TRY(refine_and_test(evidence, {OffsetCandidate{t, 0, 0, {}}}, SignificanceOptions{}, {}, added));
        if (added.empty()) return error(StatusCode::internal, "the promoted offset was not refined");
        if (kept) added.front().offset = t;  // its tests stay those of where ICP goes from it, for the report
        found = int(b.dominant.size());
        b.dominant.push_back(added.front());
      }
      if (b.dominant[std::size_t(found)].promoted)
        return error(StatusCode::invalid_argument,
                     "offsets " + std::to_string(i + 1) + " and an earlier one are the same");
      b.dominant[std::size_t(found)].promoted = true;
      b.promoted.push_back(found);
    }
    const auto t0 = std::chrono::steady_clock::now();
    detail::ShapingVertices shaping(mesh, b.normalization, options.flat_vertex_features);
    RESTITCH_TRY(detail::select_and_fit(mesh, options, options.snap_to_vertices ? &P : nullptr, shaping, b));
    std::unique_ptr<detail::TriangleSurface> surface;
    detail::AxisReadings known;
    RESTITCH_TRY(detail::phase_by_structure(mesh, options, surface, b, known));
    b.timings_ms["promotion"] = detail::elapsed_ms(t0);
    a = std::move(b);
    return {};
  });
}

// The compiled mode (restitch/detail/instantiation.hpp): the default policies.
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<>&, const Progress&))
RESTITCH_INSTANTIATE(Status promote_offsets(const Mesh&, const AnalysisOptions<>&, const std::vector<Eigen::Vector3d>&,
                                            Analysis&))

}  // namespace restitch
