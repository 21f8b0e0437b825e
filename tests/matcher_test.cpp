// Tests of restitch/matcher/{matcher,brute_force,reduced}.hpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "restitch/matcher/brute_force.hpp"
#include "restitch/matcher/matcher.hpp"
#include "restitch/matcher/reduced.hpp"

using restitch::BruteForceMatcher;
using restitch::DescriptorMatrix;
using restitch::Match;
using restitch::PointSet;
using restitch::ReducedMatcher;

static_assert(restitch::is_matcher_policy_v<BruteForceMatcher>, "BruteForceMatcher must satisfy the contract");
static_assert(restitch::is_matcher_policy_v<ReducedMatcher>, "ReducedMatcher must satisfy the contract");
static_assert(!restitch::is_matcher_policy_v<int>, "int is no matcher");

namespace {

double uniform(std::mt19937_64& g) { return double(g() >> 11) * 0x1.0p-53; }

PointSet points_of(const std::vector<Eigen::Vector3f>& p) {
  PointSet s;
  s.points.resize(static_cast<Eigen::Index>(p.size()), 3);
  s.normals = restitch::MatrixX3f::Zero(static_cast<Eigen::Index>(p.size()), 3);
  for (std::size_t i = 0; i < p.size(); ++i) s.points.row(static_cast<Eigen::Index>(i)) = p[i].transpose();
  return s;
}

// The contract, written as plainly as possible: every pair, in double.
std::vector<Match> naive(const PointSet& f, const DescriptorMatrix& d, float tau) {
  const Eigen::Index n = f.size();
  std::vector<Match> out(static_cast<std::size_t>(n));
  auto ok = [&](Eigen::Index i) { return f.points.row(i).allFinite() && d.row(i).allFinite(); };
  const double tau2 = double(tau) * double(tau);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!ok(i)) continue;
    std::vector<std::pair<Eigen::Index, double>> cand;
    double best = INFINITY;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (j == i || !ok(j)) continue;
      double off = 0;
      for (int k = 0; k < 3; ++k) {
        const double t = double(f.points(j, k)) - double(f.points(i, k));
        off += t * t;
      }
      if (!(off > tau2)) continue;
      double s = 0;
      for (Eigen::Index k = 0; k < d.cols(); ++k) {
        const double t = double(d(j, k)) - double(d(i, k));
        s += t * t;
      }
      cand.emplace_back(j, std::sqrt(s));
      best = std::min(best, std::sqrt(s));
    }
    Eigen::Index pick = -1;
    double pick_off = 0, pick_d = 0;
    for (const auto& c : cand) {
      if (!(c.second - best <= std::max(1e-6 * c.second, 1e-6))) continue;
      double off = 0;
      for (int k = 0; k < 3; ++k) {
        const double t = double(f.points(c.first, k)) - double(f.points(i, k));
        off += t * t;
      }
      if (pick < 0 || off < pick_off || (off == pick_off && c.first < pick))
        pick = c.first, pick_off = off, pick_d = c.second;
    }
    if (pick >= 0) out[static_cast<std::size_t>(i)] = Match{static_cast<std::int32_t>(pick), float(pick_d)};
  }
  return out;
}

template <class M>
std::vector<Match> run(const M& m, const PointSet& f, const DescriptorMatrix& d, float tau) {
  std::vector<Match> out;
  const restitch::Status s = m.match(f, d, tau, out, restitch::Progress{});
  REQUIRE(s.ok());
  REQUIRE(out.size() == static_cast<std::size_t>(f.size()));
  return out;
}

// The reduced matcher on its own path at any size (no brute-force fallback), with `dims` directions.
ReducedMatcher reduced(int dims = 32) {
  ReducedMatcher m;
  m.dimensions = dims;
  m.min_rows = 0;
  m.max_candidate_share = 1;
  return m;
}

std::size_t count_differences(const std::vector<Match>& a, const std::vector<Match>& b) {
  std::size_t k = 0;
  for (std::size_t i = 0; i < a.size(); ++i) k += a[i] != b[i];
  return k;
}

