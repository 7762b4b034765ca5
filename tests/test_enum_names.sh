#!/usr/bin/env bash
# Every table of names (the case file's named choices, the damping models', the fall solvers',
# the support kinds') is checked against its enum when it compiles: the files as they are
# compile, and a value planted in an enum of voussoir/def.h, with no name given to it, stops
# every file that names that enum's values (on a copy of include/: the tree is not touched).
# usage: test_enum_names.sh SOURCE_DIR BUILD_DIR CC KLU_INCLUDE_DIR
set -euo pipefail
src=$(cd "$1" && pwd) build=$(cd "$2" && pwd) cc=$3 klu=$4
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
inc=(-I"$tmp/include" -I"$build/include")
for d in "$src"/src/*/; do inc+=(-I"${d%/}"); done
inc+=(-I"$klu")
compile() { "$cc" -std=c17 -fsyntax-only "${inc[@]}" "$src/$1" >"$tmp/out" 2>&1; }
fresh() { rm -rf "$tmp/include"; cp -r "$src/include" "$tmp/include"; }

# the enums' counts and the files holding a table of their names
declare -A files=(
  [VS_SUPPORT_KIND_COUNT]="src/case/case.c src/run/report.c"
  [VS_DAMPING_MODEL_COUNT]="src/case/case.c src/model/damping.c"
  [VS_FALL_SCHEME_COUNT]="src/case/case.c"
  [VS_FALL_SOLVER_COUNT]="src/case/case.c src/fall/fall.c"
  [VS_LOAD_KIND_COUNT]="src/case/case.c"
  [VS_ANALYSIS_TYPE_COUNT]="src/case/case.c"
)

fresh
for f in $(printf '%s\n' "${files[@]}" | tr ' ' '\n' | sort -u); do
  compile "$f" || fail "$f as it is: $(cat "$tmp/out")"
done
echo "as they are: compiled"

for count in "${!files[@]}"; do
  fresh
  sed -i "s/^\( *\)$count\$/\1VS_PLANTED_VALUE,\n\1$count/" "$tmp/include/voussoir/def.h"
  grep -q VS_PLANTED_VALUE "$tmp/include/voussoir/def.h" || fail "$count: not the last line of its enum in def.h"
  for f in ${files[$count]}; do
    compile "$f" && fail "$f compiled with a value of $count's enum that has no name"
    grep -q "a name for every" "$tmp/out" || fail "$f: not refused by its check: $(cat "$tmp/out")"
  done
  echo "a value without a name before $count: refused by ${files[$count]}"
done
