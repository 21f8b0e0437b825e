// Snapping an offset onto the mesh's own vertices (offsets/snap.hpp).
#include <catch2/catch.hpp>

#include <random>

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
