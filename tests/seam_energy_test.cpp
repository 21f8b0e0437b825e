// Tests for restitch/energy/seam_energy.hpp: CellDescriptors (features grouped
// by cell, set distances, cache) and SeamMrf (labels, unary with forbidden
// labels and anchored ends, pairwise, neighbourhoods), on hand-made feature
// sets whose cells, distances and costs are known without running the library.
#include "restitch/energy/seam_energy.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>
#include "support/unit_grid.hpp"

using restitch::Analysis;
using restitch::CellDescriptors;
using restitch::Lattice;
using restitch::Neighbourhood;
using restitch::Normalization;
using restitch::SeamMrf;
using restitch::SetDistance;

namespace {

using restitch::test::unit_grid;

// One feature: a position in MODEL units and its descriptor.
struct Feature {
  Eigen::Vector3d p;
  std::vector<float> d;
};

// An Analysis holding only what CellDescriptors reads: the normalization, the
// features (stored normalized, Poisson ones first) and their descriptors.
Analysis hand_analysis(const std::vector<Feature>& poisson, const std::vector<Feature>& vertices = {},
                       const Normalization& n = {}) {
  Analysis a;
  a.normalization = n;
  const std::size_t count = poisson.size() + vertices.size();
  const Eigen::Index dim = Eigen::Index(poisson.empty() ? vertices.at(0).d.size() : poisson[0].d.size());
  a.features.points.resize(Eigen::Index(count), 3);
  a.features.normals = restitch::MatrixX3f::Zero(Eigen::Index(count), 3);
  a.descriptors.resize(Eigen::Index(count), dim);
  for (std::size_t i = 0; i < count; ++i) {
    const Feature& f = i < poisson.size() ? poisson[i] : vertices[i - poisson.size()];
    a.features.points.row(Eigen::Index(i)) = n.to_normalized(f.p).cast<float>().transpose();
    for (Eigen::Index c = 0; c < dim; ++c) a.descriptors(Eigen::Index(i), c) = f.d[std::size_t(c)];
  }
  a.sampled_features = poisson.size();
  return a;
}

// The model-space centre of cell c of the unit grid (x offset within the cell).
Eigen::Vector3d in_cell(int i, int j = 0, int k = 0, double x = 0.5) { return {i + x, j + 0.5, k + 0.5}; }

double l2(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (double(a[i]) - double(b[i])) * (double(a[i]) - double(b[i]));
  return std::sqrt(s);
}

// Brute-force set distances (method.md 2.3), in double precision.
double brute_hausdorff(const std::vector<std::vector<float>>& A, const std::vector<std::vector<float>>& B) {
  double h = 0;
  for (const auto& a : A) {
    double m = INFINITY;
    for (const auto& b : B) m = std::min(m, l2(a, b));
    h = std::max(h, m);
  }
  for (const auto& b : B) {
    double m = INFINITY;
    for (const auto& a : A) m = std::min(m, l2(a, b));
    h = std::max(h, m);
  }
  return h;
}
double brute_mean_nearest(const std::vector<std::vector<float>>& A, const std::vector<std::vector<float>>& B) {
  double sa = 0, sb = 0;
  for (const auto& a : A) {
    double m = INFINITY;
    for (const auto& b : B) m = std::min(m, l2(a, b));
    sa += m;
  }
  for (const auto& b : B) {
    double m = INFINITY;
    for (const auto& a : A) m = std::min(m, l2(a, b));
    sb += m;
  }
  return 0.5 * (sa / double(A.size()) + sb / double(B.size()));
}

// Node coordinates from the node order stated in the contract: x = i + U (j + V k).
Eigen::Array3i node_cell(int x, const Eigen::Array3i& dims) {
  return {x % dims[0], (x / dims[0]) % dims[1], x / (dims[0] * dims[1])};
}
bool inside(const Eigen::Array3i& c, const Eigen::Array3i& dims) { return (c >= 0).all() && (c < dims).all(); }

// The energy of the contract comment written out directly, as an oracle for SeamMrf.
struct ContractEnergy {
  CellDescriptors& cells;
  Eigen::Array3i k;
  double empty_mismatch, forbidden;

