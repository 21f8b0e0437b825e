// Tests for the explanations and candidates of an analysis (docs/method.md 1.10): the significance tests
// each dominant offset records, 2-copy repeats reported as candidates, and promote_offsets.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "restitch/analyze.hpp"
#include "restitch/families/families.hpp"
#include "restitch/retarget.hpp"

#include "support/mesh_builders.hpp"
#include "support/surface_distance.hpp"
#include "support/sampled_shapes.hpp"

using namespace restitch;
using Eigen::Vector3d;
using namespace restitch::test;

namespace {

// The smallest distance from each row of `from` to a row of `to`, maximised (brute force).
double max_nearest(const MatrixX3f& from, const MatrixX3f& to) {
  double worst = 0;
  for (Eigen::Index i = 0; i < from.rows(); ++i)
    worst = std::max(worst, double((to.rowwise() - from.row(i)).rowwise().norm().minCoeff()));
  return worst;
}

// `out` is a valid mesh with the real part's bounding box (within 1e-4), holding every vertex of it.
void check_has_real_part(const Mesh& out, const Mesh& real_part) {
  CHECK(validate(out).ok());
  const BoundingBox box = bounding_box(out), real = bounding_box(real_part);
  CHECK((box.min - real.min).norm() < 1e-4);
  CHECK((box.max - real.max).norm() < 1e-4);
  CHECK(max_nearest(real_part.V, out.V) < 1e-4);
}

const families::SampleModel& two_pins() {
  static const families::SampleModel m = *families::generate("pin_header", {{"pins", 2}});
  return m;
}
// The 2-pin header analysed with exact pairs off (docs/method.md 1.13): its pair stays a candidate, so the
// candidate and promotion machinery is tested on it.
const Analysis& two_pins_analysis() {
  static const Analysis a = [] {
    AnalysisOptions<> options;
    options.exact_pairs = false;
    return *analyze(two_pins().mesh, options);
  }();
  return a;
}

}  // namespace

TEST_CASE("every dominant offset records the tests it ran, and significance is exactly all of them passing",
          "[candidates][analysis]") {
  for (const char* family : {"bookshelf", "fence", "pin_header"}) {
    INFO(family);
    const Result<Analysis> a = analyze(families::generate(family)->mesh);
    REQUIRE(a.ok());
    REQUIRE(!a->dominant.empty());
    for (const DominantOffset& d : a->dominant) {
      REQUIRE(!d.tests.empty());
      if (d.from_vertices()) {  // found by the vertices, not the detector (method.md 1.14): passed its checks,
        // then the pattern tests on the surface, stopping at the first failure; significant when all passed
        std::vector<OffsetTest> pattern;
        for (const OffsetTest& t : d.tests) {
          if (t.name.rfind("vertex_", 0) == 0) {
            CHECK(t.passed);
          } else {
            CHECK(t.name.rfind("pattern_", 0) == 0);
            pattern.push_back(t);
          }
        }
        for (std::size_t k = 0; k + 1 < pattern.size(); ++k) CHECK(pattern[k].passed);
        CHECK(d.significant == (!pattern.empty() && pattern.back().passed && pattern.back().name == "pattern_stays"));
        continue;
      }
      // Two groups, each stopping at its first failure: the whole-surface tests, then (when they
      // failed and the peak had votes) the part tests, named part_... (offsets/part.hpp).
      CHECK(d.tests.front().name == "votes");
      std::vector<OffsetTest> whole, part, pair;
      for (const OffsetTest& t : d.tests) {
        CHECK(t.passed == (t.at_most ? t.value <= t.threshold : t.value >= t.threshold));
        (t.name.rfind("part_", 0) == 0 ? part : t.name.rfind("pair_", 0) == 0 ? pair : whole).push_back(t);
      }
      for (const auto* group : {&whole, &part, &pair})
        for (std::size_t k = 0; k + 1 < group->size(); ++k) CHECK((*group)[k].passed);
      const bool whole_passed = whole.size() == 6 && whole.back().passed;
      const bool part_passed = !part.empty() && part.back().passed && part.back().name == "part_axis_contrast";
      const bool pair_passed = pair.size() == 2 && pair.back().passed;  // two exact copies (method.md 1.13)
      if (whole_passed) CHECK(part.empty());  // the part test runs only where the whole surface failed
      if (!pair.empty()) CHECK(d.is_pair() != d.significant);  // tried only on pairs
      // The histogram detector runs six whole-surface tests; significant when all six passed or,
      // failing that, all the part tests did, or, a pair, the exact-pair test did.
      if (!d.significant) CHECK(!whole_passed);
      if (d.significant) CHECK((whole_passed || part_passed || pair_passed));
      CHECK((d.failed_test() == nullptr) == d.significant);
    }
  }
}

