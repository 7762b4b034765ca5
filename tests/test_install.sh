#!/usr/bin/env bash
# cmake --install into a temporary prefix, then use it as a user would: the files are where the
# documentation says; the example builds against the installed library with pkg-config and with
# find_package(voussoir), and runs; the installed program finds the installed library.
# usage: test_install.sh BUILD_DIR SOURCE_DIR CC LIBDIR [extra compiler/linker flags]
set -euo pipefail
build=$1 src=$(cd "$2" && pwd) cc=$3 libdir=$4
shift 4
extra=("$@")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
p=$tmp/prefix
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$p" >/dev/null
for f in bin/voussoir "$libdir/libvoussoir.so" include/voussoir/run.h include/voussoir/case.h \
         "$libdir/pkgconfig/voussoir.pc" "$libdir/cmake/voussoir/voussoirConfig.cmake" \
         share/man/man1/voussoir.1 share/voussoir/reference.ini share/voussoir/spreading.ini \
         share/voussoir/run_case.c share/voussoir/CMakeLists.txt share/doc/voussoir/README.md \
         share/doc/voussoir/docs/README.md share/doc/voussoir/docs/case-file.md share/voussoir/examples/paraview_record.py \
         share/voussoir/examples/fragility.py share/voussoir/python/voussoir/figures/__init__.py; do
  [ -e "$p/$f" ] || fail "$f not installed"
done
[ -e "$p/include/voussoir/sweep.h" ] && fail "sweep.h (CLI only) installed"
# The installed pages' relative links (to each other, the README, the examples) all lead to an
# installed file, as in the source tree.
while IFS= read -r -d '' md; do
  for l in $(grep -o '](\([^)#]*\)[)#]' "$md" | sed 's/^](\(.*\).$/\1/' | grep -v '^[a-z]*:'); do
    [ -e "$(dirname "$md")/$l" ] || fail "${md#"$p"/}: its link $l leads to nothing installed"
  done
