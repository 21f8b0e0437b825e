// Tests for offsets/histogram.hpp, offsets/refine.hpp, offsets/principal.hpp,
// offsets/detector.hpp and lattice/fit.hpp on synthetic data with known answers.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "restitch/lattice/fit.hpp"
#include "restitch/offsets/detector.hpp"
#include "restitch/offsets/histogram.hpp"
#include "restitch/offsets/principal.hpp"
#include "restitch/offsets/refine.hpp"

#include "support/mesh_builders.hpp"
#include "support/sampled_shapes.hpp"

using namespace restitch;
using Eigen::Vector3d;
using Eigen::Vector3i;
using namespace restitch::test;

namespace {

constexpr double kPi = 3.14159265358979323846;

void repeat(std::vector<Vector3d>& v, const Vector3d& x, int n) {
  for (int i = 0; i < n; ++i) v.push_back(x);
}

}  // namespace

TEST_CASE("histogram bins offsets by floor(v / size) and ranks bins", "[offsets][histogram]") {
  std::vector<Vector3d> v;
  repeat(v, Vector3d(0.31, 0.02, 0.01), 7);   // bin (6, 0, 0)
  repeat(v, Vector3d(0.349, 0.049, 0.0), 3);  // also bin (6, 0, 0)
  repeat(v, Vector3d(-0.01, -0.3, 0.2), 4);   // bin (-1, -6, 4)
  repeat(v, Vector3d(0.0, 0.0, -0.051), 4);   // bin (0, 0, -2): ties with the one above
  OffsetHistogram h;
  REQUIRE(build_offset_histogram(v, 0.05, h).ok());
  REQUIRE(h.offsets == 18);
  REQUIRE(h.bins.size() == 3);
  CHECK(h.bins[0].index == Vector3i(6, 0, 0));
  CHECK(h.bins[0].votes == 10);
  CHECK(h.bins[1].index == Vector3i(-1, -6, 4));  // tie on votes: lexicographically smaller index first
  CHECK(h.bins[2].index == Vector3i(0, 0, -2));
  CHECK(h.bins[1].votes == 4);
  CHECK(h.center(Vector3i(6, 0, 0)).isApprox(Vector3d(0.325, 0.025, 0.025)));

  std::vector<Vector3d> bad = v;
  bad.push_back(Vector3d(NAN, 0, 0));
  CHECK(build_offset_histogram(bad, 0.05, h).code() == StatusCode::invalid_argument);
  CHECK(build_offset_histogram(v, 0.0, h).code() == StatusCode::invalid_argument);
}

TEST_CASE("non-maximum suppression: radius, ties, split peaks, ranking by mass", "[offsets][histogram]") {
  SECTION("a bin exactly one radius away is suppressed, one just beyond is not") {
    std::vector<Vector3d> v;
    repeat(v, Vector3d(0.51, 0.01, 0.01), 9);  // bin (10, 0, 0)
    repeat(v, Vector3d(0.66, 0.01, 0.01), 5);  // bin (13, 0, 0): centre distance 0.15 -> suppressed
    repeat(v, Vector3d(0.66, 0.06, 0.01), 6);  // bin (13, 1, 0): distance sqrt(10)*0.05 > 0.15 -> a peak
    OffsetHistogram h;
    REQUIRE(build_offset_histogram(v, 0.05, h).ok());
    const auto peaks = find_peaks(h, 0.15);
    REQUIRE(peaks.size() == 2);
    CHECK(peaks[0].index == Vector3i(13, 1, 0));  // ranked first by mass: 6 + its neighbour's 5
    CHECK(peaks[0].votes == 6);
    CHECK(peaks[0].mass == 11);
    CHECK(peaks[1].index == Vector3i(10, 0, 0));
    CHECK(peaks[1].mass == 9);
    CHECK(find_peaks(h, 0.0).size() == 3);  // radius 0: every bin is a peak
  }
  SECTION("a peak split across a bin border is one peak with all its votes; ranking uses the mass") {
    std::vector<Vector3d> v;
    repeat(v, Vector3d(0.2499, 0.41, 0.01), 10);  // bin (4, 8, 0)
    repeat(v, Vector3d(0.2501, 0.41, 0.01), 10);  // bin (5, 8, 0): tied with its neighbour
    repeat(v, Vector3d(-0.41, 0.01, 0.01), 15);   // bin (-9, 0, 0): more votes in one bin, less mass
    OffsetHistogram h;
    REQUIRE(build_offset_histogram(v, 0.05, h).ok());
    const auto peaks = find_peaks(h, 0.15);
    REQUIRE(peaks.size() == 2);
    CHECK(peaks[0].index == Vector3i(4, 8, 0));  // the tie goes to the smaller index
    CHECK(peaks[0].votes == 10);
    CHECK(peaks[0].mass == 20);
    CHECK(peaks[0].center.isApprox(Vector3d(0.225, 0.425, 0.025)));
    CHECK(peaks[1].index == Vector3i(-9, 0, 0));
    CHECK(peaks[1].mass == 15);
  }
  SECTION("equal peaks far apart rank by bin index") {
    std::vector<Vector3d> v;
    repeat(v, Vector3d(0.5, 0.01, 0.01), 6);
    repeat(v, Vector3d(-0.5, 0.01, 0.01), 6);
    repeat(v, Vector3d(0.01, 0.71, 0.01), 6);
    OffsetHistogram h;
    REQUIRE(build_offset_histogram(v, 0.05, h).ok());
    const auto peaks = find_peaks(h, 0.15);
    REQUIRE(peaks.size() == 3);
    CHECK(peaks[0].index == Vector3i(-10, 0, 0));
    CHECK(peaks[1].index == Vector3i(0, 14, 0));
    CHECK(peaks[2].index == Vector3i(10, 0, 0));
  }
}