  ContractEnergy(CellDescriptors& c, const Eigen::Array3i& steps)
      : cells(c), k(steps), empty_mismatch(1000 * c.max_distance()), forbidden(1000 * empty_mismatch) {}

  Eigen::Array3i in() const { return cells.grid().dims; }
  Eigen::Array3i out() const { return in() + k; }
  bool empty(const Eigen::Array3i& c) const { return !inside(c, in()) || cells.empty(cells.grid().index(c)); }
  double D(const Eigen::Array3i& a, const Eigen::Array3i& b) const {
    if (empty(a) && empty(b)) return 0;
    if (empty(a) != empty(b)) return empty_mismatch;
    return cells.distance(cells.grid().index(a), cells.grid().index(b));
  }
  double seam(const Eigen::Array3i& x, const Eigen::Array3i& di, const Eigen::Array3i& dj) const {
    return D(x - di, x - dj);
  }
  double unary(int node, const Eigen::Array3i& d) const {
    const Eigen::Array3i x = node_cell(node, out());
    double u = inside(x - d, in()) ? 0 : forbidden;
    for (int a = 0; a < 3; ++a) {
      if (k[a] == 0) continue;
      if (out()[a] == 1) continue;  // one cell long: both ends capped whatever the label, no anchor
      if (x[a] == 0) {
        Eigen::Array3i anchor = d, outside = x;
        anchor[a] = 0;
        outside[a] -= 1;
        u += seam(x, d, anchor) + seam(outside, d, anchor);
      }
      if (x[a] == out()[a] - 1) {
        Eigen::Array3i anchor = d, outside = x;
        anchor[a] = k[a];
        outside[a] += 1;
        u += seam(x, d, anchor) + seam(outside, d, anchor);
      }
    }
    return u;
  }
  double pairwise(int x, int y, const Eigen::Array3i& di, const Eigen::Array3i& dj) const {
    return seam(node_cell(x, out()), di, dj) + seam(node_cell(y, out()), di, dj);
  }
};

// A 3D input grid with some empty cells, features with 4-D random descriptors.
Analysis grid_with_holes(const Eigen::Array3i& cells, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.1, 0.9);
  std::vector<Feature> f;
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        if ((i + 2 * j + 3 * k) % 4 == 1) continue;  // an empty cell
        const int n = 1 + int(rng() % 3);
        for (int s = 0; s < n; ++s)
          f.push_back({Eigen::Vector3d(i + u(rng), j + u(rng), k + u(rng)),
                       {float(u(rng)), float(u(rng)), float(u(rng)), float(u(rng))}});
      }
  return hand_analysis(f);
}

}  // namespace