TEST_CASE("a 2-pin header: its two exact copies are a principal offset; with exact pairs off, a candidate "
          "rejected by the repeat test",
          "[candidates][analysis]") {
  {
    const Analysis exact = *analyze(two_pins().mesh);
    REQUIRE(exact.principal.size() == 1);
    CHECK(recovered(two_pins().generators[0], exact.principal_model_units(), 1e-5, 0.01));
  }
  const Analysis& a = two_pins_analysis();
  const Vector3d pitch = two_pins().generators[0];
  CHECK(a.principal.empty());
  REQUIRE(!a.candidates.empty());
  const RepeatCandidate& c = a.candidates.front();
  CHECK(recovered(pitch, {a.model_units(c)}, 1e-4, 0.1));
  CHECK(c.copies == 2);
  CHECK(c.reason == "pair");
  REQUIRE(c.dominant >= 0);
  const DominantOffset& d = a.dominant[std::size_t(c.dominant)];
  CHECK(d.is_pair());
  REQUIRE(d.failed_test());
  CHECK(d.failed_test()->name == "repeat");
  // Two copies: shifting by 2 pitches maps (almost) nothing, far below a quarter of overlap(pitch).
  CHECK(d.failed_test()->value < 0.25);
  // Only one candidate per repeat: its negative and multiples are not listed again.
  for (std::size_t k = 1; k < a.candidates.size(); ++k)
    CHECK(!recovered(pitch, {a.model_units(a.candidates[k])}, 0.01, 1.0));
  // A size change along x uses that candidate (the first one along x); none is asked for when no
  // size change is, or along an axis a principal offset already runs along (the 6-pin header's x).
  CHECK(a.candidates_for_axes({{true, false, false}}) == std::vector<int>{0});
  CHECK(a.candidates_for_axes({{false, false, false}}).empty());
  const Result<Analysis> six = analyze(families::generate("pin_header")->mesh);
  REQUIRE(six.ok());
  CHECK(six->candidates_for_axes({{true, false, false}}).empty());
}

TEST_CASE("promoting the 2-pin pair resizes it into the real 3- and 4-pin headers", "[candidates][retarget]") {
  const families::SampleModel& two = two_pins();
  Analysis a = two_pins_analysis();
  // The offset need not be typed exactly: 2.5 refines to the 2.54 mm pitch.
  REQUIRE(promote_offsets(two.mesh, AnalysisOptions<>{}, {Vector3d(2.5, 0, 0)}, a).ok());
  REQUIRE(a.principal.size() == 1);
  CHECK(recovered(two.generators[0], a.principal_model_units(), 1e-5, 0.01));
  REQUIRE(a.promoted.size() == 1);
  CHECK(a.dominant[std::size_t(a.promoted[0])].promoted);
  for (const RepeatCandidate& c : a.candidates)  // the pair is now principal, no longer a candidate
    CHECK(!recovered(two.generators[0], {a.model_units(c)}, 0.01, 1.0));
  Retargeter<> r(two.mesh, a);
  REQUIRE(r.status().ok());
  for (const int more : {1, 2}) {
    INFO(more << " more pins");
    const auto want = families::generate("pin_header", {{"pins", 2 + more}});
    const auto out = r.retarget(*lattice_steps_from_principal(a, {more}));
    REQUIRE(out.ok());
    check_has_real_part(out->mesh, want->mesh);  // the seams' quality is docs/method.md 3
    // A pair candidate resized along on request is a detail of a larger whole as far as the analysis knows:
    // warned "pair" before the resize. Found exact (the default, 1.13), the same pair is a principal
    // offset and is not.
    bool pair = false;
    for (const ResultWarning& w : out->report.warnings) pair = pair || w.check == "pair";
    CHECK(pair);
  }
  const Analysis exact = *analyze(two.mesh);
  REQUIRE(exact.principal.size() == 1);
  Retargeter<> e(two.mesh, exact);
  const auto grown = e.retarget(*lattice_steps_from_principal(exact, {2}));
  REQUIRE(grown.ok());
  for (const ResultWarning& w : grown->report.warnings) CHECK(w.check != "pair");
}

