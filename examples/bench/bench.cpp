// restitch benchmark: prints figures as tables and writes them as JSON.
//
//   bench [--quick] [--json FILE] [--models DIR] [--only SECTION] [--family NAME]   (default FILE: bench.json)
//
// 1. analysis: time per stage on the samples at growing sizes (~2k to ~1M triangles; --quick: to
//    ~20k), on one thread and on every hardware thread, peak memory, the growth exponent, and
//    (unless --quick) the real models of --models DIR
// 2. shot: SHOT points per second on 3000 points with ~74 neighbours each
// 3. comparison: the paper's Fig. 1 / Fig. 8: each sample at one target size
//    (+2 steps along its first principal offset) with lattice labels and with
//    the regular-grid baseline: nodes, labels, solve ms, final energy
// 4. scaling: solve and stitch time against nodes x labels and against triangles
// 5. synthetic: a 10x10x10 grid, 26-neighbourhood, 30 labels (truncated linear)
// 6. detectors: the histogram and the autocorrelation offset detector on every
//    family (which true generators each recovers, time per stage) and, unless
//    --quick, on the real models in --models DIR (default ../shared/models)
//
// 7. counts (not with --quick): every family, generated at 2 to 10 modules and resized
//    from each count to the size of every other with the defaults, compared in place with the family generated
//    at that count (bounding box and surface distance within 1e-4 of the diagonal; open boundary length; results
//    with open edges that are no copies of the input's)
// 8. parameters (not with --quick): the families with their lengths drawn within 0.7..1.3 of the defaults (six
//    seeded sets; --seeds FIRST..LAST for others), from 3, 5 and 7 modules (--from) to n - 1 and n + 2 (--to FIRST..LAST:
//    every count there), judged as in 7; what is not exact (or warned) is printed with its parameters
// 9. vertex_repeats (not with --quick): the analysis time without and with the repeats of the vertices
//    (docs/method.md 1.14), each family at its defaults and each real model of --models DIR
// 10. long (not with --quick): every family at 12 to 40 modules, resized to n - 1 and n + 2 and judged as in 7,
//    and whether the period found along its repeat is the family's
//
//   bench --only detectors     runs section 6 alone
//   --family NAME              sections 7, 8 and 10 on that generated family alone
//
// Times are wall-clock (steady_clock), best of a few runs for the short ones.
// They are measurements of this machine, never asserted anywhere.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <sys/resource.h>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "restitch/families/families.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/io/json_report.hpp"
#include "restitch/restitch.hpp"
#include "restitch/runtime.hpp"
#include "../../tests/support/boundary_length.hpp"
#include "../../tests/support/surface_distance.hpp"

using namespace restitch;
using clock_type = std::chrono::steady_clock;

namespace {

double ms_since(clock_type::time_point t) {
  return std::chrono::duration<double, std::milli>(clock_type::now() - t).count();
}

template <class F>
double best_of(int n, F&& f) {
  double best = INFINITY;
  for (int i = 0; i < n; ++i) {
    const auto t = clock_type::now();
    f();
    best = std::min(best, ms_since(t));
  }
  return best;
}

// The sample with the smallest detail level giving at least `triangles`.
families::SampleModel sample_near(const std::string& family, std::size_t triangles) {
  for (int detail = 1; detail <= 64; ++detail) {
    auto s = families::generate(family, {{"detail", double(detail)}});
    if (s && (s->mesh.triangle_count() >= triangles || detail == 64)) return std::move(*s);
    if (!s) break;
  }
  return std::move(*families::generate(family));
}

int first_real_axis(const Analysis& a) {
  for (int c = 0; c < 3; ++c)
    if (!a.lattice.dummy[c]) return c;
  return -1;
}

}  // namespace