TEST_CASE("CellDescriptors: Poisson features grouped by the cell they lie in, clamped into the grid",
          "[energy][cells]") {
  // A sheared grid in model units, and a normalization that is not the identity,
  // so features stored in normalized units must be converted back to be placed right.
  Lattice grid;
  grid.A << 2, 0.5, 0, 0, 1, 0, 0, 0, 3;
  grid.origin = Eigen::Vector3d(-1, -1, 0);
  grid.cells = Eigen::Array3i(3, 2, 1);
  Normalization n;
  n.center = Eigen::Vector3d(1, 0, 0);
  n.scale = 0.5;
  auto at = [&](double u, double v, double w) -> Eigen::Vector3d {
    return grid.A * Eigen::Vector3d(u, v, w) + grid.origin;
  };
  const std::vector<float> d0{1, 0}, d1{0, 1};
  const std::vector<Feature> poisson{
      {at(0.5, 0.5, 0.5), d0},        // cell (0,0,0)
      {at(2.2, 1.7, 0.1), d0},        // cell (2,1,0)
      {at(-0.3, 0.5, 0.5), d1},       // before the grid along u: clamped to (0,0,0)
      {at(5.0, -2.0, 7.0), d1},       // past/before the grid on every axis: clamped to (2,0,0)
      {at(1.5, 1.2, -0.4), d0},       // cell (1,1,0), w clamped
      {at(0.5, 1.5, 0.5), {NAN, 0}},  // non-finite descriptor: left out
  };
  // Mesh-vertex features (after sampled_features) never enter the sets.
  const std::vector<Feature> vertices{{at(1.5, 0.5, 0.5), d0}, {at(1.5, 0.5, 0.5), d1}};
  const Analysis a = hand_analysis(poisson, vertices, n);
  CellDescriptors cells(a, grid, SetDistance::hausdorff);
  REQUIRE((cells.grid().dims == grid.cells).all());
  auto count = [&](int i, int j, int k) { return cells.features_in(cells.grid().index(Eigen::Array3i(i, j, k))); };
  CHECK(count(0, 0, 0) == 2);
  CHECK(count(1, 0, 0) == 0);  // only vertex features there
  CHECK(count(2, 0, 0) == 1);
  CHECK(count(0, 1, 0) == 0);  // only the non-finite one there
  CHECK(count(1, 1, 0) == 1);
  CHECK(count(2, 1, 0) == 1);
  CHECK(cells.empty(cells.grid().index(Eigen::Array3i(1, 0, 0))));
  CHECK_FALSE(cells.empty(cells.grid().index(Eigen::Array3i(2, 1, 0))));
  // Linear cell order of the contract: x fastest.
  CHECK(cells.grid().index(Eigen::Array3i(2, 1, 0)) == 2 + 3 * 1);
  CHECK(cells.grid().inside(Eigen::Array3i(2, 1, 0)));
  CHECK_FALSE(cells.grid().inside(Eigen::Array3i(3, 0, 0)));
  CHECK_FALSE(cells.grid().inside(Eigen::Array3i(0, -1, 0)));
  // Descriptor distances are at most 2 r, r the largest finite descriptor norm (here 1).
  CHECK(cells.max_distance() == Approx(2.0));
  // Cell (0,0,0) holds {d0, d1}, cell (2,1,0) {d0}: Hausdorff = |d1 - d0| = sqrt 2.
  CHECK(cells.distance(cells.grid().index(Eigen::Array3i(0, 0, 0)), cells.grid().index(Eigen::Array3i(2, 1, 0))) ==
        Approx(std::sqrt(2.0)));
}

TEST_CASE("CellDescriptors: Hausdorff and mean-nearest set distances on hand-made sets", "[energy][cells]") {
  // Four cells along x; descriptor sets chosen so the distances are known by hand:
  //   c0 = {(0,0,0), (1,0,0)}, c1 = {(0.5,0,0), (3,0,0)}, c2 = {(0,2,0)}, c3 = c0 in another order.
  const std::vector<Feature> f{
      {in_cell(0, 0, 0, 0.2), {0, 0, 0}},
      {in_cell(0, 0, 0, 0.7), {1, 0, 0}},
      {in_cell(1), {0.5f, 0, 0}},
      {in_cell(1, 0, 0, 0.9), {3, 0, 0}},
      {in_cell(2), {0, 2, 0}},
      {in_cell(3, 0, 0, 0.1), {1, 0, 0}},
      {in_cell(3, 0, 0, 0.8), {0, 0, 0}},
  };
  const Analysis a = hand_analysis(f);
  const Lattice grid = unit_grid({4, 1, 1});
  CellDescriptors h(a, grid, SetDistance::hausdorff);
  CellDescriptors m(a, grid, SetDistance::mean_nearest);
  CHECK(h.max_distance() == Approx(6.0));  // 2 * |(3,0,0)|
  // c0 -> c1: nearest 0.5, 0.5; c1 -> c0: nearest 0.5, 2.
  CHECK(h.distance(0, 1) == Approx(2.0));
  CHECK(m.distance(0, 1) == Approx(0.5 * ((0.5 + 0.5) / 2 + (0.5 + 2.0) / 2)));
  // c0 -> c2: nearest 2, sqrt 5; c2 -> c0: nearest 2.
  CHECK(h.distance(0, 2) == Approx(std::sqrt(5.0)));
  CHECK(m.distance(0, 2) == Approx(0.5 * ((2 + std::sqrt(5.0)) / 2 + 2)));
  // Equal sets are at distance 0 whatever the order of their features.
  CHECK(h.distance(0, 3) == Approx(0).margin(1e-6));
  CHECK(m.distance(0, 3) == Approx(0).margin(1e-6));
  CHECK(h.distance(2, 2) == 0);
  // Symmetric in its arguments.
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y) {
      CHECK(h.distance(x, y) == h.distance(y, x));
      CHECK(m.distance(x, y) == m.distance(y, x));
    }
}

