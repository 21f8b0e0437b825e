#!/usr/bin/env bash
# Renders the before/after of every bundled sample and every model in MODELS_DIR into one PNG,
# to look at: one row per (model, principal offset), columns input, +2 and -1 along that offset.
#
#   scripts/contact-sheet.sh RESTITCH_BINARY OUT_DIR [MODELS_DIR]
#
# MODELS_DIR defaults to ../shared/models next to the repository; it is skipped with a message when
# absent. Writes OUT_DIR/contact-sheet.png (3 columns of 300 px cells, labelled) and
# OUT_DIR/contact-sheet-small.png (thumbnails, for docs/contact-sheet.png), plus the models, the analyze/resize
# JSON reports and OUT_DIR/manifest.json that lists what each cell shows. A resize that fails is
# recorded in its cell (exit code and the first line of its error), not fatal; a renderer that fails
# is (non-zero exit, no PNG half written).
#
# Needs node, Debian's Chromium (/usr/bin/chromium, or $CHROMIUM) and demo_web's npm packages
# (three, playwright-core: scripts/install-deps.sh), or a node_modules folder named by
# $RESTITCH_NODE_MODULES. $RESTITCH_JOBS inputs are processed at a time (default 2).
set -euo pipefail
export LC_ALL=C  # the rows' order (globs sort by name)
if [ $# -lt 2 ]; then
  echo "usage: $0 RESTITCH_BINARY OUT_DIR [MODELS_DIR]" >&2
  exit 2
fi
bin="$(realpath "$1")"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
models="${3:-$root/../shared/models}"
node_modules="${RESTITCH_NODE_MODULES:-$root/demo_web/node_modules}"
jobs="${RESTITCH_JOBS:-2}"
[ -x "$bin" ] || { echo "contact-sheet: $bin is not an executable" >&2; exit 2; }
for p in three playwright-core; do
  [ -d "$node_modules/$p" ] || { echo "contact-sheet: $node_modules/$p is missing (scripts/install-deps.sh)" >&2; exit 2; }
done
command -v jq >/dev/null || { echo "contact-sheet: jq is missing" >&2; exit 2; }
mkdir -p "$2/in" "$2/rows"
out="$(realpath "$2")"
rm -f "$out"/rows/*.json "$out"/in/*.glb

for s in $("$bin" sample --list | cut -f1); do "$bin" sample "$s" -o "$out/in/sample_$s.glb" >/dev/null; done
if [ -d "$models" ]; then
  for m in "$models"/*.glb; do ln -sf "$(realpath "$m")" "$out/in/$(basename "$m")"; done
else
  echo "contact-sheet: $models not found, only the bundled samples"
fi

# One input: analyse it, resize it by +2 and -1 along each principal offset, and write its rows
# (rows/NAME.json, an array) for the renderer. Paths in the rows are relative to OUT_DIR.
one() {
  local bin="$1" out="$2" in="$3"
  local name; name="$(basename "$in" .glb)"
  local analysis="$out/$name.analyze.json" code=0
  "$bin" analyze "$in" --json "$analysis" >/dev/null 2>"$out/$name.analyze.err" || code=$?
  if [ "$code" != 0 ]; then
    jq -n --arg m "$name" --arg r "analyze failed, exit $code: $(head -n1 "$out/$name.analyze.err")" \
      '[{model: $m, input: "in/\($m).glb", offset_index: 0, offsets: 0, reason: $r, cells: []}]' >"$out/rows/$name.json"
    return 0
  fi
  local n; n=$(jq '.principal_offsets | length' "$analysis")
  if [ "$n" = 0 ]; then
    # Why: how many dominant offsets were found, what rejected them, how many candidates are listed.
    jq --arg m "$name" '[{model: $m, input: "in/\($m).glb", offset_index: 0, offsets: 0,
        reason: ("no principal offset: \(.dominant_offsets | length) dominant offsets, none significant"
                 + (if (.dominant_offsets | length) > 0 then " (rejected by "
                      + ([.dominant_offsets[] | .rejected_by // "?"] | group_by(.) | map("\(.[0]) x\(length)") | join(", ")) + ")"
                    else "" end)
                 + "; \(.candidates | length) candidates"), cells: []}]' "$analysis" >"$out/rows/$name.json"
    return 0
  fi
  local axis step steps tag err first rows=()
  for ((axis = 0; axis < n; ++axis)); do
    local cells=()
    for step in 2 -1; do
      steps=(0 0 0); steps[$axis]=$step
      steps="$(IFS=,; echo "${steps[*]:0:$n}")"
      tag="$name.v$((axis + 1))_$step"
      code=0
      "$bin" resize "$in" -o "$out/$tag.glb" --steps "$steps" --json "$out/$tag.json" >/dev/null 2>"$out/$tag.err" || code=$?
      first="$(grep -m1 -v '^[[:space:]]*$' "$out/$tag.err" || true)"
      [ "$code" = 0 ] || rm -f "$out/$tag.glb"
      cells+=("$(jq -n --arg f "$tag.glb" --arg s "$steps" --argjson st "$step" --argjson c "$code" --arg e "$first" \
        '{file: (if $c == 0 then $f else null end), step: $st, steps: $s, exit: $c, error: $e}')")
    done
    rows+=("$(jq --arg m "$name" --argjson k "$axis" --argjson c "[$(IFS=,; echo "${cells[*]}")]" \
      '{model: $m, input: "in/\($m).glb", offset_index: ($k + 1), offsets: (.principal_offsets | length),
        offset: .principal_offsets[$k], cells_in: .lattice_cells, cells: $c}' "$analysis")")
  done
  echo "[$(IFS=,; echo "${rows[*]}")]" | jq . >"$out/rows/$name.json"
}
export -f one
ls "$out"/in/*.glb | xargs -P "$jobs" -I{} bash -c 'one "$@"' _ "$bin" "$out" {}

# Samples first, then the models, each group by name.
rows=("$out"/rows/sample_*.json)
for f in "$out"/rows/*.json; do case "$(basename "$f")" in sample_*) ;; *) rows+=("$f") ;; esac; done
jq -s --arg v "$("$bin" --version 2>&1 | head -n1)" '{version: $v, rows: add}' "${rows[@]}" >"$out/manifest.json.tmp"
mv "$out/manifest.json.tmp" "$out/manifest.json"
echo "contact-sheet: $(jq '.rows | length' "$out/manifest.json") rows, $(jq '[.rows[].cells[] | select(.exit != 0)] | length' "$out/manifest.json") failed resizes; rendering"
CHROMIUM="${CHROMIUM:-/usr/bin/chromium}" node "$root/scripts/contact-sheet/render.mjs" "$node_modules" "$out"
