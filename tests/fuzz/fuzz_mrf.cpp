// libFuzzer target: the labelling-problem text format (parse_mrf, what `restitch solve` reads), and a
// small problem it accepts solved by alpha-expansion: a Status or a labelling, never a crash. The
// solver's promise is checked: the energy it reports never exceeds the initial one. scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "restitch/solver/alpha_expansion.hpp"
#include "restitch/solver/mrf_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  restitch::Result<restitch::TableMrf> p = restitch::parse_mrf(text, "fuzz.mrf");
  if (!p.ok()) return 0;
  // Solve only what takes microseconds: the reader's limits are what the fuzzer explores.
  if (double(p->node_count()) * p->label_count() > 4096 || p->label_count() > 16) return 0;
  std::vector<int> labels(std::size_t(p->node_count()), 0);
  restitch::SolveReport rep;
  restitch::AlphaExpansion<> solver;
  solver.max_cycles = 8;
  if (solver.solve(*p, labels, rep, {}).ok() && rep.energy > rep.initial_energy + 1e-9 * (1 + std::abs(rep.initial_energy)))
    std::abort();
  return 0;
}
