// restitch/lattice/grid.hpp - a box of cells: dimensions, linear index, the cell of a point, neighbours.
//
// Every cell grid in restitch (the input lattice's cells, the output cells a
// labelling lives on, the table of cell differences of the seam energy, the
// web page's label view) is a CellGrid: `dims` = (U, V, W) cells, cell
// (i, j, k) with 0 <= i < U etc., linear index i + U (j + V k) (x fastest),
// the order of the reports' `cell_labels` and of the solver's nodes.
//
// The cell of a point. A grid has no geometry of its own: a point is first
// turned into canonical coordinates (Lattice::to_canonical: one unit per
// cell), then `cell_of` takes the floor of each coordinate and clamps it into
// the grid, so geometry that overhangs the grid belongs to the first or last
// cell along that axis. A coordinate within `snap` of an integer is first
// snapped onto it (`snap_coordinate`), so a point meant to lie on a cell plane
// does, and goes to the cell above it (cells are half-open: [i, i+1)). The
// default snap is 0 (plain floor).
//
// Cost: every call is O(1) but neighbours(), O(26). No allocation except
// neighbour_offsets().
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace restitch {

/// Which cells are neighbours: sharing a face (6) or a face, edge or corner (26).
enum class Neighbourhood { n26, n6 };

/// `x` snapped onto the nearest integer when it is within `snap` of it.
template <class = void>
double snap_coordinate(double x, double snap) {
  const double r = std::nearbyint(x);
  return std::abs(x - r) <= snap ? r : x;
}

/// The offsets from a cell to its neighbours. With `forward_half`, only those
/// whose first non-zero component (z, then y, then x) is positive, so each
/// pair of neighbours is listed once. Order: z slowest, x fastest, -1 to 1.
/// The lists are built once (thread-safe static initialisation) and shared.
template <class = void>
const std::vector<Eigen::Array3i>& neighbour_offsets(Neighbourhood nb, bool forward_half) {
  static const auto make = [](Neighbourhood n, bool forward) {
    std::vector<Eigen::Array3i> out;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int l1 = std::abs(dx) + std::abs(dy) + std::abs(dz);
          if (l1 == 0 || (n == Neighbourhood::n6 && l1 != 1)) continue;
          const int first = dz != 0 ? dz : (dy != 0 ? dy : dx);
          if (!forward || first > 0) out.emplace_back(dx, dy, dz);
        }
    return out;
  };
  static const std::vector<Eigen::Array3i> lists[4] = {make(Neighbourhood::n26, false), make(Neighbourhood::n26, true),
                                                       make(Neighbourhood::n6, false), make(Neighbourhood::n6, true)};
  return lists[2 * int(nb == Neighbourhood::n6) + int(forward_half)];
}

struct CellGrid {
  Eigen::Array3i dims = Eigen::Array3i::Ones();  ///< cells along each axis, each >= 1

  CellGrid() = default;
  explicit CellGrid(const Eigen::Array3i& d) : dims(d) {}

  /// Number of cells (64-bit: a caller checks it against its limits before allocating).
  std::int64_t size() const { return std::int64_t(dims[0]) * dims[1] * dims[2]; }
  /// Linear index i + U (j + V k) of an inside cell.
  int index(int i, int j, int k) const { return i + dims[0] * (j + dims[1] * k); }
  int index(const Eigen::Array3i& c) const { return index(c[0], c[1], c[2]); }
  /// The cell of a linear index (the inverse of index()).
  template <class = void>
  Eigen::Array3i cell(std::int64_t x) const {
    return Eigen::Array3i(int(x % dims[0]), int((x / dims[0]) % dims[1]), int(x / (std::int64_t(dims[0]) * dims[1])));
  }
  bool inside(const Eigen::Array3i& c) const { return (c >= 0).all() && (c < dims).all(); }
  template <class = void>
  bool inside(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < dims[0] && j < dims[1] && k < dims[2];
  }
  /// The cell of a point in canonical coordinates (see the file comment).
  template <class = void>
  Eigen::Array3i cell_of(const Eigen::Vector3d& canonical, double snap = 0) const {
    Eigen::Array3i c;
    for (int a = 0; a < 3; ++a)
      c[a] = std::clamp(int(std::floor(snap_coordinate(canonical[a], snap))), 0, dims[a] - 1);
    return c;
  }
  /// Calls f(neighbour linear index) for each neighbour of cell x inside the grid,
  /// in a fixed order: the offsets of neighbour_offsets(nb, false).
  template <class F>
  void for_each_neighbour(std::int64_t x, Neighbourhood nb, F&& f) const {
    const Eigen::Array3i c = cell(x);
    for (const Eigen::Array3i& o : neighbour_offsets(nb, false))
      if (inside(c + o)) f(index(c + o));
  }
};

}  // namespace restitch
