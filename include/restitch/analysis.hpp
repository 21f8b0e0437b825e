// restitch/analysis.hpp - what an analysis found: the Analysis result, apart from the driver that computes it.
//
// `restitch::analyze` (restitch/analyze.hpp) fills an Analysis; everything
// downstream (label spaces, the seam energy, the retarget driver, reports)
// reads it through this header only, so nothing below the driver depends on
// the driver or its policies.
//
// Units: everything is normalized (the model's longest side spans [-1, 1],
// see restitch/normalization.hpp) except `lattice` (model units) and
// `principal_model_units()`.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/matcher/matcher.hpp"
#include "restitch/normalization.hpp"
#include "restitch/offsets/detector.hpp"
#include "restitch/offsets/principal.hpp"

namespace restitch {

/// A repeat the analysis found but does not resize along by itself (docs/method.md 1.10): a pair (two
/// copies: the pattern test rejected it), or a significant offset that lost the choice of principal
/// offsets to a stronger one within 60 degrees. `promote_offsets` (analyze.hpp) makes it principal.
struct RepeatCandidate {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< normalized, as refined (snapped once promoted)
  int copies = 2;       ///< copies along the offset: 2 for a pair, else estimated from overlap(2t) / overlap(t)
  std::string reason;   ///< "pair" or "parallel"
  int dominant = -1;    ///< index in Analysis::dominant
};

/// The world axis an offset runs along: the one of its largest component (the lowest axis on a tie).
template <class = void>
int world_axis_of(const Eigen::Vector3d& v) {
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(v[a]) > std::abs(v[k])) k = a;
  return k;
}

/// Everything the analysis found (see the file comment for units).
struct Analysis {
  Normalization normalization;
  PointSet dense;                          ///< dense samples, normalized
  PointSet features;                       ///< Poisson features, then vertex features; normalized
  std::size_t sampled_features = 0;        ///< features [0, sampled_features) are Poisson samples, the rest vertices
  DescriptorMatrix descriptors;            ///< #features by D
  std::vector<Match> matches;              ///< one per feature; empty when the detector ignores matches
  std::vector<DominantOffset> dominant;    ///< ranked by votes; refined offsets, normalized
  std::vector<Eigen::Vector3d> principal;  ///< the real principal offsets only, normalized, in selection order
  std::vector<RepeatCandidate> candidates; ///< repeats not resized along unless promoted, strongest first
  std::vector<int> promoted;               ///< indices in `dominant` promoted on request, in request order
  PrincipalOffsets axes;                   ///< principal offsets completed by dummies, normalized
  Lattice lattice;                         ///< model units, dummies included
  Eigen::Matrix3d A_normalized = Eigen::Matrix3d::Identity();   ///< lattice axes, normalized
  Eigen::Vector3d origin_normalized = Eigen::Vector3d::Zero();  ///< lattice origin, normalized space
  Eigen::Array3d phase = Eigen::Array3d::Zero();                ///< chosen grid phase per axis
  Sparsity sparsity;                                            ///< top7, top20 (the paper's Fig. 5)
  std::size_t histogram_peaks = 0;           ///< the detector's peaks after suppression (histogram or S_T)
  std::map<std::string, double> timings_ms;  ///< per stage (analyze.hpp), e.g. sampling, ..., lattice
  std::string descriptor_name, matcher_name, detector_name;

  /// The real principal offsets in model units.
  template <class = void>
  std::vector<Eigen::Vector3d> principal_model_units() const {
    std::vector<Eigen::Vector3d> out;
    for (const Eigen::Vector3d& v : principal) out.push_back(normalization.to_model_offset(v));
    return out;
  }
  /// For a size change along the world axes marked in `change`: per such axis along which no principal
  /// offset runs (world_axis_of), the index in `candidates` of the candidate that runs along it with the
  /// most copies (the first of those), in axis order; axes with neither are left out. Most copies: a pair
  /// of five bays is outvoted by the bay the vertices repeat at, forty times. The caller promotes them
  /// (promote_offsets) and says so.
  template <class = void>
  std::vector<int> candidates_for_axes(const std::array<bool, 3>& change) const {
    std::array<bool, 3> covered{{false, false, false}};
    for (const Eigen::Vector3d& p : principal) covered[std::size_t(world_axis_of(p))] = true;
    std::vector<int> out;
    for (int axis = 0; axis < 3; ++axis) {
      if (!change[std::size_t(axis)] || covered[std::size_t(axis)]) continue;
      int best = -1;
      for (std::size_t c = 0; c < candidates.size(); ++c)
        if (world_axis_of(candidates[c].offset) == axis &&
            (best < 0 || candidates[c].copies > candidates[std::size_t(best)].copies))
          best = int(c);
      if (best >= 0) out.push_back(best);
    }
    return out;
  }
  /// A candidate's offset in model units.
  Eigen::Vector3d model_units(const RepeatCandidate& c) const { return normalization.to_model_offset(c.offset); }
};

}  // namespace restitch
