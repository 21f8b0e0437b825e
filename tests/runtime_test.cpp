// Tests for restitch/runtime.hpp: policies chosen by name give exactly what
// the templated calls give; unknown names are refused with the known ones listed.
#include "restitch/runtime.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "restitch/detail/parallel.hpp"
#include "restitch/families/families.hpp"

using restitch::Analysis;
using restitch::AnalysisOptions;
using restitch::AnyRetargeter;
using restitch::Mesh;
using restitch::StatusCode;

namespace {

// A small pin header (5 pins): its analysis takes well under a second.
const Mesh& small_mesh() {
  static const Mesh mesh = [] {
    auto s = restitch::families::generate("pin_header", {{"pins", 5}});
    REQUIRE(s.ok());
    return s->mesh;
  }();
  return mesh;
}

const Analysis& default_analysis() {
  static const Analysis a = [] {
    auto r = restitch::analyze(small_mesh());
    REQUIRE(r.ok());
    return *r;
  }();
  return a;
}

template <class D, class M>
void check_same_as_templated(const std::string& descriptor, const std::string& matcher) {
  INFO(descriptor << " + " << matcher);
  auto named = restitch::analyze_named(small_mesh(), descriptor, matcher);
  REQUIRE(named.ok());
  auto templated = restitch::analyze(small_mesh(), AnalysisOptions<D, M>{});
  REQUIRE(templated.ok());
  CHECK(named->descriptor_name == descriptor);
  CHECK(named->matcher_name == matcher);
  CHECK(named->descriptors.cols() == D().dimension());
  CHECK(named->descriptors == templated->descriptors);
  CHECK(named->matches == templated->matches);
  CHECK(named->principal == templated->principal);
  CHECK(named->lattice.A == templated->lattice.A);
  CHECK(named->lattice.origin == templated->lattice.origin);
  CHECK((named->lattice.cells == templated->lattice.cells).all());
}

bool same_mesh(const Mesh& a, const Mesh& b) { return a.V == b.V && a.F == b.F && a.FG == b.FG && a.N == b.N; }

}  // namespace

TEST_CASE("runtime: the name lists are the shipped policies", "[runtime]") {
  CHECK(restitch::descriptor_names() == std::vector<std::string>{"shot", "fpfh"});
  CHECK(restitch::matcher_names() == std::vector<std::string>{"brute_force", "reduced"});
  CHECK(restitch::label_space_names() == std::vector<std::string>{"lattice", "regular"});
  // The names are the policies' own report names.
  CHECK(restitch::policy_name(restitch::ShotDescriptor{}) == "shot");
  CHECK(restitch::policy_name(restitch::FpfhDescriptor{}) == "fpfh");
  CHECK(restitch::policy_name(restitch::BruteForceMatcher{}) == "brute_force");
  CHECK(restitch::policy_name(restitch::ReducedMatcher{}) == "reduced");
  CHECK(std::string(restitch::LatticeLabels::name) == "lattice");
  CHECK(std::string(restitch::RegularLabels::name) == "regular");
}

TEST_CASE("runtime: analyze_named runs the named descriptor and matcher, as the templated call does", "[runtime]") {
  check_same_as_templated<restitch::ShotDescriptor, restitch::BruteForceMatcher>("shot", "brute_force");
  check_same_as_templated<restitch::ShotDescriptor, restitch::ReducedMatcher>("shot", "reduced");
  check_same_as_templated<restitch::FpfhDescriptor, restitch::BruteForceMatcher>("fpfh", "brute_force");
  check_same_as_templated<restitch::FpfhDescriptor, restitch::ReducedMatcher>("fpfh", "reduced");
  // The defaults are shot + brute_force.
  auto def = restitch::analyze_named(small_mesh());
  REQUIRE(def.ok());
  CHECK(def->descriptor_name == "shot");
  CHECK(def->matcher_name == "brute_force");
  CHECK(def->descriptors == default_analysis().descriptors);
}

TEST_CASE("runtime: analyze_named passes bad meshes and progress through", "[runtime]") {
  CHECK(restitch::analyze_named(Mesh{}, "fpfh", "reduced").status().code() == StatusCode::invalid_mesh);
  bool called = false;
  const restitch::Progress stop([&](std::string_view, double) {
    called = true;
    return false;
  });
  CHECK(restitch::analyze_named(small_mesh(), "fpfh", "reduced", stop).status().code() == StatusCode::cancelled);
  CHECK(called);
}

TEST_CASE("runtime: unknown names are invalid_argument listing the known ones", "[runtime]") {
  auto d = restitch::analyze_named(small_mesh(), "sift", "brute_force");
  REQUIRE_FALSE(d.ok());
  CHECK(d.status().code() == StatusCode::invalid_argument);
  CHECK_THAT(d.status().message(), Catch::Contains("descriptor") && Catch::Contains("'sift'") &&
                                       Catch::Contains("shot") && Catch::Contains("fpfh"));
  for (const char* desc : {"shot", "fpfh"}) {
    auto m = restitch::analyze_named(small_mesh(), desc, "kdtree");
    REQUIRE_FALSE(m.ok());
    CHECK(m.status().code() == StatusCode::invalid_argument);
    CHECK_THAT(m.status().message(), Catch::Contains("matcher") && Catch::Contains("'kdtree'") &&
                                         Catch::Contains("brute_force") && Catch::Contains("reduced"));
  }
  // Names are exact.
  CHECK(restitch::analyze_named(small_mesh(), "", "brute_force").status().code() == StatusCode::invalid_argument);
  CHECK(restitch::analyze_named(small_mesh(), "shot ", "brute_force").status().code() == StatusCode::invalid_argument);

  AnyRetargeter r(small_mesh(), default_analysis(), "hex");
  CHECK(r.status().code() == StatusCode::invalid_argument);
  CHECK_THAT(r.status().message(), Catch::Contains("label space") && Catch::Contains("'hex'") &&
                                       Catch::Contains("lattice") && Catch::Contains("regular"));
  CHECK(r.retarget({1, 0, 0}).status().code() == StatusCode::invalid_argument);
  CHECK(r.labelling_problem({1, 0, 0}).status().code() == StatusCode::invalid_argument);
  CHECK(r.steps_for_size({1, 1, 1}).status().code() == StatusCode::invalid_argument);
}

