#!/usr/bin/env bash
# Serves the restitch web demo on http://127.0.0.1:PORT/ (default 8080), installing and building what is
# missing first: Debian's Emscripten, node and npm (scripts/install-deps.sh --page), the npm packages of
# demo_web/ (three, lil-gui) and the WebAssembly module (Emscripten build in build/web).
# Usage: scripts/serve-demo.sh [PORT]      Stop with Ctrl-C.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
port="${1:-8080}"
export NODE_PATH=/usr/share/nodejs   # Emscripten's optimiser needs acorn from Debian's node modules
bash "$root/scripts/install-deps.sh" --page   # Emscripten, node and npm, as the README's first command installs
bash "$root/demo_web/tests/build.sh"
echo "restitch demo: http://127.0.0.1:${port}/"
cd "$root/demo_web"
exec python3 -m http.server "$port" --bind 127.0.0.1
