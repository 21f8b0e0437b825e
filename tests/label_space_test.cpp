// Tests for restitch/lattice/label_space.hpp: the two shipped label spaces on
// hand-made analyses and boxes of known size, so every grid and step count
// below follows from the contract by arithmetic.
#include "restitch/lattice/label_space.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "support/mesh_builders.hpp"

using restitch::Analysis;
using restitch::Lattice;
using restitch::LatticeLabels;
using restitch::Mesh;
using restitch::Normalization;
using restitch::RegularLabels;
using restitch::StatusCode;
using restitch::test::add_box;

namespace {

// An analysis with one real principal offset `v` (model units) on lattice axis 0
// and two dummies, normalized for `mesh`.
Analysis analysis_with_offset(const Mesh& mesh, const Eigen::Vector3d& v) {
  Analysis a;
  a.normalization = Normalization::of(restitch::bounding_box(mesh));
  a.principal.push_back(a.normalization.to_normalized_offset(v));
  a.lattice.A.col(0) = v;
  a.lattice.A.col(1) = Eigen::Vector3d(0, 0.3, 0);
  a.lattice.A.col(2) = Eigen::Vector3d(0, 0, 0.3);
  a.lattice.origin = Eigen::Vector3d(0.1, 0.2, 0.3);
  a.lattice.cells = Eigen::Array3i(5, 1, 1);
  a.lattice.dummy = {{false, true, true}};
  return a;
}

Mesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Mesh m;
  add_box(m, lo, hi);
  return m;
}

}  // namespace

TEST_CASE("label spaces satisfy the label-space contract", "[label_space]") {
  STATIC_REQUIRE(restitch::is_label_space_v<LatticeLabels>);
  STATIC_REQUIRE(restitch::is_label_space_v<RegularLabels>);
  STATIC_REQUIRE_FALSE(restitch::is_label_space_v<int>);
  CHECK(std::string(LatticeLabels::name) == "lattice");
  CHECK(std::string(RegularLabels::name) == "regular");
}

TEST_CASE("LatticeLabels: the grid is the analysis lattice; steps pass through, never on a dummy axis",
          "[label_space]") {
  const Mesh mesh = box({0, 0, 0}, {4, 1, 1});
  Analysis a = analysis_with_offset(mesh, {0.8, 0.1, 0});
  a.lattice.A.col(1) = Eigen::Vector3d(0.2, 0.5, 0);  // a second real, sheared axis
  a.lattice.dummy = {{false, false, true}};
  a.lattice.cells = Eigen::Array3i(5, 2, 1);
  Lattice grid;
  REQUIRE(LatticeLabels().grid(mesh, a, grid).ok());
  CHECK(grid.A == a.lattice.A);
  CHECK(grid.origin == a.lattice.origin);
  CHECK((grid.cells == a.lattice.cells).all());
  CHECK(grid.dummy == a.lattice.dummy);

  Eigen::Array3i out(9, 9, 9);
  REQUIRE(LatticeLabels().grid_steps(a, grid, {3, -1, 0}, out).ok());
  CHECK((out == Eigen::Array3i(3, -1, 0)).all());  // one label per repeat: steps are cells

  const restitch::Status s = LatticeLabels().grid_steps(a, grid, {1, 0, 2}, out);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK_THAT(s.message(), Catch::Contains("axis 3") && Catch::Contains("dummy"));
  const restitch::Status s2 = LatticeLabels().grid_steps(a, grid, {0, 0, -1}, out);
  CHECK(s2.code() == StatusCode::invalid_argument);
}

