// Tests of restitch/descriptor/{shot,fpfh,xyzn}.hpp: hand-computed SHOT and
// FPFH values from PCL's conventions (docs/descriptors.md), invariance to
// an exact translation, the edge cases (too few neighbours, a point at exactly
// R, isolated points, NaN input), argument checks, the text formats, and, when
// built with RESTITCH_PCL_ORACLE="path/to/pcl_descriptor_oracle", a comparison
// with PCL 1.13 itself.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "restitch/descriptor/fpfh.hpp"
#include "restitch/descriptor/shot.hpp"
#include "restitch/descriptor/xyzn.hpp"

using namespace restitch;

namespace {

const float nan_f = std::numeric_limits<float>::quiet_NaN();

/// A PointSet from rows {x, y, z, nx, ny, nz}.
PointSet make_points(std::initializer_list<std::array<float, 6>> rows) {
  PointSet ps;
  ps.points.resize(static_cast<Eigen::Index>(rows.size()), 3);
  ps.normals.resize(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::Index i = 0;
  for (const auto& r : rows) {
    ps.points.row(i) << r[0], r[1], r[2];
    ps.normals.row(i) << r[3], r[4], r[5];
    ++i;
  }
  return ps;
}

PointSet one_point(float x, float y, float z) { return make_points({{x, y, z, 0, 0, 1}}); }

bool row_is_nan(const DescriptorMatrix& D, Eigen::Index i) {
  for (Eigen::Index j = 0; j < D.cols(); ++j) {
    if (!std::isnan(D(i, j))) return false;
  }
  return true;
}

bool row_is_zero(const DescriptorMatrix& D, Eigen::Index i) {
  for (Eigen::Index j = 0; j < D.cols(); ++j) {
    if (D(i, j) != 0.0f) return false;
  }
  return true;
}

/// Checks that row i holds exactly `expected` (bin -> value, within tol) and 0 elsewhere.
void check_row(const DescriptorMatrix& D, Eigen::Index i, const std::vector<std::pair<int, double>>& expected,
               double tol) {
  std::vector<double> want(static_cast<std::size_t>(D.cols()), 0.0);
  for (const auto& e : expected) want[static_cast<std::size_t>(e.first)] += e.second;
  for (Eigen::Index j = 0; j < D.cols(); ++j) {
    INFO("bin " << j);
    if (want[static_cast<std::size_t>(j)] == 0.0) {
      CHECK(D(i, j) == 0.0f);
    } else {
      CHECK(D(i, j) == Approx(want[static_cast<std::size_t>(j)]).epsilon(0).margin(tol));
    }
  }
}

/// Uniform float in [0, 1) from the raw engine output (24 random bits), so the
/// numbers do not depend on the standard library's distributions.
float unit_f(std::mt19937_64& rng) { return static_cast<float>(rng() >> 40) * (1.0f / 16777216.0f); }

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("restitch_descriptor_test_" + name)).string();
}

}  // namespace

