// restitch/offsets/part.hpp - significance judged on the part of the surface that repeats.
//
// docs/method.md 1.5.1. The significance tests of offsets/detector.hpp
// measure the overlap over the whole dense surface. A part that repeats but
// covers a minority of it (windows in a flat door, muntins in a window
// frame, stringers under a pallet deck, ornaments between bars) is then
// judged together with everything that does not repeat with it: its overlap
// stays under 1/3, or the kink of its overlap drowns in the slide of the
// large faces around it. This header runs the same tests on the part that
// repeats instead.
//
// The part. A histogram peak knows which features voted for it: each vote
// is a feature x and its best match y = x + v with v in the peak's bin or
// one of its 26 neighbours (the bins its mass counts). The part is every
// dense sample within `radius` of such an x or y: the copies the votes come
// from and land on. radius = the feature spacing (0.06), because the
// feature sample is near-maximal at that spacing (offsets: sampling/), so
// the balls of that radius around the features of a module cover the
// module, and a larger radius would add surroundings that do not repeat.
// The part's anchors (mesh vertices) are chosen the same way.
//
// The tests. Those of offsets/detector.hpp, with the overlap taken over
// the part's samples (the targets stay the whole surface): ICP of the part
// onto the surface from the peak (the part's anchors pull as in
// offsets/refine.hpp), |t| > tau, overlap >= 1/3, a kink along t
// (contrast >= 0.01), and the pattern at 2t (ICP restarted at 2t stays
// within 0.25 spacings, overlap(2t) >= overlap(t) / 4, contrast at 2t >=
// 0.01). Two tests are added, because the part, chosen by the votes, has
// lost the protection the rest of the surface gave:
//  * Evidence in samples (`min_kink_samples`): a share over a small part is
//    coarse, so the kink must be carried by as many samples as the
//    whole-surface threshold asks of its 2048 sources, contrast x part
//    samples >= 0.01 x 2048 ~ 20, at t, at 2t and along the axes below. A
//    part smaller than 20 / (1/3) ~ 62 samples cannot pass: about 4 feature
//    balls (a ball of radius 0.06 holds about 15 dense samples at 0.5
//    samples per spacing squared), the smallest module the mass test (5
//    votes) describes.
//  * A strict maximum along every world axis, at t and at 2t (as the
//    autocorrelation detector asks at 2t, offsets/autocorrelation.hpp). The
//    votes favour parts that slide: a row of balusters shifted by one pitch
//    plus a slide along the balusters lands them on each other, a kink
//    along that diagonal t and again at 2t (the Sweet Home 3D railing's
//    (0.118, 0.201) passed without this). Along the balusters' axis it is a
//    slide (contrast <= 0); a true period keeps its kink along every axis,
//    because every face of the module that is transverse to an axis stops
//    matching when the shift moves off the period along it.
// Why a coincidence fails them:
//  * Two look-alike parts (two rails, two legs): the part is both, at t one
//    maps onto the other (overlap about 1/2), at 2t neither lands on
//    anything of the part (overlap(2t) about 0): the pattern test fails, as
//    on the whole surface. Restricting to the part does not help a pair.
//  * A slide (a plate or a bar along itself): on the part the overlap still
//    falls linearly with the shift, so the kink is 0 however small the part.
//  * Chance agreement of a few features: too few samples (above).
// Known weakness: faces that coincide by chance, within the overlap radius,
// at t and again at 2t. Random boxes with seed 5 (tests/support) have
// such a chain (x faces 0.174 and 0.35 apart within 0.01-0.02): without
// the screen below its part passed every test (overlap 0.94, contrast
// 0.020 = 30 samples, at 2t 0.79 and 0.016); measured at the whole
// surface's ICP offset it fails the screen. That is luck, not a guarantee.
// A 3t test did not stop it (the chain holds there too) and rejected the
// synthetic door of tests/analyze_test.cpp.
//
// Cost screen: the part's overlap and kink are first measured at the
// offset the whole surface's ICP found (3 overlaps); only when they pass
// is the part's own ICP run (it moves the offset by a fraction of a spacing
// where the part is a minority). Without the screen the part test added up
// to a third to the analysis of real models (bench, radiator); so did
// sorting nanoflann's radius results and the overlapping balls' indices
// (now unsorted searches, one mark per point, one sort).
//
// The part test runs only for a candidate that fails the whole-surface
// tests and that carries votes (the autocorrelation detector has none), so
// it never changes what was significant before, and costs nothing on a
// model whose repeats pass on the whole surface. Nor does it run on an
// integer combination of offsets already significant (twice a period, a
// diagonal): the lattice holds those whatever their part says (the test
// `part_new`, recorded by offsets/detector.hpp).
//
// Units: normalized (those of the aligner). Deterministic: the part's
// indices are sorted and thinned at an even stride like the aligner's own
// sources. Cost: per candidate, #seeds radius searches plus the tests'
// 2 ICP runs and 7 overlaps on at most max_sources points.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "restitch/offsets/refine.hpp"
#include "restitch/offsets/snap.hpp"
#include "restitch/offsets/test_record.hpp"

