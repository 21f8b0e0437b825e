#!/usr/bin/env bash
# What including restitch costs a translation unit: CPU seconds and peak memory of the compiler for
#   (a) a unit that includes <Eigen/Dense> alone (empty main): the reference
#   (b) the umbrella header <restitch/restitch.hpp> with an empty main
#   (c) the umbrella plus one pipeline call (analyze, a Retargeter, one retarget)
#   (d) the umbrella with a wrong descriptor policy, up to its static_assert (the compile fails)
#   (e) (c) in compiled mode: RESTITCH_COMPILED defined, the default policies instantiated elsewhere
#       (restitch/instantiate.hpp, the restitch::compiled target), so the unit sees extern templates
# each compiled once, one after the other, as ratios to (a).
#
#   scripts/compile-cost.sh [CXX] [FLAGS...]      default: g++ -O2
#
# Prints a Markdown table. Run it on an otherwise idle machine: one compile at a time.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cxx="${1:-g++}"
shift || true
flags=("$@")
[ ${#flags[@]} -gt 0 ] || flags=(-O2)
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

cat >"$work/a.cpp" <<'EOF'
#include <Eigen/Dense>
int main() {}
EOF
cat >"$work/b.cpp" <<'EOF'
#include <restitch/restitch.hpp>
int main() {}
EOF
cat >"$work/c.cpp" <<'EOF'
#include <restitch/restitch.hpp>
int main() {
  restitch::Mesh mesh;  // empty: the calls below fail at run time, which does not matter here
  restitch::Result<restitch::Analysis> a = restitch::analyze(mesh);
  if (!a) return 1;
  restitch::Retargeter<> r(mesh, *a);
  restitch::Result<restitch::RetargetResult> out = r.retarget({1, 0, 0});
  return out ? 0 : 1;
}
EOF
cat >"$work/d.cpp" <<'EOF'
#include <restitch/restitch.hpp>
struct NotADescriptor {};  // no dimension(), no compute(): analyze's static_assert names what is missing
int main() {
  restitch::Mesh mesh;
  restitch::AnalysisOptions<NotADescriptor> options;
  return restitch::analyze(mesh, options) ? 0 : 1;
}
EOF

inc=(-I "$root/include" -I /usr/include/eigen3)
# One compile: prints "seconds peak_MB" (user + system CPU of the compiler, its peak resident set).
measure() {
  local src="$1"; shift
  /usr/bin/time -f '%U %S %M' -o "$work/time" "$cxx" -std=c++17 "${flags[@]}" "${inc[@]}" "$@" -c "$src" \
    -o "$work/out.o" >"$work/log" 2>&1 || true
  tail -n 1 "$work/time" | awk '{ printf "%.2f %.0f\n", $1 + $2, $3 / 1024 }'
}

declare -A sec mb
for c in a b c d e; do
  case $c in
    a) r=$(measure "$work/a.cpp") ;;
    b) r=$(measure "$work/b.cpp") ;;
    c) r=$(measure "$work/c.cpp") ;;
    d) r=$(measure "$work/d.cpp")
       grep -q 'static assertion failed' "$work/log" || { echo "compile-cost: (d) did not stop at a static_assert" >&2; exit 1; } ;;
    e) r=$(measure "$work/c.cpp" -DRESTITCH_COMPILED) ;;
  esac
  sec[$c]=${r% *}; mb[$c]=${r#* }
done

echo "compiler: $("$cxx" --version | head -1), flags: ${flags[*]}"
echo
echo "| unit | CPU s | peak MB | CPU / (a) | memory / (a) |"
echo "|---|---|---|---|---|"
label() {
  case $1 in
    a) echo "(a) <Eigen/Dense> alone" ;;
    b) echo "(b) restitch.hpp, empty main" ;;
    c) echo "(c) restitch.hpp + analyze + retarget" ;;
    d) echo "(d) a wrong policy, to its static_assert" ;;
    e) echo "(e) (c) in compiled mode" ;;
  esac
}
for c in a b c d e; do
  awk -v l="$(label $c)" -v s="${sec[$c]}" -v m="${mb[$c]}" -v s0="${sec[a]}" -v m0="${mb[a]}" \
    'BEGIN { printf "| %s | %.1f | %d | %.1fx | %.1fx |\n", l, s, m, s / s0, m / m0 }'
done