TEST_CASE("SHOT: hand-computed bins and weights of a small neighbourhood", "[descriptor][shot]") {
  // R = 1. The query (at the origin, with a normal SHOT never uses) plus four
  // neighbours whose votes follow PCL's rules (S2-S6) by hand. Distances are
  // dyadic so that d = sqrt(float d^2) is exact (near the z axis acos(z/d)
  // magnifies any rounding of d).
  //   A (0.5,0,0), n.z = 1:    sector 3 (phi = 0), inner shell (d = R/2), lower (z = 0), slot 10.
  //     own 1 + 0.5 (radial) + 0.5 (elevation) + 0.5 (azimuth) = 2.5 in volume 12;
  //     0.5 to the outer shell (14), 0.5 to the upper half (13), 0.5 to sector 4 (16).
  //   B (0,0.875,0), n.z = 0:  sector 5 (phi = pi/2), outer, lower, slot 5.
  //     own 1 + (1 - (0.875-0.75)/0.5) + 0.5 + 0.5 = 2.75 in volume 22; 0.5 to 23; 0.5 to sector 6 (26).
  //   C (0,0,0.125), n.z = 0.75: on the z axis (sector 0, no azimuth step), inner, upper, b = 8.75:
  //     slot 9 gets 0.75 + (0.5 + 2*0.125) + 0.5 (elevation at 0 deg) = 2, slot 8 gets 0.25; volume 1.
  //   E (-0.625,0,0), n.z = -1: sector 7 (phi = pi), outer, lower, slot 0.
  //     own 1 + (1 - 0.25) + 0.5 + 0.5 = 2.75 in volume 30; 0.25 to the inner shell (28), 0.5 to 31,
  //     0.5 to sector 0 (volume 2).
  const PointSet ps = make_points({{0, 0, 0, 1, 0, 0},
                                   {0.5f, 0, 0, 0, 0, 1},
                                   {0, 0.875f, 0, 1, 0, 0},
                                   {0, 0, 0.125f, 0.6614378f, 0, 0.75f},
                                   {-0.625f, 0, 0, 0, 0, -1}});
  DescriptorMatrix D;
  REQUIRE(ShotDescriptor{1.0f}.compute(ps, one_point(0, 0, 0), D, Progress()).ok());
  REQUIRE(D.rows() == 1);
  REQUIRE(D.cols() == 352);
  const std::vector<std::pair<int, double>> raw = {
      {12 * 11 + 10, 2.5}, {14 * 11 + 10, 0.5}, {13 * 11 + 10, 0.5}, {16 * 11 + 10, 0.5},  // A
      {22 * 11 + 5, 2.75}, {23 * 11 + 5, 0.5},  {26 * 11 + 5, 0.5},                        // B
      {1 * 11 + 9, 2.0},   {1 * 11 + 8, 0.25},                                             // C
      {30 * 11 + 0, 2.75}, {28 * 11 + 0, 0.25}, {31 * 11 + 0, 0.5},  {2 * 11 + 0, 0.5}};   // E
  double sum_sq = 0;
  for (const auto& e : raw) sum_sq += e.second * e.second;
  std::vector<std::pair<int, double>> expected;
  for (const auto& e : raw) expected.push_back({e.first, e.second / std::sqrt(sum_sq)});
  check_row(D, 0, expected, 2e-6);
  CHECK(D.row(0).cast<double>().norm() == Approx(1.0).margin(1e-6));

  // The query's own normal is never used; the query point need not be a support point.
  const PointSet no_self = make_points({{0.5f, 0, 0, 0, 0, 1},
                                        {0, 0.875f, 0, 1, 0, 0},
                                        {0, 0, 0.125f, 0.6614378f, 0, 0.75f},
                                        {-0.625f, 0, 0, 0, 0, -1},
                                        {0, 0, 0, 0, 1, 0}});
  DescriptorMatrix D2;
  REQUIRE(ShotDescriptor{1.0f}.compute(no_self, make_points({{0, 0, 0, 0, -1, 0}}), D2, Progress()).ok());
  for (int j = 0; j < 352; ++j) CHECK(D2(0, j) == D(0, j));
}

TEST_CASE("SHOT: the cosine interpolation wraps modulo 10 (PCL's quirk)", "[descriptor][shot]") {
  // Four neighbours on the z axis at d = 0.125 (R = 1) with n.z = 0.85: b = 9.25,
  // slot 9 gets 0.75 + 0.75 + 0.5 = 2 and the spill of 0.25 goes to slot
  // (9 + 1) mod 10 = 0 of the same volume, never to slot 10.
  const float n_y = std::sqrt(1.0f - 0.85f * 0.85f);
  const PointSet ps = make_points({{0, 0, 0, 0, 0, 1},
                                   {0, 0, 0.125f, 0, n_y, 0.85f},
                                   {0, 0, 0.125f, 0, n_y, 0.85f},
                                   {0, 0, 0.125f, 0, n_y, 0.85f},
                                   {0, 0, 0.125f, 0, n_y, 0.85f}});
  DescriptorMatrix D;
  REQUIRE(ShotDescriptor{1.0f}.compute(ps, one_point(0, 0, 0), D, Progress()).ok());
  const double norm = std::sqrt(2.0 * 2.0 + 0.25 * 0.25);
  check_row(D, 0, {{1 * 11 + 9, 2.0 / norm}, {1 * 11 + 0, 0.25 / norm}}, 2e-6);
  CHECK(D(0, 1 * 11 + 10) == 0.0f);
}