TEST_CASE("sparsity: share of offsets in the top 7% and 20% of bins", "[offsets][histogram]") {
  // 15 non-empty bins: 30, 20, 10 votes and twelve bins of 1 vote: 72 offsets.
  // top 7%: ceil(1.05) = 2 bins -> 50/72; top 20%: 3 bins -> 60/72.
  std::vector<Vector3d> v;
  repeat(v, Vector3d(0.3, 0.01, 0.01), 30);
  repeat(v, Vector3d(0.01, 0.3, 0.01), 20);
  repeat(v, Vector3d(0.01, 0.01, 0.3), 10);
  for (int i = 0; i < 12; ++i) v.push_back(Vector3d(-1.0 + 0.1 * i, -0.5, 0.01));
  OffsetHistogram h;
  REQUIRE(build_offset_histogram(v, 0.05, h).ok());
  const Sparsity s = offset_sparsity(h);
  CHECK(s.bins == 15);
  CHECK(s.offsets == 72);
  CHECK(s.top7 == Approx(50.0 / 72.0));
  CHECK(s.top20 == Approx(60.0 / 72.0));
  // 100 bins of one vote each: exactly 7 and 20 bins.
  std::vector<Vector3d> u;
  for (int i = 0; i < 100; ++i) u.push_back(Vector3d(0.1 * i + 0.01, 0.01, 0.01));
  REQUIRE(build_offset_histogram(u, 0.05, h).ok());
  CHECK(offset_sparsity(h).top7 == Approx(0.07));
  CHECK(offset_sparsity(h).top20 == Approx(0.20));
  REQUIRE(build_offset_histogram({}, 0.05, h).ok());
  CHECK(offset_sparsity(h).top7 == 0);
}

TEST_CASE("translation-only ICP converges to the lattice period from half a bin off", "[offsets][refine]") {
  const PointSet cloud = lattice_cloud(7);
  const SelfAligner aligner(cloud);
  struct Case {
    Vector3d truth, start;
  };
  const Case cases[] = {
      {kT1, kT1 + Vector3d(0.025, -0.02, 0.02)},
      {kT2, kT2 + Vector3d(-0.022, 0.025, -0.015)},
      {kT1 + kT2, kT1 + kT2 + Vector3d(0.02, 0.02, 0.025)},
  };
  for (const Case& c : cases) {
    const RefinedOffset r = aligner.refine(c.start);
    INFO("truth " << c.truth.transpose() << " got " << r.offset.transpose());
    CHECK((r.offset - c.truth).norm() < 1e-3);
    CHECK(r.converged);
    CHECK(r.overlap > 0.4);
  }
  // Overlap of the period along t1: 3 of 4 columns land on the cloud (about 0.75); nothing at a wrong offset.
  CHECK(aligner.overlap(kT1) == Approx(0.75).margin(0.06));
  CHECK(aligner.overlap(Vector3d(0.5 * kT1.x(), 0.0, 0.4)) < 0.05);
  // Deterministic.
  const RefinedOffset a = aligner.refine(cases[0].start), b = aligner.refine(cases[0].start);
  CHECK(a.offset == b.offset);
}