namespace {

// Peak resident memory of this process so far, in MB (getrusage; a running maximum, so each size
// is run in increasing order and its figure includes everything before it).
double peak_rss_mb() {
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

// One analysis with `threads` workers; the timings and the total wall-clock time.
template <class M = BruteForceMatcher>
Result<Analysis> timed_analysis(const Mesh& mesh, int threads, double& total_ms) {
  AnalysisOptions<ShotDescriptor, M> options;
  options.threads = threads;
  const auto t = clock_type::now();
  Result<Analysis> a = analyze(mesh, options);
  total_ms = ms_since(t);
  return a;
}

// Least-squares slope of log(ms) against log(triangles): the measured growth exponent.
double growth_exponent(const std::vector<std::pair<double, double>>& tris_ms) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& [t, ms] : tris_ms) {
    const double x = std::log(t), y = std::log(ms);
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return n >= 2 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : NAN;
}

// 1. Analysis per stage at growing sizes, on one thread and on every hardware thread; the growth
// exponent; the real models of --models DIR.
void bench_analysis(const std::vector<std::size_t>& sizes, const std::string& models, bool quick,
                    nlohmann::json& out) {
  const int all = resolve_threads(0);
  std::printf(
      "== analysis: ms per stage on 1 thread (library defaults: SHOT, brute-force matcher); total on %d threads;\n"
      "   cli: the command line's defaults (reduced matcher, %d threads)\n",
      all, all);
  std::printf("%-15s %8s %8s %9s %9s %9s %9s %9s %9s %9s %9s %7s %9s %8s\n", "sample", "tris", "features", "sampling",
              "descript", "matching", "histogr", "refine", "lattice", "total", "total/N", "speedup", "cli", "peak MB");
  for (const std::string& family : {std::string("bookshelf"), std::string("fence")}) {
    std::vector<std::pair<double, double>> growth;
    for (std::size_t target : sizes) {
      families::SampleModel s = sample_near(family, target);
      double total = 0, total_all = 0;
      auto a = timed_analysis(s.mesh, 1, total);
      if (!a) {
        std::printf("%s: %s\n", family.c_str(), a.status().message().c_str());
        continue;
      }
      auto b = timed_analysis(s.mesh, all, total_all);
      double total_cli = 0;
      auto c = timed_analysis<ReducedMatcher>(s.mesh, all, total_cli);
      const bool same = b && c && b->matches == a->matches && c->matches == a->matches && b->principal == a->principal;
      auto ms = [&](const char* k) { return a->timings_ms.count(k) ? a->timings_ms.at(k) : 0.0; };
      const double peak = peak_rss_mb();
      std::printf("%-15s %8zu %8lld %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %7.2f %9.1f %8.0f%s\n",
                  family.c_str(), s.mesh.triangle_count(), (long long)a->features.points.rows(), ms("sampling"),
                  ms("descriptors"), ms("matching"), ms("histogram"), ms("refinement"), ms("lattice"), total,
                  total_all, total / total_all, total_cli, peak, same ? "" : "  (RESULTS DIFFER)");
      growth.emplace_back(double(s.mesh.triangle_count()), total);
      out["analysis"].push_back({{"sample", family},
                                 {"triangles", s.mesh.triangle_count()},
                                 {"features", a->features.points.rows()},
                                 {"dense", a->dense.points.rows()},
                                 {"timings_ms", a->timings_ms},
                                 {"total_ms", total},
                                 {"threads", all},
                                 {"total_ms_threads", total_all},
                                 {"total_ms_cli", total_cli},
                                 {"same_result_threads", same},
                                 {"peak_rss_mb", peak},
                                 {"principal", a->principal.size()}});
    }
    const double e = growth_exponent(growth);
    std::printf("%-15s growth exponent (1 thread, %.0f to %.0f triangles): %.2f\n", family.c_str(),
                growth.empty() ? 0.0 : growth.front().first, growth.empty() ? 0.0 : growth.back().first, e);
    out["analysis_growth"][family] = e;
  }
  if (quick) return;
  std::printf(
      "\n== analysis of the real models in %s (ms: total on 1 and %d threads; matching alone, brute force and\n"
      "   reduced, 1 thread; cli: total with the command line's defaults, reduced matcher on %d threads)\n",
      models.c_str(), all, all);
  std::printf("%-36s %8s %9s %9s %7s %9s %9s %9s\n", "model", "tris", "1 thread", "N threads", "speedup", "matching",
              "reduced", "cli");
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(models))
    for (const auto& e : std::filesystem::directory_iterator(models))
      if (e.path().extension() == ".glb") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    auto mesh = load_gltf(f.string());
    if (!mesh) continue;
    double one = 0, many = 0, red = 0;
    auto a = timed_analysis(*mesh, 1, one);
    auto b = timed_analysis(*mesh, all, many);
    auto r = timed_analysis<ReducedMatcher>(*mesh, 1, red);
    double cli = 0;
    auto c = timed_analysis<ReducedMatcher>(*mesh, all, cli);
    if (!a || !b || !r || !c) continue;
    const bool same = b->matches == a->matches && r->matches == a->matches && c->matches == a->matches &&
                      b->principal == a->principal;
    const double match_ms = a->timings_ms.count("matching") ? a->timings_ms.at("matching") : 0.0;
    const double red_ms = r->timings_ms.count("matching") ? r->timings_ms.at("matching") : 0.0;
    std::printf("%-36s %8zu %9.0f %9.0f %7.2f %9.0f %9.0f %9.0f%s\n", f.filename().string().c_str(),
                mesh->triangle_count(), one, many, one / many, match_ms, red_ms, cli, same ? "" : "  (RESULTS DIFFER)");
    out["analysis_models"].push_back({{"model", f.filename().string()},
                                      {"triangles", mesh->triangle_count()},
                                      {"total_ms", one},
                                      {"threads", all},
                                      {"total_ms_threads", many},
                                      {"matching_ms", match_ms},
                                      {"matching_ms_reduced", red_ms},
                                      {"total_ms_cli", cli},
                                      {"same_result", same}});
  }
}

// 2. SHOT speed: 3000 queries on the faces of a box, support = the same points.
void bench_shot(nlohmann::json& out) {
  {
    std::mt19937_64 rng(5);
    auto u = [&] { return float(double(rng() >> 11) * (1.0 / 9007199254740992.0)); };
    PointSet pts;
    const int n = 3000;
    pts.points.resize(n, 3);
    pts.normals.resize(n, 3);
    for (int i = 0; i < n; ++i) {
      const int face = int(rng() % 6), axis = face / 2;
      Eigen::Vector3f p(u(), u(), u()), nrm = Eigen::Vector3f::Zero();
      p[axis] = float(face % 2);
      nrm[axis] = face % 2 ? 1.f : -1.f;
      pts.points.row(i) = p;
      pts.normals.row(i) = nrm;
    }
    ShotDescriptor shot;
    shot.radius = 0.217f;  // 500 points per unit area: pi r^2 * 500 ~ 74 neighbours, as in the PCL figure
    DescriptorMatrix d;
    const double ms = best_of(5, [&] { shot.compute(pts, pts, d, {}); });
    std::size_t pairs = 0;  // neighbours per point, the query included (as PCL counts them)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        pairs += (pts.points.row(i) - pts.points.row(j)).squaredNorm() < shot.radius * shot.radius;
    std::printf(
        "\n== SHOT: %d points, radius %.3f, %.1f neighbours each: %.1f ms, %.0f points/s "
        "(PCL SHOTEstimation here: ~40-58k points/s)\n",
        n, shot.radius, double(pairs) / n, ms, n / (ms / 1000.0));
    out["shot"] = {{"points", n},
                   {"radius", shot.radius},
                   {"neighbours", double(pairs) / n},
                   {"ms", ms},
                   {"points_per_s", n / (ms / 1000.0)}};
  }
}