TEST_CASE("RegularLabels: axis-aligned cells of 0.1 normalized units over the bounding box", "[label_space]") {
  // Longest side 4 model units: 1 model unit = 0.5 normalized, so a 0.1 cell is 0.2 model units.
  const Mesh mesh = box({-1, 2, 0.5}, {3, 3, 0.8});  // size 4 x 1 x 0.3
  const Analysis a = analysis_with_offset(mesh, {0.66, 0.18, 0.02});
  Lattice grid;
  REQUIRE(RegularLabels().grid(mesh, a, grid).ok());
  CHECK(grid.A.isApprox(Eigen::Matrix3d::Identity() * 0.2, 1e-12));
  CHECK(grid.origin.isApprox(Eigen::Vector3d(-1, 2, 0.5), 1e-6));
  CHECK((grid.cells == Eigen::Array3i(20, 5, 2)).all());  // 4 / 0.2, 1 / 0.2, ceil(0.3 / 0.2)
  CHECK(grid.cells.prod() == 200);
  CHECK(grid.dummy == std::array<bool, 3>{{false, false, false}});

  // Another cell size: 0.25 normalized = 0.5 model units.
  RegularLabels coarse;
  coarse.cell = 0.25;
  REQUIRE(coarse.grid(mesh, a, grid).ok());
  CHECK(grid.A.isApprox(Eigen::Matrix3d::Identity() * 0.5, 1e-12));
  CHECK((grid.cells == Eigen::Array3i(8, 2, 1)).all());

  // A flat model still has one cell across its zero thickness.
  const Mesh flat = box({0, 0, 0}, {2, 1, 0});
  Lattice flat_grid;
  REQUIRE(RegularLabels().grid(flat, analysis_with_offset(flat, {0.5, 0, 0}), flat_grid).ok());
  CHECK((flat_grid.cells == Eigen::Array3i(20, 10, 1)).all());  // 0.1 normalized = 0.1 model units here

  RegularLabels bad;
  bad.cell = 0;
  CHECK(bad.grid(mesh, a, grid).code() == StatusCode::invalid_argument);
  bad.cell = -0.1;
  CHECK(bad.grid(mesh, a, grid).code() == StatusCode::invalid_argument);
}

TEST_CASE("RegularLabels: a step along a principal offset becomes that offset in grid cells, rounded",
          "[label_space]") {
  const Mesh mesh = box({-1, 2, 0.5}, {3, 3, 0.8});  // cells of 0.2 model units
  Analysis a = analysis_with_offset(mesh, {0.66, 0.18, 0.02});
  Lattice grid;
  REQUIRE(RegularLabels().grid(mesh, a, grid).ok());
  Eigen::Array3i out;
  // (0.66, 0.18, 0.02) / 0.2 = (3.3, 0.9, 0.1)
  REQUIRE(RegularLabels().grid_steps(a, grid, {1, 0, 0}, out).ok());
  CHECK((out == Eigen::Array3i(3, 1, 0)).all());
  // -2 steps: (-6.6, -1.8, -0.2)
  REQUIRE(RegularLabels().grid_steps(a, grid, {-2, 0, 0}, out).ok());
  CHECK((out == Eigen::Array3i(-7, -2, 0)).all());
  // 5 steps: (16.5, 4.5, 0.5) would be ties; 4 steps: (13.2, 3.6, 0.4).
  REQUIRE(RegularLabels().grid_steps(a, grid, {4, 0, 0}, out).ok());
  CHECK((out == Eigen::Array3i(13, 4, 0)).all());
  REQUIRE(RegularLabels().grid_steps(a, grid, {0, 0, 0}, out).ok());
  CHECK((out == 0).all());

  // Two real offsets add up before snapping: (0.66, 0.18, 0.02) + (0, 0.42, 0) = (0.66, 0.6, 0.02).
  a.lattice.A.col(1) = Eigen::Vector3d(0, 0.42, 0);
  a.lattice.dummy = {{false, false, true}};
  REQUIRE(RegularLabels().grid_steps(a, grid, {1, 1, 0}, out).ok());
  CHECK((out == Eigen::Array3i(3, 3, 0)).all());

  // Steps on a dummy axis of the analysis lattice are refused.
  const restitch::Status s = RegularLabels().grid_steps(a, grid, {1, 0, 1}, out);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK_THAT(s.message(), Catch::Contains("axis 3") && Catch::Contains("dummy"));
}