TEST_CASE("SHOT: fewer than 5 neighbours, a point at exactly R, duplicates, NaN", "[descriptor][shot]") {
  // R = 0.25, so R*R = 0.0625 is exact in float: a point at distance exactly R
  // is not a neighbour (strict <), and the query plus three points make 4 < 5.
  const ShotDescriptor shot{0.25f};
  DescriptorMatrix D;
  const PointSet at_r = make_points({{0, 0, 0, 0, 0, 1},
                                     {0.1f, 0, 0, 0, 0, 1},
                                     {0, 0.1f, 0, 0, 0, 1},
                                     {0, 0, 0.1f, 1, 0, 0},
                                     {0.25f, 0, 0, 0, 0, 1}});
  REQUIRE(shot.compute(at_r, one_point(0, 0, 0), D, Progress()).ok());
  CHECK(row_is_nan(D, 0));

  // Just inside R the fifth point counts and the row is a unit vector.
  const PointSet inside = make_points({{0, 0, 0, 0, 0, 1},
                                       {0.1f, 0, 0, 0, 0, 1},
                                       {0, 0.1f, 0, 0, 0, 1},
                                       {0, 0, 0.1f, 1, 0, 0},
                                       {0.2499f, 0, 0, 0, 0, 1}});
  REQUIRE(shot.compute(inside, one_point(0, 0, 0), D, Progress()).ok());
  CHECK_FALSE(row_is_nan(D, 0));
  CHECK(D.row(0).cast<double>().norm() == Approx(1.0).margin(1e-6));

  // Five exact duplicates of the query: enough neighbours, but all skipped
  // (d < 1e-15), so the norm is 0 and the row 0/0 = NaN, as in PCL.
  const PointSet dup =
      make_points({{0, 0, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 1}});
  REQUIRE(shot.compute(dup, one_point(0, 0, 0), D, Progress()).ok());
  CHECK(row_is_nan(D, 0));

  // A NaN query position gives a NaN row; other rows are unaffected.
  PointSet queries = make_points({{nan_f, 0, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 1}});
  REQUIRE(shot.compute(inside, queries, D, Progress()).ok());
  CHECK(row_is_nan(D, 0));
  CHECK_FALSE(row_is_nan(D, 1));

  // Empty support: every row NaN. Empty queries: 0 rows.
  REQUIRE(shot.compute(PointSet(), queries, D, Progress()).ok());
  CHECK(D.rows() == 2);
  CHECK(row_is_nan(D, 1));
  REQUIRE(shot.compute(inside, PointSet(), D, Progress()).ok());
  CHECK(D.rows() == 0);
  CHECK(D.cols() == 352);
}

namespace {
// Three points for FPFH by hand (R = 2, everything within range):
//   P0 (0,0,0) n (0,0,1);  P1 (1,0,0) n (0.6,0,0.8);  P2 (0,1,0) n (0,0,1).
// Pair features (docs/descriptors.md F2), bins (f1, f2, f3):
//   P0-P1: the source is P1 (its normal is more parallel to the line),
//          u = (0.6,0,0.8), v = (0,1,0), w = (-0.8,0,0.6): f1 = atan2(0.6, 0.8),
//          f2 = 0, f3 = -0.6 -> bins (6, 5, 2).
//   P0-P2: coplanar, equal normals: f = (0, 0, 0) -> (5, 5, 5).
//   P1-P2: source P1, dp = (-1,1,0): f1 = 0.438, f2 = -0.469, f3 = -0.424 -> (6, 2, 3).
// Each SPFH has k = 3, so each pair adds 100 / 2 = 50:
//   SPFH(P0) = f1 {6: 50, 5: 50}, f2 {5: 100},         f3 {2: 50, 5: 50}
//   SPFH(P1) = f1 {6: 100},       f2 {5: 50, 2: 50},   f3 {2: 50, 3: 50}
//   SPFH(P2) = f1 {5: 50, 6: 50}, f2 {5: 50, 2: 50},   f3 {5: 50, 3: 50}
PointSet fpfh_triangle() { return make_points({{0, 0, 0, 0, 0, 1}, {1, 0, 0, 0.6f, 0, 0.8f}, {0, 1, 0, 0, 0, 1}}); }
using Spfh = std::array<double, 33>;
Spfh spfh_p0() {
  Spfh h{};
  h[6] = 50, h[5] = 50, h[11 + 5] = 100, h[22 + 2] = 50, h[22 + 5] = 50;
  return h;
}
Spfh spfh_p1() {
  Spfh h{};
  h[6] = 100, h[11 + 5] = 50, h[11 + 2] = 50, h[22 + 2] = 50, h[22 + 3] = 50;
  return h;
}
Spfh spfh_p2() {
  Spfh h{};
  h[5] = 50, h[6] = 50, h[11 + 5] = 50, h[11 + 2] = 50, h[22 + 5] = 50, h[22 + 3] = 50;
  return h;
}
/// FPFH from SPFHs and weights 1/d^2, each block rescaled to 100.
std::vector<std::pair<int, double>> fpfh_expected(const std::vector<std::pair<Spfh, double>>& terms) {
  Spfh sum{};
  for (const auto& t : terms) {
    for (int b = 0; b < 33; ++b) sum[b] += t.first[b] / t.second;
  }
  std::vector<std::pair<int, double>> out;
  for (int block = 0; block < 3; ++block) {
    double total = 0;
    for (int b = 0; b < 11; ++b) total += sum[11 * block + b];
    for (int b = 0; b < 11; ++b) {
      if (sum[11 * block + b] != 0) out.push_back({11 * block + b, 100 * sum[11 * block + b] / total});
    }
  }
  return out;
}
}  // namespace

