#!/usr/bin/env bash
# Writes every model and JSON report the CLI produces for a fixed set of requests,
# so that two builds can be compared byte for byte (a refactoring must not change them).
#
#   scripts/golden.sh RESTITCH_BINARY OUT_DIR [MODELS_DIR]
#   diff -r OUT_A OUT_B      # after running it with two builds
#
# Requests: every bundled sample (default parameters) and every .glb in MODELS_DIR
# (default ../shared/models, skipped when absent): `analyze --json`, and `resize` by
# +2 and by -1 along each principal offset with --json; `--labels regular` on two
# samples. JSON timing fields (`timings_ms`) are removed, since they are wall-clock
# times; everything else is compared as written.
set -euo pipefail
bin="$(realpath "$1")"
out="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
models="${3:-$root/../shared/models}"
jobs="${RESTITCH_JOBS:-2}"
mkdir -p "$out/in"
out="$(realpath "$out")"

strip_timings() { jq -S 'del(.. | .timings_ms?)' "$1" > "$1.tmp" && mv "$1.tmp" "$1"; }
export -f strip_timings

for s in $("$bin" sample --list | cut -f1); do "$bin" sample "$s" -o "$out/in/sample_$s.glb" >/dev/null; done
if [ -d "$models" ]; then for m in "$models"/*.glb; do ln -sf "$m" "$out/in/$(basename "$m")"; done; fi

# One job per input: analyse, then resize along each principal offset.
one() {
  local bin="$1" out="$2" in="$3"
  local name; name="$(basename "$in" .glb)"
  cd "$out"  # outputs named relative to OUT_DIR, so reports name the same files whatever OUT_DIR is
  "$bin" analyze "$in" --json "$out/$name.analyze.json" >/dev/null 2>"$out/$name.analyze.err" || echo "exit $?" >>"$out/$name.analyze.err"
  strip_timings "$out/$name.analyze.json" 2>/dev/null || true
  local n; n=$(jq '.principal_offsets | length' "$out/$name.analyze.json" 2>/dev/null || echo 0)
  local axis step steps
  for ((axis = 0; axis < n; ++axis)); do
    for step in 2 -1; do
      steps=(0 0 0); steps[$axis]=$step
      local tag="$name.v$((axis + 1))_$step"
      "$bin" resize "$in" -o "$tag.glb" --steps "$(IFS=,; echo "${steps[*]:0:$n}")" --json "$out/$tag.json" \
        >/dev/null 2>"$out/$tag.err" || echo "exit $?" >>"$out/$tag.err"
      strip_timings "$out/$tag.json" 2>/dev/null || true
    done
  done
  case "$name" in sample_bookshelf|sample_fence)
    "$bin" resize "$in" -o "$name.regular.glb" --steps 1 --labels regular --json "$out/$name.regular.json" \
      >/dev/null 2>"$out/$name.regular.err" || echo "exit $?" >>"$out/$name.regular.err"
    strip_timings "$out/$name.regular.json" 2>/dev/null || true ;;
  esac
}
export -f one
ls "$out"/in/*.glb | xargs -P "$jobs" -I{} bash -c 'one "$@"' _ "$bin" "$out" {}
echo "golden: $(ls "$out" | grep -c -v '^in$') files in $out"
