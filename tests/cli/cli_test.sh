#!/usr/bin/env bash
# Command-line behaviour of `restitch`: help, samples, info on real models,
# bad input (clear error, documented exit code, no output file), and the
# Khronos glTF-Validator on every file the tool writes.
# Usage: cli_test.sh RESTITCH_BINARY SOURCE_DIR WORK_DIR
set -uo pipefail
bin="$1"; src="$2"; work="$3"; mode="${4:-full}"  # "quick" skips the slow real-model resizes (sanitizer build)
rm -rf "$work"; mkdir -p "$work"
models="$src/../shared/models"
pass=0; fail=0
ok()   { pass=$((pass + 1)); }
bad()  { fail=$((fail + 1)); echo "FAIL: $*"; }
# expect CODE CMD...: runs CMD, checks its exit code, keeps stderr in $work/err
expect() {
  local want="$1"; shift
  "$@" >"$work/out" 2>"$work/err"; local got=$?
  [ "$got" = "$want" ] && ok || bad "exit $got (wanted $want): $* -- $(head -c 300 "$work/err")"
}
expect_error() {  # expect_error CODE PATTERN CMD...: exit code, message on stderr
  local want="$1" pattern="$2"; shift 2
  expect "$want" "$@"
  grep -qi -- "$pattern" "$work/err" && ok || bad "stderr lacks '$pattern': $* -- $(head -c 300 "$work/err")"
}
validate() { node "$src/tests/cli/validate.mjs" "$@" >"$work/val" 2>&1 && ok || bad "validator: $(cat "$work/val")"; }
json_field() { node -e "const j=JSON.parse(require('fs').readFileSync(0,'utf8')); console.log(JSON.stringify(j['$1']))"; }

# Help on every subcommand.
expect 0 "$bin" --help
expect 2 "$bin"
expect 2 "$bin" no-such-command
for sub in info sample convert analyze describe resize solve; do expect 0 "$bin" "$sub" --help; done

# Samples: listed, generated, validator-clean, counted by info.
expect 0 "$bin" sample --list
names=$(cut -f1 "$work/out")
[ "$(echo "$names" | wc -l)" -ge 5 ] && ok || bad "sample --list lists fewer than 5 samples"
for name in $names; do
  expect 0 "$bin" sample "$name" -o "$work/$name.glb"
  validate "$work/$name.glb"
  tris=$("$bin" info "$work/$name.glb" --json - | json_field triangles)
  grep -q "$tris triangles" "$work/out" 2>/dev/null || true
  [ -n "$tris" ] && [ "$tris" -gt 0 ] && ok || bad "info on $name"
done
expect 0 "$bin" sample bookshelf -o "$work/shelf.gltf" --columns 6 --shelves 2
validate "$work/shelf.gltf"
expect_error 5 "columns" "$bin" sample bookshelf -o "$work/x.glb" --columns -3
[ ! -e "$work/x.glb" ] && ok || bad "a refused sample left a file"
expect_error 5 "no-such-sample" "$bin" sample no-such-sample -o "$work/x.glb"

# Real models: triangle counts as in MANIFEST.tsv, convert round trip validator-clean.
if [ -f "$models/MANIFEST.tsv" ]; then
  while IFS=$'\t' read -r file _ _ _ tris _ _ _ _ _ _ textures; do
    [ "$file" = file ] && continue
    got=$("$bin" info "$models/$file" --json - | json_field triangles)
    [ "$got" = "$tris" ] && ok || bad "info $file: $got triangles, MANIFEST says $tris"
    tex=$("$bin" info "$models/$file" --json - | json_field textures)
    [ "$tex" = "$textures" ] && ok || bad "info $file: $tex textures, MANIFEST says $textures"
    expect 0 "$bin" convert "$models/$file" -o "$work/rt-$file"
    validate "$work/rt-$file"
  done < "$models/MANIFEST.tsv"
else
  echo "SKIP: ../shared/models is absent, real-model checks skipped"
fi