TEST_CASE("FPFH: hand-computed values of a three-point cloud", "[descriptor][fpfh]") {
  const PointSet ps = fpfh_triangle();
  DescriptorMatrix D;
  REQUIRE(FpfhDescriptor{2.0f}.compute(ps, ps, D, Progress()).ok());
  REQUIRE(D.rows() == 3);
  REQUIRE(D.cols() == 33);
  // FPFH(P0) = SPFH(P1)/1 + SPFH(P2)/1 (its own SPFH is not added):
  //   f1 {6: 75, 5: 25}, f2 {5: 50, 2: 50}, f3 {2: 25, 3: 50, 5: 25}.
  check_row(D, 0, {{6, 75}, {5, 25}, {16, 50}, {13, 50}, {24, 25}, {25, 50}, {27, 25}}, 1e-4);
  // FPFH(P1) = SPFH(P0)/1 + SPFH(P2)/2 (weight 1/d^2, d^2 = 2).
  check_row(D, 1, fpfh_expected({{spfh_p0(), 1.0}, {spfh_p2(), 2.0}}), 1e-4);
  check_row(D, 2, fpfh_expected({{spfh_p0(), 1.0}, {spfh_p1(), 2.0}}), 1e-4);
  CHECK(D(1, 16) == Approx(100.0 * 125 / 150).margin(1e-4));

  // A query that is not a support point: every support neighbour's SPFH,
  // weighted by 1/d^2 with d^2 = 0.25, 1.25, 1.25.
  DescriptorMatrix Q;
  REQUIRE(FpfhDescriptor{2.0f}.compute(ps, one_point(0, 0, 0.5f), Q, Progress()).ok());
  check_row(Q, 0, fpfh_expected({{spfh_p0(), 0.25}, {spfh_p1(), 1.25}, {spfh_p2(), 1.25}}), 1e-4);
  CHECK(Q(0, 6) == Approx(100.0 * 320 / 560).margin(1e-4));
}