TEST_CASE("principal offsets: greedy 60-degree selection, sign convention, dummies", "[offsets][principal]") {
  const double s3 = std::sqrt(3.0);
  SECTION("exactly 60 degrees passes, parallel and antiparallel offsets are skipped") {
    const std::vector<Vector3d> dom = {Vector3d(-0.4, 0, 0),       Vector3d(0.8, 0.01, 0), Vector3d(0.4, 0, 0),
                                       Vector3d(0.2, 0.2 * s3, 0), Vector3d(0, 0.1, 0.0),  Vector3d(0.1, 0.1, -0.3)};
    const PrincipalOffsets p = select_principal_offsets(dom);
    REQUIRE(p.real_count == 3);
    CHECK(p.axes[0] == Vector3d(0.4, 0, 0));  // flipped: largest component positive
    CHECK(p.axes[1] == Vector3d(0.2, 0.2 * s3, 0));
    CHECK(p.axes[2] == Vector3d(-0.1, -0.1, 0.3));  // (0, 0.1, 0) is 30 degrees from v2; then the last, flipped
    CHECK(p.source == std::array<int, 3>{{0, 3, 5}});
    CHECK(p.dummy == std::array<bool, 3>{{false, false, false}});
  }
  SECTION("59.9 degrees fails") {
    const double a = 59.9 * kPi / 180;
    const std::vector<Vector3d> dom = {Vector3d(1, 0, 0), Vector3d(std::cos(a), std::sin(a), 0)};
    const PrincipalOffsets p = select_principal_offsets(dom);
    CHECK(p.real_count == 1);
    const double b = 60.0 * kPi / 180;
    CHECK(select_principal_offsets({Vector3d(1, 0, 0), Vector3d(std::cos(b), std::sin(b), 0)}).real_count == 2);
    CHECK(far_enough_apart(Vector3d(1, 0, 0), Vector3d(-0.5, s3 / 2, 0), kPi / 3));  // 120 degrees
  }
  SECTION("two real offsets: the dummy is their normalized cross product, length 0.2") {
    const PrincipalOffsets p = select_principal_offsets({Vector3d(0.3, 0, 0), Vector3d(0.1, 0.25, 0)});
    REQUIRE(p.real_count == 2);
    CHECK(p.dummy == std::array<bool, 3>{{false, false, true}});
    CHECK(p.axes[2].isApprox(Vector3d(0, 0, 0.2)));
  }
  SECTION("one real offset along an axis: the dummies are the other world axes") {
    const PrincipalOffsets p = select_principal_offsets({Vector3d(0, -0.5, 0)});
    REQUIRE(p.real_count == 1);
    CHECK(p.axes[0] == Vector3d(0, 0.5, 0));
    CHECK(p.axes[1].isApprox(Vector3d(0.2, 0, 0)));
    CHECK(p.axes[2].isApprox(Vector3d(0, 0, 0.2)));
  }
  SECTION("one real offset in a general direction: orthonormal dummies of length 0.2") {
    const Vector3d v(0.3, -0.1, 0.2);
    const PrincipalOffsets p = select_principal_offsets({v});
    REQUIRE(p.real_count == 1);
    CHECK(p.dummy == std::array<bool, 3>{{false, true, true}});
    for (int a = 1; a < 3; ++a) {
      CHECK(p.axes[std::size_t(a)].norm() == Approx(0.2));
      CHECK(std::abs(p.axes[std::size_t(a)].dot(v)) < 1e-12);
    }
    CHECK(std::abs(p.axes[1].dot(p.axes[2])) < 1e-12);
    // d1 is the y axis (x is the most aligned with v) made orthogonal to v: in the plane of y and v.
    CHECK(std::abs(p.axes[1].dot(Vector3d::UnitY().cross(v))) < 1e-12);
    CHECK(p.axes[1].y() > 0);
  }
  SECTION("no real offset (none given, or only zero/non-finite ones): the three world axes") {
    for (const auto& dom : {std::vector<Vector3d>{}, std::vector<Vector3d>{Vector3d::Zero(), Vector3d(NAN, 1, 0)}}) {
      const PrincipalOffsets p = select_principal_offsets(dom);
      CHECK(p.real_count == 0);
      CHECK(p.dummy == std::array<bool, 3>{{true, true, true}});
      for (int a = 0; a < 3; ++a) CHECK(p.axes[std::size_t(a)] == 0.2 * Vector3d::Unit(a));
    }
  }
  CHECK(canonical_sign(Vector3d(-0.1, -0.5, 0.2)) == Vector3d(0.1, 0.5, -0.2));
  CHECK(canonical_sign(Vector3d(-0.3, 0.3, 0)) == Vector3d(0.3, -0.3, 0));  // equal magnitudes: x decides
}

