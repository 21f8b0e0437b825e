#!/usr/bin/env bash
# Builds what the web demo needs and is missing or stale: demo_web/node_modules (npm ci) and
# demo_web/npm/dist/restitch_web.{mjs,wasm} (the Emscripten configuration of the tree, in build/web).
# Used by scripts/serve-demo.sh and demo_web/tests/run.sh. Jobs: RESTITCH_JOBS (default 2).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
export NODE_PATH=/usr/share/nodejs
if [ ! -d "$root/demo_web/node_modules/three" ] || [ ! -d "$root/demo_web/node_modules/lil-gui" ]; then
  (cd "$root/demo_web" && npm ci --no-audit --no-fund)
fi
build="${RESTITCH_WEB_BUILD:-$root/build/web}"  # scripts/test.sh points this at its wasm build
if [ ! -f "$build/CMakeCache.txt" ]; then
  emcmake cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DRESTITCH_BUILD_TESTS=OFF \
    -DRESTITCH_BUILD_EXAMPLES=OFF -DRESTITCH_BUILD_BENCH=OFF -DRESTITCH_BUILD_WEB=ON >/dev/null
fi
cmake --build "$build" --target restitch_web -j "${RESTITCH_JOBS:-2}"
test -f "$root/demo_web/npm/dist/restitch_web.mjs" && test -f "$root/demo_web/npm/dist/restitch_web.wasm"