// Random positions in [-1, 1]^3 and random unit descriptors, with exact and
// near duplicates (ties) mixed in.
void random_problem(std::uint64_t seed, int n, int dim, PointSet& f, DescriptorMatrix& d) {
  std::mt19937_64 g(seed);
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < n; ++i)
    p.emplace_back(float(2 * uniform(g) - 1), float(2 * uniform(g) - 1), float(2 * uniform(g) - 1));
  f = points_of(p);
  d.resize(n, dim);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < dim; ++k) d(i, k) = float(uniform(g));
    d.row(i).normalize();
  }
  for (int i = 0; i + 10 < n; i += 7) d.row(i + 3) = d.row(i);  // exact duplicates
  for (int i = 1; i + 10 < n; i += 11) {
    d.row(i + 5) = d.row(i);
    d(i + 5, 0) = std::nextafter(d(i + 5, 0), 2.0f);  // float-noise duplicates (within the 1e-6 floor)
  }
}

// Positions in a box; descriptors a smooth function of the position modulo
// a lattice (pitch 0.2 x 0.25 x 0.3) plus noise: many near ties.
void lattice_problem(std::uint64_t seed, int n, int dim, double noise, PointSet& f, DescriptorMatrix& d) {
  std::mt19937_64 g(seed);
  std::vector<Eigen::Vector3f> p;
  const double pitch[3] = {0.2, 0.25, 0.3};
  d.resize(n, dim);
  for (int i = 0; i < n; ++i) {
    // Snap to a 0.05 grid so that many points share the same phase exactly.
    Eigen::Vector3f q;
    for (int a = 0; a < 3; ++a) q[a] = float(0.05 * std::floor(40 * uniform(g)) - 1.0);
    p.push_back(q);
    double phase[3];
    for (int a = 0; a < 3; ++a) phase[a] = std::fmod(double(q[a]) + 1.0 + 1e-9, pitch[a]) / pitch[a];
    for (int k = 0; k < dim; ++k)
      d(i, k) = float(std::cos(6.283185307179586 * (phase[k % 3] * (1 + k / 3 % 3)) + k) +
                      0.5 * std::sin(6.283185307179586 * phase[(k + 1) % 3]) + noise * (2 * uniform(g) - 1));
    d.row(i).normalize();
  }
  f = points_of(p);
}

}  // namespace

TEST_CASE("BruteForceMatcher equals the naive double loop exactly", "[matcher]") {
  for (std::uint64_t seed : {1u, 2u}) {
    PointSet f;
    DescriptorMatrix d;
    random_problem(seed, 560, 16 + int(seed) * 8, f, d);  // 560 > one 512 block: off-diagonal blocks too
    const float tau = 0.15f;
    const auto want = naive(f, d, tau);
    const auto got = run(BruteForceMatcher{}, f, d, tau);
    CHECK(count_differences(got, want) == 0);
    std::size_t zero = 0;
    for (const Match& m : got) {
      REQUIRE(m.target >= 0);
      zero += m.distance == 0.0f;
    }
    CHECK(zero > 40);  // the duplicates were found as exact ties
  }
}

TEST_CASE("tau is strict: a pair exactly tau apart is excluded", "[matcher]") {
  const float tau = 0.15f;
  // 0 and 1 are identical and exactly tau apart; 2 is farther and different.
  const PointSet f = points_of({{0, 0, 0}, {tau, 0, 0}, {0.5f, 0, 0}});
  DescriptorMatrix d(3, 2);
  d << 1, 0, 1, 0, 0.6f, 0.8f;
  for (const auto& out : {run(BruteForceMatcher{}, f, d, tau), run(reduced(), f, d, tau), naive(f, d, tau)}) {
    CHECK(out[0].target == 2);
    CHECK(out[1].target == 2);
    CHECK(out[2].target == 1);  // equal distances to 0 and 1: the shorter offset (0.35 < 0.5) wins
  }
  // Just above: with tau a hair smaller, 0 and 1 match each other at distance 0.
  const auto close = run(BruteForceMatcher{}, f, d, std::nextafter(tau, 0.0f));
  CHECK(close[0] == (Match{1, 0.0f}));
  CHECK(close[1] == (Match{0, 0.0f}));
  // Random data: every match is farther than tau.
  PointSet rf;
  DescriptorMatrix rd;
  random_problem(9, 300, 16, rf, rd);
  const auto out = run(BruteForceMatcher{}, rf, rd, 0.4f);
  for (std::size_t i = 0; i < out.size(); ++i) {
    REQUIRE(out[i].target >= 0);
    CHECK((rf.points.row(out[i].target) - rf.points.row(Eigen::Index(i))).cast<double>().norm() > 0.4);
  }
}

