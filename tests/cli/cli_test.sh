#!/usr/bin/env bash
# Command-line behaviour of `restitch`: help, samples, info on real models,
# bad input (clear error, documented exit code, no output file), and the
# Khronos glTF-Validator on every file the tool writes.
# Usage: cli_test.sh RESTITCH_BINARY SOURCE_DIR WORK_DIR
set -uo pipefail
bin="$1"; src="$2"; work="$3"
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
for sub in info sample convert; do expect 0 "$bin" "$sub" --help; done

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
expect_error 5 "must end in" "$bin" convert "$work/good.glb" -o "$work/out.obj"
[ -z "$(ls "$work" | grep restitch-tmp)" ] && ok || bad "a temporary file was left behind"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
