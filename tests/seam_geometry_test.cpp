// Tests for restitch/energy/seam_geometry.hpp: CellSlabs (the geometric seam cost) and SeamMrf built on
// it, on hand-made dense samples whose mismatches are known without running the library, and against a
// brute-force implementation of the definition in the header comment.
#include "restitch/energy/seam_geometry.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "restitch/energy/seam_energy.hpp"
#include "support/unit_grid.hpp"

using restitch::Analysis;
using restitch::CellSlabs;
using restitch::Lattice;
using restitch::Neighbourhood;
using restitch::SeamMrf;

namespace {

using restitch::test::unit_grid;

// An Analysis holding only what CellSlabs reads: the dense samples (model units = normalized here).
Analysis dense_analysis(const std::vector<Eigen::Vector3d>& points) {
  Analysis a;
  a.dense.points.resize(Eigen::Index(points.size()), 3);
  a.dense.normals = restitch::MatrixX3f::Zero(Eigen::Index(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) a.dense.points.row(Eigen::Index(i)) = points[i].cast<float>().transpose();
  return a;
}

// Cells along x, each holding the plane z = 0.5 + shift[c] sampled on a 0.05 grid in x and y.
// Positions are multiples of 1/64 so that they are exact in float and relative positions compare exactly.
std::vector<Eigen::Vector3d> planes(const std::vector<double>& shift) {
  std::vector<Eigen::Vector3d> p;
  for (std::size_t c = 0; c < shift.size(); ++c)
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) p.emplace_back(double(c) + (i + 0.5) / 16.0, (j + 0.5) / 16.0, 0.5 + shift[c]);
  return p;
}

// The definition of the header comment, written out directly (no stride cap: every slab below holds
// fewer than max_queries samples).
double brute_mismatch(const std::vector<Eigen::Vector3d>& P, const Eigen::Array3i& dims, double h,
                      const Eigen::Array3i& c1, const Eigen::Array3i& c2, const Eigen::Array3i& e, double empty) {
  const double w = std::min(0.5, h), m = std::min(1.0, h);
  auto inside = [&](const Eigen::Array3i& c) { return (c >= 0).all() && (c < dims).all(); };
  auto clamp_cell = [&](const Eigen::Vector3d& p) {
    Eigen::Array3i c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(std::floor(p[a])), 0, dims[a] - 1);
    return c;
  };
  // slab (q) and around (r) of cell c toward e, relative to the cell's corner
  auto gather = [&](const Eigen::Array3i& c, std::vector<Eigen::Vector3d>& q, std::vector<Eigen::Vector3d>& r) {
    if (!inside(c)) return;
    for (const Eigen::Vector3d& p : P) {
      const Eigen::Vector3d u = p - c.cast<double>().matrix();
      bool in_q = (clamp_cell(p) == c).all(), in_r = (clamp_cell(p) - c).abs().maxCoeff() <= 1;
      for (int a = 0; a < 3; ++a) {
        double lo = e[a] > 0 ? 1 - w : 0, hi = e[a] < 0 ? w : 1;
        if (c[a] == 0 && lo == 0) lo = -1e300;
        if (c[a] == dims[a] - 1 && hi == 1) hi = 1e300;
        in_q = in_q && u[a] >= lo && u[a] < hi;
        in_r = in_r && u[a] >= lo - m && u[a] < hi + m;
      }
      if (in_q) q.push_back(u);
      if (in_r) r.push_back(u);
    }
  };
  if ((c1 == c2).all()) return 0;
  std::vector<Eigen::Vector3d> q1, r1, q2, r2;
  gather(c1, q1, r1);
  gather(c2, q2, r2);
  auto directed = [](const std::vector<Eigen::Vector3d>& Q, const std::vector<Eigen::Vector3d>& R) {
    double worst = 0;
    for (const auto& q : Q) {
      double best = INFINITY;
      for (const auto& r : R) best = std::min(best, (q - r).norm());
      worst = std::max(worst, best);
    }
    return worst;
  };
  if (q1.empty() && q2.empty()) return 0;
  if ((!q1.empty() && r2.empty()) || (!q2.empty() && r1.empty())) return empty;
  return std::max(q1.empty() ? 0.0 : directed(q1, r2), q2.empty() ? 0.0 : directed(q2, r1));
}

}  // namespace

