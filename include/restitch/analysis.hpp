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
  std::vector<Eigen::Vector3d> principal_model_units() const {
    std::vector<Eigen::Vector3d> out;
    for (const Eigen::Vector3d& v : principal) out.push_back(normalization.to_model_offset(v));
    return out;
  }
};

}  // namespace restitch
