// Measures the two seam energies (docs/method.md 2.4, 2.4b) on the sample families: each family
// generated at n = 2, 3, 4, 5 repeats along each generator is resized by +1, +2, +3, -1 and down to one
// repeat, and compared with the family generated at the new count (the ground truth), as
// tests/retarget_test.cpp does. Where the analysis has no lattice axis along the generator, the
// generator is promoted as typed (`--offsets`), marked "promoted". Prints one row per case and energy. Not part of the build:
//   g++ -O2 -std=c++17 -Iinclude -Itests -I/usr/include/eigen3 tests/tools/seam_energy_compare.cpp -o /tmp/sec
//   /tmp/sec [family]
#include <cstdio>
#include <set>

#include "restitch/families/families.hpp"
#include "restitch/restitch.hpp"
#include "support/surface_distance.hpp"

using namespace restitch;

int main(int argc, char** argv) {
  const std::string only = argc > 1 ? argv[1] : "";
  const bool only_one = argc > 2;  // just the steps down to one repeat
  std::printf("family\tgen\tn\tsteps\tenergy\tpass\tdist/size\tE\tmax_mismatch/size\twarnings\n");
  for (const families::SampleInfo& info : families::catalog()) {
    if (!only.empty() && only != "all" && info.name != only) continue;
    auto base = families::generate(info.name);
    if (!base) continue;
    for (std::size_t g = 0; g < base->generators.size(); ++g)
      for (int n : {2, 3, 4, 5}) {
        auto s = families::generate(info.name, {{base->count_parameters[g], n}});
        if (!s) {
          std::printf("%s\t%zu\t%d\tgenerate failed: %s\n", info.name.c_str(), g, n, s.status().message().c_str());
          continue;
        }
        auto a = analyze(s->mesh);
        if (!a) {
          std::printf("%s\t%zu\t%d\tanalyze failed\n", info.name.c_str(), g, n);
          continue;
        }
        const auto axis_along = [&] {
          for (int c = 0; c < 3; ++c)
            if (!a->lattice.dummy[c] &&
                std::abs(a->lattice.A.col(c).normalized().dot(s->generators[g].normalized())) > std::cos(M_PI / 180))
              return c;
          return -1;
        };
        int axis = axis_along();
        const bool promoted = axis < 0;
        if (promoted && promote_offsets(s->mesh, AnalysisOptions<>{}, {s->generators[g]}, *a)) axis = axis_along();
        if (axis < 0) {
          std::printf("%s\t%zu\t%d\tno lattice axis along the generator\n", info.name.c_str(), g, n);
          continue;
        }
        const std::set<int> steps{1, 2, 3, -1, 1 - s->counts[g]};  // the last: down to one repeat
        for (SeamEnergy energy : {SeamEnergy::geometry, SeamEnergy::descriptor}) {
          RetargetOptions o;
          o.seam_energy = energy;
          Retargeter<> r(s->mesh, *a, o);
          for (int k : steps) {
            if (only_one && k != 1 - s->counts[g]) continue;
            Eigen::Array3i st = Eigen::Array3i::Zero();
            st[axis] = k;
            auto out = r.retarget(st);
            auto truth = families::generate(info.name, {{s->count_parameters[g], s->counts[g] + k}});
            if (!out || !truth) {
              std::printf("%s\t%zu\t%d\t%+d\t%s\terror\t%s\n", info.name.c_str(), g, n, k, seam_energy_name(energy),
                          !out ? out.status().message().c_str() : truth.status().message().c_str());
              continue;
            }
            const BoundingBox bt = bounding_box(truth->mesh), bo = bounding_box(out->mesh);
            const double size = bt.size().norm();
            const bool box = (bt.min - bo.min).norm() < 1e-4 * size && (bt.max - bo.max).norm() < 1e-4 * size;
            const double d = test::symmetric_surface_distance(out->mesh, truth->mesh, 0.004 * size);
            const bool pass = box && d < 1e-4 * size;
            std::printf("%s\t%zu\t%d%s\t%+d\t%s\t%s\t%.2e\t%.4g\t%.2e\t%zu\n", info.name.c_str(), g, n,
                        promoted ? " promoted" : "", k, seam_energy_name(energy), pass ? "pass" : "FAIL", d / size,
                        out->report.energy, out->report.max_seam_mismatch / size, out->report.warnings.size());
            std::fflush(stdout);
          }
        }
      }
  }
}