TEST_CASE("FPFH: isolated points, duplicates, exact-R exclusion, NaN", "[descriptor][fpfh]") {
  // P3 is far from the triangle: alone within R = 2, so its row is all zero.
  PointSet ps = make_points({{0, 0, 0, 0, 0, 1}, {1, 0, 0, 0.6f, 0, 0.8f}, {0, 1, 0, 0, 0, 1}, {10, 10, 10, 0, 0, 1}});
  DescriptorMatrix D;
  REQUIRE(FpfhDescriptor{2.0f}.compute(ps, ps, D, Progress()).ok());
  CHECK(row_is_zero(D, 3));
  CHECK_FALSE(row_is_zero(D, 0));

  // A query with no support point within R at all: PCL's search finds nothing -> NaN.
  REQUIRE(FpfhDescriptor{2.0f}.compute(ps, one_point(-5, -5, -5), D, Progress()).ok());
  CHECK(row_is_nan(D, 0));
  // A NaN query -> NaN row.
  REQUIRE(FpfhDescriptor{2.0f}.compute(ps, one_point(nan_f, 0, 0), D, Progress()).ok());
  CHECK(row_is_nan(D, 0));

  // Exact duplicates: P0 and its copy only see each other. Their pair is
  // degenerate and binned at (5, 5, 5) with weight 100 / (2 - 1); FPFH(P0)
  // skips the copy (d^2 = 0) and is zero; a query at d^2 = 0.01 sees both SPFHs.
  const PointSet dup = make_points({{0, 0, 0, 0, 0, 1}, {0, 0, 0, 1, 0, 0}});
  REQUIRE(FpfhDescriptor{0.5f}.compute(dup, dup, D, Progress()).ok());
  CHECK(row_is_zero(D, 0));
  CHECK(row_is_zero(D, 1));
  REQUIRE(FpfhDescriptor{0.5f}.compute(dup, one_point(0.1f, 0, 0), D, Progress()).ok());
  check_row(D, 0, {{5, 100}, {16, 100}, {27, 100}}, 1e-4);

  // A point at exactly R (R = 0.5, R*R = 0.25 exact) is not a neighbour:
  // the two points are isolated from each other.
  const PointSet pair = make_points({{0, 0, 0, 0, 0, 1}, {0.5f, 0, 0, 1, 0, 0}});
  REQUIRE(FpfhDescriptor{0.5f}.compute(pair, pair, D, Progress()).ok());
  CHECK(row_is_zero(D, 0));
  CHECK(row_is_zero(D, 1));
  REQUIRE(FpfhDescriptor{0.5001f}.compute(pair, pair, D, Progress()).ok());
  CHECK_FALSE(row_is_zero(D, 0));

  // A NaN normal: its features are NaN and land in bin 0 (PCL's INT_MIN clamp).
  // Here the centre's normal is fine, so f3 = n_p.dp/|dp| = 0 is real (bin 5)
  // while f1 and f2 are NaN (bin 0).
  const PointSet bad_normal = make_points({{0, 0, 0, 0, 0, 1}, {0.1f, 0, 0, nan_f, nan_f, nan_f}});
  REQUIRE(FpfhDescriptor{0.5f}.compute(bad_normal, one_point(0, 0.1f, 0), D, Progress()).ok());
  // The query sees both: SPFH(P0) = pair (P0, P1) -> f1 bin 0, f2 bin 0, f3 bin 5;
  // SPFH(P1): its centre normal is NaN -> all three NaN -> bins 0, 0, 0.
  // Weights 1/d^2 with d^2 = 0.01 and 0.02 (exactly twice), so f3 splits 2:1.
  check_row(D, 0, {{0, 100}, {11, 100}, {22 + 5, 200.0 / 3}, {22, 100.0 / 3}}, 1e-4);
}

TEST_CASE("SHOT and FPFH are unchanged by an exact translation", "[descriptor]") {
  // Points on a 1/64 grid over two planes and a ridge, normals arbitrary; the
  // translation is dyadic too, so every float difference is exact and the
  // descriptors must be bit-identical.
  std::mt19937_64 rng(12345);
  const int n = 300;
  PointSet a;
  a.points.resize(n, 3);
  a.normals.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const float u = std::floor(unit_f(rng) * 64) / 64, v = std::floor(unit_f(rng) * 64) / 64;
    const int face = static_cast<int>(rng() % 3);
    if (face == 0) a.points.row(i) << u, v, 0;
    if (face == 1) a.points.row(i) << u, 0, v;
    if (face == 2) a.points.row(i) << u, v, std::floor(std::abs(u - 0.5f) * 32) / 64;
    Eigen::Vector3f nrm(unit_f(rng) - 0.5f, unit_f(rng) - 0.5f, unit_f(rng) + 0.1f);
    a.normals.row(i) = nrm.normalized().transpose();
  }
  PointSet b = a;
  const Eigen::RowVector3f t(3.5f, -2.25f, 1.0f);
  for (int i = 0; i < n; ++i) b.points.row(i) += t;

  DescriptorMatrix sa, sb, fa, fb;
  REQUIRE(ShotDescriptor{0.25f}.compute(a, a, sa, Progress()).ok());
  REQUIRE(ShotDescriptor{0.25f}.compute(b, b, sb, Progress()).ok());
  REQUIRE(FpfhDescriptor{0.25f}.compute(a, a, fa, Progress()).ok());
  REQUIRE(FpfhDescriptor{0.25f}.compute(b, b, fb, Progress()).ok());
  int finite_rows = 0;
  for (int i = 0; i < n; ++i) finite_rows += row_is_nan(sa, i) ? 0 : 1;
  CHECK(finite_rows > n / 2);  // the case is not vacuous
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 352; ++j) {
      if (std::isnan(sa(i, j))) {
        CHECK(std::isnan(sb(i, j)));
      } else {
        REQUIRE(sa(i, j) == sb(i, j));
      }
    }
    for (int j = 0; j < 33; ++j) REQUIRE(fa(i, j) == fb(i, j));
  }
  // The same input twice gives the same output, bit for bit.
  DescriptorMatrix again;
  REQUIRE(ShotDescriptor{0.25f}.compute(a, a, again, Progress()).ok());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 352; ++j) CHECK((sa(i, j) == again(i, j) || (std::isnan(sa(i, j)) && std::isnan(again(i, j)))));
  }
}

