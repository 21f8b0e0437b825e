// restitch/lattice/label_space.hpp - label-space policies: the cell grid labels live on.
//
// docs/method.md 2.2 and 2.6. A label is a shift d = (du, dv, dw) in cells: output
// cell x copies input cell x - d. A label space decides which grid the cells
// are (its `Lattice`) and how a request in steps along the principal offsets
// becomes a number of cells to add along each grid axis (`grid_steps`); the
// labels are then every shift with d_a between 0 and grid_steps[a] (either
// sign), so M = prod(|grid_steps[a]| + 1).
//
// Contract (checked by is_label_space_v at the retarget entry point):
//
//   struct MyLabelSpace {
//     static constexpr const char* name = "...";
//     // The cell grid, in model units, for this analysis.
//     restitch::Status grid(const restitch::Mesh& mesh, const restitch::Analysis& analysis,
//                           restitch::Lattice& out) const;
//     // Cells to add (negative: remove) along each axis of `grid` for a request
//     // of `steps` along the principal offsets of the analysis.
//     restitch::Status grid_steps(const restitch::Analysis& analysis, const restitch::Lattice& grid,
//                                 const Eigen::Array3i& steps, Eigen::Array3i& out) const;
//   };
//
// Shipped: LatticeLabels (default; the lattice of principal offsets, one cell
// per repeat, so one step is one label) and RegularLabels (the paper's
// "conventional MRF" baseline: axis-aligned cells of 0.1 normalized units and
// shifts on that grid; a step along a principal offset v becomes round(v_i /
// cell) cells along each world axis i, so the same request needs many more
// labels). Both are solved with the same energy and solver, which is the
// comparison of the paper's Fig. 1 and Fig. 8.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <type_traits>

#include "restitch/analysis.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// The lattice of principal offsets found by the analysis (default).
struct LatticeLabels {
  static constexpr const char* name = "lattice";

  template <class = void>
  Status grid(const Mesh&, const Analysis& analysis, Lattice& out) const {
    out = analysis.lattice;
    return {};
  }
  template <class = void>
  Status grid_steps(const Analysis&, const Lattice& grid, const Eigen::Array3i& steps, Eigen::Array3i& out) const {
    for (int a = 0; a < 3; ++a)
      if (grid.dummy[a] && steps[a] != 0)
        return error(StatusCode::invalid_argument,
                     "axis " + std::to_string(a + 1) +
                         " is a dummy direction (no repeat was found along it): its steps must be 0");
    out = steps;
    return {};
  }
};

/// The paper's baseline: a regular axis-aligned grid of `cell` normalized units.
struct RegularLabels {
  static constexpr const char* name = "regular";
  double cell = 0.1;  ///< normalized units (docs/method.md 2.6)

  template <class = void>
  Status grid(const Mesh& mesh, const Analysis& analysis, Lattice& out) const {
    if (!(cell > 0)) return error(StatusCode::invalid_argument, "the regular grid's cell size must be positive");
    const double size = analysis.normalization.to_model_length(cell);
    const BoundingBox box = bounding_box(mesh);
    out = Lattice();
    out.A = Eigen::Matrix3d::Identity() * size;
    out.origin = box.min;
    for (int a = 0; a < 3; ++a) {
      out.cells[a] = std::max(1, int(std::ceil(box.size()[a] / size - 1e-9)));
      out.dummy[a] = false;
    }
    return {};
  }
  template <class = void>
  Status grid_steps(const Analysis& analysis, const Lattice& grid, const Eigen::Array3i& steps,
                    Eigen::Array3i& out) const {
    // The requested translation of the far end, in model units, snapped to the grid.
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a) {
      if (steps[a] == 0) continue;
      if (analysis.lattice.dummy[a])
        return error(StatusCode::invalid_argument,
                     "axis " + std::to_string(a + 1) +
                         " is a dummy direction (no repeat was found along it): its steps must be 0");
      shift += analysis.lattice.A.col(a) * steps[a];
    }
    for (int i = 0; i < 3; ++i) out[i] = int(std::lround(shift[i] / grid.A(i, i)));
    return {};
  }
};

namespace detail {
template <class T, class = void>
struct is_label_space : std::false_type {};
template <class T>
struct is_label_space<
    T, std::void_t<decltype(T::name),
                   decltype(std::declval<const T&>().grid(std::declval<const Mesh&>(), std::declval<const Analysis&>(),
                                                          std::declval<Lattice&>())),
                   decltype(std::declval<const T&>().grid_steps(
                       std::declval<const Analysis&>(), std::declval<const Lattice&>(),
                       std::declval<const Eigen::Array3i&>(), std::declval<Eigen::Array3i&>()))>> : std::true_type {};
}  // namespace detail

template <class T>
inline constexpr bool is_label_space_v = detail::is_label_space<T>::value;

}  // namespace restitch