TEST_CASE("lattice vectors: independent offsets and integer combinations", "[offsets][principal]") {
  const Vector3d x(0.3, 0, 0), y(0.05, 0.4, 0), z(0, 0.01, 0.25);
  SECTION("independent_offsets keeps the first of each new direction, in order, at most three") {
    const std::vector<Vector3d> b =
        independent_offsets({2 * x, x, Vector3d::Zero(), x + y, y, 2 * x - y + Vector3d(0, 0, 0.005), z, x + z}, 0.01);
    REQUIRE(b.size() == 3);
    CHECK(b[0] == 2 * x);
    CHECK(b[1] == x + y);
    CHECK(b[2] == z);  // 2x - y + 0.005 z lies within 0.01 of the plane of x and y
    CHECK(independent_offsets({x, Vector3d(NAN, 0, 0), -x}, 0.01).size() == 1);
  }
  SECTION("is_lattice_vector: non-zero integer combinations within the tolerance, multiples of `other`") {
    const std::vector<Vector3d> basis = {x, y};
    CHECK(is_lattice_vector(2 * x - 3 * y + Vector3d(0.009, 0, 0), basis, nullptr, 0.01));
    CHECK_FALSE(is_lattice_vector(2 * x - 3 * y + Vector3d(0.011, 0, 0), basis, nullptr, 0.01));
    CHECK_FALSE(is_lattice_vector(1.5 * x, basis, nullptr, 0.01));
    CHECK_FALSE(is_lattice_vector(Vector3d(0.001, 0, 0), basis, nullptr, 0.01));  // zero is no lattice vector
    CHECK_FALSE(is_lattice_vector(z, basis, nullptr, 0.01));
    CHECK(is_lattice_vector(-3 * z, {}, &z, 0.01));
    CHECK_FALSE(is_lattice_vector(0.5 * z, {}, &z, 0.01));
  }
}