TEST_CASE("Descriptor policies reject bad arguments and honour cancellation", "[descriptor]") {
  const PointSet ps = fpfh_triangle();
  DescriptorMatrix D;
  for (float r : {0.0f, -1.0f, nan_f, std::numeric_limits<float>::infinity()}) {
    INFO("radius " << r);
    Status s = ShotDescriptor{r}.compute(ps, ps, D, Progress());
    CHECK(s.code() == StatusCode::invalid_argument);
    CHECK(s.message().find("radius") != std::string::npos);
    CHECK(FpfhDescriptor{r}.compute(ps, ps, D, Progress()).code() == StatusCode::invalid_argument);
  }
  PointSet bad = ps;
  bad.normals.resize(2, 3);
  Status s = ShotDescriptor{}.compute(bad, ps, D, Progress());
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(s.message().find("3 points but 2 normals") != std::string::npos);
  CHECK(ShotDescriptor{}.compute(ps, bad, D, Progress()).code() == StatusCode::invalid_argument);
  CHECK(FpfhDescriptor{}.compute(bad, ps, D, Progress()).code() == StatusCode::invalid_argument);
  CHECK(FpfhDescriptor{}.compute(ps, bad, D, Progress()).code() == StatusCode::invalid_argument);

  // A callback that says stop: the call returns cancelled.
  int calls = 0;
  const Progress stop([&](std::string_view stage, double) {
    ++calls;
    return stage != "descriptors";
  });
  CHECK(ShotDescriptor{2.0f}.compute(ps, ps, D, stop).code() == StatusCode::cancelled);
  CHECK(FpfhDescriptor{2.0f}.compute(ps, ps, D, stop).code() == StatusCode::cancelled);
  CHECK(calls == 2);
  CHECK(ShotDescriptor{2.0f}.compute(ps, ps, D, Progress()).ok());

  static_assert(ShotDescriptor{}.radius == 0.2f && FpfhDescriptor{}.radius == 0.2f, "default radius 0.2");
  CHECK(ShotDescriptor{}.dimension() == 352);
  CHECK(FpfhDescriptor{}.dimension() == 33);
}