TEST_CASE("runtime: AnyRetargeter gives what Retargeter<LabelSpace> gives", "[runtime]") {
  const Analysis& a = default_analysis();
  REQUIRE(a.principal.size() == 1);
  auto steps = restitch::lattice_steps_from_principal(a, {2});
  REQUIRE(steps.ok());
  const Eigen::Vector3d size = restitch::bounding_box(small_mesh()).size();
  const Eigen::Vector3d target = size + 1.2 * a.principal_model_units()[0].cwiseAbs();

  auto compare = [&](auto& typed, AnyRetargeter& any) {
    REQUIRE(any.status().ok());
    REQUIRE(typed.status().ok());
    auto x = any.retarget(*steps);
    auto y = typed.retarget(*steps);
    REQUIRE(x.ok());
    REQUIRE(y.ok());
    CHECK(same_mesh(x->mesh, y->mesh));
    CHECK(x->report.labels == y->report.labels);
    CHECK(x->report.energy == y->report.energy);
    CHECK((x->report.grid_steps == y->report.grid_steps).all());
    CHECK(x->grid.A == typed.grid().A);
    auto px = any.labelling_problem(*steps);
    auto py = typed.labelling_problem(*steps);
    REQUIRE(px.ok());
    REQUIRE(py.ok());
    CHECK(px->node_count() == py->node_count());
    CHECK(px->label_count() == py->label_count());
    CHECK(px->edge_count() == py->edge_count());
    auto sx = any.steps_for_size(target);
    auto sy = typed.steps_for_size(target);
    REQUIRE(sx.ok());
    REQUIRE(sy.ok());
    CHECK((*sx == *sy).all());
    return x->report.labels;
  };

  restitch::Retargeter<restitch::LatticeLabels> lattice(small_mesh(), a);
  AnyRetargeter any_lattice(small_mesh(), a, "lattice");
  const int lattice_labels = compare(lattice, any_lattice);
  CHECK(lattice_labels == 3);

  restitch::Retargeter<restitch::RegularLabels> regular(small_mesh(), a);
  AnyRetargeter any_regular(small_mesh(), a, "regular");
  const int regular_labels = compare(regular, any_regular);
  CHECK(regular_labels > lattice_labels);  // really the other label space

  // The default label space is the lattice.
  AnyRetargeter def(small_mesh(), a);
  auto p = def.labelling_problem(*steps);
  REQUIRE(p.ok());
  CHECK(p->label_count() == lattice_labels);

  // Options reach the retargeter.
  restitch::RetargetOptions tiny;
  tiny.max_problem_size = 4;
  AnyRetargeter limited(small_mesh(), a, "lattice", tiny);
  CHECK(limited.retarget(*steps).status().code() == StatusCode::too_large);
}

TEST_CASE("parallel_tasks runs every task once, reports on the caller, stops on cancel and on a throw",
          "[threads]") {
  const std::thread::id caller = std::this_thread::get_id();
  for (int threads : {0, 1, 2, 3, 8}) {
    INFO("threads " << threads);
    for (std::size_t tasks : {std::size_t(0), std::size_t(1), std::size_t(7), std::size_t(100)}) {
      std::vector<std::atomic<int>> runs(tasks);
      std::vector<std::size_t> ticks;
      bool elsewhere = false;
      const bool finished = restitch::detail::parallel_tasks(
          threads, tasks, [&](std::size_t t, int) { runs[t].fetch_add(1); },
          [&](std::size_t done) {
            elsewhere = elsewhere || std::this_thread::get_id() != caller;
            ticks.push_back(done);
            return true;
          });
      CHECK(finished);
      CHECK_FALSE(elsewhere);
      for (const auto& r : runs) CHECK(r.load() == 1);
      CHECK(std::is_sorted(ticks.begin(), ticks.end()));
      for (std::size_t d : ticks) CHECK((d >= 1 && d <= tasks));
      if (tasks > 0) CHECK((!ticks.empty() && ticks.back() == tasks));  // the last tick says all done
    }
    // A cancel at the first tick stops the loop and the call says so, whoever ran the tasks (on one
    // thread, right after the first task).
    std::atomic<int> ran{0};
    CHECK_FALSE(restitch::detail::parallel_tasks(
        threads, 10000, [&](std::size_t, int) { ran.fetch_add(1); }, [](std::size_t) { return false; }));
    if (restitch::resolve_threads(threads) == 1) CHECK(ran.load() == 1);
    // A task's exception reaches the caller after every worker stopped.
    CHECK_THROWS_AS(restitch::detail::parallel_tasks(
                        threads, 50,
                        [](std::size_t t, int) {
                          if (t == 3) throw std::runtime_error("task 3");
                        },
                        [](std::size_t) { return true; }),
                    std::runtime_error);
  }
#if !(defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__))
  CHECK(restitch::resolve_threads(3) == 3);
#endif
  CHECK(restitch::resolve_threads(0) >= 1);
}