TEST_CASE("CellSlabs: identical slabs cost 0, a slab against its shifted copy costs the shift", "[energy][slabs]") {
  // Cell 1's plane is lifted by 0.02 (below the 1/16 sample spacing, so each sample's nearest
  // counterpart is the lifted one straight above it); cells 1 and 2 are the same.
  const Analysis a = dense_analysis(planes({0.0, 0.02, 0.02}));
  CellSlabs slabs(a, unit_grid({3, 1, 1}), 1.0 / 16);
  CHECK(slabs.spacing() == 1.0 / 16);
  CHECK(slabs.half_width() == 2.0 / 16);
  CHECK(slabs.queries({0, 0, 0}, {1, 0, 0}) == 2 * 16);  // two columns of samples within 1/8 of the face
  CHECK(slabs.mismatch({1, 0, 0}, {2, 0, 0}, {1, 0, 0}) == Approx(0).margin(1e-7));
  CHECK(slabs.mismatch({1, 0, 0}, {2, 0, 0}, {-1, 0, 0}) == Approx(0).margin(1e-7));
  CHECK(slabs.mismatch({0, 0, 0}, {1, 0, 0}, {1, 0, 0}) == Approx(0.02).epsilon(1e-5));
  CHECK(slabs.mismatch({1, 0, 0}, {0, 0, 0}, {1, 0, 0}) == slabs.mismatch({0, 0, 0}, {1, 0, 0}, {1, 0, 0}));
  CHECK(slabs.mismatch({0, 0, 0}, {2, 0, 0}, {0, 1, 0}) == Approx(0.02).epsilon(1e-5));  // toward +y: an edge
  // A cell outside the grid is empty: against a slab holding samples it costs empty_mismatch.
  CHECK(slabs.empty_mismatch() == Approx(3000.0));
  CHECK(slabs.mismatch({2, 0, 0}, {3, 0, 0}, {1, 0, 0}) == slabs.empty_mismatch());
  CHECK(slabs.mismatch({-1, 0, 0}, {3, 0, 0}, {1, 0, 0}) == 0);
  // The plane lies at z = 0.5 +- 0.02: nothing within 1/8 of the top face, so the top slabs are empty.
  CHECK(slabs.queries({0, 0, 0}, {0, 0, 1}) == 0);
  CHECK(slabs.mismatch({0, 0, 0}, {1, 0, 0}, {0, 0, 1}) == 0);
  CHECK(slabs.mismatch({0, 0, 0}, {7, 0, 0}, {0, 0, 1}) == 0);
}

TEST_CASE("CellSlabs: mismatches and the SeamMrf built on them equal a brute-force computation", "[energy][slabs]") {
  // Random samples in a 3 x 2 x 1 grid, some cells left empty; overhang below x = 0 and above y = 2.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::Array3i dims(3, 2, 1);
  std::vector<Eigen::Vector3d> P;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;  // an empty cell
      for (int s = 0; s < 60; ++s) P.emplace_back(i + u(rng), j + u(rng), u(rng));
    }
  for (int s = 0; s < 10; ++s) P.emplace_back(-0.2 * u(rng), u(rng), u(rng));
  for (int s = 0; s < 10; ++s) P.emplace_back(u(rng), 2 + 0.1 * u(rng), u(rng));
  for (Eigen::Vector3d& p : P) p = p.cast<float>().cast<double>();  // as the analysis stores them
  const Analysis a = dense_analysis(P);
  const double spacing = 0.1;
  CellSlabs slabs(a, unit_grid(dims), spacing);
  const double empty = slabs.empty_mismatch();
  for (int e = 0; e < 27; ++e) {
    const Eigen::Array3i dir(e % 3 - 1, (e / 3) % 3 - 1, e / 9 - 1);
    if ((dir == 0).all()) continue;
    for (int c1 = 0; c1 < 8; ++c1)
      for (int c2 = 0; c2 < 8; ++c2) {
        const Eigen::Array3i a1(c1 % 4 - 1, c1 / 4, 0), a2(c2 % 4 - 1, c2 / 4, 0);  // x from -1 (outside) to 2
        INFO("cells " << a1.transpose() << " / " << a2.transpose() << " toward " << dir.transpose());
        CHECK(slabs.mismatch(a1, a2, dir) ==
              Approx(brute_mismatch(P, dims, 2 * spacing, a1, a2, dir, empty)).epsilon(1e-5).margin(1e-6));
      }
  }
  // The per-request table of SeamMrf against the same definition (x - di, x - dj toward the neighbour).
  for (const Eigen::Array3i& k : {Eigen::Array3i(2, 0, 0), Eigen::Array3i(-1, 1, 0)}) {
    CellSlabs fresh(a, unit_grid(dims), spacing);
    SeamMrf mrf(fresh, k, Neighbourhood::n26);
    CHECK(mrf.energy() == restitch::SeamEnergy::geometry);
    CHECK(mrf.empty_mismatch() == empty);
    const Eigen::Array3i out = dims + k;
    const auto& labels = mrf.labels();
    for (int edge = 0; edge < mrf.edge_count(); ++edge) {
      const auto [x, y] = mrf.edge(edge);
      const restitch::CellGrid g(out);
      const Eigen::Array3i cx = g.cell(x), cy = g.cell(y);
      for (int i = 0; i < mrf.label_count(); ++i)
        for (int j = 0; j < mrf.label_count(); ++j) {
          const Eigen::Array3i di = labels[std::size_t(i)], dj = labels[std::size_t(j)];
          const double want = i == j ? 0.0
                                     : brute_mismatch(P, dims, 2 * spacing, cx - di, cx - dj, cy - cx, empty) +
                                           brute_mismatch(P, dims, 2 * spacing, cy - di, cy - dj, cx - cy, empty);
          INFO("k " << k.transpose() << " edge " << cx.transpose() << " - " << cy.transpose() << " labels " << i
                    << ", " << j);
          CHECK(mrf.pairwise(edge, i, j) == Approx(want).epsilon(1e-5).margin(1e-6));
        }
    }
  }
}

TEST_CASE("SeamEnergy names", "[energy][slabs]") {
  restitch::SeamEnergy e = restitch::SeamEnergy::descriptor;
  CHECK(restitch::parse_seam_energy("geometry", e));
  CHECK(e == restitch::SeamEnergy::geometry);
  CHECK(restitch::parse_seam_energy("descriptor", e));
  CHECK(e == restitch::SeamEnergy::descriptor);
  CHECK_FALSE(restitch::parse_seam_energy("hausdorff", e));
  CHECK(e == restitch::SeamEnergy::descriptor);
  CHECK(std::string(restitch::seam_energy_name(restitch::SeamEnergy::geometry)) == "geometry");
}
