// Tests for lattice/grid.hpp (the cell-grid type), detail/cell_hash.hpp (the hashed grid) and
// detail/point_tree.hpp (the bounded nearest search), against brute-force oracles.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "restitch/detail/cell_hash.hpp"
#include "restitch/detail/point_tree.hpp"
#include "restitch/lattice/grid.hpp"

using restitch::CellGrid;
using restitch::Neighbourhood;

TEST_CASE("CellGrid: linear index is x fastest and cell() inverts it", "[grid]") {
  const CellGrid g(Eigen::Array3i(4, 3, 5));
  REQUIRE(g.size() == 60);
  int expected = 0;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) {
        CHECK(g.index(i, j, k) == expected);
        CHECK(g.index(Eigen::Array3i(i, j, k)) == expected);
        CHECK((g.cell(expected) == Eigen::Array3i(i, j, k)).all());
        ++expected;
      }
  CHECK(g.inside(Eigen::Array3i(3, 2, 4)));
  CHECK_FALSE(g.inside(Eigen::Array3i(4, 0, 0)));
  CHECK_FALSE(g.inside(Eigen::Array3i(0, -1, 0)));
  CHECK_FALSE(g.inside(std::int64_t(0), 0, 5));
}

TEST_CASE("CellGrid: the cell of a point floors, clamps and snaps onto planes", "[grid]") {
  const CellGrid g(Eigen::Array3i(3, 2, 1));
  CHECK((g.cell_of({0.5, 0.5, 0.5}) == Eigen::Array3i(0, 0, 0)).all());
  CHECK((g.cell_of({1.0, 1.999, 0.2}) == Eigen::Array3i(1, 1, 0)).all());  // on a plane: the cell above
  CHECK((g.cell_of({-7.0, 9.0, 3.0}) == Eigen::Array3i(0, 1, 0)).all());   // overhang: clamped
  // Just below a plane: floor without snapping, the plane's cell with it.
  CHECK(g.cell_of({1.0 - 1e-9, 0.5, 0.5})[0] == 0);
  CHECK(g.cell_of({1.0 - 1e-9, 0.5, 0.5}, 1e-6)[0] == 1);
  CHECK(g.cell_of({1.0 + 1e-9, 0.5, 0.5}, 1e-6)[0] == 1);
  CHECK(restitch::snap_coordinate(2.0000001, 1e-3) == 2.0);
  CHECK(restitch::snap_coordinate(2.1, 1e-3) == 2.1);
}

TEST_CASE("neighbour offsets and for_each_neighbour agree with a brute-force count", "[grid]") {
  CHECK(restitch::neighbour_offsets(Neighbourhood::n26, false).size() == 26);
  CHECK(restitch::neighbour_offsets(Neighbourhood::n26, true).size() == 13);
  CHECK(restitch::neighbour_offsets(Neighbourhood::n6, false).size() == 6);
  CHECK(restitch::neighbour_offsets(Neighbourhood::n6, true).size() == 3);
  // The forward half and its negation are the whole neighbourhood, each offset once.
  for (Neighbourhood nb : {Neighbourhood::n26, Neighbourhood::n6}) {
    std::set<std::array<int, 3>> all, half;
    for (const Eigen::Array3i& o : restitch::neighbour_offsets(nb, false)) all.insert({o[0], o[1], o[2]});
    for (const Eigen::Array3i& o : restitch::neighbour_offsets(nb, true)) {
      CHECK(half.insert({o[0], o[1], o[2]}).second);
      CHECK(half.insert({-o[0], -o[1], -o[2]}).second);
    }
    CHECK(all == half);
  }
  const CellGrid g(Eigen::Array3i(3, 4, 2));
  for (Neighbourhood nb : {Neighbourhood::n26, Neighbourhood::n6})
    for (int x = 0; x < int(g.size()); ++x) {
      std::set<int> got, want;
      g.for_each_neighbour(x, nb, [&](int y) { CHECK(got.insert(y).second); });
      const Eigen::Array3i c = g.cell(x);
      for (int y = 0; y < int(g.size()); ++y) {
        const Eigen::Array3i d = (g.cell(y) - c).abs();
        const int l1 = d.sum();
        if (y != x && d.maxCoeff() <= 1 && (nb == Neighbourhood::n26 || l1 == 1)) want.insert(y);
      }
      CHECK(got == want);
    }
}