// 3. The paper's comparison: lattice labels vs the regular baseline. The solve stage is timed on one
// thread and on every hardware thread (RetargetOptions::threads; the same labels, checked), best of 3 calls.
void bench_label_spaces(const std::vector<std::string>& families, nlohmann::json& out) {
  const int n = resolve_threads(0);
  std::printf("\n== lattice vs regular labels, +2 steps along v1 (solve: best of 3 calls, 1 and %d threads)\n", n);
  std::printf("%-15s %-8s %7s %7s %10s %10s %12s %9s %9s\n", "sample", "labels", "nodes", "labels", "solve 1thr",
              ("solve " + std::to_string(n) + "thr").c_str(), "energy", "stitch", "tris out");
  double sums[2][2] = {{0, 0}, {0, 0}};
  for (const std::string& family : families) {
    auto s = families::generate(family);
    auto a = analyze(s->mesh);
    if (!a || a->principal.empty()) continue;
    Eigen::Array3i steps = Eigen::Array3i::Zero();
    steps[first_real_axis(*a)] = 2;
    int row = 0;
    for (const std::string space : {"lattice", "regular"}) {
      double best[2] = {1e300, 1e300};
      std::optional<RetargetResult> kept;
      bool same = true;
      for (int t = 0; t < 2; ++t) {
        RetargetOptions options;
        options.threads = t == 0 ? 1 : n;
        AnyRetargeter r(s->mesh, *a, space, options);
        for (int call = 0; call < 3; ++call) {
          auto res = r.retarget(steps);
          if (!res) {
            std::printf("%-15s %-8s %s\n", family.c_str(), space.c_str(), res.status().message().c_str());
            break;
          }
          best[t] = std::min(best[t], res->report.timings_ms.at("solve"));
          if (!kept) kept = std::move(*res);
          else same = same && res->cell_labels == kept->cell_labels && res->report.energy == kept->report.energy;
        }
      }
      if (!kept) continue;
      const RetargetReport& rep = kept->report;
      std::printf("%-15s %-8s %7d %7d %10.2f %10.2f %12.5g %9.2f %9zu%s\n", family.c_str(), space.c_str(), rep.nodes,
                  rep.labels, best[0], best[1], rep.energy, rep.timings_ms.at("stitch"), rep.triangles_out,
                  same ? "" : "  LABELS DIFFER BY THREAD COUNT");
      sums[row][0] += best[0], sums[row][1] += best[1];
      nlohmann::json j = retarget_json(rep);
      j["sample"] = family;
      j["label_space"] = space;
      j["solve_ms_1_thread"] = best[0];
      j["solve_ms_threads"] = best[1];
      j["threads"] = n;
      j["same_labels_whatever_threads"] = same;
      out["comparison"].push_back(j);
      ++row;
    }
  }
  std::printf("solve summed: lattice %.2f ms (1 thread), %.2f ms (%d); regular %.2f ms (1 thread), %.2f ms (%d)\n",
              sums[0][0], sums[0][1], n, sums[1][0], sums[1][1], n);
  out["comparison_solve_ms"] = {{"lattice", {{"1_thread", sums[0][0]}, {"threads", sums[0][1]}}},
                                {"regular", {{"1_thread", sums[1][0]}, {"threads", sums[1][1]}}},
                                {"threads", n}};
}

// 4a. Scaling with nodes x labels: the fence, more and more pickets added.
void bench_scaling_labels(bool quick, nlohmann::json& out) {
  std::printf("\n== scaling with nodes x labels (fence, detail 2)\n%7s %7s %7s %10s %10s %10s %10s\n", "steps", "nodes",
              "labels", "energy ms", "solve ms", "stitch ms", "total ms");
  {
    auto s = families::generate("fence");
    auto a = analyze(s->mesh);
    Retargeter<> r(s->mesh, *a);
    for (int k : {1, 2, 4, 8, 16, 32}) {
      if (quick && k > 8) break;
      Eigen::Array3i steps = Eigen::Array3i::Zero();
      steps[first_real_axis(*a)] = k;
      r.retarget(steps);  // warm the cell-distance cache: the slider's steady state
      auto res = r.retarget(steps);
      if (!res) continue;
      const auto& t = res->report.timings_ms;
      std::printf("%7d %7d %7d %10.2f %10.2f %10.2f %10.2f\n", k, res->report.nodes, res->report.labels, t.at("energy"),
                  t.at("solve"), t.at("stitch"), t.at("total"));
      out["scaling_labels"].push_back(
          {{"steps", k}, {"nodes", res->report.nodes}, {"labels", res->report.labels}, {"timings_ms", t}});
    }
  }
}

