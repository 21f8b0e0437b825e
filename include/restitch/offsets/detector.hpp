// restitch/offsets/detector.hpp - the offset-detector policy contract and the default HistogramOffsetDetector.
//
// An offset detector turns the evidence of an analysis (dense samples,
// features, their matches) into *dominant offsets*: translations under which
// a good part of the model maps onto itself, ranked, each marked significant
// or not. Principal offsets are then chosen greedily among the significant
// ones (offsets/principal.hpp). restitch ships the paper's histogram
// detector (here, the default) and the autocorrelation detector
// (offsets/autocorrelation.hpp, docs/method.md 1.9). Both hand their
// candidates to `refine_and_test` (steps 2 and 3 below), so their dominant
// offsets mean the same.
//
// The contract (checked by `is_offset_detector_v<T>`; the analysis
// static_asserts it with a readable message):
//
//   struct MyDetector {
//     // A short, stable name for reports ("histogram").
//     static constexpr const char* name = "...";
//     // Fills `out` (overwritten): dominant offsets in normalized units,
//     // ranked (strongest first), and the sparsity of the evidence. Must not
//     // throw; returns invalid_argument for inconsistent evidence, cancelled
//     // when `progress.report` returns false. Deterministic.
//     restitch::Status detect(const restitch::OffsetEvidence& evidence,
//                             restitch::OffsetDetection& out,
//                             const restitch::Progress& progress) const;
//   };
//
// Run-time parameters are members of the policy object. A detector that
// never reads `evidence.features` / `evidence.matches` may declare
// `static constexpr bool uses_matches = false;`: analyze() then skips the
// matching stage and passes an empty match list (`detector_uses_matches_v`).
//
// HistogramOffsetDetector (docs/method.md 1.4-1.5):
//  1. Histogram: one vote per matched feature, v = y - x, bins of 0.05, peaks
//     by non-maximum suppression with radius 0.15, ranked by mass
//     (offsets/histogram.hpp). Sparsity of the histogram (Fig. 5).
//  2. (Steps 2 and 3 are `refine_and_test`, shared by every shipped
//     detector.) The `max_peaks` (20; the paper reports "about 20 dominant
//     offsets") top peaks with at least `min_votes` mass are refined by translation-only ICP
//     of the dense cloud onto itself, from the bin centre, with the mesh
//     vertices (evidence.anchors) as exact point-to-point anchors
//     (offsets/refine.hpp). A peak that refines to within the overlap radius
//     of a stronger one is the same offset and is dropped; so is one that
//     refines to within tau of 0 (it slid onto the trivial self-match).
//  3. Significance. A model without repetition must yield no principal
//     offset, so every peak must earn its place. overlap() is the share of
//     dense points that land on the surface when shifted (offsets/refine.hpp).
//     A dominant offset t is significant when all of these hold:
//     * mass >= min_votes (5). Offsets are longer than tau = 0.15, so a
//       repeated module is at least 0.15 across, and even one of its faces
//       holds about (0.15 / 0.06)^2 ~ 6 features at the feature spacing, each
//       voting for the same offset. Fewer votes are a coincidence of a few
//       features, not a repeated module.
//     * overlap(t) >= min_overlap (1/3): shifting n >= 3 copies of a module by
//       its period maps (n-1)/n >= 2/3 of the repeated part onto itself; 1/3
//       leaves room for end caps and parts that do not repeat. A chance
//       coincidence between two unrelated parts maps only faces of one part
//       that face the same way onto the other, well under half of the
//       smaller part.
//     * a peak, not a slide: along its own direction the overlap has a kink
//       at t: contrast = overlap(t) - (overlap(t - d u) + overlap(t + d u)) / 2
//       >= min_contrast (0.01), u = t / |t|, d = 2 overlap radii (so no pair
//       that overlaps at t still overlaps at t +- d u through the same
//       partner). Sliding convex parts (a plate, a bar, a plain wall) along
//       themselves overlaps linearly less the longer the slide, so their
//       second difference is 0 however large they are; a real period is a
//       strict maximum, its transverse surface overlapping only at t. The
//       threshold only has to clear the sampling noise of the second
//       difference on 2048 points (about +-0.005 measured on slides); a wall
//       with small windows reaches only a few hundredths, so it must stay
//       this low.
//     * a pattern, not a pair: overlap(2t) >= overlap(t) / 4. For n copies of
//       a module, overlap(2t) / overlap(t) = (n-2)/(n-1), at least 1/2 once
//       there are three copies, but about 0 for two look-alike parts (the two
//       rails of a fence, two legs): continuing a pair is not resizing a
//       pattern. (So a structure must repeat at least three times to be
//       resized along; 1/4 leaves half of the three-copy ratio as margin.)
//     A candidate that fails these on the whole surface but carries votes
//     (`OffsetCandidate::seeds`, filled by the histogram detector) is tested
//     again on the part that repeats, the dense samples near the features
//     that voted for it (offsets/part.hpp, `DominantOffset::part`): a
//     minority repeat (windows in a flat door) is drowned on the whole
//     surface. Passing there makes it significant, at the part's offset.
//     Insignificant dominant offsets stay in the list (flagged) so a report
//     can show why a peak was rejected.
//
// Units: normalized. Cost: histogram O(#matches); refinement
// O(max_peaks * (2 * iterations + 5) * 2048 * log #dense) plus k-d tree builds
// O(#dense log #dense + #anchors log #anchors).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/detail/parallel.hpp"
#include "restitch/matcher/matcher.hpp"
#include "restitch/offsets/histogram.hpp"
#include "restitch/offsets/part.hpp"
#include "restitch/offsets/principal.hpp"
#include "restitch/offsets/refine.hpp"
#include "restitch/offsets/test_record.hpp"
#include "restitch/progress.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// What a detector gets to look at (all normalized; references, nothing copied).
struct OffsetEvidence {
  const PointSet& dense;              ///< dense surface samples with normals
  const PointSet& features;           ///< the features that were matched
  const std::vector<Match>& matches;  ///< one per feature; target -1 = no match
  double dense_spacing;               ///< the spacing `dense` was sampled at
  double tau;                         ///< the matcher's minimum offset length
  const PointSet* anchors = nullptr;  ///< mesh vertices (normalized, with normals) as exact ICP anchors; may be null
};