TEST_CASE("CellHashMap matches std::map on random cells, through growth", "[grid]") {
  using restitch::detail::Cell;
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<std::int64_t> small(-40, 40);
  std::uniform_int_distribution<std::int64_t> huge(-(std::int64_t(1) << 60), std::int64_t(1) << 60);
  restitch::detail::CellHashMap<int> map;  // starts small: it must grow
  std::map<Cell, int> oracle;
  for (int n = 0; n < 20000; ++n) {
    const bool far = n % 7 == 0;
    const Cell c{far ? huge(rng) : small(rng), small(rng), far ? huge(rng) : small(rng)};
    const auto got = map.get(c, n);
    const auto want = oracle.emplace(c, n);
    CHECK(got.second == want.second);
    CHECK(*got.first == want.first->second);
    if (n % 3 == 0) ++*got.first, ++want.first->second;
  }
  CHECK(map.size() == oracle.size());
  for (const auto& [c, v] : oracle) {
    const int* f = map.find(c);
    REQUIRE(f);
    CHECK(*f == v);
  }
  CHECK(map.find(Cell{1000, 1000, 1000}) == nullptr);
}

TEST_CASE("CellChains lists exactly the items inserted into each cell", "[grid]") {
  using restitch::detail::Cell;
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> d(-5, 5);
  restitch::detail::CellChains chains(10);
  std::map<Cell, std::multiset<int>> oracle;
  for (int i = 0; i < 3000; ++i) {
    const Cell c{d(rng), d(rng), d(rng)};
    chains.insert(c, i);
    oracle[c].insert(i);
  }
  for (std::int64_t x = -6; x <= 6; ++x)
    for (std::int64_t y = -6; y <= 6; ++y)
      for (std::int64_t z = -6; z <= 6; ++z) {
        std::multiset<int> got;
        chains.for_each(Cell{x, y, z}, [&](int i) { got.insert(i); });
        const auto it = oracle.find(Cell{x, y, z});
        CHECK(got == (it == oracle.end() ? std::multiset<int>{} : it->second));
        const bool any = chains.any_of(Cell{x, y, z}, [](int i) { return i % 2 == 0; });
        bool want = false;
        for (int i : got) want = want || i % 2 == 0;
        CHECK(any == want);
      }
}

TEST_CASE("NearestWithin: the bounded search answers as the unbounded one, or none beyond the bound", "[grid]") {
  // Points on a coarse grid (many equal distances) plus random ones; queries anywhere, bounds from
  // 0 to past every point. Oracle: the unbounded one-nearest search and a scan of every point.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(0, 1);
  restitch::MatrixX3f P(400, 3);
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    for (int c = 0; c < 3; ++c) P(i, c) = i < 200 ? std::round(u(rng) * 8) / 8 : u(rng);
  restitch::detail::PointSetAdaptor adaptor{&P};
  restitch::detail::PointSetTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  int found = 0, none = 0;
  for (int k = 0; k < 2000; ++k) {
    const float q[3] = {std::round(u(rng) * 16) / 16 * 1.2f - 0.1f, u(rng) * 1.2f - 0.1f, u(rng)};
    const float bound2 = k % 7 == 0 ? 0.0f : u(rng) * u(rng) * 0.05f;
    float least = std::numeric_limits<float>::infinity();
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      float d = 0;
      for (int c = 0; c < 3; ++c) d += (P(i, c) - q[c]) * (P(i, c) - q[c]);
      least = std::min(least, d);
    }
    std::uint32_t idx = 0;
    float d2 = 0;
    nanoflann::KNNResultSet<float, std::uint32_t> all(1);
    all.init(&idx, &d2);
    tree.findNeighbors(all, q, nanoflann::SearchParams());
    restitch::detail::NearestWithin near(bound2);
    tree.findNeighbors(near, q, nanoflann::SearchParams());
    REQUIRE(d2 == least);
    if (least < bound2) {
      ++found;
      REQUIRE(near.found);
      CHECK(near.index == idx);  // the same point, ties included
      CHECK(near.dist == least);
    } else {
      ++none;
      CHECK_FALSE(near.found);
    }
  }
  CHECK(found > 200);  // both branches exercised
  CHECK(none > 200);
}
