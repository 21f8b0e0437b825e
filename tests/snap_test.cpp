// Snapping an offset onto the mesh's own vertices (offsets/snap.hpp).
#include <catch2/catch.hpp>

#include <random>
#include <vector>

#include "restitch/offsets/snap.hpp"

using namespace restitch;

namespace {
// A random module of `n` points in [0, 0.1]^3 copied `copies` times along t.
Eigen::Matrix<double, Eigen::Dynamic, 3> repeated(int n, int copies, const Eigen::Vector3d& t, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto u = [&] { return double(rng() >> 11) * (1.0 / 9007199254740992.0); };
  Eigen::Matrix<double, Eigen::Dynamic, 3> module(n, 3);
  for (int i = 0; i < n; ++i) module.row(i) = Eigen::RowVector3d(u(), u(), u()) * 0.1;
  Eigen::Matrix<double, Eigen::Dynamic, 3> P(n * copies, 3);
  for (int c = 0; c < copies; ++c)
    for (int i = 0; i < n; ++i) P.row(c * n + i) = module.row(i) + c * t.transpose();
  return P;
}
}  // namespace

TEST_CASE("snap: an approximate offset of exactly copied points becomes exact", "[offsets][snap]") {
  const Eigen::Vector3d t(0.25, 0.0625, -0.03125);
  const auto P = repeated(200, 4, t, 7);
  const SnapResult r = snap_offset(P, t + Eigen::Vector3d(0.006, -0.004, 0.003));
  REQUIRE(r.snapped);
  CHECK((r.offset - t).norm() < 1e-12);
  CHECK(r.pairs == 600u);  // three of four copies have a successor
}

TEST_CASE("snap: above max_queries an even stride of the vertices looks for partners", "[offsets][snap]") {
  // 4 copies of 200 points, in copy order: the last copy's points have no successor. Queried by 100
  // (every 8th point), 75 of them do; the offset is as exact as with all 800.
  const Eigen::Vector3d t(0.25, 0.0625, -0.03125);
  const auto P = repeated(200, 4, t, 7);
  SnapOptions few;
  few.max_queries = 100;
  const SnapResult r = snap_offset(P, t + Eigen::Vector3d(0.006, -0.004, 0.003), few);
  REQUIRE(r.snapped);
  CHECK((r.offset - t).norm() < 1e-12);
  CHECK(r.pairs == 75u);
  // The share is of the querying points: 75 of 100 pass a share of 0.7 (75 of 800 would not).
  few.min_share = 0.7;
  CHECK(snap_offset(P, t + Eigen::Vector3d(0.006, -0.004, 0.003), few).snapped);
  few.max_queries = 0;  // 0: every point queries
  CHECK(snap_offset(P, t, few).pairs == 600u);
}

TEST_CASE("snap: an offset one tessellation step off moves to the one that maps every copied vertex",
          "[offsets][snap]") {
  // Four columns 0.4 apart, each a board meshed every 0.025 along z (0 to 0.3) plus a random "book"
  // (the bookshelf at --detail 4). Started at t + (0, 0, 0.025) (where ICP stopped: the boards still map
  // onto each other there, 12 of 13 rows), the descent alone stays there; the vertices left unpaired (the
  // books) vote for the step back, which maps every copied vertex.
  const Eigen::Vector3d t(0.4, 0, 0);
  const int columns = 4, rows = 13;
  std::mt19937_64 rng(5);
  auto u = [&] { return double(rng() >> 11) * (1.0 / 9007199254740992.0); };
  std::vector<Eigen::RowVector3d> module;
  for (int j = 0; j < rows; ++j)
    for (const double y : {0.0, 0.02, 0.3, 0.32}) module.emplace_back(0.1, y, 0.025 * j);
  for (int i = 0; i < 60; ++i) module.emplace_back(0.15 + 0.1 * u(), 0.05 + 0.2 * u(), 0.01 + 0.28 * u());
  Eigen::Matrix<double, Eigen::Dynamic, 3> P(Eigen::Index(module.size()) * columns, 3);
  for (int c = 0; c < columns; ++c)
    for (std::size_t i = 0; i < module.size(); ++i) P.row(Eigen::Index(c * module.size() + i)) = module[i] + c * t.transpose();
  const SnapResult r = snap_offset(P, t + Eigen::Vector3d(0.003, 0, 0.024));
  REQUIRE(r.snapped);
  CHECK((r.offset - t).norm() < 1e-12);
  CHECK(r.pairs == std::size_t(3 * module.size()));
}