/// A dominant offset: a peak (of the histogram, or of S_T) after refinement.
struct DominantOffset {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();      ///< refined, normalized
  Eigen::Vector3d bin_center = Eigen::Vector3d::Zero();  ///< where ICP started: the peak bin's centre (or S_T peak)
  std::size_t votes = 0;            ///< peak mass (bin and 26 neighbours; autocorrelation: S_T x #dense)
  std::size_t bin_votes = 0;        ///< votes in the peak bin alone (autocorrelation: = votes)
  double overlap = 0;               ///< see offsets/refine.hpp
  double contrast = 0;              ///< see the header comment
  double overlap_double = 0;        ///< overlap(2 t)
  double contrast_double = 0;       ///< contrast at 2 t
  double axis_contrast_double = 0;  ///< least contrast at 2 t along t and the world axes (if tested)
  /// t without its components along the world axes in which the overlap at t is flat (a slide: the
  /// model is uniform that way, so t plus any shift along it overlaps as well); t itself when none is.
  Eigen::Vector3d unslid = Eigen::Vector3d::Zero();
  double double_drift = 0;          ///< |refine(2 t) - 2 t|
  int iterations = 0;               ///< ICP iterations
  bool significant = false;
  /// The peak was `divisor` periods long and `offset` is its fundamental
  /// period (offsets/fundamental.hpp, applied by the analysis); 1: as found.
  int divisor = 1;
  /// The tests on the part that repeats (offsets/part.hpp), run when the
  /// whole-surface tests fail and the candidate has votes; `part.passed`
  /// made it significant (then `offset` is the part's refined offset).
  PartTest part;
  /// The significance tests in the order they ran: the whole-surface tests (the run stops at the
  /// first failure), then, for a candidate with votes that failed them, "part_new" (1: not an integer
  /// combination of significant offsets; 0, failed: one, so its part is not tested) and, when the
  /// part test ran, its tests named "part_..." (offsets/part.hpp).
  std::vector<OffsetTest> tests;
  /// Made principal on request (promote_offsets, `--offsets`), whatever its tests say.
  bool promoted = false;
  /// A repeat of the vertices (docs/method.md 1.14, from_vertices()): the cells along it found copies of a
  /// neighbour; 0 for the detector's offsets.
  int copies = 0;

