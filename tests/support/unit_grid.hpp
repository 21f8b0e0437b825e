// tests/support/unit_grid.hpp - test-only: an axis-aligned grid of unit cells at the origin.
#pragma once

#include <Eigen/Core>

#include "restitch/lattice/lattice.hpp"

namespace restitch::test {

// An axis-aligned unit-cell grid of `cells` at the origin.
inline Lattice unit_grid(const Eigen::Array3i& cells) {
  Lattice L;
  L.cells = cells;
  return L;
}

}  // namespace restitch::test