TEST_CASE("promote_offsets: an empty list restores the detected offsets; bad requests change nothing",
          "[candidates][analysis]") {
  const families::SampleModel sample = *families::generate("pin_header");
  const Analysis detected = *analyze(sample.mesh);
  REQUIRE(detected.principal.size() == 1);
  Analysis a = detected;
  const std::vector<Vector3d> bad[] = {
      {Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1), Vector3d(1, 1, 1)},  // more than three
      {Vector3d::Zero()},
      {Vector3d(std::nan(""), 0, 0)},
      {Vector3d(2.54, 0, 0), Vector3d(5.08, 0.1, 0)},  // parallel
      {Vector3d(0.05, 0, 0)},                          // slides onto the model itself
  };
  for (const auto& offsets : bad) {
    const Status s = promote_offsets(sample.mesh, AnalysisOptions<>{}, offsets, a);
    CHECK(s.code() == StatusCode::invalid_argument);
    CHECK(a.principal == detected.principal);
    CHECK(a.dominant.size() == detected.dominant.size());
    CHECK(a.promoted.empty());
  }
  // Promote twice the pitch (a longer module), then go back.
  REQUIRE(promote_offsets(sample.mesh, AnalysisOptions<>{}, {Vector3d(5.08, 0, 0)}, a).ok());
  REQUIRE(a.principal.size() == 1);
  CHECK(recovered(Vector3d(5.08, 0, 0), a.principal_model_units(), 1e-4, 0.1));
  REQUIRE(promote_offsets(sample.mesh, AnalysisOptions<>{}, {}, a).ok());
  CHECK(a.principal == detected.principal);
  CHECK(a.promoted.empty());
  for (const DominantOffset& d : a.dominant) CHECK(!d.promoted);
}

TEST_CASE("fences of 2 and 3 pickets: no vote for the picket pitch, but the vertices repeat at it, a repeat that "
          "resizes them into the real fences",
          "[candidates][retarget]") {
  // The pickets' features match each other up and down their own uniform sides, and the rails are one pair
  // across: the matching casts no vote for the pitch along x (docs/method.md 1.14). The default fence at 2
  // pickets, and one at 3 with other lengths (a set `bench --only parameters` draws).
  const std::map<std::string, double> other = {
      {"picket_pitch", 0.111365},   {"picket_width", 0.108357},    {"picket_height", 0.772797},
      {"picket_thickness", 0.0208317}, {"point_height", 0.0577342}, {"post_width", 0.0711249},
      {"post_height", 0.833035},    {"rail_height", 0.0594113},    {"rail_thickness", 0.0226839}};
  for (const auto& [n, lengths] : {std::pair<int, std::map<std::string, double>>{2, {}}, {3, other}}) {
    INFO(n << " pickets");
    std::map<std::string, double> params = lengths;
    params["pickets"] = n;
    const auto fence = families::generate("fence", params);
    REQUIRE(fence.ok());
    const Vector3d pitch = fence->generators[0];
    Analysis a = *analyze(fence->mesh);
    // Three pickets are a pattern on the surface at the pitch (docs/method.md 1.14, vertex_pattern): the
    // repeat of the vertices is a principal offset. Two are not (a pattern holds at twice its offset): a
    // candidate, promoted as `restitch resize --size` does.
    std::size_t along = 0;  // the pitch's index among the principal offsets
    if (n == 3) {
      const std::vector<Vector3d> principal = a.principal_model_units();
      while (along < principal.size() && !recovered(pitch, {principal[along]}, 1e-5, 0.01)) ++along;
      REQUIRE(along < principal.size());
      const DominantOffset& d = a.dominant[std::size_t(a.axes.source[along])];
      CHECK(d.votes == 0);
      CHECK(d.from_vertices());
      CHECK(d.significant);
      CHECK(a.candidates_for_axes({{true, false, false}}).empty());
    } else {
      for (const Vector3d& p : a.principal_model_units()) CHECK(world_axis_of(p) != 0);
      const std::vector<int> use = a.candidates_for_axes({{true, false, false}});
      REQUIRE(use.size() == 1);
      const RepeatCandidate& c = a.candidates[std::size_t(use[0])];
      CHECK(c.reason == "vertices");
      CHECK(c.copies >= 2);
      CHECK(recovered(pitch, {a.model_units(c)}, 1e-5, 0.01));
      REQUIRE(c.dominant >= 0);
      const DominantOffset& d = a.dominant[std::size_t(c.dominant)];
      CHECK(d.votes == 0);
      CHECK(d.from_vertices());
      CHECK_FALSE(d.significant);
      // Promoted: the candidate's offset in model units, first.
      REQUIRE(promote_offsets(fence->mesh, AnalysisOptions<>{}, {a.model_units(c)}, a).ok());
      REQUIRE(!a.principal.empty());
      CHECK(recovered(pitch, {a.principal_model_units()[0]}, 1e-5, 0.01));
    }
    Retargeter<> r(fence->mesh, a);
    REQUIRE(r.status().ok());
    for (const int more : {1, 2, -1}) {
      INFO(more << " more pickets");
      if (n + more < 1) continue;
      params["pickets"] = n + more;
      const auto want = families::generate("fence", params);
      std::vector<int> steps(a.principal.size(), 0);
      steps[along] = more;
      const auto out = r.retarget(*lattice_steps_from_principal(a, steps));
      REQUIRE(out.ok());
      // The same fence: the real one's box and vertices are in the result, and their surfaces lie on each
      // other (the pickets in place, no part twice; seams cut the rails where the copies continue each other).
      check_has_real_part(out->mesh, want->mesh);
      CHECK(symmetric_surface_distance(out->mesh, want->mesh, 0.01) < 1e-4 * bounding_box(want->mesh).size().norm());
    }
  }
}