  /// The test that rejected this offset (the first that failed), or null when it is significant.
  template <class = void>
  const OffsetTest* failed_test() const {
    if (significant) return nullptr;
    for (const OffsetTest& t : tests)
      if (!t.passed) return &t;
    return nullptr;
  }
  /// Found by the lags of the vertices along an axis the matching found nothing on and checked against the
  /// structure (docs/method.md 1.14), not by the detector: a candidate of reason "vertices".
  bool from_vertices() const {
    return !tests.empty() && tests.front().name == "vertex_lag" &&
           std::any_of(tests.begin(), tests.end(), [](const OffsetTest& t) { return t.name == "vertex_structure" && t.passed; });
  }
  /// Significant as two exact copies (docs/method.md 1.13): its last pair test, "pair_third_copy", passed.
  bool exact_pair() const {
    return significant &&
           std::any_of(tests.begin(), tests.end(), [](const OffsetTest& t) { return t.name == "pair_third_copy" && t.passed; });
  }
  /// Not significant, and on the whole surface it passed votes, overlap and contrast and failed a
  /// pattern test: two copies, not a pattern.
  template <class = void>
  bool is_pair() const {
    const OffsetTest* f = failed_test();
    return f && is_pattern_test(f->name);
  }
};

/// A basis of the lattice the significant offsets of `offsets` span (independent_offsets,
/// offsets/principal.hpp), for is_lattice_vector with the same `tolerance`.
template <class = void>
std::vector<Eigen::Vector3d> significant_basis(const std::vector<DominantOffset>& offsets, double tolerance) {
  std::vector<Eigen::Vector3d> significant;
  for (const DominantOffset& o : offsets)
    if (o.significant) significant.push_back(o.offset);
  return independent_offsets(significant, tolerance);
}

/// A detector's answer.
struct OffsetDetection {
  std::vector<DominantOffset> dominant;  ///< ranked, strongest first
  Sparsity sparsity;
  std::size_t peaks = 0;                     ///< peaks (histogram or S_T) before the max_peaks cap
  std::map<std::string, double> timings_ms;  ///< per stage, e.g. "histogram", "refinement"
};

namespace detail {
template <class T, class = void>
struct is_offset_detector : std::false_type {};
template <class T>
struct is_offset_detector<
    T, std::void_t<decltype(T::name), decltype(std::declval<const T&>().detect(std::declval<const OffsetEvidence&>(),
                                                                               std::declval<OffsetDetection&>(),
                                                                               std::declval<const Progress&>()))>>
    : std::bool_constant<std::is_convertible_v<decltype(T::name), const char*> &&
                         std::is_same_v<decltype(std::declval<const T&>().detect(std::declval<const OffsetEvidence&>(),
                                                                                 std::declval<OffsetDetection&>(),
                                                                                 std::declval<const Progress&>())),
                                        Status>> {};

inline double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}
}  // namespace detail

template <class T>
inline constexpr bool is_offset_detector_v = detail::is_offset_detector<T>::value;

namespace detail {
template <class T, class = void>
struct detector_uses_matches : std::true_type {};
template <class T>
struct detector_uses_matches<T, std::void_t<decltype(T::uses_matches)>> : std::bool_constant<bool(T::uses_matches)> {};
}  // namespace detail

/// False when the detector declares `static constexpr bool uses_matches = false;` (see the header comment).
template <class T>
inline constexpr bool detector_uses_matches_v = detail::detector_uses_matches<T>::value;

