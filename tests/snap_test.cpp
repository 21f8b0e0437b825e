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

TEST_CASE("repeat_precision: exact copies keep the base, copies off by a known distance give the rung past it, "
          "no repeat keeps the base; shares equal a brute-force count",
          "[offsets][snap]") {
  const Eigen::Vector3d t(0.25, 0.0625, -0.03125);
  auto P = repeated(300, 4, t, 11);
  Eigen::Vector3d lo = P.colwise().minCoeff().transpose(), hi = P.colwise().maxCoeff().transpose();
  const double diag = (hi - lo).norm(), base = 1e-6;

  // Brute force: the share of points with a point within base 2^k diag of p + t.
  auto brute = [&](const Eigen::Matrix<double, Eigen::Dynamic, 3>& Q, int k) {
    std::size_t c = 0;
    for (Eigen::Index i = 0; i < Q.rows(); ++i) {
      double best = INFINITY;
      for (Eigen::Index j = 0; j < Q.rows(); ++j) best = std::min(best, (Q.row(j) - Q.row(i) - t.transpose()).norm());
      c += best <= base * std::ldexp(1.0, k) * diag;
    }
    return double(c) / double(Q.rows());
  };

  SECTION("exact copies") {
    const RepeatPrecision r = repeat_precision(P, {t}, diag, base);
    CHECK(r.tolerance == base);
    REQUIRE(r.shares.size() == 1);
    REQUIRE(r.shares[0].size() == 7);
    CHECK(r.shares[0][0] == Approx(0.75));  // every copy but the last has its partner
    for (int k = 0; k < 7; ++k) CHECK(r.shares[0][std::size_t(k)] == brute(P, k));
  }
  SECTION("every copy moved by 5e-6 of the diagonal: the pairs appear at rung 8e-6, the tolerance is 1.6e-5") {
    // Copy c moves by c * delta along a fixed direction: neighbouring copies differ by exactly delta.
    const Eigen::Vector3d dir = Eigen::Vector3d(1, 2, 2) / 3.0;
    const double delta = 5e-6 * diag;
    for (Eigen::Index i = 0; i < P.rows(); ++i) P.row(i) += double(i / 300) * delta * dir.transpose();
    const RepeatPrecision r = repeat_precision(P, {t}, diag, base);
    CHECK(r.tolerance == 16 * base);
    CHECK(r.shares[0][2] == 0);  // 4e-6: no pair yet
    CHECK(r.shares[0][3] == Approx(0.75));
    for (int k = 0; k < 7; ++k) CHECK(r.shares[0][std::size_t(k)] == brute(P, k));
    // The largest over the offsets: an exact second offset does not lower it.
    CHECK(repeat_precision(P, {t, Eigen::Vector3d(0.5, 0, 0)}, diag, base).tolerance == 16 * base);
  }
  SECTION("past the work bound (every point in one cell) the measure gives up: the base, no shares") {
    for (Eigen::Index i = 0; i < P.rows(); ++i) P.row(i) += double(i / 300) * 5e-6 * diag * Eigen::RowVector3d(1, 0, 0);
    RepeatPrecisionOptions few;
    few.max_visits_per_query = 0.25;  // three queries in four look at their one partner here
    CHECK(repeat_precision(P, {t}, diag, base).tolerance == 16 * base);
    const RepeatPrecision r = repeat_precision(P, {t}, diag, base, few);
    CHECK(r.tolerance == base);
    CHECK(r.shares.empty());
    Eigen::Matrix<double, Eigen::Dynamic, 3> crowd(2000, 3);  // all within one cell, one far point
    for (Eigen::Index i = 0; i < crowd.rows(); ++i) crowd.row(i) = Eigen::RowVector3d(1e-9 * double(i), 0, 0);
    crowd.row(0) = Eigen::RowVector3d(1, 1, 1);
    CHECK(repeat_precision(crowd, {Eigen::Vector3d(1e-9, 0, 0)}, std::sqrt(3.0), base).shares.empty());
  }
  SECTION("copies off by more than the largest rung, or no repeat at all: the base stays") {
    const Eigen::Vector3d dir(0, 0, 1);
    for (Eigen::Index i = 0; i < P.rows(); ++i) P.row(i) += double(i / 300) * 1e-3 * diag * dir.transpose();
    CHECK(repeat_precision(P, {t}, diag, base).tolerance == base);
    CHECK(repeat_precision(repeated(300, 1, t, 5), {t}, diag, base).tolerance == base);
  }
  SECTION("one copy moved by 0 to 1.5e-5 of the diagonal, evenly: the pairs are complete by rung 1.6e-5 (the share "
          "grows until then), the tolerance is 3.2e-5") {
    const Eigen::Vector3d dir = Eigen::Vector3d(2, -1, 2) / 3.0;
    for (Eigen::Index i = 300; i < 600; ++i)  // the second copy only: its pairs with the first and the third
      P.row(i) += ((double(i - 300) + 0.5) / 300.0) * 1.5e-5 * diag * dir.transpose();  // off the rungs
    const RepeatPrecision r = repeat_precision(P, {t}, diag, base);
    for (int k = 0; k < 7; ++k) CHECK(r.shares[0][std::size_t(k)] == brute(P, k));
    CHECK(r.shares[0][3] < 0.95 * r.shares[0][4]);
    CHECK(r.tolerance == 32 * base);
  }
}

TEST_CASE("snap: the lags along a direction at which vertices repeat, most pairs first", "[offsets][snap]") {
  // Two runs of three copies of a random module, a pitch s apart, the second run T after the first (T no
  // multiple of s: slats in two runs split by a rail). Lags shorter than 0.5 along d and their pairs:
  // s 4 per module point, T 3, 2s, T - s and T + s 2, T - 2s and T + 2s 1.
  const Eigen::Vector3d d = Eigen::Vector3d(1, 2, -0.5).normalized();
  const double s = 0.07, T = 0.27;
  const int n = 50;
  const auto run = repeated(n, 3, s * d, 11);
  Eigen::Matrix<double, Eigen::Dynamic, 3> P(2 * run.rows(), 3);
  P.topRows(run.rows()) = run;
  P.bottomRows(run.rows()) = run.rowwise() + (T * d).transpose();
  const std::vector<Eigen::Vector3d> all = vertex_lags(P, 0.5 * d, 2e-5, 0.01, 8, 10);
  REQUIRE(all.size() == 7);
  CHECK((all[0] - s * d).norm() < 1e-12);
  CHECK((all[1] - T * d).norm() < 1e-12);
  for (const Eigen::Vector3d& lag : all) CHECK((lag - lag.dot(d) * d).norm() < 1e-12);  // along d
  // min_pairs: only the lags with at least 3 n pairs; count: at most that many; min_length: none shorter.
  const std::vector<Eigen::Vector3d> most = vertex_lags(P, 0.5 * d, 2e-5, 0.01, 3 * n, 10);
  REQUIRE(most.size() == 2);
  CHECK(vertex_lags(P, 0.5 * d, 2e-5, 0.01, 8, 1).size() == 1);
  for (const Eigen::Vector3d& lag : vertex_lags(P, 0.5 * d, 2e-5, 0.15, 8, 10)) CHECK(lag.norm() >= 0.15);
  // Points on no common line along d: no lag.
  CHECK(vertex_lags(repeated(200, 1, d, 5), d, 2e-5, 0.01, 8, 10).empty());
}
