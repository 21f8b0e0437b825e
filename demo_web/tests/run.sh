#!/usr/bin/env bash
# The web demo's tests: builds the WebAssembly module when missing or stale (build/web, Emscripten),
# runs the node tests (node --test: the module, and the page's state machine and worker client against
# fakes), the end-to-end test of the page in Debian's Chromium (playwright-core) and the npm package's test
# (tests/package.mjs: packed, installed elsewhere, compared with the native tool: RESTITCH_CLI or
# build/native/restitch), and ends with one line "N passed, M failed" over all checks.
# Exits non-zero on any failure. Called by scripts/test.sh; runs alone too.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
here="$root/demo_web/tests"
export NODE_PATH=/usr/share/nodejs
export RESTITCH_JOBS="${RESTITCH_JOBS:-2}"
passed=0; failed=0
log="$(mktemp -d)"
trap 'rm -rf "$log"' EXIT

echo "--- web demo: building the WebAssembly module (build/web)"
if ! bash "$here/build.sh"; then
  echo "the WebAssembly module did not build"
  echo "0 passed, 1 failed"
  exit 1
fi

echo "--- web demo: node tests (the module, the session state machine, the worker client, the peak words)"
node --test --test-reporter=tap "$here/module.test.mjs" "$here/session.test.mjs" "$here/worker-client.test.mjs" \
  "$here/peaks.test.mjs" "$here/layers.test.mjs" 2>&1 |
  tee "$log/node.tap"
p=$(grep -E '^# pass [0-9]+' "$log/node.tap" | tail -1 | awk '{print $3}')
f=$(grep -E '^# fail [0-9]+' "$log/node.tap" | tail -1 | awk '{print $3}')
if [ -z "$p" ] || [ -z "$f" ]; then failed=$((failed + 1)); else passed=$((passed + p)); failed=$((failed + f)); fi

echo "--- web demo: end to end in Chromium"
if [ -x /usr/bin/chromium ]; then
  node "$here/e2e.mjs" 2>&1 | tee "$log/e2e.log"
  line=$(grep -E '^e2e: [0-9]+ passed, [0-9]+ failed' "$log/e2e.log" | tail -1)
  if [ -z "$line" ]; then failed=$((failed + 1)); else
    passed=$((passed + $(echo "$line" | awk '{print $2}'))); failed=$((failed + $(echo "$line" | awk '{print $4}')))
  fi
else
  echo "/usr/bin/chromium is missing: the end-to-end test cannot run (scripts/install-deps.sh installs it)"
  failed=$((failed + 1))
fi

echo "--- web demo: the npm package (packed, installed elsewhere; node, npx, TypeScript, three.js in Chromium)"
if [ -x /usr/bin/chromium ]; then
  node "$here/package.mjs" 2>&1 | tee "$log/package.log"
  line=$(grep -E '^package: [0-9]+ passed, [0-9]+ failed' "$log/package.log" | tail -1)
  if [ -z "$line" ]; then failed=$((failed + 1)); else
    passed=$((passed + $(echo "$line" | awk '{print $2}'))); failed=$((failed + $(echo "$line" | awk '{print $4}')))
  fi
else
  failed=$((failed + 1))
fi

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