TEST_CASE("ties go to the shortest offset: a lattice votes for its pitch", "[matcher]") {
  // 1-D lattice, pitch 0.1, identical descriptors (then tiny noise inside the tie floor).
  const int n = 40;
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < n; ++i) p.emplace_back(0.1f * float(i) - 1.0f, 0.25f, -0.5f);
  const PointSet f = points_of(p);
  DescriptorMatrix d(n, 48);
  std::mt19937_64 g(5);
  for (Eigen::Index k = 0; k < d.cols(); ++k) d(0, k) = float(uniform(g));
  d.row(0).normalize();
  for (int i = 1; i < n; ++i) d.row(i) = d.row(0);
  DescriptorMatrix noisy = d;
  for (int i = 0; i < n; ++i) noisy(i, i % 48) += 1e-7f * float(i % 5);

  for (const DescriptorMatrix* desc : {&d, &noisy}) {
    for (float tau : {0.05f, 0.15f}) {
      const double expect = tau < 0.1f ? 0.1 : 0.2;  // the shortest admissible multiple of the pitch
      for (const auto& out :
           {run(BruteForceMatcher{}, f, *desc, tau), run(reduced(8), f, *desc, tau)}) {
        for (int i = 0; i < n; ++i) {
          REQUIRE(out[std::size_t(i)].target >= 0);
          const double off = (f.points.row(out[std::size_t(i)].target) - f.points.row(i)).cast<double>().norm();
          CHECK(off == Approx(expect).epsilon(1e-5));
        }
      }
      CHECK(count_differences(run(BruteForceMatcher{}, f, *desc, tau), naive(f, *desc, tau)) == 0);
    }
  }
}

TEST_CASE("rows with NaN never match and are never matched", "[matcher]") {
  PointSet f;
  DescriptorMatrix d;
  random_problem(4, 200, 20, f, d);
  d(10, 3) = NAN;
  d(20, 0) = NAN;
  d.row(21) = d.row(22);  // 22's best partner is the exact duplicate 21...
  f.points(30, 1) = NAN;  // ...and a feature without a position
  d(40, 5) = INFINITY;
  for (const auto& out :
       {run(BruteForceMatcher{}, f, d, 0.15f), run(reduced(6), f, d, 0.15f)}) {
    for (int bad : {10, 20, 30, 40}) CHECK(out[std::size_t(bad)] == Match{});
    for (const Match& m : out) CHECK((m.target != 10 && m.target != 20 && m.target != 30 && m.target != 40));
    CHECK(count_differences(out, naive(f, d, 0.15f)) == 0);
  }
}

TEST_CASE("ReducedMatcher equals BruteForceMatcher on random and lattice data", "[matcher]") {
  SECTION("random unit descriptors with duplicates") {
    PointSet f;
    DescriptorMatrix d;
    random_problem(11, 600, 48, f, d);
    const auto bf = run(BruteForceMatcher{}, f, d, 0.15f);
    CHECK(count_differences(bf, naive(f, d, 0.15f)) == 0);
    for (int dims : {4, 16})
      CHECK(count_differences(run(reduced(dims), f, d, 0.15f), bf) == 0);
  }
  SECTION("lattice-structured descriptors, float-level noise (ties) and 1e-3 noise") {
    for (double noise : {1e-7, 1e-3}) {
      PointSet f;
      DescriptorMatrix d;
      lattice_problem(12, 600, 36, noise, f, d);
      const auto bf = run(BruteForceMatcher{}, f, d, 0.15f);
      CHECK(count_differences(bf, naive(f, d, 0.15f)) == 0);
      for (int dims : {3, 12})
        CHECK(count_differences(run(reduced(dims), f, d, 0.15f), bf) == 0);
      // The votes: most offsets are lattice vectors (multiples of the pitches).
      std::size_t on_lattice = 0;
      for (std::size_t i = 0; i < bf.size(); ++i) {
        if (bf[i].target < 0) continue;
        const Eigen::Vector3d v = (f.points.row(bf[i].target) - f.points.row(Eigen::Index(i))).cast<double>();
        const double pitch[3] = {0.2, 0.25, 0.3};
        bool ok = true;
        for (int a = 0; a < 3; ++a) ok = ok && std::abs(v[a] / pitch[a] - std::round(v[a] / pitch[a])) < 1e-3;
        on_lattice += ok;
      }
      CHECK(on_lattice > bf.size() * 9 / 10);
    }
  }
}

