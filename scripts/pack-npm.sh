#!/usr/bin/env bash
# Packs the npm package `restitch`: writes OUT_DIR/restitch-VERSION.tgz (npm pack) and prints its path.
#   scripts/pack-npm.sh OUT_DIR
# The package is demo_web/npm (its JavaScript, typings and README) plus what this builds with Debian's
# Emscripten (scripts/install-deps.sh --page installs it): the library's module (dist/restitch_web.mjs and
# .wasm) and the command-line tool (cli/restitch.cjs and .wasm, run by `npx restitch`), the repository's
# LICENSE, and the version of CMakeLists.txt's project(). Build folder: RESTITCH_WEB_BUILD (default build/web,
# shared with the page's build); jobs: RESTITCH_JOBS (default 2).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ $# -ne 1 ]; then echo "usage: scripts/pack-npm.sh OUT_DIR" >&2; exit 2; fi
mkdir -p "$1"
out="$(cd "$1" && pwd)"
export NODE_PATH=/usr/share/nodejs   # Emscripten's optimiser needs acorn from Debian's node modules
bash "$root/scripts/install-deps.sh" --page
build="${RESTITCH_WEB_BUILD:-$root/build/web}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  emcmake cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRESTITCH_BUILD_TESTS=OFF \
    -DRESTITCH_BUILD_EXAMPLES=OFF -DRESTITCH_BUILD_BENCH=OFF -DRESTITCH_BUILD_WEB=ON >/dev/null
fi
cmake --build "$build" --target restitch_web restitch_cli -j "${RESTITCH_JOBS:-2}"

version="$(sed -nE 's/^project\(restitch VERSION ([0-9.]+).*/\1/p' "$root/CMakeLists.txt")"
[ -n "$version" ] || { echo "pack-npm: no version in CMakeLists.txt's project()" >&2; exit 1; }
stage="$(mktemp -d)"
trap 'rm -rf "$stage"' EXIT
src="$root/demo_web/npm"
cp -r "$src/package.json" "$src/index.js" "$src/index.d.ts" "$src/three.js" "$src/three.d.ts" "$src/README.md" \
  "$src/THIRD_PARTY_NOTICES.md" "$src/bin" "$root/LICENSE" "$stage/"
mkdir -p "$stage/dist" "$stage/cli"
cp "$src/dist/restitch_web.mjs" "$src/dist/restitch_web.wasm" "$stage/dist/"
# Emscripten names the tool restitch.js; the package is "type": "module", so the CommonJS loader is .cjs.
cp "$build/restitch.js" "$stage/cli/restitch.cjs"
cp "$build/restitch.wasm" "$stage/cli/restitch.wasm"
(cd "$stage" && npm pkg set version="$version" >/dev/null &&
  npm pack --pack-destination "$out" --loglevel=error >/dev/null)
test -f "$out/restitch-$version.tgz"
echo "$out/restitch-$version.tgz"