# Analysis and resize of the samples: JSON fields, known offsets, validator-clean outputs.
"$bin" sample pin_header -o "$work/pins.glb" >/dev/null
expect 0 "$bin" analyze "$work/pins.glb" --json "$work/pins-analysis.json"
grep -q "principal offset 1" "$work/out" && ok || bad "analyze does not print the principal offset"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  for (const k of ["scale","features","dominant_offsets","principal_offsets","dummy_directions","lattice_cells","sparsity","timings_ms"])
    if (!(k in j)) { console.error("missing " + k); process.exit(1); }
  const p = j.principal_offsets;
  if (p.length !== 1 || Math.abs(Math.hypot(...p[0]) - 2.54) > 0.0127) { console.error("pitch " + JSON.stringify(p)); process.exit(1); }
  if (!(j.sparsity.top7 > 0 && j.sparsity.top7 <= j.sparsity.top20 && j.sparsity.top20 <= 1)) process.exit(1);
' "$work/pins-analysis.json" && ok || bad "analyze --json fields or the pin pitch are wrong"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins+3.glb" --steps 3 --json "$work/pins+3.json" --dump-mrf "$work/pins+3.mrf"
grep -q "seams (descriptor energy): .* worst mismatch" "$work/out" && ok || bad "resize: no seam summary line: $(cat "$work/out")"
validate "$work/pins+3.glb"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  for (const k of ["steps","nodes","labels","cycles","energy","timings_ms","output"]) if (!(k in j)) process.exit(1);
  if (j.labels !== 4 || !(j.output.triangles > 0) || Math.abs(j.size_out[0] - j.size_in[0] - 3 * 2.54) > 0.01) process.exit(1);
' "$work/pins+3.json" && ok || bad "resize --json fields or the grown size are wrong"
expect 0 "$bin" solve "$work/pins+3.mrf" --json "$work/solve.json"
node -e '
  const a = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  const b = JSON.parse(require("fs").readFileSync(process.argv[2], "utf8"));
  if (a.nodes !== b.nodes || a.labels !== b.labels || Math.abs(a.energy - b.energy) > 1e-6 * Math.max(1, a.energy)) process.exit(1);
' "$work/pins+3.json" "$work/solve.json" && ok || bad "solve of the dumped problem disagrees with resize"
# A centred key notch, resized by an odd count, is moved half a pitch alone (docs/method.md 2.10): said in
# the summary and the JSON (half -1), no warning, and the 7-column header's box (a valid glTF).
"$bin" sample box_header --columns 6 -o "$work/bh6.glb" >/dev/null
expect 0 "$bin" resize "$work/bh6.glb" -o "$work/bh7.glb" --steps 1 --json "$work/bh7.json"
grep -q "at the centre), moved 1 cell(s) and half a period back, alone" "$work/out" && ok || bad "resize: the centred notch's move is not in the summary: $(cat "$work/out")"
validate "$work/bh7.glb"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  const c = j.parts.filter(p => p.anchor === "centre");
  if (c.length !== 1 || c[0].half !== -1 || c[0].shift !== 1 || j.warnings.length !== 0) process.exit(1);
  if (j.parts.some(p => p.anchor !== "centre" && p.half !== 0)) process.exit(1);
' "$work/bh7.json" && ok || bad "resize --json: the centred notch is not reported moved half a period, or warned"
# The solver's moves on 1 and 3 threads: the same labelling and energy (docs/method.md 2.5); -1 refused.
expect 0 "$bin" solve "$work/pins+3.mrf" --threads 1 --json "$work/solve1.json"
expect 0 "$bin" solve "$work/pins+3.mrf" --threads 3 --json "$work/solve3.json"
node -e '
  const a = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  const b = JSON.parse(require("fs").readFileSync(process.argv[2], "utf8"));
  delete a.ms; delete b.ms;
  if (JSON.stringify(a) !== JSON.stringify(b)) process.exit(1);
