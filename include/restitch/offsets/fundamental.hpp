// restitch/offsets/fundamental.hpp - the fundamental period of a dominant offset.
//
// Matching finds the offsets a feature's best partner lies at, and on models
// whose module is short or nearly featureless (radiator sections, keys, slats,
// ornaments) the best partner is often two or more modules away: the
// dominant offset t is then a multiple k p of the true period p. Nothing in
// the histogram says so; the geometry does.
//
// The test. For n copies of a module at period p, shifting by m p maps
// (n - m) / n of the repeated part onto itself, so the overlap (the share of
// the dense surface that lands on the surface, offsets/refine.hpp) at the
// fundamental is never lower than at any of its multiples, and the kink of
// the overlap along the direction (the contrast of offsets/detector.hpp) is
// at least as sharp: the transverse surface that stops matching when the
// shift moves off the period is (n - 1) copies' worth at p, (n - m) at m p.
// A shift that is not a period does not have both properties: t / 2 on a
// wall with windows slides the wall onto itself (high overlap) but lands
// windows on wall (no kink); t / 3 of a bookshelf column lands boards in the
// air (low overlap). So t / k is accepted when
//   * overlap(t / k) >= overlap(t) - overlap_slack, and
//   * contrast(t / k) >= max(min_contrast, contrast_share * contrast(t)),
// for k = max_divisor down to 2, the first (shortest) accepted wins, and the
// search repeats on the result (so 6 p is found as 3 p, then p, where the
// resolution below allows it). Because t / k is a period exactly when t is
// exactly k periods, no ICP is needed: the analysis snaps the result onto the
// mesh's vertices afterwards.
//
// Exact copies. Where the mesh's own vertices repeat at t (offsets/snap.hpp
// snaps t), the model was built by copying, and then a period's vertices
// repeat too, and pair at least as often as at any multiple (each vertex has
// one partner; (n - 1) copies' worth at p, (n - k) at k p). So with the
// vertices given, a t that snaps accepts t / k only when t / k snaps with at
// least as many pairs; the overlap alone is too coarse (1.5 spacings) to tell
// a period from an offset that lands parts on similar-looking parts: a
// Japanese screen's lattice rails at 20 units look alike at 10 to the
// overlap, but no vertex repeats at 10. The result is then the snapped,
// exact period. Where t does not snap (irregular pitch, different
// tessellations), the overlap test decides alone.
//
// Resolution. The overlap cannot tell apart shifts closer than one overlap
// radius, so a divisor k is tried only when its period is farther than that
// from the next candidate: |t| / k - |t| / (k + 1) > overlap radius. (On a
// radiator whose dominant offset spans seven irregular sections, t / 8 is
// within a radius of t / 7 and would pass the test as well as the truth.)
//
// Parameters and why:
//  * overlap_slack 0.02: the overlap is a share of 2048 source points; its
//    sampling noise between nearby offsets is below 1% (measured on slides
//    in offsets/detector.hpp), so 2% separates "as high" from "lower".
//  * contrast_share 1/2: the ideal ratio contrast(p) / contrast(k p) is
//    (n - 1) / (n - k) >= 1; half leaves room for noise and for the end
//    modules; a non-period has a contrast near 0 (a slide) or negative.
//  * min_contrast 0.01, as the detector's: the noise floor of a second
//    difference of overlaps.
//  * min_length: 3 dense spacings. The contrast compares overlaps 2 overlap
//    radii (3 spacings) either side of the shift; a shorter shift would
//    compare it with the trivial self-match at 0. This is the shortest repeat
//    restitch can resolve: 3 x 0.02 = 0.06 normalized units, 3% of the
//    model's longest side.
//  * max_divisor 8: the matcher's tau (0.15) makes the shortest dominant
//    offset about 0.15, so 8 reaches periods of 0.02, below min_length; the
//    divisors tried are further limited by min_length.
//
// Units: those of the aligner's points (normalized in the analysis).
// Cost: per offset up to 3 (max_divisor - 1) overlap evaluations of
// max_sources k-d tree queries each; with vertices, a vertex snap (O(#V), offsets/snap.hpp) of t and
// of each divisor that passes the overlap tests, none when no divisor does. Deterministic.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "restitch/offsets/refine.hpp"
#include "restitch/offsets/snap.hpp"

namespace restitch {

struct FundamentalOptions {
  int max_divisor = 8;
  double overlap_slack = 0.02;
  double contrast_share = 0.5;
  double min_contrast = 0.01;
  double min_length = 3;  ///< in dense spacings (the aligner's IcpOptions::spacing)
  SnapOptions snap{};     ///< for the exact-copy test (see the file comment)
};

/// The contrast of the overlap at t along its own direction (offsets/detector.hpp).
template <class = void>
double overlap_contrast(const SelfAligner& aligner, const Eigen::Vector3d& t, double at_t) {
  const Eigen::Vector3d step = t.normalized() * (2 * aligner.options().overlap_radius());
  return at_t - 0.5 * (aligner.overlap(t - step) + aligner.overlap(t + step));
}

struct FundamentalPeriod {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< t / divisor
  int divisor = 1;                                   ///< 1: t is its own fundamental
  double overlap = 0, contrast = 0;                  ///< at the result
};

/// The shortest t / k (see the file comment); t itself (divisor 1) when no
/// divisor passes. `overlap_t` and `contrast_t` are those of t. `vertices`
/// (optional, #P by 3 unique positions in the aligner's units) enables the
/// exact-copy test.
template <class = void>
FundamentalPeriod fundamental_period(const SelfAligner& aligner, const Eigen::Vector3d& t, double overlap_t,
                                            double contrast_t, const FundamentalOptions& options = {},
                                            const Eigen::Matrix<double, Eigen::Dynamic, 3>* vertices = nullptr) {
  FundamentalPeriod best;
  best.offset = t;
  best.overlap = overlap_t;
  best.contrast = contrast_t;
  const double min_length = options.min_length * aligner.options().spacing;
  if (!t.allFinite() || !(min_length > 0)) return best;
  const double radius = aligner.options().overlap_radius();
  SnapResult exact;     // t's vertex pairs, when its vertices repeat
  bool snapped = false;  // exact computed (only once a divisor passes the overlap tests: most offsets have none)
  for (bool found = true; found;) {  // each round divides the current best further
    found = false;
    const double len = best.offset.norm();
    const double need_contrast = std::max(options.min_contrast, options.contrast_share * best.contrast);
    for (int k = std::min(options.max_divisor, int(std::floor(len / min_length))); k >= 2 && !found; --k) {
      if (len / (double(k) * (k + 1)) <= radius) continue;  // not resolvable (see the file comment)
      const Eigen::Vector3d p = best.offset / double(k);
      const double o = aligner.overlap(p);
      if (o < best.overlap - options.overlap_slack) continue;
      const double c = overlap_contrast(aligner, p, o);
      if (c < need_contrast) continue;
      if (vertices && !snapped) exact = snap_offset(*vertices, t, options.snap), snapped = true;
      if (exact.snapped) {
        const SnapResult s = snap_offset(*vertices, p, options.snap);
        if (!s.snapped || s.pairs < exact.pairs) continue;
        exact = s;
      }
      best.offset = exact.snapped ? exact.offset : p, best.divisor *= k, best.overlap = o, best.contrast = c;
      found = true;
    }
  }
  return best;
}

}  // namespace restitch
