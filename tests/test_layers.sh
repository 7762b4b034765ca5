#!/usr/bin/env bash
# .ci/layers: the tree as it is passes, and a planted violation of each rule fails, on a copy of
# src/ and include/ in a temporary directory (the tree itself is not touched).
# usage: test_layers.sh SOURCE_DIR
set -euo pipefail
src=$(cd "$1" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
fresh() { rm -rf "$tmp/t"; mkdir -p "$tmp/t/.ci"; cp -r "$src/src" "$src/include" "$tmp/t/"; }
check() { "$src/.ci/layers" --root "$tmp/t" >"$tmp/out" 2>&1; }

fresh
check || fail "the tree as it is: $(cat "$tmp/out")"
echo "as it is: $(tail -n 1 "$tmp/out")"

# an upward include: the model including the run's private header
fresh
sed -i '0,/^#include/s//#include "run_internal.h"\n#include/' "$tmp/t/src/model/geometry.c"
check && fail "an upward include (model -> run) passed"
grep -q 'src/model/geometry.c (model) includes src/run/run_internal.h (run): an upward include' \
  "$tmp/out" || fail "upward include not named: $(cat "$tmp/out")"
echo "upward include: refused"

# an upward include of a public header: the solvers including run.h
fresh
sed -i '0,/^#include/s//#include "voussoir\/run.h"\n#include/' "$tmp/t/src/solve/stability.c"
check && fail "an upward public include (solve -> run.h) passed"
grep -q 'includes include/voussoir/run.h (run): an upward include' "$tmp/out" ||
  fail "upward public include not named: $(cat "$tmp/out")"
echo "upward public include: refused"

# the engine including the INI case
fresh
sed -i '0,/^#include/s//#include "voussoir\/case.h"\n#include/' "$tmp/t/src/solve/stability.c"
check && fail "the INI case included by the solvers passed"
grep -q 'the engine takes the run.s definition' "$tmp/out" || fail "case.h not named: $(cat "$tmp/out")"
echo "the INI case in the engine: refused"

# the umbrella header reaching a third-party header
fresh
sed -i '0,/^#include "voussoir\/status.h"/s//#include <sundials\/sundials_matrix.h>\n#include "voussoir\/status.h"/' \
  "$tmp/t/include/voussoir/geometry.h"
check && fail "SUNDIALS reached from voussoir.h passed"
grep -q 'voussoir.h reaches <sundials/sundials_matrix.h>' "$tmp/out" ||
  fail "third-party header not named: $(cat "$tmp/out")"
echo "a third-party header under the umbrella: refused"

# a file outside the layer folders, and a folder that is no layer
fresh
echo 'int x;' >"$tmp/t/src/stray.c"
mkdir "$tmp/t/src/misc"
check && fail "a stray file and folder passed"
grep -q 'src/stray.c: a file outside the layer folders' "$tmp/out" || fail "stray file not named"
grep -q 'src/misc/: not a layer' "$tmp/out" || fail "stray folder not named"
echo "a file and a folder outside the layers: refused"