' "$work/solve1.json" "$work/solve3.json" && ok || bad "solve --threads 1 and 3 disagree"
expect 2 "$bin" solve "$work/pins+3.mrf" --threads -1
# Seams (docs/method.md 2.8): every seam in the JSON with its mismatch, the worst one printed; none over
# the default tolerance on the exact pin header, and the result check (2.11) passed: no warning, no new
# open edge. A tolerance of 1e-9 (below any sampling noise) puts seams over it but warns of nothing (the
# estimate is not the check). The paper's regular labels on the connector cut its walls where nothing
# continues them: the check says "open seam" on stderr and in the JSON, and --strict exits 7 (the output
# is written).
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  if (j.seam_energy !== "descriptor" || !Array.isArray(j.seams) || !Array.isArray(j.warnings) || j.warnings.length !== 0) process.exit(1);
  if (j.checked !== true || j.boundary_edges.new !== 0 || !(j.boundary_edges.out >= 0)) process.exit(1);
  if (!(j.seam_tolerance > 0) || !(j.sample_spacing > 0) || j.seams.length === 0) process.exit(1);
  let worst = 0;
  for (const s of j.seams) { if (s.cells.length !== 2 || s.labels.length !== 2 || !(s.mismatch >= 0)) process.exit(1); worst = Math.max(worst, s.mismatch); }
  if (worst !== j.max_seam_mismatch || worst > j.seam_tolerance) process.exit(1);
' "$work/pins+3.json" && ok || bad "resize --json: seams, warnings, check or max_seam_mismatch wrong"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-tol.glb" --steps 3 --seam-tolerance 1e-9 --json "$work/pins-tol.json"
grep -q "check: passed" "$work/out" && ok || bad "resize: the summary does not say the check passed: $(cat "$work/out")"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  if (j.seam_tolerance !== 1e-9 || j.warnings.length !== 0 || j.seams.filter(s => s.mismatch > 1e-9).length === 0) process.exit(1);
' "$work/pins-tol.json" && ok || bad "resize --seam-tolerance: seams over it should be listed, and warn of nothing"
# The regular label space's grid cuts the fence's rails where the copies do not continue each other.
expect 0 "$bin" sample fence -o "$work/fence-strict-in.glb"
expect_error 7 "strict" "$bin" resize "$work/fence-strict-in.glb" -o "$work/fence-strict.glb" --steps 1 --labels regular --strict --json "$work/fence-strict.json"
grep -q "restitch: warning: open seam: [0-9]* edge(s) of the output are open where the input is closed" "$work/err" && ok || bad "resize --strict: no open-seam warning on stderr: $(cat "$work/err")"
[ -s "$work/fence-strict.glb" ] && ok || bad "resize --strict: the output was not written"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  if (j.warnings.length === 0 || j.warnings[0].check !== "open seam" || !(j.boundary_edges.new > 0)) process.exit(1);
' "$work/fence-strict.json" && ok || bad "resize --strict: the JSON does not name the open seam"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-strict.glb" --steps 3 --strict
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-geo.glb" --steps 3 --seam-energy geometry --json "$work/pins-geo.json"
[ "$(json_field seam_energy < "$work/pins-geo.json")" = '"geometry"' ] && ok || bad "resize --seam-energy geometry: not in the JSON"
expect_error 2 "seam-energy" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps 1 --seam-energy hausdorff
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins0.glb" --steps 0
tris0=$("$bin" info "$work/pins0.glb" --json - | json_field triangles); trisin=$("$bin" info "$work/pins.glb" --json - | json_field triangles)
[ "$tris0" = "$trisin" ] && ok || bad "--steps 0 changed the triangle count"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-size.glb" --size 30,0,0
grep -q "nearest achievable with steps" "$work/out" && ok || bad "--size does not say which steps it chose"
# Placement: the pivot stays put (default: the origin, here at the min end); --pivot per axis.
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-max.glb" --steps 3 --pivot max,origin,origin --json "$work/pins-max.json"
grep -q "pivot max,origin,origin at (20.92, 0, 0): translated by (-7.62, 0, 0)" "$work/out" && ok || bad "resize --pivot max: summary line: $(grep pivot "$work/out")"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  const p = j.pivot;
  if (p.modes.join() !== "max,origin,origin" || Math.abs(p.point[0] - 20.92) > 1e-4 || Math.abs(p.translation[0] + 3 * 2.54) > 1e-4) process.exit(1);
  if (p.low_end_cells[0] !== 3 || j.exact.applied !== false) process.exit(1);' "$work/pins-max.json" && ok || bad "resize --pivot max: JSON pivot wrong"