TEST_CASE("CellDescriptors: set distances equal a brute-force computation on random sets", "[energy][cells]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Array3i dims(3, 2, 2);
  std::vector<Feature> f;
  std::vector<std::vector<std::vector<float>>> sets(std::size_t(dims.prod()));
  for (int c = 0; c < dims.prod(); ++c) {
    const Eigen::Array3i cell = node_cell(c, dims);
    const int n = 1 + int(rng() % 6);
    for (int s = 0; s < n; ++s) {
      std::vector<float> d(8);
      for (float& x : d) x = float(g(rng));
      f.push_back({Eigen::Vector3d(cell[0] + u(rng), cell[1] + u(rng), cell[2] + u(rng)), d});
      sets[std::size_t(c)].push_back(d);
    }
  }
  std::shuffle(f.begin(), f.end(), rng);  // the grouping must not depend on the feature order
  const Analysis a = hand_analysis(f);
  CellDescriptors h(a, unit_grid(dims), SetDistance::hausdorff);
  CellDescriptors m(a, unit_grid(dims), SetDistance::mean_nearest);
  double r = 0;
  for (const Feature& x : f) r = std::max(r, l2(x.d, std::vector<float>(8, 0.0f)));
  CHECK(h.max_distance() == Approx(2 * r).epsilon(1e-6));
  for (int x = 0; x < dims.prod(); ++x) {
    CHECK(h.features_in(x) == sets[std::size_t(x)].size());
    for (int y = 0; y < dims.prod(); ++y) {
      INFO("cells " << x << " and " << y);
      CHECK(h.distance(x, y) == Approx(brute_hausdorff(sets[std::size_t(x)], sets[std::size_t(y)])).epsilon(1e-4));
      CHECK(m.distance(x, y) == Approx(brute_mean_nearest(sets[std::size_t(x)], sets[std::size_t(y)])).epsilon(1e-4));
    }
  }
}

TEST_CASE("CellDescriptors: distances are computed once per pair and cached", "[energy][cells]") {
  const Analysis a = grid_with_holes({4, 3, 1}, 3);
  CellDescriptors cells(a, unit_grid({4, 3, 1}), SetDistance::hausdorff);
  CellDescriptors fresh(a, unit_grid({4, 3, 1}), SetDistance::hausdorff);
  std::vector<int> full;
  for (int c = 0; c < 12; ++c)
    if (!cells.empty(c)) full.push_back(c);
  REQUIRE(full.size() >= 4);
  CHECK(cells.cached_pairs() == 0);
  const double d01 = cells.distance(full[0], full[1]);
  CHECK(cells.cached_pairs() == 1);
  CHECK(cells.distance(full[0], full[1]) == d01);  // from the cache
  CHECK(cells.distance(full[1], full[0]) == d01);  // one entry per unordered pair
  CHECK(cells.cached_pairs() == 1);
  CHECK(cells.distance(full[2], full[2]) == 0);  // a cell to itself: nothing to cache
  CHECK(cells.cached_pairs() == 1);
  const double d23 = cells.distance(full[3], full[2]);
  CHECK(cells.cached_pairs() == 2);
  // Cached values equal what a fresh object computes.
  CHECK(fresh.distance(full[2], full[3]) == d23);
  CHECK(fresh.distance(full[1], full[0]) == d01);
  CHECK(d01 > 0);
}

