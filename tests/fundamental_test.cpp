// Tests for offsets/fundamental.hpp: a multiple of the period is reduced to the
// period on the generated families (known generators), and a period is not
// divided further where a fraction of it is no period (the facade's wall slides).
#include <catch2/catch.hpp>

#include "restitch/analyze.hpp"
#include "restitch/families/families.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/retarget.hpp"
#include "restitch/offsets/fundamental.hpp"
#include "restitch/sampling/poisson_disk.hpp"
#include "support/mesh_builders.hpp"
#include "support/surface_distance.hpp"

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

// Many copies: the analysis's lengths scale with the longest side (docs/method.md 1.1), so a long model has
// its period short in them, under the matching's minimum length (tau) and the descriptors' radius, and at
// most a multiple of it gets votes: a 32-pin connector had no principal offset (its pair of eight pins was a
// candidate), a 24-column box header five pitches, a 32-column bookshelf no shelf pitch, a 24-column facade
// neither repeat. The vertices repeat at the period (1.14), and on samples fine enough for it the surface
// is a pattern there (vertex_pattern); a multiple decided by copies farther apart is divided (1.12). Each
// family is written to .glb and read back, as a user's file is (float positions: the failures above were
// seen so), and must have every generator as a principal offset and no other, and grow by two modules into
// the family at that count, in place.
TEST_CASE("analysis: long families have their generators as principal offsets, and grow in place",
          "[fundamental][analyze][slow]") {
  const std::vector<std::pair<std::string, int>> cases{{"connector", 32}, {"box_header", 24}, {"radiator", 32},
                                                       {"railing", 12},   {"facade", 24},     {"bookshelf", 32}};
  for (const auto& [family, n] : cases) {
    INFO(family << " at " << n);
    const std::string count = restitch::families::generate(family)->count_parameters[0];
    auto s = restitch::families::generate(family, {{count, n}});
    REQUIRE(s.ok());
    auto bytes = save_glb_to_memory(s->mesh);
    REQUIRE(bytes.ok());
    auto mesh = load_gltf_from_memory(bytes->data(), bytes->size());
    REQUIRE(mesh.ok());
    auto a = analyze(*mesh);
    REQUIRE(a.ok());
    const std::vector<Eigen::Vector3d> principal = a->principal_model_units();
    CHECK(principal.size() == s->generators.size());
    int along = -1;  // the lattice axis of generator 0
    for (const Eigen::Vector3d& g : s->generators) {
      bool found = false;
      for (std::size_t k = 0; k < principal.size(); ++k)
        if ((principal[k].cwiseAbs() - g.cwiseAbs()).norm() < 1e-4 * g.norm()) {
          found = true;
          if (&g == &s->generators[0]) along = int(k);
        }
      CHECK(found);
    }
    REQUIRE(along >= 0);
    Retargeter<> r(*mesh, *a);
    REQUIRE(r.status().ok());
    Eigen::Array3i steps = Eigen::Array3i::Zero();
    steps[along] = 2;  // principal offsets come first in the lattice
    auto out = r.retarget(steps);
    REQUIRE(out.ok());
    auto truth = restitch::families::generate(family, {{count, n + 2}});
    REQUIRE(truth.ok());
    const BoundingBox bt = bounding_box(truth->mesh), bo = bounding_box(out->mesh);
    const double size = bt.size().norm();
    CHECK((bt.min - bo.min).norm() < 1e-4 * size);
    CHECK((bt.max - bo.max).norm() < 1e-4 * size);
    CHECK(test::symmetric_surface_distance(out->mesh, truth->mesh, 0.004 * size) < 1e-4 * size);
  }
}