// 4b. Retarget (solve + stitch) against triangles: the bookshelf at growing detail, +2 columns.
void bench_scaling_triangles(const std::vector<std::size_t>& sizes, nlohmann::json& out) {
  std::printf(
      "\n== retarget after analysis against triangles (bookshelf, +2 columns, second call)\n%9s %10s %10s %10s %10s\n",
      "tris", "energy ms", "solve ms", "stitch ms", "total ms");
  for (std::size_t target : sizes) {
    families::SampleModel s = sample_near("bookshelf", target);
    auto a = analyze(s.mesh);
    if (!a || a->principal.empty()) continue;
    Retargeter<> r(s.mesh, *a);
    Eigen::Array3i steps = Eigen::Array3i::Zero();
    steps[first_real_axis(*a)] = 2;
    r.retarget(steps);
    double best = INFINITY;
    RetargetReport rep;
    for (int i = 0; i < 3; ++i) {
      auto res = r.retarget(steps);
      if (res && res->report.timings_ms.at("total") < best)
        best = res->report.timings_ms.at("total"), rep = res->report;
    }
    std::printf("%9zu %10.2f %10.2f %10.2f %10.2f\n", s.mesh.triangle_count(), rep.timings_ms["energy"],
                rep.timings_ms["solve"], rep.timings_ms["stitch"], rep.timings_ms["total"]);
    out["scaling_triangles"].push_back(
        {{"triangles", s.mesh.triangle_count()}, {"triangles_out", rep.triangles_out}, {"timings_ms", rep.timings_ms}});
  }
}

// 5. Synthetic: 1000 nodes x 30 labels, 26-neighbourhood, truncated linear.
void bench_synthetic(bool quick, nlohmann::json& out) {
  {
    const int side = 10, m = 30;
    TableMrf mrf(side * side * side, m);
    std::mt19937_64 rng(9);
    auto u = [&] { return double(rng() >> 11) * (1.0 / 9007199254740992.0); };
    for (int i = 0; i < mrf.node_count(); ++i)
      for (int l = 0; l < m; ++l) mrf.set_unary(i, l, 10.0 * u());
    auto id = [&](int x, int y, int z) { return x + side * (y + side * z); };
    std::vector<double> table(std::size_t(m * m));
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) table[std::size_t(a * m + b)] = std::min(std::abs(a - b), 4) * 1.0;
    for (int z = 0; z < side; ++z)
      for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int first = dz != 0 ? dz : (dy != 0 ? dy : dx);
                const int X = x + dx, Y = y + dy, Z = z + dz;
                if (first <= 0 || X < 0 || Y < 0 || Z < 0 || X >= side || Y >= side || Z >= side) continue;
                mrf.add_edge(id(x, y, z), id(X, Y, Z), table);
              }
    // The default back end (push-relabel) and Boykov-Kolmogorov's, the default before it.
    SolveReport rep, bk_rep;
    const double ms = best_of(quick ? 1 : 3, [&] {
      std::vector<int> labels(std::size_t(mrf.node_count()), 0);
      AlphaExpansion<>().solve(mrf, labels, rep, {});
    });
    const double bk_ms = best_of(quick ? 1 : 3, [&] {
      std::vector<int> labels(std::size_t(mrf.node_count()), 0);
      AlphaExpansion<BkMaxFlow<double>>().solve(mrf, labels, bk_rep, {});
    });
    // Moves proposed on every hardware thread (AlphaExpansion::threads): the same labels.
    const int n = resolve_threads(0);
    SolveReport par_rep;
    const double par_ms = best_of(quick ? 1 : 3, [&] {
      std::vector<int> labels(std::size_t(mrf.node_count()), 0);
      AlphaExpansion<> solver;
      solver.threads = n;
      solver.solve(mrf, labels, par_rep, {});
    });
    std::printf(
        "\n== synthetic: %d nodes x %d labels, %d edges (26-neighbourhood, truncated linear): %.1f ms, %d cycles, "
        "energy %.6g (BkMaxFlow back end: %.1f ms, energy %.6g; %d threads: %.1f ms, energy %.6g)\n",
        mrf.node_count(), m, mrf.edge_count(), ms, rep.cycles, rep.energy, bk_ms, bk_rep.energy, n, par_ms,
        par_rep.energy);
    out["synthetic"] = {{"nodes", mrf.node_count()}, {"labels", m},         {"edges", mrf.edge_count()},
                        {"ms", ms},                  {"cycles", rep.cycles}, {"energy", rep.energy},
                        {"bk_ms", bk_ms},            {"bk_energy", bk_rep.energy},
                        {"threads", n},              {"threads_ms", par_ms}, {"threads_energy", par_rep.energy}};
  }
}

// 6. The offset detectors side by side: time per stage and what each finds.
struct DetectorRun {
  Result<Analysis> analysis = error(StatusCode::internal, "not run");
  double total_ms = 0;
};

template <class Detector>
DetectorRun run_detector(const Mesh& mesh) {
  AnalysisOptions<ShotDescriptor, BruteForceMatcher, Detector> options;
  DetectorRun run;
  const auto t = clock_type::now();
  run.analysis = analyze(mesh, options);
  run.total_ms = ms_since(t);
  return run;
}

// True when g equals one of `found` up to sign, within 1% of its length and 1 degree.
bool recovered(const Eigen::Vector3d& g, const std::vector<Eigen::Vector3d>& found) {
  for (const Eigen::Vector3d& f : found) {
    const double cosine = std::abs(f.dot(g)) / (f.norm() * g.norm());
    if (std::abs(f.norm() - g.norm()) <= 0.01 * g.norm() && cosine >= std::cos(3.14159265358979323846 / 180))
      return true;
  }
  return false;
}