TEST_CASE("matchers check their input and honour cancellation", "[matcher]") {
  PointSet f;
  DescriptorMatrix d;
  random_problem(3, 50, 40, f, d);
  std::vector<Match> out;
  for (int which = 0; which < 2; ++which) {
    auto call = [&](const DescriptorMatrix& dd, float tau, const restitch::Progress& pr = {}) {
      return which == 0 ? BruteForceMatcher{}.match(f, dd, tau, out, pr)
                        : reduced(4).match(f, dd, tau, out, pr);
    };
    CHECK(call(d.topRows(49), 0.1f).code() == restitch::StatusCode::invalid_argument);
    CHECK(call(d, -1.0f).code() == restitch::StatusCode::invalid_argument);
    CHECK(call(d, NAN).code() == restitch::StatusCode::invalid_argument);
    CHECK(call(DescriptorMatrix(50, 0), 0.1f).code() == restitch::StatusCode::invalid_argument);
    std::string stage;
    restitch::Progress stop([&](std::string_view s, double) {
      stage = std::string(s);
      return false;
    });
    CHECK(call(d, 0.1f, stop).code() == restitch::StatusCode::cancelled);
    CHECK(stage == "matching");
    // Empty and single-feature inputs.
    PointSet none;
    CHECK(BruteForceMatcher{}.match(none, DescriptorMatrix(0, 4), 0.1f, out, {}).ok());
    CHECK(out.empty());
    const PointSet one = points_of({{0, 0, 0}});
    CHECK(ReducedMatcher{}.match(one, DescriptorMatrix::Ones(1, 100), 0.1f, out, {}).ok());
    REQUIRE(out.size() == 1);
    CHECK(out[0] == Match{});
  }
}

TEST_CASE("the matchers give the same matches on any number of threads", "[matcher][threads]") {
  // 1300 rows: three row blocks of 512 (the scan's tasks), so workers share unequal blocks.
  PointSet f;
  DescriptorMatrix d;
  random_problem(21, 1300, 40, f, d);
  PointSet lf;
  DescriptorMatrix ld;
  lattice_problem(22, 1300, 40, 1e-7, lf, ld);  // many near ties
  for (const auto* problem : {&d, &ld}) {
    const PointSet& pf = problem == &d ? f : lf;
    const auto reference = naive(pf, *problem, 0.15f);
    for (int threads : {1, 2, 3, 5}) {
      BruteForceMatcher bf;
      bf.threads = threads;
      ReducedMatcher rm = reduced(8);
      rm.threads = threads;
      CHECK(count_differences(run(bf, pf, *problem, 0.15f), reference) == 0);
      CHECK(count_differences(run(rm, pf, *problem, 0.15f), reference) == 0);
    }
  }
  // Cancelled on the calling thread whatever the number of workers, at the first report.
  for (int threads : {2, 4}) {
    BruteForceMatcher bf;
    bf.threads = threads;
    int reports = 0;
    bool elsewhere = false;  // a report from a thread other than the caller's
    const std::thread::id caller = std::this_thread::get_id();
    std::vector<Match> out;
    const restitch::Progress stop([&](std::string_view, double) {
      elsewhere = elsewhere || std::this_thread::get_id() != caller;
      return ++reports < 2;
    });
    CHECK(bf.match(f, d, 0.15f, out, stop).code() == restitch::StatusCode::cancelled);
    CHECK(reports == 2);
    CHECK_FALSE(elsewhere);
  }
}

TEST_CASE("the reduced matcher's brute-force fallbacks give the same matches", "[matcher]") {
  // Below min_rows, above the probe's share, and the reduced path itself: one answer, the contract's.
  PointSet f;
  DescriptorMatrix d;
  lattice_problem(31, 900, 40, 1e-7, f, d);  // near ties everywhere: a high candidate share
  const auto reference = naive(f, d, 0.15f);
  ReducedMatcher small;  // 900 rows < min_rows
  CHECK(count_differences(run(small, f, d, 0.15f), reference) == 0);
  for (double share : {0.0, 0.125, 1.0}) {
    ReducedMatcher m = reduced(8);
    m.max_candidate_share = share;
    CHECK(count_differences(run(m, f, d, 0.15f), reference) == 0);
    m.probe_rows = 1;
    CHECK(count_differences(run(m, f, d, 0.15f), reference) == 0);
  }
}