[ "$("$bin" info "$work/pins-max.glb" --json - | json_field bbox_max | node -e 'console.log(JSON.parse(require("fs").readFileSync(0,"utf8"))[0].toFixed(4))')" = 20.9200 ] && ok || bad "resize --pivot max moved the max end"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-c.glb" --steps 3 --pivot center --json "$work/pins-c.json"
[ "$(json_field pivot < "$work/pins-c.json" | node -e 'const p=JSON.parse(require("fs").readFileSync(0,"utf8")); console.log(p.low_end_cells[0], p.translation[0].toFixed(3))')" = "1 -3.810" ] && ok || bad "resize --pivot center: +3 is not 1 cell at the min end, 2 at the max end, moved back half a pitch to keep the centre"
[ "$(json_field pivot < "$work/pins+3.json" | node -e 'const p=JSON.parse(require("fs").readFileSync(0,"utf8")); console.log(p.modes.join(), p.translation.join())')" = "origin,origin,origin 0,0,0" ] && ok || bad "resize: the default pivot is not the origin, or the origin at the min end moved"
expect_error 2 "pivot" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps 1 --pivot middle
expect_error 2 "pivot" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps 1 --pivot min,max
# Sizes: a negative size and a change along an axis with no repeat are refused naming the axis; the
# current size is no change; --exact reaches the size by a scale about the pivot, reported.
expect_error 5 "along y" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --size 30,-1,0
expect_error 5 "no repeat runs along y" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --size 30,20,0
expect_error 5 "no repeat runs along z" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --size 0,0,5 --exact
[ ! -e "$work/x.glb" ] && ok || bad "a refused --size left a file"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-same.glb" --size 20.92,11.5,2.5
grep -q "nearest achievable with steps 0" "$work/out" && ok || bad "--size equal to the current size is a change"
# The current size as a viewer shows it, rounded to 4 significant digits, is no change along y and z (no
# repeat runs there); one more in the last digit is refused.
"$bin" resize "$work/pins.glb" -o "$work/pins-same.glb" --steps 0 --json "$work/pins-same.json" >/dev/null 2>&1
shown=$(json_field size_in < "$work/pins-same.json" | node -e 'console.log(JSON.parse(require("fs").readFileSync(0,"utf8")).map(v => Number(v.toPrecision(4))).join(","))')
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-same.glb" --size "$shown"
grep -q "nearest achievable with steps 0" "$work/out" && ok || bad "--size $shown (the size rounded as shown) is a change"
bumped=$(echo "$shown" | node -e 'const v=require("fs").readFileSync(0,"utf8").trim().split(",").map(Number); const e=Math.floor(Math.log10(v[1])); v[1]=Number((v[1]+Math.pow(10,e-3)).toPrecision(4)); console.log(v.join(","))')
expect_error 5 "no repeat runs along y" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --size "$bumped"
expect 2 "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps 1 --exact
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-exact.glb" --size 30,0,0 --exact --json "$work/pins-exact.json"
grep -q "exact: 31.08 x 11.5 x 2.5 scaled by 0.965251 x 1 x 1 about the pivot" "$work/out" && ok || bad "resize --exact: no summary line: $(cat "$work/out")"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  const e = j.exact;
  if (!e.applied || Math.abs(j.size_out[0] - 30) > 30e-6 || Math.abs(e.scale[0] - 30 / e.size_nearest[0]) > 1e-12 || e.scale[1] !== 1) process.exit(1);' "$work/pins-exact.json" && ok || bad "resize --exact: JSON exact wrong"
"$bin" info "$work/pins-exact.glb" --json - > "$work/pins-exact-info.json"
node -e '
  const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  if (Math.abs(j.bbox_max[0] - j.bbox_min[0] - 30) > 30e-6 || Math.abs(j.bbox_min[0]) > 1e-6) process.exit(1);' "$work/pins-exact-info.json" && ok || bad "resize --exact: the written model is not 30 long from the pivot"