void bench_detector_model(const std::string& name, const Mesh& mesh, const std::vector<Eigen::Vector3d>* truth,
                          nlohmann::json& out, std::map<std::string, int>& score) {
  for (const std::string detector : {"histogram", "autocorrelation"}) {
    const DetectorRun run = detector == "histogram" ? run_detector<HistogramOffsetDetector>(mesh)
                                                    : run_detector<AutocorrelationOffsetDetector>(mesh);
    if (!run.analysis) {
      std::printf("%-34s %-15s %s\n", name.c_str(), detector.c_str(), run.analysis.status().message().c_str());
      continue;
    }
    const Analysis& a = *run.analysis;
    auto ms = [&](const char* k) { return a.timings_ms.count(k) ? a.timings_ms.at(k) : 0.0; };
    const std::vector<Eigen::Vector3d> principal = a.principal_model_units();
    std::string found;
    int hits = 0;
    if (truth) {
      for (const Eigen::Vector3d& g : *truth) hits += recovered(g, principal);
      found = std::to_string(hits) + "/" + std::to_string(truth->size()) + " true, ";
      score[detector] += hits;
    } else {
      score[detector] += principal.empty() ? 0 : 1;
    }
    found += std::to_string(principal.size()) + " principal:";
    nlohmann::json offsets = nlohmann::json::array();
    for (const Eigen::Vector3d& v : principal) {
      char buf[96];
      std::snprintf(buf, sizeof buf, " (%.4g, %.4g, %.4g)", v.x(), v.y(), v.z());
      found += buf;
      offsets.push_back({v.x(), v.y(), v.z()});
    }
    std::printf("%-34s %-15s %8.1f %8.1f %8.1f %8.1f %8.1f %8.1f %8.1f  %s\n", name.c_str(), detector.c_str(),
                ms("sampling"), ms("descriptors"), ms("matching"),
                ms(detector == "histogram" ? "histogram" : "autocorrelation"), ms("refinement"), ms("lattice"),
                run.total_ms, found.c_str());
    nlohmann::json j = {{"sample", name},
                        {"detector", detector},
                        {"triangles", mesh.triangle_count()},
                        {"timings_ms", a.timings_ms},
                        {"total_ms", run.total_ms},
                        {"principal", offsets},
                        {"peaks", a.histogram_peaks}};
    if (truth) j["generators_recovered"] = hits;
    out["detectors"].push_back(j);
  }
}

void bench_detectors(const std::vector<std::string>& families, const std::string& models, bool quick,
                     nlohmann::json& out) {
  std::printf(
      "\n== offset detectors: histogram vs autocorrelation (SHOT, brute force; ms per stage; the\n"
      "   autocorrelation detector skips matching); found: true generators recovered within 1%%\n");
  std::printf("%-34s %-15s %8s %8s %8s %8s %8s %8s %8s  %s\n", "model", "detector", "sampling", "descript", "matching",
              "peaks", "refine", "lattice", "total", "found");
  std::map<std::string, int> family_score, model_score;
  for (const std::string& family : families) {
    auto s = families::generate(family);
    if (s) bench_detector_model(family, s->mesh, &s->generators, out, family_score);
  }
  int model_count = 0;
  if (!quick && std::filesystem::is_directory(models)) {
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(models))
      if (e.path().extension() == ".glb") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    for (const std::string& f : files) {
      auto mesh = load_gltf(f);
      if (!mesh) continue;
      ++model_count;
      bench_detector_model(std::filesystem::path(f).stem().string(), *mesh, nullptr, out, model_score);
    }
  }
  for (const std::string detector : {"histogram", "autocorrelation"}) {
    std::printf("%s: %d true generators recovered on the families", detector.c_str(), family_score[detector]);
    if (model_count) std::printf(", a principal offset on %d of %d real models", model_score[detector], model_count);
    std::printf("\n");
    out["detector_summary"][detector] = {{"family_generators", family_score[detector]},
                                         {"models_with_principal", model_score[detector]},
                                         {"models", model_count}};
  }
}

// A generated sample analysed, with a candidate promoted along its repeat where no principal offset runs along
// it (as `restitch resize --size` does), and the lattice axis along the repeat (-1: none).
struct Prepared {
  Result<families::SampleModel> sample = error(StatusCode::internal, "");
  Result<Analysis> analysis = error(StatusCode::internal, "");
  int axis = -1;
};

// With `glb`, the sample is written to .glb and read back first (float positions), as a user's file is.
Prepared prepare(const std::string& name, const std::map<std::string, double>& params, bool glb = false) {
  Prepared p;
  p.sample = families::generate(name, params);
  if (!p.sample.ok()) return p;
  if (glb) {
    auto bytes = save_glb_to_memory(p.sample->mesh);
    auto mesh = bytes ? load_gltf_from_memory(bytes->data(), bytes->size()) : Result<Mesh>(bytes.status());
    if (!mesh) {
      p.sample = mesh.status();
      return p;
    }
    p.sample->mesh = std::move(*mesh);
  }
  const families::SampleModel& s = *p.sample;
  p.analysis = analyze(s.mesh);
  if (!p.analysis.ok()) return p;
  Analysis& a = *p.analysis;
  std::array<bool, 3> change{{false, false, false}};
  change[std::size_t(world_axis_of(s.generators[0]))] = true;
  std::vector<Eigen::Vector3d> offsets;
  for (const int c : a.candidates_for_axes(change)) offsets.push_back(a.model_units(a.candidates[std::size_t(c)]));
  if (!offsets.empty() && !promote_offsets(s.mesh, AnalysisOptions<>{}, offsets, a)) return p;
  for (int b = 0; b < 3; ++b)
    if (!a.lattice.dummy[b] &&
        std::abs(a.lattice.A.col(b).normalized().dot(s.generators[0].normalized())) > std::cos(M_PI / 180))
      p.axis = b;
  return p;
}

// Tallies of resizes judged by `judge`.
struct Tally {
  std::map<char, int> letters;
  int opened = 0, opened_warned = 0;  // resizes with open edges that are no copies of the input's
};

