// Fault injection: with any one allocation made to fail, every public entry point returns a Status
// (too_large, "... out of memory ...") instead of letting std::bad_alloc escape, and a failed call leaves
// nothing behind that changes a later one (a Retargeter's caches, for one).
//
// This file replaces the global operator new/delete of the test binary. Disarmed (the default) they are
// malloc and free; armed with a countdown k, the k-th allocation from then on throws std::bad_alloc, once.
// Each sweep first counts the allocations a call makes, then fails each of them in turn (or an even spread
// of them when there are many). Allocations Eigen makes itself (it calls malloc) are not reached; every
// standard container's are.
#include <atomic>
#include <catch2/catch.hpp>
#include <climits>
#include <fstream>
#include <memory>
#include <cstdlib>
#include <map>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "restitch/descriptor/xyzn.hpp"
#include "restitch/families/families.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/restitch.hpp"
#include "restitch/solver/mrf_io.hpp"

namespace {

std::atomic<long long> g_countdown{-1};  // allocations to let through before the failing one; < 0: off
std::atomic<long long> g_seen{0};        // allocations seen while armed
std::atomic<bool> g_fired{false};

void* allocate(std::size_t n) {
  if (g_countdown.load(std::memory_order_relaxed) >= 0) {
    g_seen.fetch_add(1, std::memory_order_relaxed);
    if (g_countdown.fetch_sub(1, std::memory_order_relaxed) == 0) {
      g_fired.store(true, std::memory_order_relaxed);
      throw std::bad_alloc();
    }
  }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}

}  // namespace

// Every form that pairs with the plain delete is replaced, so new and delete always meet (AddressSanitizer
// checks it). The nothrow forms are not failed: their callers take a null as "use less memory" and go on
// (std::stable_sort's temporary buffer), which is no error to report.
void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return std::malloc(n ? n : 1); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return std::malloc(n ? n : 1); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace {

using restitch::Status;
using restitch::StatusCode;

struct SweepResult {
  long long allocations = 0;             // made by the call, undisturbed
  int runs = 0;                          // calls with one allocation failed
  int escaped = 0;                       // of which let an exception out
  std::map<std::string, int> codes;      // the codes returned, with how often
  std::string first_wrong;               // the first status that is not too_large/out of memory
};

// Counts the allocations of `call` (a Status-returning callable), then fails allocation k for
// `max_runs` values of k spread evenly over them (all of them when there are fewer), calling `after`
// undisturbed after each faulted call.
template <class Call, class After>
SweepResult sweep(Call&& call, int max_runs, After&& after) {
  SweepResult out;
  g_seen = 0;
  g_countdown = LLONG_MAX;
  const Status reference = call();
  g_countdown = -1;
  out.allocations = g_seen;
  INFO(reference.message());
  REQUIRE(reference.ok());
  REQUIRE(out.allocations > 0);
  std::vector<long long> ks;
  if (out.allocations <= max_runs) {
    for (long long k = 0; k < out.allocations; ++k) ks.push_back(k);
  } else {
    for (int i = 0; i < max_runs; ++i) ks.push_back(i * (out.allocations - 1) / (max_runs - 1));
  }
  for (const long long k : ks) {
    g_fired = false;
    Status s;
    bool escaped = false;
    g_countdown = k;
    try {
      s = call();
    } catch (...) {
      escaped = true;
    }
    g_countdown = -1;
    if (!g_fired) continue;  // this run made fewer allocations (nothing was failed)
    ++out.runs;
    if (escaped) {
      ++out.escaped;
      continue;
    }
    ++out.codes[restitch::to_string(s.code())];
    const bool right = s.code() == StatusCode::too_large && s.message().find("out of memory") != std::string::npos;
    if (!right && out.first_wrong.empty())
      out.first_wrong = "allocation " + std::to_string(k) + ": " + restitch::to_string(s.code()) + " " + s.message();
    after();
  }
  return out;
}

template <class Call>
SweepResult sweep(Call&& call, int max_runs) {
  return sweep(std::forward<Call>(call), max_runs, [] {});
}

void check_sweep(const SweepResult& r) {
  std::ostringstream codes;
  for (const auto& kv : r.codes) codes << kv.first << ": " << kv.second << "  ";
  INFO("allocations " << r.allocations << ", faulted runs " << r.runs << ", codes " << codes.str());
  INFO(r.first_wrong);
  CHECK(r.runs > 0);
  CHECK(r.escaped == 0);
  CHECK(r.codes.size() == 1);
  CHECK(r.codes.count("too_large") == 1);
  CHECK(r.first_wrong.empty());
}

const restitch::families::SampleModel& small_sample() {
  static const restitch::families::SampleModel s = [] {
    auto r = restitch::families::generate("pin_header", {{"pins", 4}});
    REQUIRE(r.ok());
    return *r;
  }();
  return s;
}

// Coarse samples, so that one analysis is a few milliseconds and a sweep of them stays short.
restitch::AnalysisOptions<> coarse() {
  restitch::AnalysisOptions<> o;
  o.dense_spacing = 0.04;
  o.feature_spacing = 0.12;
  o.vertex_cap = 200;
  return o;
}

const restitch::Analysis& small_analysis() {
  static const restitch::Analysis a = [] {
    auto r = restitch::analyze(small_sample().mesh, coarse());
    INFO(r.status().message());
    REQUIRE(r.ok());
    REQUIRE(!r->principal.empty());
    return *r;
  }();
  return a;
}

bool same_mesh(const restitch::Mesh& a, const restitch::Mesh& b) {
  return a.V == b.V && a.F == b.F && a.FG == b.FG && a.N == b.N;
}

}  // namespace

