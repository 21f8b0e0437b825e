#!/usr/bin/env bash
# Installs what restitch needs on Debian 12, only what is missing.
#   scripts/install-deps.sh          everything (native build, Emscripten, Chromium, npm packages)
#   scripts/install-deps.sh --native only what the native library and CLI need
#   scripts/install-deps.sh --page   what the web page needs to be built and served (scripts/serve-demo.sh)
#   scripts/install-deps.sh --python what the Python module needs (scripts/pack-blender.sh)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
native=(cmake make ninja-build g++ libeigen3-dev libnanoflann-dev libtinygltf-dev nlohmann-json3-dev catch2 libcli11-dev)
page=(emscripten nodejs npm)
python=(pybind11-dev python3-dev python3-pytest python3-numpy)  # the Python module and its tests
blender=("${python[@]}" blender)                                   # and the Blender add-on's test
web=("${page[@]}" "${blender[@]}" chromium clang-14 libclang-rt-14-dev jq)  # and the browser tests, fuzz targets (scripts/fuzz.sh), golden.sh
want=("${native[@]}")
case "${1:-}" in
  --native) ;;
  --page) want+=("${page[@]}") ;;
  --python) want+=("${python[@]}") ;;
  *) want+=("${web[@]}") ;;
esac

missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node and npm may come from outside Debian's packages on some images: accept them if present.
if command -v node >/dev/null && command -v npm >/dev/null; then
  missing=($(printf '%s\n' "${missing[@]}" | grep -vx -e nodejs -e npm || true))
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "restitch: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" = 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
if [ "${1:-}" != "--native" ] && [ "${1:-}" != "--python" ] && { [ ! -d "$root/demo_web/node_modules/playwright-core" ] || [ ! -d "$root/demo_web/node_modules/gltf-validator" ] ||
  [ ! -d "$root/demo_web/node_modules/typescript" ] || [ ! -d "$root/demo_web/node_modules/@types/three" ]; }; then
  (cd "$root/demo_web" && npm ci --no-audit --no-fund --loglevel=error)
fi