// The prepared sample resized to the size of `truth` along its repeat (the nearest whole periods), compared in
// place with it; one letter as in section 7's table.
char judge(Retargeter<>& r, const families::SampleModel& s, const Mesh& truth, Tally& tally) {
  const BoundingBox bt = bounding_box(truth);
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  const int w = world_axis_of(s.generators[0]);
  target[w] = bt.size()[w];
  auto res = r.retarget_to_size(target, false);
  if (!res.ok()) return 'R';
  if (res->report.boundary_edges_new() > 0) {
    ++tally.opened;
    tally.opened_warned += !res->report.warnings.empty();
  }
  const BoundingBox bo = bounding_box(res->mesh);
  const double size = bt.size().norm();
  const bool exact = (bt.min - bo.min).norm() < 1e-4 * size && (bt.max - bo.max).norm() < 1e-4 * size &&
                     test::symmetric_surface_distance(res->mesh, truth, 0.004 * size) < 1e-4 * size;
  const double open = test::open_boundary_length(truth);
  bool centred = false;
  for (const ResultWarning& x : res->report.warnings) centred = centred || x.check == "part off centre";
  if (exact)
    return test::open_boundary_length(res->mesh) > open + 1e-6 * (1 + open) ? 'o'
           : res->report.warnings.empty()                                   ? '.'
                                                                            : 'e';
  return centred ? 'W' : res->report.warnings.empty() ? 'X' : 'w';
}

nlohmann::json tally_json(const Tally& t) {
  std::map<char, int> c = t.letters;
  return {{"exact", c['.'] + c['e']}, {"exact_more_open", c['o']}, {"exact_warned", c['e']},
          {"centred_off", c['W']},    {"warned", c['w']},          {"silent", c['X']},
          {"refused", c['R']},        {"no_repeat", c['A']},       {"opened", t.opened},
          {"opened_warned", t.opened_warned}};
}

void print_tally(const Tally& t) {
  std::map<char, int> c = t.letters;
  std::printf("  exact %d (more open %d, warned %d), centred part off by half a period %d, wrong and warned %d, wrong "
              "silently %d, refused %d, no repeat found %d; new open edges in %d (warned %d)\n",
              c['.'] + c['e'], c['o'], c['e'], c['W'], c['w'], c['X'], c['R'], c['A'], t.opened, t.opened_warned);
}

std::string only_family;  // --family: sections 7, 8 and 10 on this family alone

std::vector<std::string> count_families() {
  static const std::vector<std::string> f{"connector", "box_header", "dip",   "cabinet",   "radiator",
                                          "railing",   "shutter",    "fence", "pin_header", "bookshelf",
                                          "facade",    "facade_sheared", "tube_rail"};
  if (only_family.empty()) return f;
  return {only_family};
}

// The families of sections 7 and 8, and variants: a family with integer parameters other than its defaults
// (the connector with a one-piece housing, `--one_piece 1`: outer faces tessellated over the whole length, as
// a CAD export).
struct Variant {
  std::string label, name;
  std::map<std::string, double> params;
};

std::vector<Variant> count_variants() {
  std::vector<Variant> list;
  for (const std::string& name : count_families()) {
    list.push_back({name, name, {}});
    if (name == "connector") list.push_back({"connector_one_piece", name, {{"one_piece", 1}}});
  }
  return list;
}

// Section 7: each family at n = 2..10 modules resized to the size of the family at every other count m along
// the repeat (the nearest whole periods, Retargeter::retarget_to_size), compared in place with the family
// generated at m. One letter per resize: '.' exact in place and no more open boundary than the
// truth, no warning; 'e' the same with a warning (a false alarm); 'o' exact in shape, more open boundary; 'W' a
// centred part half a period off, which the report warns of (whole periods cannot keep it centred); 'w' wrong,
// with a warning; 'X' wrong, no warning; 'R' refused; 'A' neither a principal offset nor a candidate along the
// family's repeat at n (a candidate is used as `restitch resize --size` uses it).
void bench_counts(nlohmann::json& out) {
  std::printf("\n== every count to every other (n = 2..10 modules, rows: from n, columns: to m)\n");
  for (const Variant& row_of : count_variants()) {
    const std::string& name = row_of.name;
    const std::string count = families::generate(name)->count_parameters[0];
    Tally tally;
    nlohmann::json rows = nlohmann::json::array();
    std::printf("%s (%s):\n", row_of.label.c_str(), count.c_str());
    const auto at = [&](int n) {
      std::map<std::string, double> q = row_of.params;
      q[count] = n;
      return q;
    };
    for (int n = 2; n <= 10; ++n) {
      Prepared p = prepare(name, at(n));
      std::optional<Retargeter<>> r;
      if (p.axis >= 0) r.emplace(p.sample->mesh, *p.analysis);
      std::string row;
      for (int m = 2; m <= 10; ++m) {
        const char c = m == n ? '-' : p.axis < 0 ? 'A' : judge(*r, *p.sample, families::generate(name, at(m))->mesh, tally);
        if (m != n) ++tally.letters[c];
        row += c;
      }
      std::printf("  %2d  %s\n", n, row.c_str());
      rows.push_back(row);
    }
    print_tally(tally);
    out["counts"][row_of.label] = tally_json(tally);
    out["counts"][row_of.label]["rows"] = rows;
  }
}

