// Tests for offsets/fundamental.hpp: a multiple of the period is reduced to the
// period on the generated families (known generators), and a period is not
// divided further where a fraction of it is no period (the facade's wall slides).
#include <catch2/catch.hpp>

#include "restitch/analyze.hpp"
#include "restitch/families/families.hpp"
#include "restitch/offsets/fundamental.hpp"
#include "restitch/sampling/poisson_disk.hpp"
#include "support/mesh_builders.hpp"

using namespace restitch;

namespace {

struct Cloud {
  Normalization norm;
  PointSet dense;
  std::vector<Eigen::Vector3d> generators;  // normalized
};

Cloud cloud_of(const std::string& family) {
  auto s = families::generate(family);
  REQUIRE(s);
  Cloud c;
  c.norm = Normalization::of(bounding_box(s->mesh));
  auto dense = poisson_disk_sample(s->mesh, c.norm, 0.02, 1);
  REQUIRE(dense);
  c.dense = std::move(*dense);
  for (const Eigen::Vector3d& g : s->generators) c.generators.push_back(c.norm.to_normalized_offset(g));
  return c;
}

FundamentalPeriod reduce(const SelfAligner& aligner, const Eigen::Vector3d& t) {
  const double o = aligner.overlap(t);
  return fundamental_period(aligner, t, o, overlap_contrast(aligner, t, o));
}

}  // namespace

TEST_CASE("fundamental_period: two and three periods become one; one period stays", "[fundamental]") {
  for (const char* family : {"fence", "bookshelf", "facade", "pin_header"}) {
    INFO(family);
    const Cloud c = cloud_of(family);
    IcpOptions icp;
    icp.spacing = 0.02;
    const SelfAligner aligner(c.dense, icp);
    const Eigen::Vector3d g = c.generators[0];
    const FundamentalPeriod one = reduce(aligner, g);
    CHECK(one.divisor == 1);
    CHECK((one.offset - g).norm() == 0);
    for (int k : {2, 3}) {
      if (g.norm() * k > 1.9) continue;  // the multiple must fit in the model
      INFO("k = " << k);
      const FundamentalPeriod f = reduce(aligner, k * g);
      CHECK(f.divisor == k);
      CHECK((f.offset - g).norm() < 1e-12);
      CHECK(f.overlap >= aligner.overlap(k * g) - 0.02);
    }
  }
}

TEST_CASE("fundamental_period: a divisor closer than the overlap radius to the next is not tried", "[fundamental]") {
  const Cloud c = cloud_of("fence");
  IcpOptions icp;
  icp.spacing = 0.02;
  const SelfAligner aligner(c.dense, icp);
  // A long offset whose divisors 2.. are all within a radius of their neighbours.
  const Eigen::Vector3d t = Eigen::Vector3d(0.09, 0, 0);  // t/2 - t/3 = 0.015 < 0.03
  const FundamentalPeriod f = fundamental_period(aligner, t, 1.0, 1.0);
  CHECK(f.divisor == 1);
  // min_length: 3 spacings; no divisor gives less.
  FundamentalOptions o;
  o.overlap_slack = 1, o.contrast_share = 0, o.min_contrast = -1;  // accept anything resolvable
  const FundamentalPeriod any = fundamental_period(aligner, Eigen::Vector3d(0.5, 0, 0), 0.0, 0.0, o);
  CHECK(any.offset.norm() >= 3 * 0.02 - 1e-12);
  CHECK(any.divisor >= 2);
}

// docs/method.md 1.6.1: a period under 3 dense spacings (2.5 here) is out of reach of the search
// of 1.6; the analysis finds it on finer samples, from a multiple that is significant or a pair, and the
// structure check of 1.12 from an exact multiple.
TEST_CASE("short periods: 40 slats 2.5 dense spacings apart are found on finer samples", "[fundamental][analyze]") {
  const double pitch = 0.1, width = 4.0;  // normalized pitch 0.1 / (width / 2) = 0.05 < 3 x 0.02
  Mesh m;
  for (int j = 0; j < 40; ++j) test::add_box(m, {0, j * pitch, 0}, {width, j * pitch + 0.02, 0.25});
  for (const double x : {0.5, 3.5}) test::add_box(m, {x, -0.05, 0.26}, {x + 0.03, 40 * pitch, 0.29});  // two cords
  REQUIRE(validate(m).ok());
  const Normalization n = Normalization::of(bounding_box(m));
  AnalysisOptions<> options;
  REQUIRE(n.to_normalized_offset(Eigen::Vector3d(0, pitch, 0)).norm() <
          options.fundamental.min_length * options.dense_spacing);
  const auto has_pitch = [&](const Analysis& a) {
    for (const Eigen::Vector3d& p : a.principal_model_units())  // the pitch within 1% of it
      if (std::abs(std::abs(p.y()) - pitch) < 0.01 * pitch && std::abs(p.x()) + std::abs(p.z()) < 0.01 * pitch)
        return true;
    return false;
  };
  auto found = analyze(m, options);
  REQUIRE(found);
  CHECK(has_pitch(*found));
  bool fine = false;
  for (const DominantOffset& d : found->dominant)
    for (const OffsetTest& t : d.tests) fine = fine || (d.significant && t.name == "fine_divisor" && t.passed);
  CHECK(fine);
  // Without the finer search the structure still proves the pitch (an exact divisor of a multiple whose
  // cells are copies, docs/method.md 1.12); without both it is out of reach.
  options.find_short_periods = false;
  auto structure = analyze(m, options);
  REQUIRE(structure);
  CHECK(has_pitch(*structure));
  bool divided = false;
  for (const DominantOffset& d : structure->dominant)
    for (const OffsetTest& t : d.tests) divided = divided || (t.name == "structure_divisor" && t.passed);
  CHECK(divided);
  options.verify_periods = false;
  auto coarse = analyze(m, options);
  REQUIRE(coarse);
  CHECK_FALSE(has_pitch(*coarse));
}

// A period plus a slide along a direction in which the model is uniform is that period (docs/method.md
// 1.5, the slide test): a radiator's sections are uniform vertically, so the section pitch plus any height
// overlaps as well as the pitch; at 6 sections such an offset had 11 votes and passed every other test,
// and became a second principal offset. At every count the pitch is the only one.
TEST_CASE("analysis: a period plus a slide along a uniform direction is that period, not a second offset",
          "[analysis][samples]") {
  for (const int n : {3, 4, 5, 6, 7, 8, 10}) {
    INFO(n << " sections");
    auto s = restitch::families::generate("radiator", {{"sections", n}});
    REQUIRE(s.ok());
    auto a = restitch::analyze(s->mesh);
    REQUIRE(a.ok());
    REQUIRE(a->principal.size() == 1);
    CHECK((a->principal_model_units()[0].cwiseAbs() - s->generators[0].cwiseAbs()).norm() < 1e-4);
    for (const restitch::DominantOffset& d : a->dominant) {
      const Eigen::Vector3d t = a->normalization.to_model_offset(d.offset);
      // An offset one pitch along x and clearly off the x axis is a slide: never significant.
      if (std::abs(std::abs(t.x()) - 0.07) < 1e-3 && std::abs(t.y()) > 0.01) CHECK_FALSE(d.significant);
    }
  }
}
