#!/usr/bin/env bash
# Packs the Blender add-on: writes OUT_DIR/restitch_blender-VERSION.zip and prints its path. Blender 3.4
# installs it with Edit > Preferences > Add-ons > Install... (or bpy.ops.preferences.addon_install).
#   scripts/pack-blender.sh OUT_DIR
# The zip holds examples/blender/restitch_blender (the add-on: bl_info and its Python), the restitch Python
# module built for Debian's Python 3 (/usr/bin/python3, the Python of Debian's Blender 3.4; pybind11-dev from
# Debian), LICENSE and the third-party notices. Build folder: RESTITCH_PYTHON_BUILD (default build/python, a
# configuration with RESTITCH_BUILD_PYTHON=ON); jobs: RESTITCH_JOBS (default 2). Deterministic: the same
# module gives the same zip bytes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ $# -ne 1 ]; then echo "usage: scripts/pack-blender.sh OUT_DIR" >&2; exit 2; fi
mkdir -p "$1"
out="$(cd "$1" && pwd)"
bash "$root/scripts/install-deps.sh" --python
build="${RESTITCH_PYTHON_BUILD:-$root/build/python}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DRESTITCH_BUILD_PYTHON=ON \
    -DPython3_EXECUTABLE=/usr/bin/python3 -DRESTITCH_BUILD_TESTS=OFF -DRESTITCH_BUILD_TOOL=OFF \
    -DRESTITCH_BUILD_EXAMPLES=OFF -DRESTITCH_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" --target restitch_python -j "${RESTITCH_JOBS:-2}"
module="$(ls "$build"/python/restitch.cpython-*.so)"
version="$(sed -nE 's/^project\(restitch VERSION ([0-9.]+).*/\1/p' "$root/CMakeLists.txt")"
zip="$out/restitch_blender-$version.zip"
/usr/bin/python3 - "$zip" "$root" "$module" <<'PY'
import sys, zipfile, os
zip_path, root, module = sys.argv[1:]
files = [
    (os.path.join(root, "examples/blender/restitch_blender/__init__.py"), "restitch_blender/__init__.py"),
    (module, "restitch_blender/" + os.path.basename(module)),
    (os.path.join(root, "examples/python/restitch.pyi"), "restitch_blender/restitch.pyi"),
    (os.path.join(root, "LICENSE"), "restitch_blender/LICENSE"),
    (os.path.join(root, "examples/blender/THIRD_PARTY_NOTICES.md"), "restitch_blender/THIRD_PARTY_NOTICES.md"),
]
tmp = zip_path + ".tmp"
with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
    for src, name in files:
        info = zipfile.ZipInfo(name, date_time=(2026, 1, 1, 0, 0, 0))
        info.external_attr = 0o644 << 16
        info.compress_type = zipfile.ZIP_DEFLATED
        with open(src, "rb") as f:
            z.writestr(info, f.read())
os.replace(tmp, zip_path)
PY
echo "$zip"