TEST_CASE("xyzn reading and CSV writing", "[descriptor][io]") {
  const std::string in = temp_path("read.xyzn");
  {
    std::FILE* f = std::fopen(in.c_str(), "wb");
    REQUIRE(f);
    std::fputs("# x y z nx ny nz\n\n1 2 3 0 0 1\r\n  -0.5\t1e-3 2.5e2 0.6 0 -0.8\n   \n# end\nnan 0 0 0 1 0", f);
    std::fclose(f);
  }
  Result<PointSet> r = read_xyzn(in);
  REQUIRE(r.ok());
  REQUIRE(r->size() == 3);
  CHECK(r->points(0, 2) == 3.0f);
  CHECK(r->normals(0, 2) == 1.0f);
  CHECK(r->points(1, 0) == -0.5f);
  CHECK(r->points(1, 1) == 1e-3f);
  CHECK(r->points(1, 2) == 250.0f);
  CHECK(r->normals(1, 2) == -0.8f);
  CHECK(std::isnan(r->points(2, 0)));
  CHECK(r->normals(2, 1) == 1.0f);

  // Malformed lines name the line number.
  const char* bad_files[] = {"1 2 3 4 5 6\n# c\n1 2 3 4 5\n", "1 2 3 4 5 6\n\n1 2 3 4 5 6 7\n",
                             "1 2 3 4 5 6\n1 2 3 4 5 6\n1 2 x 4 5 6\n", "1 2 3 4 5 6\n1 2 3\n1,2,3,4,5,6\n"};
  const char* line_tags[] = {":3:", ":3:", ":3:", ":2:"};
  for (int k = 0; k < 4; ++k) {
    std::FILE* f = std::fopen(in.c_str(), "wb");
    REQUIRE(f);
    std::fputs(bad_files[k], f);
    std::fclose(f);
    Result<PointSet> b = read_xyzn(in);
    INFO(bad_files[k]);
    REQUIRE_FALSE(b.ok());
    CHECK(b.status().code() == StatusCode::parse_error);
    CHECK(b.status().message().find(line_tags[k]) != std::string::npos);
  }
  std::remove(in.c_str());
  CHECK(read_xyzn(temp_path("does_not_exist.xyzn")).status().code() == StatusCode::io_error);

  // CSV round trip: every float comes back bit for bit, NaN as "nan".
  DescriptorMatrix M(3, 4);
  M << 0.1f, -1.0f / 3.0f, 1e-30f, 123456.789f, nan_f, 0.0f, 3.4e38f, -7.0f, 1.0f, 2.0f, 3.0f, 1.17549435e-38f;
  const std::string out = temp_path("out.csv");
  REQUIRE(write_descriptor_csv(out, M).ok());
  CHECK_FALSE(std::filesystem::exists(out + ".tmp"));
  std::FILE* f = std::fopen(out.c_str(), "rb");
  REQUIRE(f);
  std::string text;
  for (int c; (c = std::fgetc(f)) != EOF;) text.push_back(static_cast<char>(c));
  std::fclose(f);
  CHECK(text.find("nan,0,") != std::string::npos);
  std::vector<float> values;
  int lines = 0;
  for (const char* s = text.c_str(); *s;) {
    char* end = nullptr;
    values.push_back(std::strtof(s, &end));
    REQUIRE(end != s);
    if (*end == '\n') ++lines;
    s = (*end == ',' || *end == '\n') ? end + 1 : end;
  }
  CHECK(lines == 3);
  REQUIRE(values.size() == 12);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      const float v = values[static_cast<std::size_t>(4 * i + j)];
      CHECK((v == M(i, j) || (std::isnan(v) && std::isnan(M(i, j)))));
    }
  }
  std::remove(out.c_str());

  // An unwritable destination: io_error, and nothing left behind.
  const std::string nowhere = temp_path("no_such_dir/out.csv");
  CHECK(write_descriptor_csv(nowhere, M).code() == StatusCode::io_error);
  CHECK_FALSE(std::filesystem::exists(nowhere));
}

#ifdef RESTITCH_PCL_ORACLE
namespace {

/// A few hundred points on a box, a floor plane and a tilted plane, with
/// jittered normals, plus isolated points (NaN SHOT rows, zero FPFH rows).
PointSet oracle_cloud(std::uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  PointSet ps;
  ps.points.resize(n, 3);
  ps.normals.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    const float a = unit_f(rng) - 0.5f, b = unit_f(rng) - 0.5f;
    const int face = static_cast<int>(rng() % 8);
    Eigen::Vector3f p, nrm;
    if (face < 6) {  // box [-0.5, 0.5]^3
      const int ax = face / 2;
      const float s = (face % 2) ? 1.0f : -1.0f;
      p.setZero();
      nrm.setZero();
      p[ax] = 0.5f * s;
      p[(ax + 1) % 3] = a;
      p[(ax + 2) % 3] = b;
      nrm[ax] = s;
    } else if (face == 6) {  // floor
      p = Eigen::Vector3f(2 * a, 2 * b, -0.6f);
      nrm = Eigen::Vector3f(0, 0, 1);
    } else {  // tilted plane
      p = Eigen::Vector3f(1.2f + 0.5f * a, b, 0.3f * a);
      nrm = Eigen::Vector3f(-0.3f, 0, 1);
    }
    nrm += 0.1f * Eigen::Vector3f(unit_f(rng) - 0.5f, unit_f(rng) - 0.5f, unit_f(rng) - 0.5f);
    ps.points.row(i) = p.transpose();
    ps.normals.row(i) = nrm.normalized().transpose();
  }
  for (int i = 0; i < 3; ++i) ps.points.row(n - 1 - i) << 5.0f + i, 5.0f, 5.0f;  // isolated
  return ps;
}

void write_xyzn(const std::string& path, const PointSet& ps) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  REQUIRE(f);
  for (Eigen::Index i = 0; i < ps.size(); ++i) {
    std::fprintf(f, "%.9g %.9g %.9g %.9g %.9g %.9g\n", ps.points(i, 0), ps.points(i, 1), ps.points(i, 2),
                 ps.normals(i, 0), ps.normals(i, 1), ps.normals(i, 2));
  }
  std::fclose(f);
}