validate "$work/pins-exact.glb"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-regular.glb" --steps 1 --labels regular
validate "$work/pins-regular.glb"
expect_error 5 "limit" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps 50 --max-problem 100
[ ! -e "$work/x.glb" ] && ok || bad "a refused resize left a file"
expect_error 5 "principal offset" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps 1,1
expect_error 5 "shrink" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps -20
expect 2 "$bin" resize "$work/pins.glb" -o "$work/x.glb"
"$bin" sample bookshelf -o "$work/shelf.glb" >/dev/null
expect 0 "$bin" resize "$work/shelf.glb" -o "$work/shelf+.glb" --steps 2,-1 --descriptor fpfh --matcher reduced
validate "$work/shelf+.glb"
# --threads and --matcher change how fast, never what: the same model bytes and the same report (its JSON
# without the timings, the matcher's name and the output file name) on 1 and 2 threads, with the reduced
# matcher (the default) and brute force.
expect 0 "$bin" resize "$work/shelf.glb" -o "$work/shelf-t1.glb" --steps 1,1 --threads 1 --json "$work/shelf-t1.json"
expect 0 "$bin" resize "$work/shelf.glb" -o "$work/shelf-t2.glb" --steps 1,1 --threads 2 --matcher brute_force \
  --json "$work/shelf-t2.json"
cmp -s "$work/shelf-t1.glb" "$work/shelf-t2.glb" && ok || bad "resize: outputs differ between --threads 1 and 2"
strip_run() { node -e "const j=JSON.parse(require('fs').readFileSync(0,'utf8')); const drop=(o)=>{if(o&&typeof o==='object'){for(const k of Object.keys(o)){if(k==='timings_ms'||k==='matcher'||k==='file')delete o[k];else drop(o[k]);}}}; drop(j); console.log(JSON.stringify(j))"; }
[ "$(strip_run < "$work/shelf-t1.json")" = "$(strip_run < "$work/shelf-t2.json")" ] && ok || bad "resize --json differs between --threads 1 and 2"
expect_error 2 "threads" "$bin" analyze "$work/shelf.glb" --threads -1
# --weld-tolerance: a fraction of the diagonal in [0, 0.01]; out of range it is a usage error (exit 2).
expect_error 2 "weld-tolerance" "$bin" resize "$work/pins.glb" -o "$work/x.glb" --steps 1 --weld-tolerance 0.5
[ ! -e "$work/x.glb" ] && ok || bad "a refused --weld-tolerance left a file"
expect 0 "$bin" resize "$work/pins.glb" -o "$work/pins-weld.glb" --steps 1 --weld-tolerance 1e-4 --json "$work/pins-weld.json"
validate "$work/pins-weld.glb"
# --detector: the autocorrelation detector finds the shelf's two repeats and says so in the JSON.
expect 0 "$bin" analyze "$work/shelf.glb" --detector autocorrelation --json "$work/shelf-ac.json"
[ "$(json_field detector < "$work/shelf-ac.json")" = '"autocorrelation"' ] && ok || bad "analyze --detector: JSON detector field"
[ "$(json_field principal_offsets < "$work/shelf-ac.json" | node -e 'console.log(JSON.parse(require("fs").readFileSync(0,"utf8")).length)')" = 2 ] && ok || bad "analyze --detector autocorrelation: not 2 principal offsets on the bookshelf"
expect 0 "$bin" analyze "$work/shelf.glb" --json "$work/shelf-h.json"
[ "$(json_field detector < "$work/shelf-h.json")" = '"histogram"' ] && ok || bad "analyze: default detector field"
expect 0 "$bin" resize "$work/shelf.glb" -o "$work/shelf-ac+.glb" --steps 1,1 --detector autocorrelation
validate "$work/shelf-ac+.glb"
expect 2 "$bin" analyze "$work/shelf.glb" --detector fourier