TEST_CASE("histogram detector: a lattice is significant, sliding on a plate is not", "[offsets][detector]") {
  SECTION("matches along the lattice periods") {
    const PointSet cloud = lattice_cloud(11);
    // Features = the cloud; each feature is matched to the point nearest to x + t1 (or + t2 on every third).
    std::vector<Match> matches(std::size_t(cloud.size()));
    for (Eigen::Index i = 0; i < cloud.size(); ++i) {
      const Vector3d t = i % 3 == 0 ? kT2 : kT1;
      const Vector3d q = cloud.points.row(i).cast<double>().transpose() + t;
      double best = 0.03;
      for (Eigen::Index j = 0; j < cloud.size(); ++j) {
        const double d = (cloud.points.row(j).cast<double>().transpose() - q).norm();
        if (d < best) best = d, matches[std::size_t(i)].target = std::int32_t(j);
      }
    }
    OffsetDetection det;
    const HistogramOffsetDetector detector;
    REQUIRE(detector.detect({cloud, cloud, matches, 0.02, 0.15}, det, {}).ok());
    REQUIRE(det.dominant.size() >= 2);
    CHECK(det.dominant[0].significant);
    CHECK((det.dominant[0].offset - kT1).norm() < 1e-3);
    CHECK(det.dominant[1].significant);
    CHECK((det.dominant[1].offset - kT2).norm() < 1e-3);
    CHECK(det.dominant[0].contrast >= 0.05);
    CHECK(det.timings_ms.count("histogram") == 1);
    CHECK(det.timings_ms.count("refinement") == 1);
    CHECK(det.sparsity.top7 > 0.2);
    CHECK(det.sparsity.top7 <= det.sparsity.top20);
    CHECK(det.sparsity.offsets > 4000);
    // Cancellation is honoured.
    const Progress cancel([](std::string_view, double) { return false; });
    CHECK(detector.detect({cloud, cloud, matches, 0.02, 0.15}, det, cancel).code() == StatusCode::cancelled);
    // Inconsistent evidence.
    std::vector<Match> few(3);
    CHECK(detector.detect({cloud, cloud, few, 0.02, 0.15}, det, {}).code() == StatusCode::invalid_argument);
  }
  SECTION("a plain plate: every feature matched 0.2 along the plate gives a strong peak, but no repetition") {
    std::mt19937_64 rng(5);
    std::vector<Vector3d> P, N;
    sample_box(P, N, Vector3d(-0.5, -0.35, -0.02), Vector3d(0.5, 0.35, 0.02), 0.02, rng);
    const PointSet cloud = to_point_set(P, N);
    std::vector<Match> matches(std::size_t(cloud.size()));
    const Vector3d t(0.2, 0.0, 0.0);
    for (Eigen::Index i = 0; i < cloud.size(); ++i) {
      const Vector3d q = cloud.points.row(i).cast<double>().transpose() + t;
      double best = 0.03;
      for (Eigen::Index j = 0; j < cloud.size(); ++j) {
        const double d = (cloud.points.row(j).cast<double>().transpose() - q).norm();
        if (d < best && cloud.normals.row(j).dot(cloud.normals.row(i)) > 0.5)
          best = d, matches[std::size_t(i)].target = std::int32_t(j);
      }
    }
    OffsetDetection det;
    REQUIRE(HistogramOffsetDetector{}.detect({cloud, cloud, matches, 0.02, 0.15}, det, {}).ok());
    REQUIRE(!det.dominant.empty());
    CHECK(det.dominant[0].overlap > 0.5);    // the plate overlaps itself a lot...
    CHECK(det.dominant[0].contrast < 0.01);  // ...but linearly in the slide: no kink at t, not a repeat
    for (const DominantOffset& d : det.dominant) CHECK_FALSE(d.significant);
  }
}

TEST_CASE("lattice fit: cell planes fall in the gaps between modules; cell count; slivers", "[lattice][fit]") {
  // Five boxes 0.6 wide at pitch 1 along x (gaps 0.4), model units; optional thin end plate past the last gap.
  for (bool end_plate : {false, true}) {
    Mesh mesh;
    std::mt19937_64 rng(3);
    std::vector<Vector3d> P, N;
    for (int i = 0; i < 5; ++i) add_box(mesh, Vector3d(i, 0, 0), Vector3d(i + 0.6, 0.5, 0.5));
    if (end_plate) add_box(mesh, Vector3d(4.85, 0, 0), Vector3d(4.9, 0.5, 0.5));
    REQUIRE(validate(mesh).ok());
    const Normalization norm = Normalization::of(bounding_box(mesh));
    for (int i = 0; i < 5; ++i) sample_box(P, N, Vector3d(i, 0, 0), Vector3d(i + 0.6, 0.5, 0.5), 0.01, rng);
    if (end_plate) sample_box(P, N, Vector3d(4.85, 0, 0), Vector3d(4.9, 0.5, 0.5), 0.01, rng);
    for (Vector3d& p : P) p = norm.to_normalized(p);
    const PointSet dense = to_point_set(P, N);
    const PrincipalOffsets axes = select_principal_offsets({norm.to_normalized_offset(Vector3d(1, 0, 0))});
    const Result<LatticeFit> fit = fit_lattice(mesh, norm, dense, axes);
    REQUIRE(fit.ok());
    const Lattice& L = fit->lattice;
    INFO("end plate " << end_plate << " origin " << L.origin.transpose() << " cells " << L.cells.transpose());
    CHECK(L.A.col(0).isApprox(Vector3d(1, 0, 0)));
    CHECK(L.dummy == std::array<bool, 3>{{false, true, true}});
    CHECK(L.cells[0] == 5);
    // Every cell plane along x lies inside a gap (0.6, 1) mod 1, clear of the boxes.
    const double frac = L.origin.x() - std::floor(L.origin.x());
    CHECK(frac > 0.62);
    CHECK(frac < 0.98);
    if (!end_plate) CHECK(frac == Approx(0.8).margin(0.03));  // the middle of the gap
    // Every vertex is in the grid or in an overhang of less than half a cell (the sliver rule).
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
      const Vector3d c = L.to_canonical(mesh.V.row(v).cast<double>().transpose());
      for (int a = 0; a < 3; ++a) {
        CHECK(c[a] > -0.5);
        CHECK(c[a] < L.cells[a] + 0.5);
      }
    }
    // Canonical coordinates use model units: box 2's centre lies in cell 2.
    CHECK(int(std::floor(L.to_canonical(Vector3d(2.3, 0.25, 0.25)).x())) == 2);
  }
}

