#!/usr/bin/env bash
# Runs every restitch test on a fresh Debian 12 machine (installs what is missing):
#   1. native build, all tests (unit, command line + glTF-Validator, install consumer, the Python module with
#      pytest, the Blender add-on in headless Blender)
#   2. the unit tests and the command-line tests under AddressSanitizer + UndefinedBehaviorSanitizer
#      (clang), then a 20 s fuzz smoke per libFuzzer target (scripts/fuzz.sh)
#   3. the Emscripten build of the unit tests, run under node
#   4. the web demo's node and browser tests, and the npm package's (packed, installed, compared with the
#      native tool)
# Ends with a line "N passed, N failed" over all stages; exits non-zero on any failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
"$root/scripts/install-deps.sh" || { echo "restitch: installing dependencies failed"; exit 1; }
export NODE_PATH=/usr/share/nodejs
jobs="${RESTITCH_JOBS:-2}"
passed=0; failed=0; broken=0

# Runs ctest in $1 and adds its counts to the totals.
run_ctest() {
  local dir="$1"; shift
  local log="$dir/ctest.log"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" "$@" 2>&1 | tee "$log"
  local line
  line=$(grep -E "tests passed, [0-9]+ tests failed out of [0-9]+" "$log" | tail -1)
  if [ -z "$line" ]; then broken=$((broken + 1)); return; fi
  local f t
  f=$(echo "$line" | sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\1/')
  t=$(echo "$line" | sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\2/')
  passed=$((passed + t - f)); failed=$((failed + f))
}
# Each stage's wall time, printed at the end (where a CI run's time goes).
times=""; stage_name=""; stage_start=$SECONDS
end_stage() { [ -z "$stage_name" ] || times+="  $((SECONDS - stage_start)) s  $stage_name"$'\n'; }
stage() { end_stage; stage_name="$1"; stage_start=$SECONDS; echo; echo "=== restitch: $* ==="; }
build() {  # build DIR "TARGETS" [cmake args...]   (TARGETS "" = all)
  local dir="$1" targets="$2"; shift 2
  local t=(); [ -n "$targets" ] && t=(--target $targets)
  # Ninja starts a target's units while the libraries it links are still compiling (Make waits).
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$dir/CMakeCache.txt"; then
    rm -rf "$dir"
  fi
  cmake -S "$root" -B "$dir" -G Ninja "$@" >/dev/null && cmake --build "$dir" "${t[@]}" -j "$jobs" || { broken=$((broken + 1)); return 1; }
}

stage "native build and tests"
build build/native "" -DCMAKE_BUILD_TYPE=Release -DRESTITCH_BUILD_PYTHON=ON -DPython3_EXECUTABLE=/usr/bin/python3 &&
  run_ctest build/native

stage "AddressSanitizer + UndefinedBehaviorSanitizer"
# clang-14, as the fuzz targets: it compiles the sanitized test units in about 0.6 of GCC's time (GCC's
# UndefinedBehaviorSanitizer alone doubles them; docs/benchmarks.md, "Compile cost").
build build/sanitize "restitch_tests restitch_cli" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1" \
  -DCMAKE_CXX_COMPILER=clang++-14 -DRESTITCH_SANITIZE=ON -DRESTITCH_BUILD_BENCH=OFF -DRESTITCH_PCL_ORACLE=OFF &&
  run_ctest build/sanitize -E "install_consumer|example_"

stage "fuzz smoke: each libFuzzer target for 20 s on its corpus (clang-14, ASan + UBSan)"
# scripts/fuzz.sh builds the targets (build/fuzz) and fails on any crash, leak, timeout or sanitizer report;
# a fixed seed, so a failure here is reproducible (new inputs are searched for by longer runs).
for t in gltf mrf xyzn pipeline; do
  if bash "$root/scripts/fuzz.sh" "$t" 20 -seed=1; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done

stage "WebAssembly (Emscripten) build of the tests, under node"
# The same configuration builds the web demo's module (demo_web/npm/dist) and the command-line tool's
# WebAssembly build, reused by stage 4 (the page, and the npm package packed and installed).
if build build/wasm "restitch_tests restitch_web restitch_cli" \
    -DCMAKE_TOOLCHAIN_FILE=/usr/share/emscripten/cmake/Modules/Platform/Emscripten.cmake \
    -DCMAKE_BUILD_TYPE=Release -DRESTITCH_BUILD_EXAMPLES=OFF -DRESTITCH_BUILD_BENCH=OFF -DRESTITCH_BUILD_WEB=ON \
    -DCMAKE_CROSSCOMPILING_EMULATOR=/usr/bin/node; then
  run_ctest build/wasm
fi

if [ -f "$root/demo_web/tests/run.sh" ]; then
  stage "web demo: node and browser tests"
  log=build/web-tests.log
  RESTITCH_WEB_BUILD="$root/build/wasm" RESTITCH_CLI="$root/build/native/restitch" bash "$root/demo_web/tests/run.sh" 2>&1 | tee "$log"
  line=$(grep -E "^[0-9]+ passed, [0-9]+ failed" "$log" | tail -1)
  if [ -z "$line" ]; then broken=$((broken + 1)); else
    passed=$((passed + $(echo "$line" | cut -d' ' -f1))); failed=$((failed + $(echo "$line" | cut -d' ' -f3 | tr -d ,)))
  fi
fi

end_stage
echo
echo "wall time per stage (total $SECONDS s):"; printf '%s' "$times"
[ "$broken" -eq 0 ] || echo "restitch: $broken stage(s) did not build or run"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$broken" -eq 0 ]