TEST_CASE("fault injection: the operator new of this binary fails the allocation it is told to, once",
          "[fault]") {
  bool threw = false;
  std::vector<std::unique_ptr<int>> kept;
  kept.reserve(8);  // the vector allocates nothing while armed
  g_fired = false;
  g_countdown = 2;
  try {
    for (int i = 0; i < 5; ++i) kept.push_back(std::make_unique<int>(i));
  } catch (const std::bad_alloc&) {
    threw = true;
  }
  g_countdown = -1;
  CHECK(threw);
  CHECK(g_fired);
  CHECK(kept.size() == 2);  // the first two went through, the third failed
}

TEST_CASE("fault injection: glTF load and save return out of memory around tinygltf's JSON code", "[fault]") {
  // tinygltf's JSON reading and writing (nlohmann::json 3.11.2, Debian's) are not exception safe: an
  // allocation that fails inside them leaves a json value whose type says object with no object, and
  // its destructor then asserts or crashes (measured: 1 of the first 10 allocations of
  // save_glb_to_memory, and the parse of load_gltf_from_memory ends in std::terminate). What restitch
  // runs before and after them is swept here, under the guard that the entry points run it under:
  // decoding the parsed model into a Mesh, and building the model to write.
  auto glb = restitch::save_glb_to_memory(small_sample().mesh);
  REQUIRE(glb.ok());
  const std::vector<std::uint8_t> bytes = *glb;
  tinygltf::Model parsed;
  restitch::GltfLoadReport report;
  REQUIRE(restitch::detail::parse_model(bytes.data(), bytes.size(), "", true, parsed, report).ok());
  const restitch::GltfLimits limits;
  check_sweep(sweep(
      [&] {
        return restitch::detail::guarded("load_gltf_from_memory", [&]() -> Status {
          restitch::Mesh mesh;
          restitch::GltfLoadReport r;
          return restitch::detail::build_mesh(parsed, mesh, r, limits);
        });
      },
      200));
  check_sweep(sweep(
      [&] {
        return restitch::detail::guarded("save_glb_to_memory", [&]() -> Status {
          tinygltf::Model m;
          return restitch::detail::build_model(small_sample().mesh, m);
        });
      },
      200, [&] {
        auto again = restitch::save_glb_to_memory(small_sample().mesh);  // nothing left behind
        REQUIRE(again.ok());
        CHECK(*again == bytes);
      }));
}

