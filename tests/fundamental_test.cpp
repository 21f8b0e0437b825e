// Tests for offsets/fundamental.hpp: a multiple of the period is reduced to the
// period on the generated families (known generators), and a period is not
// divided further where a fraction of it is no period (the facade's wall slides).
#include <catch2/catch.hpp>

#include "restitch/families/families.hpp"
#include "restitch/offsets/fundamental.hpp"
#include "restitch/sampling/poisson_disk.hpp"

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