TEST_CASE("lattice fit: sheared axes, phase tie rule, bad axes", "[lattice][fit]") {
  CHECK(detail::choose_phase({3, 0, 0, 0, 2, 0, 0, 1}) == 2);  // widest run 1..3, centre 2
  CHECK(detail::choose_phase({0, 0, 5, 0, 0, 5, 5, 0}) == 0);  // runs {7,0,1} (wraps) and {3,4}: centre of 7,0,1 is 0
  CHECK(detail::choose_phase({4, 4, 4, 4}) == 0);              // all equal
  CHECK(detail::choose_phase({1, 0, 0, 1, 0, 0, 1, 1}) == 1);  // equal widths: the first start, lower centre

  Mesh mesh;
  add_box(mesh, Vector3d(0, 0, 0), Vector3d(1, 1, 1));
  const Normalization norm = Normalization::of(bounding_box(mesh));
  PrincipalOffsets bad;
  bad.axes = {{Vector3d(0.3, 0, 0), Vector3d(0.6, 0, 0), Vector3d(0, 0, 0.2)}};
  CHECK(fit_lattice(mesh, norm, PointSet{}, bad).status().code() == StatusCode::invalid_argument);

  // A sheared 2-D lattice: canonical coordinates of a vertex round-trip, cells cover the vertices.
  PrincipalOffsets sheared = select_principal_offsets({Vector3d(0.5, 0, 0), Vector3d(0.25, 0.5, 0)});
  const Result<LatticeFit> fit = fit_lattice(mesh, norm, PointSet{}, sheared);
  REQUIRE(fit.ok());
  const Lattice& L = fit->lattice;
  CHECK(L.A.col(1).isApprox(Vector3d(0.25, 0.5, 0) / norm.scale));
  const Vector3d p(1, 1, 1);
  CHECK(L.to_model(L.to_canonical(p)).isApprox(p));
  CHECK(fit->phase.isApprox(Eigen::Array3d::Zero()));  // no samples: every phase costs 0 -> phase 0
}

