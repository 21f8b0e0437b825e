// restitch resize IN -o OUT (--steps | --size) [...]   and   restitch solve FILE [...]
#include <array>
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/io/json_report.hpp"
#include "restitch/runtime.hpp"
#include "restitch/solver/mrf_io.hpp"

namespace restitch::cli {

Result<Analysis> load_and_analyze(const std::string& input, const PolicyNames& policies, Mesh& mesh, bool quiet);
void add_policy_options(CLI::App* cmd, PolicyNames& policies);
bool offsets_are_triples(const PolicyNames& policies);

namespace {
std::string join(const std::vector<int>& v) {
  std::string s;
  for (int x : v) s += (s.empty() ? "" : ",") + std::to_string(x);
  return s;
}
}  // namespace

namespace {

struct ResizeArgs {
  std::string input, output, json, dump_mrf, labels = "lattice", pivot = "origin", seam_energy = "descriptor";
  bool exact = false, strict = false, seams_on_cells = false;
  double seam_tolerance = 0, weld_tolerance = 0;
  PolicyNames policies;
  std::vector<int> steps;
  std::vector<double> size;
  std::size_t max_problem = RetargetOptions().max_problem_size;
};

// A --size change along a world axis no principal offset runs along uses a candidate that runs along
// it (Analysis::candidates_for_axes), unless --offsets chose the offsets; says so.
Status use_candidates_for_size(const ResizeArgs& args, const Mesh& mesh, Analysis& a, bool quiet) {
  if (args.size.empty() || !args.policies.offsets.empty()) return {};
  const Eigen::Vector3d size_in = bounding_box(mesh).size();
  const std::array<bool, 3> change =
      size_changes(Eigen::Vector3d(args.size[0], args.size[1], args.size[2]), size_in);
  const std::vector<int> use = a.candidates_for_axes(change);
  if (use.empty()) return {};
  std::vector<Eigen::Vector3d> offsets;
  for (const int c : use) {
    const RepeatCandidate& cand = a.candidates[std::size_t(c)];
    offsets.push_back(a.model_units(cand));
    const Eigen::Vector3d& v = offsets.back();
    if (!quiet)
      std::printf("no principal offset runs along %c: using candidate %d (%.5g, %.5g, %.5g) (%s, %d copies)\n",
                  "xyz"[world_axis_of(cand.offset)], c + 1, printable(v.x(), v.norm()), printable(v.y(), v.norm()),
                  printable(v.z(), v.norm()),
                  cand.reason.c_str(),
                  cand.copies);
  }
  return promote_offsets_named(mesh, offsets, a);
}

// The lattice steps of a request: --steps as given, or the nearest to --size.
Result<Eigen::Array3i> requested_steps(const ResizeArgs& args, const Analysis& a, AnyRetargeter& r, bool quiet) {
  if (!args.steps.empty()) return lattice_steps_from_principal(a, args.steps);
  Result<Eigen::Array3i> s = r.steps_for_size(Eigen::Vector3d(args.size[0], args.size[1], args.size[2]));
  if (s && !quiet)
    std::printf("size %g x %g x %g: nearest achievable with steps %s\n", args.size[0], args.size[1], args.size[2],
                join(principal_steps_from_lattice(a, *s)).c_str());
  return s;
}

void print_resize_summary(const ResizeArgs& args, const Analysis& a, const Eigen::Array3i& steps,
                          const RetargetReport& rep) {
  const Placement& p = rep.placement;
  const auto principal = a.principal_model_units();
  std::printf("%s: %zu principal offset(s)", args.input.c_str(), principal.size());
  for (const auto& v : principal) std::printf("  (%.4g, %.4g, %.4g)", v.x(), v.y(), v.z());
  std::printf("\n  steps %s: %d x %d x %d cells -> %d x %d x %d\n",
              join(principal_steps_from_lattice(a, steps)).c_str(), rep.cells_in[0], rep.cells_in[1], rep.cells_in[2],
              rep.cells_out[0], rep.cells_out[1], rep.cells_out[2]);
  std::printf("  graph cut (%s labels): %d nodes, %d labels, %d cycles, energy %.6g, solve %.1f ms\n",
              args.labels.c_str(), rep.nodes, rep.labels, rep.cycles, rep.energy,
              rep.timings_ms.count("solve") ? rep.timings_ms.at("solve") : 0.0);
  std::printf("  pivot %s,%s,%s at (%.5g, %.5g, %.5g): translated by (%.5g, %.5g, %.5g)\n", pivot_name(p.modes[0]),
              pivot_name(p.modes[1]), pivot_name(p.modes[2]), printable(p.pivot.x()), printable(p.pivot.y()),
              printable(p.pivot.z()), printable(p.translation.x()), printable(p.translation.y()),
              printable(p.translation.z()));
  if (rep.exact)
    std::printf("  exact: %.4g x %.4g x %.4g scaled by %.6g x %.6g x %.6g about the pivot\n", rep.size_nearest.x(),
                rep.size_nearest.y(), rep.size_nearest.z(), rep.scale.x(), rep.scale.y(), rep.scale.z());
  std::printf("  size %.4g x %.4g x %.4g -> %.4g x %.4g x %.4g\n", rep.size_in.x(), rep.size_in.y(), rep.size_in.z(),
              rep.size_out.x(), rep.size_out.y(), rep.size_out.z());
  std::printf("  seams (%s energy): %zu, worst mismatch %.4g model units (tolerance %.4g)", seam_energy_name(rep.seam_energy),
              rep.seams.size(), rep.max_seam_mismatch, rep.seam_tolerance);
  const SeamReport* worst = nullptr;
  for (const SeamReport& s : rep.seams)
    if (!worst || s.mismatch > worst->mismatch) worst = &s;
  if (worst)
    std::printf(" between cells (%d,%d,%d) and (%d,%d,%d)%s", worst->cell_a[0], worst->cell_a[1], worst->cell_a[2],
                worst->cell_b[0], worst->cell_b[1], worst->cell_b[2], worst->outer ? " (the end)" : "");
  if (rep.seams_moved > 0)
    std::printf("\n  seam planes moved off their cell planes: %d (to where the copies continue each other)",
                rep.seams_moved);
  for (const PartReport& part : rep.parts)  // docs/method.md 2.10
    std::printf("\n  kept once: cells %d-%d along axis %d (at the %s), moved %d cell(s)%s", part.first + 1, part.last + 1,
                part.axis + 1, part_anchor_name(part.anchor), part.shift,
                part.half > 0 ? " and half a period on, alone (to stay centred)"
                : part.half < 0 ? " and half a period back, alone (to stay centred)" : "");
  std::printf("\n  wrote %s: %zu triangles in, %zu out\n", args.output.c_str(), rep.triangles_in, rep.triangles_out);
  std::printf("  boundary edges (positions welded): %zu in, %zu out, %zu new\n", rep.boundary_edges_in,
              rep.boundary_edges_out, rep.boundary_edges_new());
  std::printf("  check: %s\n", rep.warnings.empty() ? "passed (no open or unmatched seam, parts once, size as asked, no floating piece, one piece)"
                                                     : (std::to_string(rep.warnings.size()) + " warning(s)").c_str());
  if (rep.weld_tolerance_measured)
    std::printf("  weld tolerance %.3g of the diagonal, measured: the copies' vertices coincide to that (docs/method.md 3)\n",
                rep.weld_tolerance);
}

// `restitch resize`: returns the exit code.
int run_resize(const ResizeArgs& args) {
  if (args.steps.empty() && args.size.empty()) {
    std::fprintf(stderr, "restitch resize: give --steps a[,b[,c]] or --size X,Y,Z\n");
    return exit_usage;
  }
  if (!offsets_are_triples(args.policies)) return exit_usage;
  Result<Pivots> pivots = parse_pivots(args.pivot);
  if (!pivots) {
    std::fprintf(stderr, "restitch resize: --pivot: %s\n", pivots.status().message().c_str());
    return exit_usage;
  }
  if (!args.size.empty())  // before the (slow) analysis
    if (Status s = check_size_values(Eigen::Vector3d(args.size[0], args.size[1], args.size[2])); !s) return fail(s);
  const bool quiet = args.json == "-";
  Mesh mesh;
  Result<Analysis> a = load_and_analyze(args.input, args.policies, mesh, quiet);
  if (!a) return fail(a.status());
  if (Status s = use_candidates_for_size(args, mesh, *a, quiet); !s) return fail(s);
  RetargetOptions options;
  options.max_problem_size = args.max_problem;
  options.pivot = *pivots;
  options.seam_tolerance = args.seam_tolerance;
  options.weld_tolerance = args.weld_tolerance;
  options.move_seams = !args.seams_on_cells;
  if (!parse_seam_energy(args.seam_energy, options.seam_energy)) return exit_usage;  // CLI11 checked it
  options.threads = args.policies.threads;  // the solver's moves too (same labels whatever the count)
  AnyRetargeter r(mesh, *a, args.labels, options);
  if (!r.status()) return fail(r.status());
  Result<Eigen::Array3i> steps = requested_steps(args, *a, r, quiet);
  if (!steps) return fail(steps.status());
  if (!args.dump_mrf.empty()) {
    Result<SeamMrf> problem = r.labelling_problem(*steps);
    if (!problem) return fail(problem.status());
    if (Status s = write_mrf(args.dump_mrf, *problem); !s) return fail(s, true);
  }
  Result<RetargetResult> out =
      args.size.empty()
          ? r.retarget(*steps, terminal_progress())
          : r.retarget_to_size(Eigen::Vector3d(args.size[0], args.size[1], args.size[2]), args.exact,
                               terminal_progress());
  if (!out) return fail(out.status());
  if (Status s = save_gltf(out->mesh, args.output); !s) return fail(s, true);
  nlohmann::json j = retarget_json(out->report);
  j["steps_principal"] = principal_steps_from_lattice(*a, *steps);
  j["label_space"] = args.labels;
  j["promoted_offsets"] = nlohmann::json::array();
  for (const int i : a->promoted)
    j["promoted_offsets"].push_back(detail::vec3(a->normalization.to_model_offset(a->dominant[std::size_t(i)].offset)));
  j["file"] = args.output;
  if (!quiet) print_resize_summary(args, *a, *steps, out->report);
  for (const ResultWarning& w : out->report.warnings)
    std::fprintf(stderr, "restitch: warning: %s: %s\n", w.check.c_str(), w.message.c_str());
  if (!args.json.empty())
    if (Status s = write_json(j, args.json); !s) return fail(s, true);
  if (args.strict && !out->report.warnings.empty()) {
    std::fprintf(stderr, "restitch: --strict: %zu warning(s) (exit %d)\n", out->report.warnings.size(), int(exit_flagged));
    return exit_flagged;
  }
  return exit_ok;
}

void register_resize(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<ResizeArgs>();
  CLI::App* cmd = app.add_subcommand("resize", "Resize a model along its repeats by graph-cut stitching");
  cmd->add_option("input", args->input, "input model (.glb or .gltf)")->required();
  cmd->add_option("-o,--output", args->output, "output model (.glb or .gltf)")->required()->check(gltf_output_path());
  auto* steps =
      cmd->add_option("--steps", args->steps, "repeats to add along principal offsets 1[,2[,3]] (negative removes)")
          ->delimiter(',')
          ->expected(1, 3);
  auto* size = cmd->add_option("--size", args->size, "target bounding-box size X,Y,Z in model units (0 keeps an axis)")
                   ->delimiter(',')
                   ->expected(3);
  steps->excludes(size);
  cmd->add_option("--pivot", args->pivot,
                  "what stays put: origin (the model's origin, clamped into its box), min, center or max; one for "
                  "all axes or x,y,z (e.g. min,origin,max)")
      ->capture_default_str();
  cmd->add_flag("--exact", args->exact,
                "with --size: scale the nearest whole-repeat result along each asked axis about the pivot to the "
                "exact size (factors reported)")
      ->needs(size);
  add_policy_options(cmd, args->policies);
  cmd->add_option("--labels", args->labels,
                  "label space: lattice (principal offsets) or regular (the paper's baseline)")
      ->check(CLI::IsMember(label_space_names()))
      ->capture_default_str();
  cmd->add_option("--seam-energy", args->seam_energy,
                  "pairwise term: descriptor (the paper's whole-cell descriptor sets) or geometry (the "
                  "surfaces at the seam)")
      ->check(CLI::IsMember(seam_energy_names()))
      ->capture_default_str();
  cmd->add_option("--seam-tolerance", args->seam_tolerance,
                  "list seams mismatching by more than this as over it (model units; 0: 3 x the sample spacing; an estimate: the result check says whether a seam is open)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--weld-tolerance", args->weld_tolerance,
                  "merge seam vertices and split T-junctions this close, as a fraction of the bounding-box diagonal "
                  "(0: 1e-6, exact copies, raised up to 6.4e-5 where the copies' vertices are measured to coincide "
                  "only to that; 1e-4 closes most seams of models whose copies differ slightly)")
      ->check(CLI::Range(0.0, 1e-2))
      ->capture_default_str();
  cmd->add_flag("--seams-on-cells", args->seams_on_cells,
                "keep every seam on a cell plane, as the paper does (by default a seam moves within half a cell to "
                "where the two copies continue each other)");
  cmd->add_flag("--strict", args->strict,
                "exit 7 when the result check flags the result: an open seam, a part that occurs once copied a wrong "
                "number of times, a size not the one asked, a floating piece, copies side by side, an axis or centred part whole "
                "periods cannot decide, or two copies that cannot tell their ends' content from their own (the output is "
                "still written)");
  cmd->add_option("--max-problem", args->max_problem, "refuse requests with more nodes x labels than this")
      ->capture_default_str();
  cmd->add_option("--dump-mrf", args->dump_mrf,
                  "also write the labelling problem solved to FILE (see `restitch solve`)");
  cmd->add_option("--json", args->json, "also write the report as JSON to FILE, or - for standard output");
  cmd->callback([args, exit_code] { *exit_code = run_resize(*args); });
}

struct SolveArgs {
  std::string input, json, solver = "alpha_expansion";
  int threads = 0;
};

// `restitch solve`: returns the exit code.
int run_solve(const SolveArgs& args) {
  Result<TableMrf> problem = read_mrf(args.input);
  if (!problem) return fail(problem.status());
  std::vector<int> labels(std::size_t(problem->node_count()), 0);
  SolveReport rep;
  AlphaExpansion<> solver;
  solver.threads = args.threads;
  if (Status s = solver.solve(*problem, labels, rep, terminal_progress()); !s) return fail(s);
  nlohmann::json j = {{"solver", args.solver}, {"nodes", rep.nodes},
                      {"labels", rep.labels},  {"edges", rep.edges},
                      {"energy", rep.energy},  {"initial_energy", rep.initial_energy},
                      {"cycles", rep.cycles},  {"non_metric", rep.non_metric_detected},
                      {"ms", rep.ms},          {"labelling", labels}};
  if (args.json != "-")
    std::printf("%s: %d nodes, %d labels, %d edges; %s: energy %.10g after %d cycles in %.2f ms%s\n",
                args.input.c_str(), rep.nodes, rep.labels, rep.edges, args.solver.c_str(), rep.energy, rep.cycles,
                rep.ms, rep.non_metric_detected ? " (non-metric terms met)" : "");
  if (!args.json.empty())
    if (Status s = write_json(j, args.json); !s) return fail(s, true);
  return exit_ok;
}

void register_solve(CLI::App& app, int* exit_code) {
  auto args = std::make_shared<SolveArgs>();
  CLI::App* cmd = app.add_subcommand("solve", "Solve a labelling problem written by `restitch resize --dump-mrf`");
  cmd->add_option("input", args->input, "problem file (format: restitch/solver/mrf_io.hpp)")->required();
  cmd->add_option("--solver", args->solver, "solver")->check(CLI::IsMember({"alpha_expansion"}))->capture_default_str();
  cmd->add_option("--threads", args->threads,
                  "threads proposing expansion moves; 0: every hardware thread. The result is the same whatever "
                  "the number")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_option("--json", args->json, "also write the result as JSON to FILE, or - for standard output");
  cmd->callback([args, exit_code] { *exit_code = run_solve(*args); });
}

}  // namespace

void register_retarget_commands(CLI::App& app, int* exit_code) {
  register_resize(app, exit_code);
  register_solve(app, exit_code);
}

}  // namespace restitch::cli