TEST_CASE("promote_offsets: a value typed that the vertices repeat at is not traded for a dominant offset nearby",
          "[candidates][retarget]") {
  // 3 pickets between posts (set 99 of `bench --only parameters --seeds 91..120`): the candidate is the picket
  // pitch, 0.170, from the vertices; ICP from it slides, and the dominant offset 0.154 (a picket to a post,
  // 0.026 of the normalized length away, within the overlap radius) was promoted instead: undecided, and the
  // grow opened 227 edges. The value typed repeats the vertices; 0.154 does not snap to it.
  std::map<std::string, double> params = {
      {"picket_pitch", 0.17002857044583772},   {"picket_width", 0.1079251963818344},
      {"picket_height", 1.1404375639965985},   {"picket_thickness", 0.022412108611403348},
      {"point_height", 0.048959271754391902},  {"post_width", 0.12864088389415693},
      {"post_height", 1.2036311557971313},     {"rail_height", 0.070578183981580944},
      {"rail_thickness", 0.036327336099425164}, {"pickets", 3}};
  const auto fence = families::generate("fence", params);
  REQUIRE(fence.ok());
  const Vector3d pitch = fence->generators[0];
  Analysis a = *analyze(fence->mesh);
  const std::vector<int> use = a.candidates_for_axes({{true, false, false}});
  REQUIRE(use.size() == 1);
  const Vector3d typed = a.model_units(a.candidates[std::size_t(use[0])]);
  CHECK(recovered(pitch, {typed}, 1e-5, 0.01));
  REQUIRE(promote_offsets(fence->mesh, AnalysisOptions<>{}, {typed}, a).ok());
  REQUIRE(!a.principal.empty());
  CHECK(recovered(pitch, {a.principal_model_units()[0]}, 1e-5, 0.01));
  Retargeter<> r(fence->mesh, a);
  REQUIRE(r.status().ok());
  for (const int more : {-1, 2}) {
    INFO(more << " more pickets");
    params["pickets"] = 3 + more;
    const auto want = families::generate("fence", params);
    std::vector<int> steps(a.principal.size(), 0);
    steps[0] = more;
    const auto out = r.retarget(*lattice_steps_from_principal(a, steps));
    REQUIRE(out.ok());
    check_has_real_part(out->mesh, want->mesh);
    CHECK(symmetric_surface_distance(out->mesh, want->mesh, 0.01) < 1e-4 * bounding_box(want->mesh).size().norm());
    CHECK(out->report.boundary_edges_new() == 0);
  }
}

