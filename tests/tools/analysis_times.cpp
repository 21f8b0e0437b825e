// Analysis wall time, per stage, of every sample family (defaults) and every model of ../shared/models:
// best of REPS runs each, and a total. The same source builds against any commit's include/, so two
// commits can be compared run for run (e.g. main against 196638d, interleaving the runs;
// for commits before the part test, delete the DUMP block, which reads its fields).
// DUMP=1 also prints each analysis's dominant offsets, lattice and candidate count, to check that a
// speed change keeps the answers bit for bit (diff two runs' outputs without the timing lines).
// Not part of the build:
//   g++ -O2 -DNDEBUG -std=c++17 -Iinclude -I/usr/include/eigen3 tests/tools/analysis_times.cpp \
//       examples/support/gltf_implementation.cpp -o /tmp/atime
//   [RESTITCH_MODELS=DIR] /tmp/atime [REPS [NAME_PART]]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>
#include <dirent.h>
#include "restitch/families/families.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/restitch.hpp"
using namespace restitch;
using C = std::chrono::steady_clock;
int main(int argc, char** argv) {
  std::vector<std::pair<std::string, Mesh>> in;
  for (const auto& s : families::catalog()) {
    auto m = families::generate(s.name);
    if (m) in.push_back({s.name, m->mesh});
  }
  std::string dir = std::getenv("RESTITCH_MODELS") ? std::getenv("RESTITCH_MODELS") : "../shared/models";  // run from the repository
  std::vector<std::string> files;
  if (DIR* d = opendir(dir.c_str())) {
    while (auto* e = readdir(d)) { std::string n = e->d_name; if (n.size() > 4 && n.substr(n.size()-4) == ".glb") files.push_back(n); }
    closedir(d);
  }
  std::sort(files.begin(), files.end());
  for (auto& f : files) { auto m = load_gltf(dir + "/" + f); if (m) in.push_back({f, *m}); }
  if (argc > 2) { std::vector<std::pair<std::string, Mesh>> keep; for (auto& p : in) if (p.first.find(argv[2]) != std::string::npos) keep.push_back(p); in = keep; }
  int reps = argc > 1 ? std::atoi(argv[1]) : 2;
  double total = 0;
  for (auto& [name, mesh] : in) {
    double best = 1e30; int np = 0;
    for (int r = 0; r < reps; ++r) {
      auto t = C::now();
      auto a = analyze(mesh);
      double ms = std::chrono::duration<double, std::milli>(C::now() - t).count();
      best = std::min(best, ms);
      if (a) np = int(a->principal.size());
      if (a && r == reps - 1 && std::getenv("DUMP")) {
        std::printf("  dom %zu:", a->dominant.size());
        for (auto& d : a->dominant) std::printf(" [%.9g %.9g %.9g %d %d]", d.offset.x(), d.offset.y(), d.offset.z(), int(d.significant), d.divisor);
        std::printf("\n  lat:");
        for (int c = 0; c < 3; ++c) std::printf(" %d:%.9g,%.9g o%.9g", a->lattice.cells[c], a->lattice.end_low[c], a->lattice.end_high[c], a->lattice.origin[c]);
        int skipped = 0, ran = 0;
        for (auto& d : a->dominant) { for (auto& t : d.tests) if (t.name == "part_new" && !t.passed) ++skipped; if (d.part.ran) ++ran; }
        std::printf("\n  cand %zu\n", a->candidates.size());
        std::fprintf(stderr, "%s part_new skipped %d, part ran %d\n", name.c_str(), skipped, ran);
      }
      if (a && r == reps - 1) { for (auto& kv : a->timings_ms) std::printf("   %s=%.0f", kv.first.c_str(), kv.second); std::printf("\n"); }
    }
    total += best;
    std::printf("%-42s %8zu tris %9.1f ms  principal %d\n", name.c_str(), mesh.triangle_count(), best, np);
    std::fflush(stdout);
  }
  std::printf("TOTAL %.1f ms\n", total);
}
