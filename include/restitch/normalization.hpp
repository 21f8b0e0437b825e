// restitch/normalization.hpp - the normalized frame every analysis length lives in.
//
// docs/method.md: the model is centred and scaled so that its longest bounding-box
// side spans [-1, 1]: p_norm = (p - center) * scale, scale = 2 / longest side.
// All analysis parameters (sampling spacings, descriptor radius, tau, bin
// size, suppression radius) are in these units; everything reported to a
// user is converted back to model units with `to_model_length` /
// `to_model_offset`.
#pragma once

#include <Eigen/Core>

#include "restitch/mesh.hpp"

namespace restitch {

struct Normalization {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double scale = 1.0;  ///< normalized length per model unit

  /// The normalization of a bounding box; scale 1 for a degenerate (zero-size) box.
  template <class = void>
  static Normalization of(const BoundingBox& box) {
    Normalization n;
    if (!box.valid()) return n;
    n.center = box.center();
    const double longest = box.size().maxCoeff();
    n.scale = longest > 0 ? 2.0 / longest : 1.0;
    return n;
  }
  Eigen::Vector3d to_normalized(const Eigen::Vector3d& p) const { return (p - center) * scale; }
  Eigen::Vector3d to_model(const Eigen::Vector3d& q) const { return q / scale + center; }
  /// An offset (difference of two points): scaled, not shifted.
  Eigen::Vector3d to_model_offset(const Eigen::Vector3d& v) const { return v / scale; }
  Eigen::Vector3d to_normalized_offset(const Eigen::Vector3d& v) const { return v * scale; }
  double to_model_length(double l) const { return l / scale; }
};

}  // namespace restitch