TEST_CASE("SeamMrf: labels, nodes and label lookup for given grid steps", "[energy][mrf]") {
  const Analysis a = grid_with_holes({2, 2, 2}, 1);
  CellDescriptors cells(a, unit_grid({2, 2, 2}), SetDistance::hausdorff);
  const Eigen::Array3i k(2, -1, 0);
  SeamMrf mrf(cells, k, Neighbourhood::n6);
  CHECK((mrf.out_grid().dims == Eigen::Array3i(4, 1, 2)).all());
  CHECK(mrf.node_count() == 8);
  // Every shift with d_a between 0 and k_a (sign of k_a), x fastest: M = prod(|k_a| + 1).
  const std::vector<Eigen::Array3i> want{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, -1, 0}, {1, -1, 0}, {2, -1, 0}};
  REQUIRE(mrf.label_count() == int(want.size()));
  for (std::size_t l = 0; l < want.size(); ++l) {
    CHECK((mrf.labels()[l] == want[l]).all());
    CHECK(mrf.label_of(want[l]) == int(l));
  }
  CHECK(mrf.label_of({3, 0, 0}) == -1);
  CHECK(mrf.label_of({0, 1, 0}) == -1);  // wrong sign
  CHECK(mrf.label_of({0, 0, 1}) == -1);  // k_z = 0
  // Shrinking on every axis.
  SeamMrf shrink(cells, Eigen::Array3i(-1, -1, -1), Neighbourhood::n6);
  CHECK(shrink.node_count() == 1);
  CHECK(shrink.label_count() == 8);
  for (const Eigen::Array3i& d : shrink.labels()) CHECK(((d == 0) || (d == -1)).all());
}

TEST_CASE("SeamMrf: a label whose source cell lies outside the input is forbidden", "[energy][mrf]") {
  const Analysis a = grid_with_holes({3, 2, 2}, 5);
  CellDescriptors cells(a, unit_grid({3, 2, 2}), SetDistance::hausdorff);
  for (const Eigen::Array3i& k :
       {Eigen::Array3i(2, 0, 0), Eigen::Array3i(1, 1, 0), Eigen::Array3i(-1, 0, 1), Eigen::Array3i(-2, -1, 0)}) {
    INFO("k = " << k.transpose());
    SeamMrf mrf(cells, k, Neighbourhood::n26);
    CHECK(mrf.forbidden() == Approx(1e6 * cells.max_distance()));
    REQUIRE((mrf.out_grid().dims == cells.grid().dims + k).all());
    for (int x = 0; x < mrf.node_count(); ++x)
      for (int l = 0; l < mrf.label_count(); ++l) {
        const bool source_inside =
            inside(node_cell(x, mrf.out_grid().dims) - mrf.labels()[std::size_t(l)], cells.grid().dims);
        INFO("node " << x << " label " << l);
        CHECK((mrf.unary(x, l) >= mrf.forbidden()) == !source_inside);
        CHECK(std::isfinite(mrf.unary(x, l)));
      }
    // The starting labelling copies the input's own ends: never forbidden, 0 at the first node.
    const std::vector<int> start = mrf.initial_labels();
    REQUIRE(int(start.size()) == mrf.node_count());
    for (int x = 0; x < mrf.node_count(); ++x) {
      REQUIRE(start[std::size_t(x)] >= 0);
      CHECK(mrf.unary(x, start[std::size_t(x)]) < mrf.forbidden());
    }
    CHECK(start.front() == mrf.label_of({0, 0, 0}));
    // The last node is at the high end of every axis (where it has more than one cell): shift k.
    if ((mrf.out_grid().dims > 1).all()) CHECK(start.back() == mrf.label_of(k));
  }
}