// Section 8: the families away from their defaults. Per family, six parameter sets (seeds 1..6, or --seeds): every length
// parameter drawn uniformly from 0.7 to 1.3 times its default (clamped to its range; counts and detail kept),
// each generated at 3, 5 and 7 modules (--from) and resized to the size of the family at n - 1 and n + 2 modules
// (--to FIRST..LAST: at every count there but n), judged as in section 7. A set the family refuses at a count (parameters that do not fit together) is skipped there.
// Every result that is not exact, or exact and warned, is printed with its parameters, for `restitch sample`.
// The variants of section 7 too, their integer parameters kept.
unsigned seed_first = 1, seed_last = 6;  // --seeds FIRST..LAST: section 8's parameter sets
std::vector<int> from_counts = {3, 5, 7};  // --from N[,N...]: section 8's counts resized
int to_first = 0, to_last = -1;            // --to FIRST..LAST: every count there but n; default n - 1 and n + 2

// "4,5,6" into counts of at least 1; false on anything else.
bool parse_counts(const char* text, std::vector<int>& counts) {
  std::vector<int> read;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const long n = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || n < 1 || n > 1000) return false;
    read.push_back(int(n));
  }
  if (read.empty()) return false;
  counts = read;
  return true;
}

void bench_parameters(nlohmann::json& out) {
  std::string from;
  for (const int n : from_counts) from += (from.empty() ? "" : ", ") + std::to_string(n);
  const std::string to = to_first <= to_last ? "every count from " + std::to_string(to_first) + " to " + std::to_string(to_last)
                                             : std::string("n - 1, n + 2");
  std::printf("\n== other parameters (sets %u..%u of lengths within 0.7..1.3 of the defaults; from %s modules to %s)\n",
              seed_first, seed_last, from.c_str(), to.c_str());
  for (const Variant& variant : count_variants()) {
    const std::string& name = variant.name;
    families::SampleInfo info;
    for (const families::SampleInfo& i : families::catalog())
      if (i.name == name) info = i;
    const std::string count = families::generate(name)->count_parameters[0];
    Tally tally;
    int skipped = 0;
    std::printf("%s:\n", variant.label.c_str());
    for (unsigned seed = seed_first; seed <= seed_last; ++seed) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> factor(0.7, 1.3);
      std::map<std::string, double> params = variant.params;
      std::string args;
      for (const auto& [q, x] : variant.params) args += " --" + q + " " + std::to_string(int(x));
      for (const families::Parameter& q : info.parameters) {
        if (q.integer) continue;
        params[q.name] = std::clamp(q.value * factor(rng), q.min, q.max);
        char b[96];
        std::snprintf(b, sizeof b, " --%s %.17g", q.name.c_str(), params[q.name]);
        args += b;
      }
      for (const int n : from_counts) {
        std::map<std::string, double> at = params;
        at[count] = n;
        Prepared p = prepare(name, at);
        if (!p.sample.ok()) {
          ++skipped;
          continue;
        }
        std::optional<Retargeter<>> r;
        if (p.axis >= 0) r.emplace(p.sample->mesh, *p.analysis);
        std::vector<int> targets = {n - 1, n + 2};
        if (to_first <= to_last) {
          targets.clear();
          for (int m = to_first; m <= to_last; ++m)
            if (m != n) targets.push_back(m);
        }
        for (const int m : targets) {
          at[count] = m;
          auto truth = families::generate(name, at);
          if (!truth.ok()) {
            ++skipped;
            continue;
          }
          const char c = p.axis < 0 ? 'A' : judge(*r, *p.sample, truth->mesh, tally);
          ++tally.letters[c];
          if (c != '.') std::printf("  %c  set %u: --%s %d to %d:%s\n", c, seed, count.c_str(), n, m, args.c_str());
        }
      }
    }
    print_tally(tally);
    out["parameters"][variant.label] = tally_json(tally);
    out["parameters"][variant.label]["skipped"] = skipped;
  }
}

// Section 10: many copies. Each family at 12 to 40 modules (the counts it accepts), written to .glb and read back
// as a user's file is, resized to the size of the
// family at n - 1 and n + 2 modules, judged as in section 7, and the period along its repeat: 'p' when the
// principal offset along the repeat (or the candidate promoted) is the family's generator within 1e-3 of it,
// 'm' when it is another length, '-' when nothing runs along the repeat. A long model has its period short in
// the normalized frame (docs/method.md 1.1: lengths scale with the longest side), where detection is weakest.
void bench_long(nlohmann::json& out) {
  std::printf("\n== many copies (n = 12..40 modules, read from .glb, to n - 1 and n + 2; period: p true, m another length)\n");
  for (const std::string& name : count_families()) {
    const std::string count = families::generate(name)->count_parameters[0];
    Tally tally;
    int wrong_period = 0;
    std::string line;
    for (const int n : {12, 16, 20, 24, 32, 40}) {
      Prepared p = prepare(name, {{count, n}}, true);
      if (!p.sample.ok()) continue;
      const Eigen::Vector3d g = p.sample->generators[0];
      char period = '-';
      if (p.axis >= 0) {
        const Eigen::Vector3d v = p.analysis->lattice.A.col(p.axis);  // model units
        period = std::abs(std::abs(v.dot(g.normalized())) - g.norm()) < 1e-3 * g.norm() ? 'p' : 'm';
      }
      wrong_period += period != 'p';
      std::optional<Retargeter<>> r;
      if (p.axis >= 0) r.emplace(p.sample->mesh, *p.analysis);
      char b[32];
      std::snprintf(b, sizeof b, " %d:%c", n, period);
      line += b;
      for (const int m : {n - 1, n + 2}) {
        auto truth = families::generate(name, {{count, m}});
        if (!truth.ok()) continue;
        const char c = p.axis < 0 ? 'A' : judge(*r, *p.sample, truth->mesh, tally);
        ++tally.letters[c];
        line += c;
      }
    }
    std::printf("%-16s%s\n", name.c_str(), line.c_str());
    print_tally(tally);
    out["long"][name] = tally_json(tally);
    out["long"][name]["wrong_period"] = wrong_period;
    out["long"][name]["row"] = line;
  }
}

