// custom_solver.cpp - one idea: plug your own solver policy into restitch.
//
// restitch's solver contract (restitch/solver/mrf.hpp) is a class with a
// `solve(problem, labels, report, progress)` member template. Here the policy
// is ICM (iterated conditional modes: give each node in turn its best label
// given its neighbours, until a sweep changes nothing), written in this file,
// not in the library. It runs on a TableMrf read from a file written by
// `restitch resize --dump-mrf` / restitch::write_mrf, or on a tiny problem
// built in code; and, end to end, as the solver of a Retargeter.
//
//   example_custom_solver [FILE.mrf]
//   example_custom_solver --resize
//
// The first prints one line, `energy <value>` (%.17g). On the built-in problem
// ICM stops at `energy 3` (a local minimum; alpha-expansion reaches 1.2
// there), so a test can run the program without arguments and compare that
// line. `--resize` grows the 8-pin header sample by two pins with
// `Retargeter<LatticeLabels, IcmSolver>` and with the default solver, and
// prints both results' triangle counts, energies and whether the two meshes
// are the same (from the analysis' start ICM reaches the optimum there).
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

#include "restitch/families/families.hpp"
#include "restitch/restitch.hpp"
#include "restitch/solver/mrf.hpp"
#include "restitch/solver/mrf_io.hpp"

namespace {

struct IcmSolver {
  int max_sweeps = 100;

  template <class Problem>
  restitch::Status solve(const Problem& problem, std::vector<int>& labels, restitch::SolveReport& report,
                         const restitch::Progress& progress) const {
    static_assert(restitch::is_labelling_problem_v<Problem>, "IcmSolver: not a labelling problem");
    const int n = problem.node_count(), m = problem.label_count();
    if (labels.empty()) labels.assign(static_cast<std::size_t>(n), 0);
    if (static_cast<int>(labels.size()) != n)
      return restitch::error(restitch::StatusCode::invalid_argument, "one initial label per node, please");
    for (int l : labels)
      if (l < 0 || l >= m) return restitch::error(restitch::StatusCode::invalid_argument, "initial label out of range");

    // Edges of each node: (edge id, node is the edge's first end).
    std::vector<std::vector<std::pair<int, bool>>> incident(static_cast<std::size_t>(n));
    for (int e = 0; e < problem.edge_count(); ++e) {
      const std::pair<int, int> ij = problem.edge(e);
      incident[static_cast<std::size_t>(ij.first)].emplace_back(e, true);
      incident[static_cast<std::size_t>(ij.second)].emplace_back(e, false);
    }
    report = restitch::SolveReport();
    report.nodes = n;
    report.labels = m;
    report.edges = problem.edge_count();
    report.initial_energy = restitch::energy(problem, labels);
    for (int sweep = 0; sweep < max_sweeps; ++sweep) {
      report.cycles = sweep + 1;
      bool changed = false;
      for (int i = 0; i < n; ++i) {
        const auto local = [&](int label) {  // the terms that depend on node i's label
          double c = problem.unary(i, label);
          for (const auto& [e, first] : incident[static_cast<std::size_t>(i)]) {
            const std::pair<int, int> ij = problem.edge(e);
            c += first ? problem.pairwise(e, label, labels[static_cast<std::size_t>(ij.second)])
                       : problem.pairwise(e, labels[static_cast<std::size_t>(ij.first)], label);
          }
          return c;
        };
        int& li = labels[static_cast<std::size_t>(i)];
        double best = local(li);
        ++report.expansions;
        for (int a = 0; a < m; ++a) {
          const double c = local(a);
          if (c < best) {  // strictly lower: the energy never rises
            best = c;
            li = a;
            changed = true;
            ++report.moves_accepted;
          }
        }
      }
      report.cycle_energies.push_back(restitch::energy(problem, labels));
      if (!changed) {
        report.converged = true;
        break;
      }
      if (!progress.report("icm", 1.0 - 1.0 / (sweep + 2)))
        return restitch::error(restitch::StatusCode::cancelled, "ICM cancelled");
    }
    report.energy = restitch::energy(problem, labels);
    return restitch::Status();
  }
};

static_assert(restitch::is_graph_solver_v<IcmSolver>, "IcmSolver must satisfy restitch's solver contract");

// Three nodes in a chain, two labels. Label 1 is cheaper everywhere (0.4 vs
// 1), but changing one node alone breaks a Potts term of weight 1, so ICM
// stays at all zeros (energy 3); the optimum is all ones (energy 1.2).
restitch::TableMrf built_in_problem() {
  restitch::TableMrf p(3, 2);
  for (int i = 0; i < 3; ++i) {
    p.set_unary(i, 0, 1.0);
    p.set_unary(i, 1, 0.4);
  }
  for (int i = 0; i < 2; ++i) {
    const int e = p.add_edge(i, i + 1);
    p.set_pairwise(e, 0, 1, 1.0);
    p.set_pairwise(e, 1, 0, 1.0);
  }
  return p;
}

// The policy plugged into a Retargeter: the pin header grown by two pins, with ICM and with the default
// alpha-expansion, compared.
int resize_with_icm() {
  restitch::Result<restitch::families::SampleModel> sample = restitch::families::generate("pin_header", {{"pins", 8}});
  if (!sample) return std::fprintf(stderr, "error: %s\n", sample.status().message().c_str()), 1;
  restitch::Result<restitch::Analysis> analysis = restitch::analyze(sample->mesh);
  if (!analysis) return std::fprintf(stderr, "error: %s\n", analysis.status().message().c_str()), 1;
  restitch::Result<Eigen::Array3i> steps = restitch::lattice_steps_from_principal(*analysis, {2});
  if (!steps) return std::fprintf(stderr, "error: %s\n", steps.status().message().c_str()), 1;
  restitch::Retargeter<restitch::LatticeLabels, IcmSolver> icm(sample->mesh, *analysis);
  restitch::Retargeter<> reference(sample->mesh, *analysis);
  auto a = icm.retarget(*steps);
  auto b = reference.retarget(*steps);
  if (!a) return std::fprintf(stderr, "error: %s\n", a.status().message().c_str()), 1;
  if (!b) return std::fprintf(stderr, "error: %s\n", b.status().message().c_str()), 1;
  const restitch::Mesh &x = a->mesh, &y = b->mesh;
  const bool same = x.V.rows() == y.V.rows() && x.F.rows() == y.F.rows() && (x.V.array() == y.V.array()).all() &&
                    (x.F.array() == y.F.array()).all();
  std::printf("icm (sweeps %d): %d triangles, energy %.6g; alpha-expansion: %d triangles, energy %.6g; %s\n",
              a->report.cycles, int(x.F.rows()), a->report.energy, int(y.F.rows()), b->report.energy,
              same ? "the same mesh" : "different meshes");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "--resize") == 0) return resize_with_icm();
  restitch::TableMrf problem;
  if (argc > 1) {
    restitch::Result<restitch::TableMrf> read = restitch::read_mrf(argv[1]);
    if (!read) {
      std::fprintf(stderr, "error: %s\n", read.status().message().c_str());
      return 1;
    }
    problem = std::move(*read);
  } else {
    problem = built_in_problem();
  }
  std::vector<int> labels(static_cast<std::size_t>(problem.node_count()), 0);
  restitch::SolveReport report;
  const restitch::Status s = IcmSolver().solve(problem, labels, report, restitch::Progress());
  if (!s) {
    std::fprintf(stderr, "error: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("energy %.17g\n", report.energy);
  return 0;
}