namespace restitch {

/// Parameters of the part test (see the header comment for each reason).
struct PartOptions {
  bool enabled = true;                    ///< false: the paper's whole-surface tests only
  double radius = 0.06;                   ///< part = dense samples within this of a voting feature (the feature spacing)
  double min_kink_samples = 0.01 * 2048;  ///< contrast x part samples at least this (at t, 2t and along the axes)
};

/// What the part test measured (all 0 when it did not run).
struct PartTest {
  bool ran = false, passed = false;
  std::size_t samples = 0;  ///< dense samples in the part (before thinning to max_sources)
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< refined on the part
  double overlap = 0, contrast = 0, overlap_double = 0, contrast_double = 0, double_drift = 0;
  double axis_contrast = 0, axis_contrast_double = 0;  ///< least contrast along a world axis at t and 2t
  double rms = 0;  ///< point-to-plane RMS of the part's ICP at t
  /// The tests as run, for reports (docs/method.md 1.10): part_screen_overlap and
  /// part_screen_contrast (at the whole surface's offset, a cost screen), part_length (|t| vs tau),
  /// part_overlap, part_contrast, part_double_drift (in dense spacings), part_repeat,
  /// part_contrast_double, part_axis_contrast; a contrast's threshold is max(min_contrast,
  /// min_kink_samples / samples). The run stops at the first failure.
  std::vector<OffsetTest> tests;
};

/// The dense samples and anchors within `radius` of any seed, sorted, thinned
/// at an even stride to the aligner's max_sources.
template <class = void>
SelfAligner::Sources repeated_part(const SelfAligner& aligner, const std::vector<Eigen::Vector3d>& seeds,
                                          double radius, std::size_t* samples = nullptr, bool with_anchors = true) {
  SelfAligner::Sources part;
  // Each index once (a mark per point; the balls overlap a lot), then sorted.
  std::vector<std::uint8_t> in_cloud(std::size_t(aligner.cloud().size()), 0), in_anchors;
  if (with_anchors && aligner.anchors()) in_anchors.assign(std::size_t(aligner.anchors()->size()), 0);
  std::vector<std::uint32_t> found;
  const auto keep = [&found](std::vector<std::uint8_t>& mark, std::vector<std::uint32_t>& out) {
    for (std::uint32_t i : found)
      if (!mark[i]) mark[i] = 1, out.push_back(i);
    found.clear();
  };
  // A feature is the target of many votes: each distinct seed is searched once (same part, less work).
  std::vector<Eigen::Vector3d> unique_seeds = seeds;
  std::sort(unique_seeds.begin(), unique_seeds.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  unique_seeds.erase(std::unique(unique_seeds.begin(), unique_seeds.end()), unique_seeds.end());
  for (const Eigen::Vector3d& s : unique_seeds) {
    aligner.cloud_within(s, radius, found);
    keep(in_cloud, part.cloud);
    if (in_anchors.empty()) continue;
    aligner.anchors_within(s, radius, found);
    keep(in_anchors, part.anchors);
  }
  const std::size_t cap = std::max<std::size_t>(aligner.options().max_sources, 1);
  for (std::vector<std::uint32_t>* v : {&part.cloud, &part.anchors}) {
    std::sort(v->begin(), v->end());
    if (v == &part.cloud && samples) *samples = v->size();
    if (v->size() > cap) {
      std::vector<std::uint32_t> thin;
      thin.reserve(cap);
      for (std::size_t k = 0; k < cap; ++k) thin.push_back((*v)[k * v->size() / cap]);
      v->swap(thin);
    }
  }
  return part;
}

namespace detail {
/// The drift at 2t measured on the mesh's vertices (docs/method.md 1.5): with s = t snapped onto the
/// vertices (offsets/snap.hpp), |snap(2 s) - 2 s| when the vertices repeat at s and at 2 s, else NaN.
/// ICP on the surface at 2t is pulled by whatever else overlaps there (a fence's posts, where only one
/// picket of three still overlaps); vertex copies at exactly 2 s are direct evidence that the repeat
/// continues. `anchors`: the mesh's vertices (may be null).
template <class = void>
double vertex_double_drift(const PointSet* anchors, const Eigen::Vector3d& t, const SnapOptions& options = {}) {
  if (!anchors || anchors->size() == 0) return NAN;
  const Eigen::Matrix<double, Eigen::Dynamic, 3> P = anchors->points.cast<double>();
  const SnapResult once = snap_offset(P, t, options);
  if (!once.snapped) return NAN;
  const SnapResult twice = snap_offset(P, 2 * once.offset, options);
  return twice.snapped ? (twice.offset - 2 * once.offset).norm() : NAN;
}
/// The smaller of two drifts, a NaN one ignored.
inline double least_drift(double icp, double vertices) { return std::isnan(vertices) ? icp : std::min(icp, vertices); }
}  // namespace detail

/// The significance tests of offsets/detector.hpp on the part (see the
/// header comment). `min_overlap` etc. are the detector's thresholds; `tau`
/// the matcher's minimum offset length.
template <class = void>
PartTest test_on_part(const SelfAligner& aligner, const Eigen::Vector3d& start, const Eigen::Vector3d& refined,
                             const std::vector<Eigen::Vector3d>& seeds, double tau, double min_overlap,
                             double min_contrast, double min_repeat_ratio, double max_double_drift,
                             const PartOptions& options) {
  PartTest p;
  if (!options.enabled || seeds.empty()) return p;
  p.ran = true;
  // The anchors (many more vertices than samples on a finely tessellated
  // part) are gathered only once the screen below has passed.
  SelfAligner::Sources part = repeated_part(aligner, seeds, options.radius, &p.samples, false);
  const double n = double(part.cloud.size());
  if (n == 0) return p;
  const double radius = aligner.options().overlap_radius(), spacing = aligner.options().spacing;
  const auto kink = [&](const Eigen::Vector3d& t, double at_t) {
    const Eigen::Vector3d step = t.normalized() * (2 * radius);
    return at_t - 0.5 * (aligner.overlap(t - step, part.cloud) + aligner.overlap(t + step, part.cloud));
  };
  const double need_kink = std::max(min_contrast, options.min_kink_samples / n);  // contrast, and samples behind it
  const auto test = [&p](const char* name, double value, double threshold, bool at_most = false) {
    return record_test(p.tests, name, value, threshold, at_most);
  };
  // Screen (cost only): the part's overlap and kink at the whole surface's
  // refined offset must already pass, before the part's own ICP is run.
  const double screen = aligner.overlap(refined, part.cloud);
  if (!test("part_screen_overlap", screen, min_overlap) ||
      !test("part_screen_contrast", kink(refined, screen), need_kink))
    return p;
  part.anchors = repeated_part(aligner, seeds, options.radius, nullptr, true).anchors;
  const RefinedOffset r = aligner.refine(start, part);
  p.offset = r.offset;
  p.overlap = r.overlap;
  p.rms = r.rms;
  bool ok = test("part_length", r.offset.norm(), tau) && test("part_overlap", p.overlap, min_overlap);
  if (ok) p.contrast = kink(r.offset, p.overlap), ok = test("part_contrast", p.contrast, need_kink);
  if (ok) {
    const RefinedOffset r2 = aligner.refine(2 * r.offset, part);
    p.double_drift = detail::least_drift((r2.offset - 2 * r.offset).norm(),
                                         detail::vertex_double_drift(aligner.anchors(), r.offset));
    p.overlap_double = aligner.overlap(2 * r.offset, part.cloud);
    ok = test("part_double_drift", p.double_drift / spacing, max_double_drift, true) &&
         test("part_repeat", p.overlap > 0 ? p.overlap_double / p.overlap : 1.0, min_repeat_ratio);
  }
  if (ok) p.contrast_double = kink(2 * r.offset, p.overlap_double), ok = test("part_contrast_double", p.contrast_double, need_kink);
  const auto axis_kink = [&](const Eigen::Vector3d& t, double at_t) {
    double least = at_t;
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d step = Eigen::Vector3d::Unit(axis) * (2 * radius);
      least = std::min(least, at_t - 0.5 * (aligner.overlap(t - step, part.cloud) + aligner.overlap(t + step, part.cloud)));
    }
    return least;
  };
  if (ok) {
    p.axis_contrast = axis_kink(r.offset, p.overlap);
    p.axis_contrast_double = axis_kink(2 * r.offset, p.overlap_double);
    ok = test("part_axis_contrast", std::min(p.axis_contrast, p.axis_contrast_double), need_kink);
  }
  p.passed = ok;
  return p;
}

}  // namespace restitch