# Two copies: a 2-pin header's pair of pins pairs vertex for vertex, so it is a principal offset
# (docs/method.md 1.13); --verbose shows the pair tests; --size grows it into one 3-pin part.
"$bin" sample pin_header --pins 2 -o "$work/pins2.glb" >/dev/null
expect 0 "$bin" analyze "$work/pins2.glb" --verbose --json "$work/pins2.json"
grep -q "principal offset 1: (2.54, 0, 0)" "$work/out" && ok || bad "analyze: the exact pair is not principal: $(cat "$work/out")"
grep -Eq "pair_third_copy +[0-9.e-]+ <= 0\.25 +passed" "$work/out" && ok || bad "analyze --verbose: no pair test line with value and threshold"
node -e '
const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
const p = j.principal_offsets;
if (p.length !== 1 || Math.abs(p[0][0] - 2.54) > 1e-3) process.exit(1);
if (!j.dominant_offsets.some(d => d.tests.some(t => t.name === "pair_exact_area" && t.passed))) process.exit(1);' "$work/pins2.json" && ok || bad "analyze --json: the pair is not principal with its tests in $work/pins2.json"
expect 0 "$bin" resize "$work/pins2.glb" -o "$work/pins2to3.glb" --size 8.22,0,0 --json "$work/pins2to3.json"
[ "$(json_field size_out < "$work/pins2to3.json" | node -e 'console.log(JSON.parse(require("fs").readFileSync(0,"utf8"))[0].toFixed(3))')" = 8.220 ] && ok || bad "resize --size along the pair: wrong size"
validate "$work/pins2to3.glb"
# Candidates: a fence's two rails are a pair that is a detail of the whole (docs/method.md 1.13), so a
# candidate: --verbose explains the rejection, --size along y uses the candidate (one more period:
# 1.19 -> 1.74 tall) and says so.
"$bin" sample fence -o "$work/fence.glb" >/dev/null
expect 0 "$bin" analyze "$work/fence.glb" --verbose --json "$work/fence.json"
grep -q "candidate 1: (0, 0.55, 0).*a pair (2 copies).*--offsets 0,0.55,0" "$work/out" && ok || bad "analyze: the pair candidate is not listed: $(cat "$work/out")"
grep -q "rejected by repeat" "$work/out" && ok || bad "analyze --verbose: no rejection explained"
grep -Eq "repeat +0\.[0-9]+ >= 0\.25 +FAILED" "$work/out" && ok || bad "analyze --verbose: no test line with value and threshold"
node -e '
const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
const c = j.candidates[0], d = j.dominant_offsets[c.dominant];
if (j.principal_offsets.length !== 1 || c.copies !== 2 || c.reason !== "pair" || Math.abs(c.offset[1] - 0.55) > 1e-3) process.exit(1);
const last = d.tests.at(-1);
if (last.passed || !(last.at_most ? last.value > last.threshold : last.value < last.threshold)) process.exit(1);' "$work/fence.json" && ok || bad "analyze --json: candidates or tests wrong in $work/fence.json"
expect 0 "$bin" resize "$work/fence.glb" -o "$work/fence-tall.glb" --size 0,1.74,0 --json "$work/fence-tall.json"
grep -q "no principal offset runs along y: using candidate 1" "$work/out" && ok || bad "resize --size: the candidate fallback is not reported"
[ "$(json_field size_out < "$work/fence-tall.json" | node -e 'console.log(JSON.parse(require("fs").readFileSync(0,"utf8"))[1].toFixed(2))')" = 1.74 ] && ok || bad "resize --size along a candidate: wrong size"
validate "$work/fence-tall.glb"
# A 2-picket fence: the matching casts no vote for its picket pitch, its vertices repeat at it (docs/method.md
# 1.14): analyze lists the candidate, --size along x uses it (two more pickets: 0.5 -> 0.8 long).
"$bin" sample fence --pickets 2 -o "$work/fence2.glb" >/dev/null
expect 0 "$bin" analyze "$work/fence2.glb" --verbose
grep -Eq "candidate [0-9]: \(0.15, 0, 0\).*a repeat of the vertices \([0-9]+ copies\)" "$work/out" && ok || bad "analyze: the vertices' candidate is not listed: $(cat "$work/out")"
grep -Eq "vertex_structure +[0-9.]+ >= 0.5 +passed" "$work/out" && ok || bad "analyze --verbose: the vertices' candidate's tests are not shown"
expect 0 "$bin" resize "$work/fence2.glb" -o "$work/fence4.glb" --size 0.8,0,0 --json "$work/fence4.json"
grep -Eq "no principal offset runs along x: using candidate [0-9] \(0.15, 0, 0\) \(vertices" "$work/out" && ok || bad "resize --size: the vertices' candidate is not reported: $(cat "$work/out")"
[ "$(json_field size_out < "$work/fence4.json" | node -e 'console.log(JSON.parse(require("fs").readFileSync(0,"utf8"))[0].toFixed(3))')" = 0.800 ] && ok || bad "resize --size along the vertices' candidate: wrong size"
validate "$work/fence4.glb"
expect 0 "$bin" resize "$work/pins2.glb" -o "$work/pins2to4.glb" --offsets 2.5,0,0 --steps 2 --json "$work/pins2to4.json"
[ "$(json_field size_out < "$work/pins2to4.json" | node -e 'console.log(JSON.parse(require("fs").readFileSync(0,"utf8"))[0].toFixed(3))')" = 10.760 ] && ok || bad "resize --offsets 2.5,0,0 --steps 2: not 4 pins long"
expect_error 2 "triples" "$bin" analyze "$work/pins2.glb" --offsets 1,2
expect_error 5 "zero" "$bin" resize "$work/pins2.glb" -o "$work/x.glb" --offsets 0,0,0 --steps 1
expect_error 5 "no repeat" "$bin" resize "$work/pins2.glb" -o "$work/x.glb" --offsets 0.3,0,0 --steps 1
[ ! -e "$work/x.glb" ] && ok || bad "a refused --offsets left a file"