done < <(find "$p/share/doc/voussoir" -name '*.md' -print0)
so=$(readlink -f "$p/$libdir/libvoussoir.so")
ver=$(sed -n 's/^project(voussoir VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
abi=$(sed -n 's/^set(VS_SOVERSION \([0-9]*\)).*/\1/p' "$src/CMakeLists.txt")
[ -n "$abi" ] || fail "no VS_SOVERSION in CMakeLists.txt"
[ "$(basename "$so")" = "libvoussoir.so.$ver" ] || fail "library is $(basename "$so"), expected libvoussoir.so.$ver"
[ -e "$p/$libdir/libvoussoir.so.$abi" ] || fail "no SONAME link libvoussoir.so.$abi"
soname=$(objdump -p "$so" | awk '$1 == "SONAME" {print $2}')
[ "$soname" = "libvoussoir.so.$abi" ] || fail "soname $soname, expected libvoussoir.so.$abi"

# The installed program runs and loads the installed library, not the build tree's.
"$p/bin/voussoir" --version | grep -q "$ver" || fail "installed voussoir --version"
ldd "$p/bin/voussoir" | grep libvoussoir | grep -q "$p/" || fail "installed voussoir does not load $p/$libdir"
# Its plugins are the installed record and plot libraries, loaded from the prefix.
for f in libvoussoir-record.so.$abi libvoussoir-plot.so.$abi; do
  [ -e "$p/$libdir/$f" ] || fail "$libdir/$f not installed"
done
LD_DEBUG=files "$p/bin/voussoir" run "$p/share/voussoir/reference.ini" -q --first-limit \
  -o "$tmp/first.h5" >/dev/null 2>"$tmp/ld" || fail "installed voussoir run -o: $(grep -v '^ *[0-9]*:' "$tmp/ld")"
grep -q "file=$p/.*libvoussoir-record\.so" "$tmp/ld" || fail "the record plugin not loaded from $p"
[ -s "$tmp/first.h5" ] || fail "installed voussoir run -o wrote no record"
# voussoir plot's charts: the package installed beside the program (share/voussoir/python), not
# the source tree's nor PYTHONPATH's (a decoy there must not be taken)
if /usr/bin/python3 -c "import matplotlib, h5py, numpy, cffi" 2>/dev/null; then
  mkdir -p "$tmp/decoy/voussoir"
  echo 'raise ImportError("the decoy package on PYTHONPATH was taken")' >"$tmp/decoy/voussoir/__init__.py"
  PYTHONPATH=$tmp/decoy VOUSSOIR_PYTHON=/usr/bin/python3 "$p/bin/voussoir" plot "$tmp/first.h5" \
    -o "$tmp/pics" >/dev/null 2>"$tmp/err" || fail "installed voussoir plot: $(cat "$tmp/err")"
  [ -s "$tmp/pics/curves.pdf" ] && [ -s "$tmp/pics/arch_reference.png" ] ||
    fail "installed voussoir plot: no charts"
fi

# The example through pkg-config, run on the installed reference case.
export PKG_CONFIG_PATH=$p/$libdir/pkgconfig
[ "$(pkg-config --modversion voussoir)" = "$ver" ] || fail "pkg-config --modversion"
read -r -a pc <<<"$(pkg-config --cflags --libs voussoir)"
"$cc" -std=c17 -Wall -Wextra -Werror "${extra[@]}" "$src/examples/run_case.c" "${pc[@]}" \
  -Wl,-rpath,"$(pkg-config --variable=libdir voussoir)" -lm -o "$tmp/run_case_pc"
# (the fall to rest is left out, as the program leaves it out without a record: it is most of a
# run's time and changes nothing the example prints)
"$tmp/run_case_pc" "$p/share/voussoir/reference.ini" dynamic.fall_s=0 >"$tmp/out_pc" ||
  fail "example failed"
cat "$tmp/out_pc"
grep -q '^collapse delta_u = ' "$tmp/out_pc" || fail "example printed no collapse"

# The same case through the installed program: the same collapse displacement (both come from
# the installed library; this checks the example uses the API as the program does).
ex=$(sed -n 's/^collapse delta_u = \([0-9.]*\) mm.*/\1/p' "$tmp/out_pc")
cli=$("$p/bin/voussoir" run "$p/share/voussoir/reference.ini" --json --no-record -q |
      sed -n 's/.*"collapse": *{[^}]*"delta_mm": *\([0-9.eE+-]*\).*/\1/p')
[ -n "$cli" ] || fail "no collapse delta_mm in the program's JSON"
awk -v a="$ex" -v b="$cli" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d < 1e-3) }' ||
  fail "example collapse $ex mm, program $cli mm"

# Bad input: exit 2 with the field named.
set +e
"$tmp/run_case_pc" "$p/share/voussoir/reference.ini" joints.kn_N_mm3=-1 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] && grep -q kn_N_mm3 "$tmp/err" || fail "bad input: exit $rc, $(cat "$tmp/err")"

# The example through find_package(voussoir).
mkdir "$tmp/cm"
cat >"$tmp/cm/CMakeLists.txt" <<CM
cmake_minimum_required(VERSION 3.25)
project(use_voussoir C)
find_package(voussoir $ver REQUIRED)
add_executable(run_case "$src/examples/run_case.c")
target_compile_options(run_case PRIVATE ${extra[*]})
target_link_options(run_case PRIVATE ${extra[*]})
target_link_libraries(run_case PRIVATE voussoir::voussoir m)
CM
cmake -S "$tmp/cm" -B "$tmp/cm/build" -DCMAKE_C_COMPILER="$cc" -DCMAKE_PREFIX_PATH="$p" >/dev/null
cmake --build "$tmp/cm/build" >/dev/null
"$tmp/cm/build/run_case" "$p/share/voussoir/reference.ini" dynamic.fall_s=0 | grep -q "^collapse delta_u = $ex mm" ||
  fail "find_package build of the example gives another result"
echo "install: ok ($p)"