/// A candidate dominant offset for the shared refinement and significance
/// tests (refine_and_test): where ICP starts and how strong its evidence is.
struct OffsetCandidate {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  ///< ICP start (normalized): a bin centre, an S_T peak...
  std::size_t votes = 0;                            ///< evidence mass (DominantOffset::votes)
  std::size_t bin_votes = 0;                        ///< evidence at the start alone (DominantOffset::bin_votes)
  /// The positions of the features that voted for it, both ends of each
  /// vote (the histogram detector): they define the part that repeats
  /// (offsets/part.hpp). Empty: no part test.
  std::vector<Eigen::Vector3d> seeds;
};

/// Thresholds of the significance tests (see the header comment), shared by the shipped detectors.
struct SignificanceOptions {
  std::size_t min_votes = 5;
  double min_overlap = 1.0 / 3.0;
  double min_contrast = 0.01;
  double min_repeat_ratio = 0.25;  ///< overlap(2t) / overlap(t) at least this
  double max_double_drift = 0.25;  ///< |refine(2t) - 2t| at most this many dense spacings
  IcpOptions icp{};                ///< `icp.spacing` is replaced by the evidence's dense spacing
  /// Also require the contrast at 2t along each world axis (the autocorrelation detector; see
  /// offsets/autocorrelation.hpp): a period combined with a slide is no strict maximum at 2t.
  bool axis_contrast = false;
  /// The same tests on the part that repeats, for candidates with seeds (offsets/part.hpp).
  PartOptions part{};
  /// Workers for the refinement and the tests (detail/parallel.hpp; 0: every hardware thread). The
  /// dominant offsets are the same whatever the number.
  int threads = 1;

  template <class = void>
  bool valid() const {
    return min_overlap >= 0 && min_overlap <= 1 && std::isfinite(min_contrast) && min_repeat_ratio >= 0 &&
           std::isfinite(min_repeat_ratio) && max_double_drift >= 0;
  }
};

namespace detail {
/// The part test (offsets/part.hpp), after every candidate had its
/// whole-surface tests: for each `failed` (index into `out`, index into
/// `todo`), in rank order, when it passes on its part and its part-refined
/// offset is not, up to sign, one already significant, it becomes
/// significant at that offset. Run last so that an offset the whole surface
/// accepts (at either sign) keeps its whole-surface value.
template <class = void>
void significant_on_part(const SelfAligner& aligner, const OffsetEvidence& ev,
                                const std::vector<OffsetCandidate>& todo, const SignificanceOptions& tests,
                                const std::vector<std::pair<std::size_t, std::size_t>>& failed,
                                std::vector<DominantOffset>& out) {
  const double radius = aligner.options().overlap_radius();
  for (const auto& f : failed) {
    DominantOffset& d = out[f.first];
    const OffsetCandidate& c = todo[f.second];
    if (c.seeds.empty() || d.votes < tests.min_votes) continue;
    // An integer combination of significant offsets (a multiple, a diagonal) is a lattice vector of
    // repeats already found: whatever its part says, the lattice holds it, so its part is not tested.
    const std::vector<Eigen::Vector3d> basis = significant_basis(out, radius);  // grows as parts pass
    if (!record_test(d.tests, "part_new", is_lattice_vector(d.offset, basis, nullptr, radius) ? 0.0 : 1.0, 1.0))
      continue;
    d.part = test_on_part(aligner, c.start, d.offset, c.seeds, ev.tau, tests.min_overlap, tests.min_contrast,
                          tests.min_repeat_ratio, tests.max_double_drift, tests.part);
    d.tests.insert(d.tests.end(), d.part.tests.begin(), d.part.tests.end());
    if (!d.part.passed) continue;
    bool known = false;
    for (const DominantOffset& o : out)
      known = known || (o.significant && ((o.offset - d.part.offset).norm() <= radius ||
                                           (o.offset + d.part.offset).norm() <= radius));
    if (known) continue;
    d.offset = d.part.offset;
    d.significant = true;
  }
}
}  // namespace detail

