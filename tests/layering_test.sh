#!/usr/bin/env bash
# The library's include layering (docs/README.md, "Layout"): data apart from drivers, opt-in headers kept out of the umbrella.
#   tests/layering_test.sh SOURCE_DIR
# Fails, naming the offending include, when
#   * a header other than the umbrella and runtime.hpp includes the analysis driver (restitch/analyze.hpp);
#   * a header outside io/ includes tinygltf or nlohmann::json (glTF and JSON stay opt-in);
#   * the umbrella includes an opt-in header (io/, families/, xyzn.hpp, mrf_io.hpp, runtime.hpp).
set -u
inc="$1/include/restitch"
bad=0
report() { echo "layering: $*"; bad=1; }
while IFS= read -r line; do report "$line includes the driver restitch/analyze.hpp"; done < <(
  grep -rln '#include "restitch/analyze.hpp"' "$inc" | grep -v -e '/restitch.hpp$' -e '/runtime.hpp$')
while IFS= read -r line; do report "$line includes tinygltf or nlohmann::json outside io/"; done < <(
  grep -rlE '#include [<"](tiny_gltf.h|nlohmann/json.hpp)' "$inc" | grep -v "^$inc/io/")
while IFS= read -r line; do report "the umbrella includes the opt-in header $line"; done < <(
  grep '^#include' "$inc/restitch.hpp" | grep -oE 'restitch/(io/[a-z_/]+|families/[a-z_]+|descriptor/xyzn|solver/mrf_io|runtime)\.hpp')
[ "$bad" -eq 0 ] && echo "layering: ok"
exit "$bad"