TEST_CASE("fault injection: generating a sample and analysing it return out of memory, never throw",
          "[fault]") {
  // The arguments are built outside the sweeps: their allocations are the caller's.
  const std::string name = "pin_header";
  const std::map<std::string, double> params{{"pins", 4}};
  check_sweep(sweep([&] { return restitch::families::generate(name, params).status(); }, 60));
  const restitch::AnalysisOptions<> options = coarse();
  check_sweep(sweep([&] { return restitch::analyze(small_sample().mesh, options).status(); }, 40));
  const std::vector<Eigen::Vector3d> offsets{small_analysis().principal_model_units().front()};
  restitch::Analysis expected = small_analysis();
  REQUIRE(restitch::promote_offsets(small_sample().mesh, options, offsets, expected).ok());
  REQUIRE(expected.promoted.size() == 1);
  restitch::Analysis a = expected;  // a promotion replaces the earlier one: each call gives `expected` again
  check_sweep(sweep([&] { return restitch::promote_offsets(small_sample().mesh, options, offsets, a); }, 25, [&] {
    // a failed promotion leaves the analysis as it was
    CHECK(a.promoted == expected.promoted);
    CHECK(a.lattice.A == expected.lattice.A);
    CHECK(a.dominant.size() == expected.dominant.size());
  }));
}

TEST_CASE("fault injection: a Retargeter that failed for memory resizes as if it never had", "[fault]") {
  const restitch::Mesh& mesh = small_sample().mesh;
  const restitch::Analysis& a = small_analysis();
  const Eigen::Array3i steps(1, 0, 0);
  auto fresh = restitch::retarget(mesh, a, steps);
  REQUIRE(fresh.ok());
  const restitch::Mesh expected = fresh->mesh;

  check_sweep(sweep(
      [&] {
        restitch::Retargeter<> r(mesh, a);
        return r.status();
      },
      60));
  // One Retargeter, faulted again and again: every later undisturbed call gives the fresh result.
  restitch::Retargeter<> r(mesh, a);
  REQUIRE(r.status().ok());
  check_sweep(sweep([&] { return r.retarget(steps).status(); }, 80, [&] {
    auto again = r.retarget(steps);
    REQUIRE(again.ok());
    CHECK(same_mesh(again->mesh, expected));
  }));
  check_sweep(sweep([&] { return r.retarget({-1, 0, 0}).status(); }, 40));
  check_sweep(sweep([&] { return r.labelling_problem(Eigen::Array3i(2, 0, 0)).status(); }, 40));
}

TEST_CASE("fault injection: the MRF and xyzn readers and their consumers return out of memory", "[fault]") {
  const std::string mrf =
      "restitch-mrf 1\n"
      "nodes 3 labels 2 edges 2\n"
      "0 1\n1 0\n0.5 0.5\n"
      "0 1\n0 1\n1 0\n"
      "1 2\n0 2\n2 0\n";
  const std::string mrf_name = "chain.mrf", xyzn_name = "grid.xyzn";
  check_sweep(sweep([&] { return restitch::parse_mrf(mrf, mrf_name).status(); }, 100));
  auto problem = restitch::parse_mrf(mrf, mrf_name);
  REQUIRE(problem.ok());
  check_sweep(sweep(
      [&] {
        std::vector<int> labels;
        restitch::SolveReport report;
        return restitch::AlphaExpansion<>().solve(*problem, labels, report, restitch::Progress());
      },
      100));

  std::ostringstream xyzn;
  for (int i = 0; i < 40; ++i)
    xyzn << (i % 5) * 0.1 << ' ' << (i / 5) * 0.1 << " 0 0 0 1\n";
  const std::string xyzn_text = xyzn.str();
  check_sweep(sweep([&] { return restitch::parse_xyzn(xyzn_text, xyzn_name).status(); }, 100));
  auto points = restitch::parse_xyzn(xyzn_text, xyzn_name);
  REQUIRE(points.ok());
  check_sweep(sweep(
      [&] {
        restitch::DescriptorMatrix d;
        return restitch::ShotDescriptor{0.3f}.compute(*points, *points, d, restitch::Progress());
      },
      100));
}