# describe: a tiny point set, SHOT and FPFH rows in input order.
printf '0 0 0 0 0 1\n0.1 0 0 0 0 1\n0 0.1 0 0 0 1\n0.1 0.1 0 0 0 1\n0.05 0.05 0.05 0 1 0\n5 5 5 0 0 1\n' > "$work/p.xyzn"
expect 0 "$bin" describe "$work/p.xyzn" --descriptor shot --radius 0.3 -o "$work/p-shot.csv"
[ "$(wc -l < "$work/p-shot.csv")" = 6 ] && [ "$(head -1 "$work/p-shot.csv" | tr ',' '\n' | wc -l)" = 352 ] && ok || bad "describe shot: wrong CSV shape"
tail -1 "$work/p-shot.csv" | grep -q "^nan" && ok || bad "describe shot: an isolated point must give a nan row"
expect 0 "$bin" describe "$work/p.xyzn" --descriptor fpfh --radius 0.3 -o "$work/p-fpfh.csv"
[ "$(head -1 "$work/p-fpfh.csv" | tr ',' '\n' | wc -l)" = 33 ] && ok || bad "describe fpfh: wrong CSV shape"
printf '0 0 0 0 0\n' > "$work/bad.xyzn"
expect_error 3 "bad.xyzn:1:" "$bin" describe "$work/bad.xyzn" --radius 0.3 -o "$work/bad.csv"
[ ! -e "$work/bad.csv" ] && ok || bad "describe of a bad file left an output"

# Real models: resize by +2 and -1 along the first principal offset, validator-clean.
if [ -f "$models/MANIFEST.tsv" ] && [ "$mode" = full ]; then
  # A model with no principal offset is refused in words (exit 4) and writes nothing.
  while IFS=$'\t' read -r file _; do
    [ "$file" = file ] && continue
    for k in 2 -1; do
      "$bin" resize "$models/$file" -o "$work/resized$k-$file" --steps "$k" >"$work/out" 2>"$work/err"; rc=$?
      if [ "$rc" = 4 ] && grep -q "no repetition was found" "$work/err" && [ ! -e "$work/resized$k-$file" ]; then
        echo "NOTE: $file: no principal offset found, resize refused"; ok; break
      fi
      [ "$rc" = 0 ] && ok || bad "exit $rc (wanted 0): resize $file --steps $k -- $(head -c 300 "$work/err")"
      validate "$work/resized$k-$file"
    done
  done < "$models/MANIFEST.tsv"
