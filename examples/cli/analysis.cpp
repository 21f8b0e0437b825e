// restitch analyze IN [...]   and   restitch describe POINTS.xyzn [...]
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "cli.hpp"
#include "restitch/descriptor/xyzn.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/io/json_report.hpp"
#include "restitch/runtime.hpp"

namespace restitch::cli {

Result<Analysis> load_and_analyze(const std::string& input, const PolicyNames& policies, Mesh& mesh, bool quiet) {
  GltfLoadReport report;
  Result<Mesh> loaded = load_gltf(input, &report, policies.limits);
  if (!loaded) return loaded.status();
  if (!quiet)
    for (const std::string& w : report.warnings) std::fprintf(stderr, "restitch: warning: %s\n", w.c_str());
  mesh = std::move(*loaded);
  Result<Analysis> a =
      analyze_named(mesh, policies.descriptor, policies.matcher, policies.detector, terminal_progress(),
                    policies.threads);
  if (!a || policies.offsets.empty()) return a;
  std::vector<Eigen::Vector3d> offsets;
  for (std::size_t i = 0; i + 2 < policies.offsets.size(); i += 3)
    offsets.emplace_back(policies.offsets[i], policies.offsets[i + 1], policies.offsets[i + 2]);
  RESTITCH_TRY(promote_offsets_named(mesh, offsets, *a));
  return a;
}

void add_limit_options(CLI::App* cmd, GltfLimits& limits) {
  cmd->add_option("--max-vertices", limits.max_vertices,
                  "refuse a model with more vertices than this (counted over the scene, instances included)")
      ->capture_default_str();
  cmd->add_option("--max-triangles", limits.max_triangles,
                  "refuse a model with more triangles than this (counted over the scene, instances included)")
      ->capture_default_str();
}

void add_policy_options(CLI::App* cmd, PolicyNames& policies) {
  add_limit_options(cmd, policies.limits);
  cmd->add_option("--descriptor", policies.descriptor, "descriptor policy")
      ->check(CLI::IsMember(descriptor_names()))
      ->capture_default_str();
  cmd->add_option(
         "--matcher", policies.matcher,
         "matcher policy: reduced (PCA lower bounds, exact re-ranking; brute force where that is faster) or "
         "brute_force (the reference); the same matches")
      ->check(CLI::IsMember(matcher_names()))
      ->capture_default_str();
  cmd->add_option("--detector", policies.detector,
                  "offset detector: histogram (the paper's matched-descriptor offsets) or autocorrelation (peaks of "
                  "the surface's FFT autocorrelation; skips matching)")
      ->check(CLI::IsMember(detector_names()))
      ->capture_default_str();
  cmd->add_option("--threads", policies.threads,
                  "threads for the analysis (descriptors, matching, offset refinement) and, on resize, the solver's "
                  "expansion moves; 0: every hardware thread. The result is the same whatever the number")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_option("--offsets", policies.offsets,
                  "make these offsets principal, first: X,Y,Z[,X,Y,Z[,X,Y,Z]] in model units (e.g. a candidate "
                  "that `analyze` lists); each is refined on the model, so it need not be exact")
      ->delimiter(',')
      ->check([](const std::string& v) {
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        return end != v.c_str() && *end == 0 && std::isfinite(x) ? std::string() : "not a number: " + v;
      });
}

/// --offsets must come in whole triples (CLI11 checks each number, this the count).
bool offsets_are_triples(const PolicyNames& policies) {
  if (policies.offsets.size() % 3 == 0 && policies.offsets.size() <= 9) return true;
  std::fprintf(stderr, "restitch: --offsets takes one to three X,Y,Z triples (%zu numbers given)\n",
               policies.offsets.size());
  return false;
}

namespace {
std::string v3(const Eigen::Vector3d& v) {
  char buf[96];
  const double n = v.norm();
  std::snprintf(buf, sizeof buf, "(%.5g, %.5g, %.5g)", printable(v.x(), n), printable(v.y(), n), printable(v.z(), n));
  return std::string(buf);
}

// --verbose: every dominant offset with the tests it ran (value, threshold) and its verdict.
void print_dominant_offsets(const Analysis& a) {
  for (std::size_t i = 0; i < a.dominant.size(); ++i) {
    const DominantOffset& d = a.dominant[i];
    const OffsetTest* failed = d.failed_test();
    // A repeat of the vertices that is no pattern on the surface (1.14) is a candidate, whatever test it failed.
    const bool vertices = !d.significant && d.from_vertices();
    std::printf("  dominant %zu: %s, %zu votes: %s%s%s\n", i + 1, v3(a.normalization.to_model_offset(d.offset)).c_str(),
                d.votes,
                vertices ? "a repeat of the vertices"
                : failed ? "rejected by "
                         : (d.significant ? "significant" : "not tested"),
                vertices && failed ? ", no pattern on the surface: " : "", failed ? failed->name.c_str() : "");
    for (const OffsetTest& t : d.tests)
      std::printf("      %-21s %9.4g %s %-9.4g %s\n", t.name.c_str(), t.value, t.at_most ? "<=" : ">=", t.threshold,
                  t.passed ? "passed" : "FAILED");
    if (d.divisor > 1) std::printf("      fundamental period: the peak was %d periods long\n", d.divisor);
    if (d.promoted) std::printf("      promoted on request (--offsets)\n");
  }
}
}  // namespace

/// The candidates (pairs, parallel repeats) and how to resize along one.
void print_candidates(const Analysis& a) {
  for (std::size_t i = 0; i < a.candidates.size(); ++i) {
    const RepeatCandidate& c = a.candidates[i];
    const Eigen::Vector3d v = a.model_units(c);
    std::printf("  candidate %zu: (%.4g, %.4g, %.4g), length %.4g, %s (%s%d copies): resize along it with --offsets "
                "%.4g,%.4g,%.4g\n",
                i + 1, printable(v.x(), v.norm()), printable(v.y(), v.norm()), printable(v.z(), v.norm()), v.norm(),
                c.reason == "pair"       ? "a pair"
                : c.reason == "parallel" ? "parallel to a principal offset"
                                         : "a repeat of the vertices",
                c.reason == "parallel" ? "about " : "",
                c.copies, printable(v.x(), v.norm()), printable(v.y(), v.norm()), printable(v.z(), v.norm()));
  }
}

void print_analysis(const std::string& input, const Analysis& a, bool verbose) {
  std::printf("%s\n", input.c_str());
  if (a.detector_name == "histogram") {  // the default's lines, as they always were
    std::printf("  %lld features (%s descriptors, %s matching), %zu histogram peaks, %zu dominant offsets\n",
                (long long)a.features.points.rows(), a.descriptor_name.c_str(), a.matcher_name.c_str(),
                a.histogram_peaks, a.dominant.size());
    std::printf("  sparsity: %.1f%% of offsets in the top 7%% of bins, %.1f%% in the top 20%%\n", 100 * a.sparsity.top7,
                100 * a.sparsity.top20);
  } else {
    std::printf("  %lld features (%s descriptors), %s detector: %zu peaks, %zu dominant offsets\n",
                (long long)a.features.points.rows(), a.descriptor_name.c_str(), a.detector_name.c_str(),
                a.histogram_peaks, a.dominant.size());
  }
  const auto principal = a.principal_model_units();
  if (principal.empty()) {
    std::printf("  no repetition found: zero principal offsets, nothing to resize along\n");
  } else {
    for (std::size_t i = 0; i < principal.size(); ++i)
      std::printf("  principal offset %zu: %s, length %.5g\n", i + 1, v3(principal[i]).c_str(), principal[i].norm());
  }
  for (int c = 0; c < 3; ++c)
    if (a.lattice.dummy[c]) std::printf("  dummy direction: %s (not resized)\n", v3(a.lattice.A.col(c)).c_str());
  print_candidates(a);
  if (verbose) print_dominant_offsets(a);
  std::printf("  lattice: %d x %d x %d cells\n", a.lattice.cells[0], a.lattice.cells[1], a.lattice.cells[2]);
  double total = 0;
  std::string stages;
  for (const auto& [stage, ms] : a.timings_ms) {
    total += ms;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%s %.0f", stages.empty() ? "" : ", ", stage.c_str(), ms);
    stages += buf;
  }
  std::printf("  time: %.0f ms (%s)\n", total, stages.c_str());
}

void register_analysis_commands(CLI::App& app, int* exit_code) {
  {
    struct Args {
      std::string input, json;
      PolicyNames policies;
      bool verbose = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        app.add_subcommand("analyze", "Find how a model repeats: dominant and principal offsets, and its lattice");
    cmd->add_option("input", args->input, "input model (.glb or .gltf)")->required();
    add_policy_options(cmd, args->policies);
    cmd->add_option("--json", args->json, "also write the analysis as JSON to FILE, or - for standard output");
    cmd->add_flag("-v,--verbose", args->verbose,
                  "also print every dominant offset with the significance tests it ran (values and thresholds)");
    cmd->callback([args, exit_code] {
      if (!offsets_are_triples(args->policies)) {
        *exit_code = exit_usage;
        return;
      }
      Mesh mesh;
      Result<Analysis> a = load_and_analyze(args->input, args->policies, mesh, args->json == "-");
      if (!a) {
        *exit_code = fail(a.status());
        return;
      }
      if (args->json != "-") print_analysis(args->input, *a, args->verbose);
      if (!args->json.empty())
        if (Status s = write_json(analysis_json(*a), args->json); !s) {
          *exit_code = fail(s, true);
          return;
        }
      *exit_code = exit_ok;
    });
  }
  {
    struct Args {
      std::string input, output, descriptor = "shot";
      double radius = 0;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "describe",
        "Compute SHOT or FPFH descriptors of a point set: x y z nx ny nz lines in, one CSV row per point out");
    cmd->add_option("input", args->input, "points with normals, one 'x y z nx ny nz' line each")->required();
    cmd->add_option("--descriptor", args->descriptor, "descriptor")
        ->check(CLI::IsMember(descriptor_names()))
        ->capture_default_str();
    cmd->add_option("--radius", args->radius, "support radius, in the file's units")->required();
    cmd->add_option("-o,--output", args->output, "output CSV (NaN rows written as nan)")->required();
    cmd->callback([args, exit_code] {
      Result<PointSet> points = read_xyzn(args->input);
      if (!points) {
        *exit_code = fail(points.status());
        return;
      }
      DescriptorMatrix out;
      Status s;
      if (args->descriptor == "shot") {
        ShotDescriptor d;
        d.radius = float(args->radius);
        s = d.compute(*points, *points, out, terminal_progress());
      } else {
        FpfhDescriptor d;
        d.radius = float(args->radius);
        s = d.compute(*points, *points, out, terminal_progress());
      }
      if (!s) {
        *exit_code = fail(s);
        return;
      }
      if (Status w = write_descriptor_csv(args->output, out); !w) {
        *exit_code = fail(w, true);
        return;
      }
      std::printf("wrote %s: %lld %s descriptors of %lld values\n", args->output.c_str(), (long long)out.rows(),
                  args->descriptor.c_str(), (long long)out.cols());
      *exit_code = exit_ok;
    });
  }
}

}  // namespace restitch::cli