/// Step 2 and 3 of the header comment, for any detector: refines each
/// candidate, in the given order, by translation-only ICP of the dense cloud
/// onto itself (with the evidence's anchors), drops it when it slides to
/// within tau of 0 or to within the overlap radius of an offset already kept,
/// and runs the significance tests on the rest. Appends to `out` (which it
/// does not clear: earlier entries count as kept offsets). Reports progress
/// under "refinement" (fractions in [0, 1), never 1: the caller closes the
/// stage); a cancel gives StatusCode::cancelled. Deterministic.
/// Cost: O(#candidates * (2 * iterations + 5) * 2048 * log #dense) plus the
/// k-d tree builds, none when there is no candidate or no dense point.
template <class = void>
Status refine_and_test(const OffsetEvidence& ev, const std::vector<OffsetCandidate>& todo,
                              const SignificanceOptions& tests, const Progress& progress,
                              std::vector<DominantOffset>& out) {
  if (todo.empty() || ev.dense.size() == 0) return {};
  IcpOptions options = tests.icp;
  options.spacing = ev.dense_spacing;
  const SelfAligner aligner(ev.dense, options, ev.anchors);
  const double radius = options.overlap_radius();
  const int threads = resolve_threads(tests.threads);
  // Every candidate's ICP (independent: tasks on the workers), then, in order, the duplicates out,
  // then the tests of those kept (independent again), then the part test in order.
  std::vector<RefinedOffset> refined(todo.size());
  const auto tick = [&](double from, std::size_t done, std::size_t of) {
    return progress.report("refinement", from + 0.5 * double(done) / double(of + 1));
  };
  if (!detail::parallel_tasks(
          threads, todo.size(), [&](std::size_t k, int) { refined[k] = aligner.refine(todo[k].start); },
          [&](std::size_t done) { return tick(0, done, todo.size()); }))
    return error(StatusCode::cancelled, "cancelled during offset refinement");
  std::vector<std::size_t> kept;  // indices into todo
  for (std::size_t k = 0; k < todo.size(); ++k) {
    const RefinedOffset& r = refined[k];
    bool duplicate = r.offset.norm() <= ev.tau;  // slid onto the trivial self-match t = 0
    for (const DominantOffset& d : out) duplicate = duplicate || (d.offset - r.offset).norm() <= radius;
    for (const std::size_t e : kept) duplicate = duplicate || (refined[e].offset - r.offset).norm() <= radius;
    if (!duplicate) kept.push_back(k);
  }
  std::vector<DominantOffset> tested(kept.size());
  const auto test_one = [&](std::size_t task, int) {
    const std::size_t k = kept[task];
    const RefinedOffset& r = refined[k];
    DominantOffset& d = tested[task];
    d.offset = r.offset;
    d.bin_center = todo[k].start;
    d.votes = todo[k].votes;
    d.bin_votes = todo[k].bin_votes;
    d.overlap = r.overlap;
    d.iterations = r.iterations;
    // Significance, cheapest tests first; the run stops at the first failure (later fields stay 0).
    const auto test = [&d](const char* name, double value, double threshold, bool at_most = false) {
      return record_test(d.tests, name, value, threshold, at_most);
    };
    const auto kink = [&](const Eigen::Vector3d& t, double at_t) {
      const Eigen::Vector3d step = t.normalized() * (2 * radius);
      return at_t - 0.5 * (aligner.overlap(t - step) + aligner.overlap(t + step));
    };
    bool ok = test("votes", double(d.votes), double(tests.min_votes)) &&
              test("overlap", d.overlap, tests.min_overlap);
    if (ok) d.contrast = kink(r.offset, r.overlap), ok = test("contrast", d.contrast, tests.min_contrast);
    if (ok) {
      const RefinedOffset r2 = aligner.refine(2 * r.offset);
      d.double_drift = detail::least_drift((r2.offset - 2 * r.offset).norm(),
                                           detail::vertex_double_drift(ev.anchors, r.offset));
      d.overlap_double = aligner.overlap(2 * r.offset);
      ok = test("double_drift", d.double_drift / ev.dense_spacing, tests.max_double_drift, true) &&
           test("repeat", d.overlap > 0 ? d.overlap_double / d.overlap : 1.0, tests.min_repeat_ratio);
    }
    if (ok)
      d.contrast_double = kink(2 * r.offset, d.overlap_double),
      ok = test("contrast_double", d.contrast_double, tests.min_contrast);
    if (ok && tests.axis_contrast) {
      d.axis_contrast_double = d.contrast_double;
      for (int axis = 0; axis < 3; ++axis) {
        const Eigen::Vector3d step = Eigen::Vector3d::Unit(axis) * (2 * radius);
        d.axis_contrast_double = std::min(
            d.axis_contrast_double,
            d.overlap_double - 0.5 * (aligner.overlap(2 * r.offset - step) + aligner.overlap(2 * r.offset + step)));
      }
      ok = test("axis_contrast_double", d.axis_contrast_double, tests.min_contrast);
    }
    // Slides: along a world axis in which t has a component, an overlap at t no higher than beside it.
    d.unslid = r.offset;
    if (ok)
      for (int axis = 0; axis < 3; ++axis) {
        if (std::abs(r.offset[axis]) <= radius) continue;
        const Eigen::Vector3d step = Eigen::Vector3d::Unit(axis) * (2 * radius);
        const double flat = r.overlap - 0.5 * (aligner.overlap(r.offset - step) + aligner.overlap(r.offset + step));
        if (flat < tests.min_contrast) d.unslid[axis] = 0;
      }
    d.significant = ok;
  };
  if (!detail::parallel_tasks(threads, kept.size(), test_one,
                              [&](std::size_t done) { return tick(0.5, done, kept.size()); }))
    return error(StatusCode::cancelled, "cancelled during offset refinement");
  // An offset that is another significant offset plus a slide is that offset: the radiator's section
  // pitch plus any height (a uniform vertical section slides onto its neighbour at every height).
  for (std::size_t e = 0; e < kept.size(); ++e) {
    DominantOffset& d = tested[e];
    if (!d.significant || (d.unslid - d.offset).norm() <= radius) continue;
    double nearest = std::numeric_limits<double>::infinity();
    const auto near = [&](const DominantOffset& o) {
      if (&o == &d || !o.significant) return;
      nearest = std::min({nearest, (o.offset - d.unslid).norm(), (o.offset + d.unslid).norm()});
    };
    for (const DominantOffset& o : out) near(o);
    for (const DominantOffset& o : tested) near(o);
    d.significant = record_test(d.tests, "slide", nearest, radius);
  }
  std::vector<std::pair<std::size_t, std::size_t>> failed;  // (index in out, index in todo)
  for (std::size_t e = 0; e < kept.size(); ++e) {
    if (!tested[e].significant) failed.emplace_back(out.size(), kept[e]);  // for the part test below
    out.push_back(std::move(tested[e]));
  }
  detail::significant_on_part(aligner, ev, todo, tests, failed, out);  // offsets/part.hpp
  return {};
}