DescriptorMatrix read_csv(const std::string& path, int cols) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  REQUIRE(f);
  std::vector<float> v;
  std::string tok;
  for (int c; (c = std::fgetc(f)) != EOF;) {
    if (c == ',' || c == '\n') {
      v.push_back(std::strtof(tok.c_str(), nullptr));
      tok.clear();
    } else {
      tok.push_back(static_cast<char>(c));
    }
  }
  std::fclose(f);
  REQUIRE(v.size() % static_cast<std::size_t>(cols) == 0);
  DescriptorMatrix D(static_cast<Eigen::Index>(v.size()) / cols, cols);
  for (Eigen::Index i = 0; i < D.rows(); ++i) {
    for (int j = 0; j < cols; ++j) D(i, j) = v[static_cast<std::size_t>(i * cols + j)];
  }
  return D;
}

/// Largest |ours - pcl| over rows that are finite in both; NaN rows must match.
double compare(const DescriptorMatrix& ours, const DescriptorMatrix& pcl, int* nan_rows) {
  REQUIRE(ours.rows() == pcl.rows());
  REQUIRE(ours.cols() == pcl.cols());
  double worst = 0;
  *nan_rows = 0;
  for (Eigen::Index i = 0; i < ours.rows(); ++i) {
    const bool a = row_is_nan(ours, i), b = row_is_nan(pcl, i);
    INFO("row " << i);
    REQUIRE(a == b);
    if (a) {
      ++*nan_rows;
      continue;
    }
    for (Eigen::Index j = 0; j < ours.cols(); ++j) {
      worst = std::max(worst, std::abs(static_cast<double>(ours(i, j)) - static_cast<double>(pcl(i, j))));
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("SHOT and FPFH equal PCL 1.13's on a seeded cloud", "[descriptor][pcl]") {
  const PointSet support = oracle_cloud(2024, 600);
  const PointSet queries = oracle_cloud(77, 120);
  const std::string sup_path = temp_path("oracle_support.xyzn"), q_path = temp_path("oracle_queries.xyzn"),
                    csv = temp_path("oracle.csv");
  write_xyzn(sup_path, support);
  write_xyzn(q_path, queries);
  // Reading the file back gives exactly the floats PCL reads.
  Result<PointSet> sup = read_xyzn(sup_path);
  Result<PointSet> qry = read_xyzn(q_path);
  REQUIRE(sup.ok());
  REQUIRE(qry.ok());

  struct Case {
    const char* kind;
    float radius;
    bool separate_queries;
    double tol;
  };
  for (const Case& c : {Case{"shot", 0.3f, false, 1e-5}, Case{"shot", 0.3f, true, 1e-5},
                        Case{"fpfh", 0.25f, false, 1e-3}, Case{"fpfh", 0.25f, true, 1e-3}}) {
    char radius[32];
    std::snprintf(radius, sizeof radius, "%.9g", static_cast<double>(c.radius));
    std::string cmd = std::string("\"") + RESTITCH_PCL_ORACLE + "\" " + c.kind + " " + radius + " \"" + sup_path +
                      "\" \"" + csv + "\"";
    if (c.separate_queries) cmd += " \"" + q_path + "\"";
    INFO(cmd);
    REQUIRE(std::system(cmd.c_str()) == 0);
    const PointSet& q = c.separate_queries ? *qry : *sup;
    DescriptorMatrix ours;
    Status s = std::string(c.kind) == "shot" ? ShotDescriptor{c.radius}.compute(*sup, q, ours, Progress())
                                             : FpfhDescriptor{c.radius}.compute(*sup, q, ours, Progress());
    REQUIRE(s.ok());
    int nan_rows = 0;
    const double worst = compare(ours, read_csv(csv, std::string(c.kind) == "shot" ? 352 : 33), &nan_rows);
    WARN(c.kind << (c.separate_queries ? " (separate queries)" : "") << ": max |ours - PCL| = " << worst << " over "
                << ours.rows() << " rows, " << nan_rows << " NaN rows");
    CHECK(worst <= c.tol);
    if (std::string(c.kind) == "shot") CHECK(nan_rows >= 3);  // the isolated points
  }
  std::remove(sup_path.c_str());
  std::remove(q_path.c_str());
  std::remove(csv.c_str());
}
#else
TEST_CASE("SHOT and FPFH equal PCL 1.13's on a seeded cloud", "[descriptor][pcl]") {
  WARN("PCL oracle not built; install libpcl-dev to compare");
}
#endif