fi

# Bad input: a clear error, the documented exit code, and no output file.
"$bin" sample pin_header -o "$work/good.glb" >/dev/null
head -c 700 "$work/good.glb" > "$work/truncated.glb"
{ printf 'XXXX'; tail -c +5 "$work/good.glb"; } > "$work/magic.glb"
printf '{"asset": {"version": "2.0"}, "meshes": [' > "$work/broken.gltf"
printf '{"asset":{"version":"2.0"},"scenes":[{"nodes":[]}],"scene":0}' > "$work/empty.gltf"
printf '{"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],"bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,"componentType":5126,"count":30,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}' > "$work/range.gltf"
printf '{"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AADAfwAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],"bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}' > "$work/nan.gltf"
expect_error 3 "no such file" "$bin" info "$work/missing.glb"
expect_error 3 "directory" "$bin" info "$work"
expect_error 3 "truncated" "$bin" info "$work/truncated.glb"
expect_error 3 "not a glTF" "$bin" info "$work/magic.glb"
expect_error 3 "valid glTF" "$bin" info "$work/broken.gltf"
expect_error 4 "no triangles" "$bin" info "$work/empty.gltf"
expect_error 3 "past the end" "$bin" info "$work/range.gltf"
expect_error 4 "NaN" "$bin" info "$work/nan.gltf"
for f in truncated magic broken empty range nan; do
  ext=glb; [ -f "$work/$f.gltf" ] && ext=gltf
  "$bin" convert "$work/$f.$ext" -o "$work/out-$f.glb" >/dev/null 2>&1
  [ ! -e "$work/out-$f.glb" ] && ok || bad "convert of a bad input ($f) left an output file"
done
expect_error 6 "cannot write" "$bin" convert "$work/good.glb" -o "$work/no/such/dir/out.glb"
expect_error 2 "must end in" "$bin" convert "$work/good.glb" -o "$work/out.obj"
expect_error 2 "must end in" "$bin" resize "$work/good.glb" -o "$work/out.obj" --steps 1
# The rest of the table of bad inputs in docs/robustness.md (each row's exit code and message).
: > "$work/zero.glb"
expect_error 3 "empty" "$bin" info "$work/zero.glb"
printf '{"asset":{"version":"2.0"},"buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAkA"}],"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}' > "$work/index.gltf"
expect_error 3 "out of range" "$bin" info "$work/index.gltf"
printf '{"asset":{"version":"2.0"},"accessors":[{"componentType":5126,"count":2147483648,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}' > "$work/absurd.gltf"
expect_error 5 "max-vertices" "$bin" info "$work/absurd.gltf"
expect_error 5 "max-triangles" "$bin" info "$work/good.glb" --max-triangles 10
printf '{"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAQAAAAAAAAAAA"}],"bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0}' > "$work/degenerate.gltf"
expect_error 4 "degenerate" "$bin" info "$work/degenerate.gltf"
printf '{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"],"scenes":[{"nodes":[]}],"scene":0}' > "$work/draco.gltf"
expect_error 4 "KHR_draco_mesh_compression" "$bin" info "$work/draco.gltf"
"$bin" sample pin_header --pins 1 -o "$work/one.glb" >/dev/null
expect_error 4 "no repetition" "$bin" resize "$work/one.glb" -o "$work/x.glb" --steps 1
expect_error 5 "max-problem" "$bin" resize "$work/good.glb" -o "$work/x.glb" --steps 100000
expect_error 5 "at most" "$bin" resize "$work/good.glb" -o "$work/x.glb" --steps -100
[ ! -e "$work/x.glb" ] && ok || bad "a refused resize left an output file"
[ -z "$(ls "$work" | grep restitch-tmp)" ] && ok || bad "a temporary file was left behind"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