TEST_CASE("snap: copies that are not exact keep the sample-based offset", "[offsets][snap]") {
  const Eigen::Vector3d t(0.3, 0, 0);
  auto P = repeated(100, 3, t, 3);
  // The third copy is placed 0.001 too far: pairs 1->2 say 0.3, 2->3 say 0.301.
  P.bottomRows(100).col(0).array() += 0.001;
  const Eigen::Vector3d start = t + Eigen::Vector3d(0.0005, 0, 0);
  const SnapResult r = snap_offset(P, start);
  // Halfway between 0.300 and 0.301, every pair is 0.0005 off: no pair survives the final radius.
  CHECK_FALSE(r.snapped);
  CHECK(r.offset == start);
}

TEST_CASE("snap: no supported repeat leaves the offset unchanged", "[offsets][snap]") {
  const auto P = repeated(300, 1, Eigen::Vector3d::Zero(), 11);  // one module only, 0.1 wide
  const Eigen::Vector3d t(0.5, 0, 0);                            // nothing lies 0.5 away
  const SnapResult r = snap_offset(P, t);
  CHECK_FALSE(r.snapped);
  CHECK(r.offset == t);
  const SnapResult none = snap_offset(Eigen::Matrix<double, Eigen::Dynamic, 3>(0, 3), t);
  CHECK_FALSE(none.snapped);
}

namespace {
// snap_offset with every point searched at every radius (no grid): the oracle of the grid's cell range.
SnapResult snap_by_brute_force(const Eigen::Matrix<double, Eigen::Dynamic, 3>& P, const Eigen::Vector3d& t,
                               const SnapOptions& o = {}) {
  SnapResult result;
  result.offset = t;
  Eigen::Vector3d cur = t;
  std::size_t pairs = 0;
  for (double r = o.start_radius; r >= o.end_radius * 0.999; r *= 0.5) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    pairs = 0;
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      const Eigen::Vector3d q = P.row(i).transpose() + cur;
      double best = r * r;
      Eigen::Index hit = -1;
      for (Eigen::Index j = 0; j < P.rows(); ++j) {
        const double d2 = (P.row(j).transpose() - q).squaredNorm();
        if (d2 < best || (d2 == best && hit >= 0 && j < hit)) best = d2, hit = j;
      }
      if (hit >= 0) sum += P.row(hit).transpose() - P.row(i).transpose(), ++pairs;
    }
    if (pairs < o.min_pairs) return result;
    cur = sum / double(pairs);
  }
  if (pairs < o.min_pairs || double(pairs) < o.min_share * double(P.rows())) return result;
  result.offset = cur, result.snapped = true, result.pairs = pairs;
  return result;
}
}  // namespace

TEST_CASE("snap: the grid's cell range gives exactly the brute-force answer", "[offsets][snap]") {
  // Exact copies, copies off by less than the radii (pairs lost on the way), points on cell planes
  // (multiples of the 0.02 cell size) and starts off by up to a radius: offset and pairs bit for bit.
  for (int trial = 0; trial < 12; ++trial) {
    const Eigen::Vector3d t(0.25 + 0.01 * trial, 0.02 * (trial % 3), -0.04);
    auto P = repeated(60, 3, t, std::uint64_t(trial));
    if (trial % 2) P.bottomRows(60).array() += 1e-4 * double(trial);  // the third copy a little off
    if (trial % 3 == 0) P.topRows(10) = (P.topRows(10) / 0.02).array().round().matrix() * 0.02;
    const Eigen::Vector3d start =
        t + 0.015 * Eigen::Vector3d(std::cos(trial), std::sin(trial), std::cos(2.0 * trial));
    const SnapResult grid = snap_offset(P, start), brute = snap_by_brute_force(P, start);
    CHECK(grid.snapped == brute.snapped);
    CHECK(grid.pairs == brute.pairs);
    CHECK(grid.offset == brute.offset);
  }
}
