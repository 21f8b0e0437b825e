#!/usr/bin/env bash
# The Blender add-on's test: packs the zip (scripts/pack-blender.sh, from the build folder given) and runs
# tests/blender/test_addon.py in Debian's Blender, headless, on the bookshelf sample and a shared model.
#   tests/blender/run.sh BUILD_DIR RESTITCH_CLI [MODELS_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$1"; cli="$2"; models="${3:-$root/../shared/models}"
if ! command -v blender >/dev/null; then
  echo "blender is missing: scripts/install-deps.sh installs Debian's blender"; exit 1
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
zip="$(RESTITCH_PYTHON_BUILD="$build" bash "$root/scripts/pack-blender.sh" "$work/zip" | tail -1)"
extra=()
[ -f "$models/sh3d-default_railing.glb" ] && extra+=("$models/sh3d-default_railing.glb")
[ -f "$models/blendswap-cc0_pallet.glb" ] && extra+=("$models/blendswap-cc0_pallet.glb")
# A user folder of its own, so the zip is installed where no earlier run left a copy.
export BLENDER_USER_CONFIG="$work/config" BLENDER_USER_SCRIPTS="$work/scripts"
blender -b --factory-startup --python "$root/tests/blender/test_addon.py" -- "$zip" "$cli" "$work/run" "${extra[@]}" 2>&1 |
  grep -v -E '^(Blender quit|Read prefs|Info: |Color management)' | tee "$work/log"
grep -q -E '^blender: [0-9]+ passed, 0 failed' "$work/log"