TEST_CASE("SeamMrf: anchored ends and seams on a 1D row, by hand", "[energy][mrf]") {
  // Three full cells with descriptors a=(0,0,0), b=(1,0,0), c=(0,3,0):
  // D(0,1) = 1, D(1,2) = sqrt 10, D(0,2) = 3; r = 3, so empty_mismatch = 6000.
  const std::vector<Feature> f{{in_cell(0), {0, 0, 0}}, {in_cell(1), {1, 0, 0}}, {in_cell(2), {0, 3, 0}}};
  const Analysis a = hand_analysis(f);
  CellDescriptors cells(a, unit_grid({3, 1, 1}), SetDistance::hausdorff);
  const double E = 6000, s10 = std::sqrt(10.0);
  REQUIRE(cells.max_distance() == Approx(6.0));

  SECTION("shrinking by one: the ends are pulled towards copying the input's ends") {
    SeamMrf mrf(cells, {-1, 0, 0}, Neighbourhood::n26);
    REQUIRE(mrf.node_count() == 2);
    const int l0 = mrf.label_of({0, 0, 0}), l1 = mrf.label_of({-1, 0, 0});
    REQUIRE(l0 >= 0);
    REQUIRE(l1 >= 0);
    // Node 0 (low face) copying cell 0: its anchor (shift 0) agrees.
    CHECK(mrf.unary(0, l0) == Approx(0).margin(1e-9));
    // Node 0 copying cell 1: seams to the anchor, D(1,0) inside and D(0,-1) outside.
    CHECK(mrf.unary(0, l1) == Approx(1 + E));
    // Node 1 (high face) copying cell 2: its anchor (shift k) agrees.
    CHECK(mrf.unary(1, l1) == Approx(0).margin(1e-9));
    // Node 1 copying cell 1: D(1,2) inside, D(2,3) with cell 3 outside the input.
    CHECK(mrf.unary(1, l0) == Approx(s10 + E));
    REQUIRE(mrf.edge_count() == 1);
    CHECK(mrf.pairwise(0, l0, l1) == Approx(1 + s10));  // D(0,1) + D(1,2)
    CHECK(mrf.pairwise(0, l1, l0) == Approx(1 + s10));
    CHECK(mrf.pairwise(0, l1, l1) == 0);
  }
  SECTION("growing by one") {
    SeamMrf mrf(cells, {1, 0, 0}, Neighbourhood::n26);
    REQUIRE(mrf.node_count() == 4);
    const int l0 = mrf.label_of({0, 0, 0}), l1 = mrf.label_of({1, 0, 0});
    CHECK(mrf.unary(0, l1) >= mrf.forbidden());  // copies cell -1
    CHECK(mrf.unary(3, l0) >= mrf.forbidden());  // copies cell 3
    CHECK(mrf.unary(0, l0) == Approx(0).margin(1e-9));
    CHECK(mrf.unary(3, l1) == Approx(0).margin(1e-9));
    CHECK(mrf.unary(1, l0) == 0);
    CHECK(mrf.unary(2, l1) == 0);
    REQUIRE(mrf.edge_count() == 3);
    for (int e = 0; e < 3; ++e) {
      const auto [x, y] = mrf.edge(e);
      const int lo = std::min(x, y), hi = std::max(x, y);
      REQUIRE(hi == lo + 1);
      // A seam between nodes lo and lo+1 with shifts 0 and 1: D(lo, lo-1) + D(lo+1, lo).
      const double want = lo == 0 ? E + 1 : lo == 1 ? 1 + s10 : s10 + E;
      CHECK(mrf.pairwise(e, l0, l1) == Approx(want));
    }
  }
}

TEST_CASE("SeamMrf: empty cells cost nothing next to empty cells and empty_mismatch next to full ones",
          "[energy][mrf]") {
  // Cells 0 and 3 full, 1 and 2 empty.
  const std::vector<Feature> f{{in_cell(0), {1, 0}}, {in_cell(3), {0, 1}}};
  const Analysis a = hand_analysis(f);
  CellDescriptors cells(a, unit_grid({4, 1, 1}), SetDistance::hausdorff);
  const double E = 1000 * cells.max_distance();
  SeamMrf mrf(cells, {1, 0, 0}, Neighbourhood::n6);
  const int l0 = mrf.label_of({0, 0, 0}), l1 = mrf.label_of({1, 0, 0});
  REQUIRE(mrf.edge_count() == 4);
  for (int e = 0; e < mrf.edge_count(); ++e) {
    const int lo = std::min(mrf.edge(e).first, mrf.edge(e).second);
    // seam(lo) = D(lo, lo-1), seam(lo+1) = D(lo+1, lo)
    const double want[4] = {E + E /* D(0,-1), D(1,0) */, E + 0 /* D(1,0), D(2,1) */, 0 + E /* D(2,1), D(3,2) */,
                            E + E /* D(3,2), D(4,3) */};
    INFO("edge " << e << " between " << lo << " and " << lo + 1);
    CHECK(mrf.pairwise(e, l0, l1) == Approx(want[lo]));
  }
}

