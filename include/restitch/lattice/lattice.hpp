// restitch/lattice/lattice.hpp - the lattice of principal offsets: canonical space and cells.
//
// docs/method.md 1.7: A = [v1 v2 v3] holds the principal offsets as columns (dummy
// directions fill up to three). Canonical coordinates c = A^-1 (p - origin)
// turn the lattice into unit cubes, so a sheared lattice becomes
// axis-aligned. Cell (i, j, k) is the unit cube [i, i+1) x [j, j+1) x [k, k+1)
// in canonical space. The input occupies cells [0, cells[a]) along axis a.
//
// Everything here is in MODEL units (A's columns are offsets in model units,
// origin is a model-space point), so the stitcher can work on the mesh as it
// is. The analysis also keeps the normalized-unit view.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>

namespace restitch {

struct Lattice {
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();   ///< columns: v1, v2, v3 (model units)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< model-space point of canonical (0,0,0)
  Eigen::Array3i cells = Eigen::Array3i::Ones();     ///< input cells U_in, V_in, W_in
  std::array<bool, 3> dummy{{false, false, false}};  ///< column a is a dummy direction (never resized)
  /// Where the input's ends begin, as canonical positions within the first cell (end_low, in [0, 1])
  /// and within the last cell (end_high, in [0, 1]; the plane at cells[a] - 1 + end_high). An output
  /// end whose cell is not the input's end cell is cut there and given the input's end from there on
  /// (an end cap, restitch/stitch/stitch.hpp). The outer cell planes (end_low 0, end_high 1: the cap is
  /// the overhang) unless an end cell is not full or not periodic, so that the end starts inside it;
  /// end_low 1 / end_high 0 when the whole end cell is the end (restitch/lattice/fit.hpp).
  Eigen::Array3d end_low = Eigen::Array3d::Zero(), end_high = Eigen::Array3d::Ones();

  /// A's inverse; A is invertible by construction (principal offsets are at least 60 degrees apart).
  Eigen::Matrix3d A_inverse() const { return A.inverse(); }
  Eigen::Vector3d to_canonical(const Eigen::Vector3d& p) const { return A.inverse() * (p - origin); }
  Eigen::Vector3d to_model(const Eigen::Vector3d& c) const { return A * c + origin; }
  /// Model-space translation of a label shift d (in cells).
  Eigen::Vector3d shift(const Eigen::Array3i& d) const { return A * d.cast<double>().matrix(); }
  /// Number of resizable (non-dummy) directions.
  int principal_count() const { return int(!dummy[0]) + int(!dummy[1]) + int(!dummy[2]); }
};

}  // namespace restitch