TEST_CASE("a repeat of the vertices that is a detail of one part (three ribs at one end of a long bar) is no "
          "candidate",
          "[candidates][analysis]") {
  Mesh m;
  add_box(m, Vector3d(0, 0, 0), Vector3d(10, 1, 1));
  for (int i = 0; i < 3; ++i) add_box(m, Vector3d(1 + 0.3 * i, 1, 0.2), Vector3d(1.1 + 0.3 * i, 1.2, 0.8));
  AnalysisOptions<> options;
  const Result<Analysis> a = analyze(m, options);
  REQUIRE(a.ok());
  for (const RepeatCandidate& c : a->candidates) CHECK(c.reason != "vertices");
  for (const Vector3d& p : a->principal_model_units()) CHECK(!recovered(Vector3d(0.3, 0, 0), {p}, 1e-3, 0.1));
  // The same ribs along the whole bar are its content: then the vertices' repeat is a candidate (or the
  // matching finds the rib pitch itself).
  Mesh full;
  add_box(full, Vector3d(0, 0, 0), Vector3d(10, 1, 1));
  for (int i = 0; i < 30; ++i) add_box(full, Vector3d(0.1 + 0.3 * i, 1, 0.2), Vector3d(0.2 + 0.3 * i, 1.2, 0.8));
  const Result<Analysis> b = analyze(full, options);
  REQUIRE(b.ok());
  std::vector<Vector3d> found = b->principal_model_units();
  for (const RepeatCandidate& c : b->candidates) found.push_back(b->model_units(c));
  CHECK(recovered(Vector3d(0.3, 0, 0), found, 1e-4, 0.01));
}

TEST_CASE("a size along an axis uses the candidate there with the most copies, and a multiple of a shorter "
          "candidate is none",
          "[candidates]") {
  // Of a pair of five bays (listed first, as pairs are) and the bay the vertices repeat at forty times, a size
  // along x uses the bay; of two candidates with as many copies, the first.
  Analysis a;
  RepeatCandidate five_bays, bay;
  five_bays.offset = Vector3d(0.5, 0.05, 0), five_bays.copies = 2, five_bays.reason = "pair";
  bay.offset = Vector3d(0.1, 0, 0), bay.copies = 40, bay.reason = "vertices";
  a.candidates = {five_bays, bay};
  CHECK(a.candidates_for_axes({{true, false, false}}) == std::vector<int>{1});
  CHECK(a.candidates_for_axes({{false, true, true}}).empty());
  a.candidates[1].copies = 2;
  CHECK(a.candidates_for_axes({{true, false, false}}) == std::vector<int>{0});

  // collect_candidates: a pair eight pitches long is a multiple of the pitch the vertices repeat at, listed
  // after it, and is dropped; a pair off the pitch's line is not.
  Analysis b;
  DominantOffset pair, pitch, other;
  pair.offset = Vector3d(0.8, 0, 0);
  for (const char* t : {"votes", "overlap", "contrast"}) record_test(pair.tests, t, 1, 0);
  record_test(pair.tests, "repeat", 0, 0.25);  // two copies: a pattern test failed
  pitch.offset = Vector3d(0.1, 0, 0);
  pitch.copies = 8;
  record_test(pitch.tests, "vertex_lag", 100, 8);
  record_test(pitch.tests, "vertex_structure", 1, 0.5);
  record_test(pitch.tests, "pattern_contrast", 0, 0.01);  // no pattern on the surface: still a candidate
  other = pair;
  other.offset = Vector3d(0.8, 0.3, 0);
  b.dominant = {pair, other, pitch};
  REQUIRE(b.dominant[0].is_pair());
  REQUIRE(b.dominant[2].from_vertices());
  detail::collect_candidates(0.02, b);
  REQUIRE(b.candidates.size() == 2);
  CHECK(b.candidates[0].dominant == 1);
  CHECK(b.candidates[1].dominant == 2);
  CHECK(b.candidates[1].reason == "vertices");
  CHECK(b.candidates[1].copies == 8);
}