// Section 9: what the repeats of the vertices (docs/method.md 1.14) cost the analysis: each family at its
// defaults and each real model of `models`, analysed on one thread with AnalysisOptions::vertex_repeats off
// and on (best of three each), and the candidates of reason "vertices" it gives.
void bench_vertex_repeats(const std::string& models, nlohmann::json& out) {
  std::printf("\n== repeats of the vertices: analysis ms on one thread (best of 3) without and with them\n");
  std::vector<std::pair<std::string, Mesh>> inputs;
  for (const std::string& name : count_families())
    if (auto s = families::generate(name)) inputs.emplace_back(name, s->mesh);
  if (std::filesystem::is_directory(models)) {
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(models))
      if (e.path().extension() == ".glb") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    for (const std::string& f : files)
      if (auto mesh = load_gltf(f)) inputs.emplace_back(std::filesystem::path(f).stem().string(), std::move(*mesh));
  }
  double total[2] = {0, 0};
  for (const auto& [name, mesh] : inputs) {
    double ms[2] = {0, 0};
    int found = 0;
    for (const bool on : {false, true}) {
      AnalysisOptions<> options;
      options.vertex_repeats = on;
      options.threads = 1;
      ms[on] = INFINITY;
      for (int run = 0; run < 3; ++run) {
        const auto t0 = std::chrono::steady_clock::now();
        const Result<Analysis> a = analyze(mesh, options);
        ms[on] = std::min(ms[on], std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        if (a && on)
          found = int(std::count_if(a->candidates.begin(), a->candidates.end(),
                                    [](const RepeatCandidate& c) { return c.reason == "vertices"; }));
      }
      total[on] += ms[on];
    }
    std::printf("%-40s %9.1f %9.1f  %+6.1f%%  %d candidate(s) of the vertices\n", name.c_str(), ms[0], ms[1],
                100 * (ms[1] / ms[0] - 1), found);
    out["vertex_repeats"][name] = {{"ms_without", ms[0]}, {"ms_with", ms[1]}, {"candidates", found}};
  }
  std::printf("%-40s %9.1f %9.1f  %+6.1f%%\n", "all", total[0], total[1], 100 * (total[1] / total[0] - 1));
  out["vertex_repeats"]["all"] = {{"ms_without", total[0]}, {"ms_with", total[1]}};
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path = "bench.json", only;
#ifdef RESTITCH_SHARED_MODELS
  std::string models = RESTITCH_SHARED_MODELS;
#else
  std::string models = "../shared/models";
#endif
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--json") && i + 1 < argc)
      json_path = argv[++i];
    else if (!std::strcmp(argv[i], "--models") && i + 1 < argc)
      models = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc)
      only = argv[++i];
    else if (!std::strcmp(argv[i], "--family") && i + 1 < argc)
      only_family = argv[++i];
    else if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc &&
             std::sscanf(argv[++i], "%u..%u", &seed_first, &seed_last) == 2 && seed_first >= 1 && seed_first <= seed_last)
      continue;
    else if (!std::strcmp(argv[i], "--to") && i + 1 < argc &&
             std::sscanf(argv[++i], "%d..%d", &to_first, &to_last) == 2 && to_first >= 1 && to_first <= to_last)
      continue;
    else if (!std::strcmp(argv[i], "--from") && i + 1 < argc && parse_counts(argv[++i], from_counts))
      continue;
    else
      return std::fprintf(stderr,
                          "usage: bench [--quick] [--json FILE] [--models DIR] [--only "
                          "analysis|shot|comparison|scaling|synthetic|detectors|counts|parameters|vertex_repeats|long] [--family NAME]\n"
                          "             [--seeds FIRST..LAST (section 8's parameter sets, default 1..6)]\n"
                          "             [--from N[,N...] (section 8's counts, default 3,5,7)] [--to FIRST..LAST (every count there; default n - 1, n + 2)]\n"),
             2;
  }
  const auto run = [&](const char* section) { return only.empty() || only == section; };
  nlohmann::json out;
  const std::vector<std::string> families = {"bookshelf", "facade", "facade_sheared", "fence", "pin_header"};
  const std::vector<std::size_t> sizes =
      quick ? std::vector<std::size_t>{0, 20000} : std::vector<std::size_t>{0, 20000, 50000, 200000};
  if (run("analysis"))
    bench_analysis(quick ? sizes : std::vector<std::size_t>{0, 20000, 50000, 200000, 1000000}, models, quick, out);
  if (run("shot")) bench_shot(out);
  if (run("comparison")) bench_label_spaces(families, out);
  if (run("scaling")) bench_scaling_labels(quick, out);
  if (run("scaling")) bench_scaling_triangles(sizes, out);
  if (run("synthetic")) bench_synthetic(quick, out);
  if (run("detectors")) bench_detectors(families, models, quick, out);
  if (run("counts") && (!quick || only == "counts")) bench_counts(out);  // minutes: not in --quick
  if (run("parameters") && (!quick || only == "parameters")) bench_parameters(out);  // minutes: not in --quick
  if (run("vertex_repeats") && (!quick || only == "vertex_repeats")) bench_vertex_repeats(models, out);
  if (run("long") && (!quick || only == "long")) bench_long(out);  // minutes: not in --quick
  std::ofstream(json_path) << out.dump(2) << "\n";
  std::printf("\nwrote %s\n", json_path.c_str());
  return 0;
}