namespace detail {
/// For each candidate (a peak at a bin centre), both ends of every vote in
/// its bin or one of the 26 neighbours (the votes its mass counts), each
/// feature once, in index order: the seeds of its part (offsets/part.hpp).
template <class = void>
void collect_part_seeds(const PointSet& features, const std::vector<Eigen::Vector3d>& offsets,
                               const std::vector<std::pair<std::int32_t, std::int32_t>>& voters, double bin_size,
                               std::vector<OffsetCandidate>& todo) {
  std::vector<Eigen::Vector3d> peak_bins;
  for (const OffsetCandidate& c : todo) peak_bins.push_back((c.start / bin_size).array().floor().matrix());
  std::vector<std::vector<std::int32_t>> ends(todo.size());  // feature indices, each once (cost only)
  for (std::size_t v = 0; v < offsets.size(); ++v) {
    const Eigen::Vector3d b = (offsets[v] / bin_size).array().floor().matrix();
    for (std::size_t k = 0; k < todo.size(); ++k)
      if ((b - peak_bins[k]).cwiseAbs().maxCoeff() <= 1.5)
        ends[k].push_back(voters[v].first), ends[k].push_back(voters[v].second);
  }
  for (std::size_t k = 0; k < todo.size(); ++k) {
    std::sort(ends[k].begin(), ends[k].end());
    ends[k].erase(std::unique(ends[k].begin(), ends[k].end()), ends[k].end());
    for (std::int32_t f : ends[k]) todo[k].seeds.push_back(features.points.row(f).cast<double>().transpose());
  }
}
}  // namespace detail