TEST_CASE("lattice fit: the phases at local minima of the cut cost; a phase forced; one axis refitted alone",
          "[lattice][fit]") {
  // Runs of equal cost with both neighbours dearer, each at its centre (the lower one for an even length),
  // cheapest first, ties by index; a run wrapping around counts once; a flat cost has none.
  CHECK(detail::phase_minima({3, 0, 0, 0, 2, 1, 2, 1}) == std::vector<int>{2, 5, 7});
  CHECK(detail::phase_minima({0, 5, 5, 0, 4, 0}) == std::vector<int>{3, 5});  // {5, 0} wraps: centre 5
  CHECK(detail::phase_minima({2, 2, 2}).empty());
  CHECK(detail::phase_minima({1, 2, 1, 2}) == std::vector<int>{0, 2});

  // Five boxes at pitch 1 along x and three at pitch 1 along y: forcing x's phase moves x's planes only, and
  // refitting x alone from the cheapest fit gives the same lattice as a whole fit with that phase.
  Mesh mesh;
  std::mt19937_64 rng(5);
  std::vector<Vector3d> P, N;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 3; ++j) {
      add_box(mesh, Vector3d(i, j, 0), Vector3d(i + 0.6, j + 0.5, 0.5));
      sample_box(P, N, Vector3d(i, j, 0), Vector3d(i + 0.6, j + 0.5, 0.5), 0.01, rng);
    }
  const Normalization norm = Normalization::of(bounding_box(mesh));
  for (Vector3d& p : P) p = norm.to_normalized(p);
  const PointSet dense = to_point_set(P, N);
  const PrincipalOffsets axes = select_principal_offsets(
      {norm.to_normalized_offset(Vector3d(1, 0, 0)), norm.to_normalized_offset(Vector3d(0, 1, 0))});
  const Result<LatticeFit> cheapest = fit_lattice(mesh, norm, dense, axes);
  REQUIRE(cheapest.ok());
  LatticeFitOptions forced;
  forced.phase[0] = (int(std::lround(cheapest->phase[0] * 64)) + 32) % 64;  // half a period off
  const Result<LatticeFit> whole = fit_lattice(mesh, norm, dense, axes, forced);
  const Result<LatticeFit> alone = refit_axis(mesh, norm, dense, axes, forced, *cheapest, 0);
  REQUIRE(whole.ok());
  REQUIRE(alone.ok());
  CHECK(whole->phase[0] == Approx(forced.phase[0] / 64.0));
  CHECK(whole->phase[1] == cheapest->phase[1]);
  CHECK(std::abs(whole->lattice.origin.x() - cheapest->lattice.origin.x()) > 0.4);
  CHECK(whole->lattice.origin.y() == Approx(cheapest->lattice.origin.y()));
  CHECK(alone->lattice.origin.isApprox(whole->lattice.origin, 1e-12));
  CHECK(alone->lattice.cells.matrix() == whole->lattice.cells.matrix());
  CHECK(alone->lattice.end_low.matrix() == whole->lattice.end_low.matrix());
  CHECK(alone->lattice.end_high.matrix() == whole->lattice.end_high.matrix());
  CHECK(alone->phase.matrix() == whole->phase.matrix());
  CHECK(alone->phase_cost == whole->phase_cost);
  forced.phase[1] = 64;
  CHECK(fit_lattice(mesh, norm, dense, axes, forced).status().code() == StatusCode::invalid_argument);
  CHECK(refit_axis(mesh, norm, dense, axes, LatticeFitOptions{}, *cheapest, 3).status().code() ==
        StatusCode::invalid_argument);
}

TEST_CASE("vertex_double_drift: 0 where the vertices repeat at t and 2t, NaN for two copies or no repeat",
          "[offsets][detector]") {
  // n unit-ish boxes 0.15 apart along x (8 corners each), plus one big box that does not repeat (a post):
  // the vertices repeat at t = 0.15 and 2t from three boxes on.
  const auto corners = [](int n) {
    std::vector<Vector3d> P;
    const auto box = [&P](const Vector3d& lo, const Vector3d& hi) {
      for (int c = 0; c < 8; ++c)
        P.emplace_back(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z());
    };
    for (int i = 0; i < n; ++i) box(Vector3d(0.03 + 0.15 * i, 0, 0), Vector3d(0.12 + 0.15 * i, 1, 0.02));
    box(Vector3d(0.15 * n + 0.01, -0.1, -0.05), Vector3d(0.15 * n + 0.11, 1.2, 0.05));
    PointSet s;
    s.points.resize(Eigen::Index(P.size()), 3);
    s.normals.setZero(Eigen::Index(P.size()), 3);
    for (std::size_t i = 0; i < P.size(); ++i) s.points.row(Eigen::Index(i)) = P[i].cast<float>().transpose();
    return s;
  };
  const Vector3d t(0.15, 0, 0), off(0.004, 0.002, 0);  // ICP's offset: within a dense spacing of the true one
  for (const int n : {3, 4, 6}) {
    INFO(n << " copies");
    const PointSet s = corners(n);
    CHECK(detail::vertex_double_drift(&s, t + off) < 1e-6);
    CHECK(detail::vertex_double_drift(&s, -(t + off)) < 1e-6);
  }
  const PointSet two = corners(2);
  CHECK(std::isnan(detail::vertex_double_drift(&two, t + off)));  // no vertex at 2t: ICP's drift stands
  CHECK(std::isnan(detail::vertex_double_drift(&two, Vector3d(0.07, 0, 0))));  // no repeat at t
  CHECK(std::isnan(detail::vertex_double_drift(nullptr, t)));
  // least_drift keeps ICP's where the vertices say nothing.
  CHECK(detail::least_drift(2.0, NAN) == 2.0);
  CHECK(detail::least_drift(2.0, 0.0) == 0.0);
  CHECK(detail::least_drift(0.1, 0.5) == 0.1);
}
