#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang-14, ASan and UBSan, and runs one.
#
#   scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]     TARGET: gltf, mrf, xyzn, pipeline
#   scripts/fuzz.sh all SECONDS                               each target for SECONDS (the test command's smoke)
#
# Corpus: the seeds in tests/fuzz/corpus/TARGET (hand-made, and every input that ever crashed a target,
# each also a regression test in tests/) plus, for gltf, the bundled samples (generated with
# $RESTITCH_CLI, default build/native/restitch, when it exists); new inputs found are kept
# in build/fuzz/corpus/TARGET across runs. A crash, leak, timeout (10 s per input) or sanitizer report
# is written to build/fuzz/artifacts/ and makes this script exit non-zero. Prints libFuzzer's final
# statistics (executions, coverage). Needs clang-14 and libFuzzer (Debian: clang-14, libclang-rt-14-dev).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ $# -lt 2 ]; then
  echo "usage: $0 gltf|mrf|xyzn|pipeline|all SECONDS [libFuzzer options...]" >&2
  exit 2
fi
target="$1" seconds="$2"; shift 2
targets=(gltf mrf xyzn pipeline)
[ "$target" = all ] || targets=("$target")
for t in "${targets[@]}"; do
  case "$t" in gltf|mrf|xyzn|pipeline) ;; *) echo "fuzz: unknown target '$t'" >&2; exit 2;; esac
done
build="$root/build/fuzz"
CXX="${RESTITCH_FUZZ_CXX:-clang++-14}" cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DRESTITCH_FUZZ=ON -DRESTITCH_BUILD_TESTS=OFF -DRESTITCH_BUILD_EXAMPLES=OFF -DRESTITCH_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --target $(printf 'fuzz_%s ' "${targets[@]}") -j "${RESTITCH_JOBS:-2}" >/dev/null
mkdir -p "$build/artifacts" "$build/samples"
cli="${RESTITCH_CLI:-$root/build/native/restitch}"  # the samples as seeds, when a restitch is built
if [ -x "$cli" ]; then
  for s in $("$cli" sample --list | cut -f1); do
    [ -f "$build/samples/$s.glb" ] || "$cli" sample "$s" -o "$build/samples/$s.glb" >/dev/null
  done
fi
status=0
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t"
  seeds=("$root/tests/fuzz/corpus/$t")
  [ "$t" = gltf ] && seeds+=("$build/samples")
  echo "=== fuzz_$t for ${seconds} s ==="
  "$build/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$build/artifacts/$t-" "$@" "$build/corpus/$t" "${seeds[@]}" 2>"$build/$t.log" || status=1
  grep -E "^(stat::|#[0-9]+ +DONE|==[0-9]+==ERROR|SUMMARY|INFO: Seed)" "$build/$t.log" | tail -n 12
  [ "$status" = 0 ] || { echo "fuzz_$t failed: see $build/$t.log and $build/artifacts/"; tail -n 30 "$build/$t.log"; }
done
exit "$status"
