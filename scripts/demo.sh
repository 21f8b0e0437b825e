#!/usr/bin/env bash
# The main job, end to end, on a fresh Debian 12 machine: installs what the
# native build needs, builds the restitch tool, generates a bundled sample
# model, finds how it repeats and resizes it, printing what it did.
# Output files go to out/ (or the folder given as $1).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out}"
"$root/scripts/install-deps.sh" --native
cmake -S "$root" -B "$root/build/demo" -DCMAKE_BUILD_TYPE=Release -DRESTITCH_BUILD_TESTS=OFF -DRESTITCH_BUILD_BENCH=OFF >/dev/null
cmake --build "$root/build/demo" --target restitch_cli -j 2 >/dev/null
restitch="$root/build/demo/restitch"
mkdir -p "$out"
echo "== a bookshelf sample, 4 columns x 4 shelves"
"$restitch" sample bookshelf -o "$out/bookshelf.glb"
echo; echo "== how it repeats"
"$restitch" analyze "$out/bookshelf.glb"
echo; echo "== two columns wider and one shelf taller"
"$restitch" resize "$out/bookshelf.glb" --steps 2,1 -o "$out/bookshelf-resized.glb"
echo; echo "== and one column narrower"
"$restitch" resize "$out/bookshelf.glb" --steps -1,0 -o "$out/bookshelf-narrower.glb"
echo; echo "Done. Open $out/*.glb in any glTF viewer, or run scripts/serve-demo.sh for the browser demo."