/// The paper's detector: histogram, non-maximum suppression, ICP refinement, significance (see header).
struct HistogramOffsetDetector {
  static constexpr const char* name = "histogram";

  double bin_size = 0.05;
  double suppression_radius = 0.15;
  std::size_t max_peaks = 20;
  /// The significance tests (mass, overlap, contrast, pattern, the part test), for refine_and_test.
  SignificanceOptions significance{};

  template <class = void>
  Status detect(const OffsetEvidence& ev, OffsetDetection& out, const Progress& progress) const {
    return detail::guarded("HistogramOffsetDetector::detect", [&]() -> Status {
      out = OffsetDetection{};
      if (ev.matches.size() != std::size_t(ev.features.size()))
        return error(StatusCode::invalid_argument, "the detector needs exactly one match per feature");
      if (ev.dense.normals.rows() != ev.dense.points.rows())
        return error(StatusCode::invalid_argument, "the dense samples need one normal per point");
      if (!(ev.dense_spacing > 0) || !std::isfinite(ev.dense_spacing) || !(ev.tau >= 0) || !std::isfinite(ev.tau))
        return error(StatusCode::invalid_argument, "the dense spacing must be positive and tau non-negative");
      if (!(max_peaks >= 1 && significance.valid() && suppression_radius >= 0 && std::isfinite(suppression_radius)))
        return error(StatusCode::invalid_argument, "HistogramOffsetDetector parameters out of range");

      // 1. Histogram and peaks.
      auto t0 = std::chrono::steady_clock::now();
      if (!progress.report("histogram", 0))
        return error(StatusCode::cancelled, "cancelled during the offset histogram");
      std::vector<Eigen::Vector3d> offsets;
      std::vector<std::pair<std::int32_t, std::int32_t>> voters;  // (x, y) of each offset, for the part test
      offsets.reserve(ev.matches.size());
      for (std::size_t i = 0; i < ev.matches.size(); ++i) {
        const std::int32_t j = ev.matches[i].target;
        if (j < 0) continue;
        if (j >= ev.features.size())
          return error(StatusCode::invalid_argument,
                       "match " + std::to_string(i) + " names a feature that does not exist");
        offsets.push_back(
            (ev.features.points.row(j) - ev.features.points.row(Eigen::Index(i))).cast<double>().transpose());
        voters.emplace_back(std::int32_t(i), j);
      }
      OffsetHistogram hist;
      RESTITCH_TRY(build_offset_histogram(offsets, bin_size, hist));
      out.sparsity = offset_sparsity(hist);
      std::vector<HistogramPeak> peaks = find_peaks(hist, suppression_radius);
      out.peaks = peaks.size();
      out.timings_ms["histogram"] = detail::elapsed_ms(t0);
      if (!progress.report("histogram", 1))
        return error(StatusCode::cancelled, "cancelled during the offset histogram");

      // 2. Refinement and significance.
      t0 = std::chrono::steady_clock::now();
      std::vector<OffsetCandidate> todo;
      for (const HistogramPeak& p : peaks)
        if (p.mass >= significance.min_votes && todo.size() < max_peaks)
          todo.push_back({p.center, p.mass, p.votes, {}});
      if (significance.part.enabled) detail::collect_part_seeds(ev.features, offsets, voters, bin_size, todo);
      RESTITCH_TRY(refine_and_test(ev, todo, significance, progress, out.dominant));
      out.timings_ms["refinement"] = detail::elapsed_ms(t0);
      if (!progress.report("refinement", 1)) return error(StatusCode::cancelled, "cancelled during offset refinement");
      return {};
    });
  }
};

}  // namespace restitch