TEST_CASE("SeamMrf: unary and pairwise equal the energy of the contract on a 3D grid with holes", "[energy][mrf]") {
  const Analysis a = grid_with_holes({3, 2, 2}, 11);
  for (const SetDistance kind : {SetDistance::hausdorff, SetDistance::mean_nearest})
    for (const Eigen::Array3i& k : {Eigen::Array3i(2, 0, 0), Eigen::Array3i(1, 1, 0), Eigen::Array3i(-1, 1, -1)}) {
      INFO("k = " << k.transpose() << (kind == SetDistance::hausdorff ? " hausdorff" : " mean_nearest"));
      CellDescriptors cells(a, unit_grid({3, 2, 2}), kind);
      CellDescriptors oracle_cells(a, unit_grid({3, 2, 2}), kind);
      const ContractEnergy oracle(oracle_cells, k);
      SeamMrf mrf(cells, k, Neighbourhood::n26);
      const auto& labels = mrf.labels();
      for (int x = 0; x < mrf.node_count(); ++x)
        for (int l = 0; l < mrf.label_count(); ++l) {
          INFO("node " << x << " label " << l);
          CHECK(mrf.unary(x, l) == Approx(oracle.unary(x, labels[std::size_t(l)])).epsilon(1e-12).margin(1e-9));
        }
      for (int e = 0; e < mrf.edge_count(); ++e) {
        const auto [x, y] = mrf.edge(e);
        for (int i = 0; i < mrf.label_count(); ++i)
          for (int j = 0; j < mrf.label_count(); ++j) {
            const double p = mrf.pairwise(e, i, j);
            INFO("edge " << x << "-" << y << " labels " << i << ", " << j);
            CHECK(p == mrf.pairwise(e, j, i));  // symmetric
            if (i == j)
              CHECK(p == 0);
            else
              CHECK(p == Approx(oracle.pairwise(x, y, labels[std::size_t(i)], labels[std::size_t(j)]))
                             .epsilon(1e-12)
                             .margin(1e-9));
          }
      }
    }
}

TEST_CASE("SeamMrf: 26- and 6-neighbourhood edges equal a brute-force enumeration", "[energy][mrf]") {
  const Analysis a = grid_with_holes({2, 2, 2}, 2);
  CellDescriptors cells(a, unit_grid({2, 2, 2}), SetDistance::hausdorff);
  for (const Eigen::Array3i& k : {Eigen::Array3i(1, 1, 1), Eigen::Array3i(2, 0, -1), Eigen::Array3i(0, 0, 0)})
    for (const Neighbourhood nb : {Neighbourhood::n26, Neighbourhood::n6}) {
      SeamMrf mrf(cells, k, nb);
      const Eigen::Array3i out = cells.grid().dims + k;
      INFO("out " << out.transpose() << (nb == Neighbourhood::n26 ? " n26" : " n6"));
      // Every unordered pair of distinct cells, neighbours by the Chebyshev (26) or Manhattan (6) distance.
      std::set<std::pair<int, int>> want;
      const int n = out.prod();
      for (int x = 0; x < n; ++x)
        for (int y = x + 1; y < n; ++y) {
          const Eigen::Array3i d = (node_cell(x, out) - node_cell(y, out)).abs();
          if (nb == Neighbourhood::n26 ? d.maxCoeff() == 1 : d.sum() == 1) want.insert({x, y});
        }
      std::set<std::pair<int, int>> got;
      for (int e = 0; e < mrf.edge_count(); ++e) {
        const auto [x, y] = mrf.edge(e);
        got.insert({std::min(x, y), std::max(x, y)});
      }
      CHECK(int(got.size()) == mrf.edge_count());  // each pair once
      CHECK(got == want);
    }
  // A 3 x 3 x 3 output: 54 face neighbours, and (7^3 - 27) / 2 = 158 pairs in the 26-neighbourhood.
  CHECK(SeamMrf(cells, {1, 1, 1}, Neighbourhood::n6).edge_count() == 54);
  CHECK(SeamMrf(cells, {1, 1, 1}, Neighbourhood::n26).edge_count() == 158);
}
