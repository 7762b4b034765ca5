#!/usr/bin/env bash
# The public API is exactly what the installed headers declare, and there is one version.
# - Each shared library exports (nm -D) only functions that an installed header declares with
#   VS_API, plus its plugin table; every VS_API function is exported by one of them.
# - The version of CMake's project() is the one `voussoir --version`, the generated version.h,
#   pkg-config --modversion, the man page and the Python package give.
# usage: test_api.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# what the installed headers declare
/usr/bin/python3 - "$src"/include/voussoir/*.h >"$tmp/declared" <<'PY'
import re, sys
names = set()
for p in sys.argv[1:]:
    text = re.sub(r"/\*.*?\*/", " ", open(p).read(), flags=re.S)  # comments out
    for m in re.finditer(r"^VS_API\b([^;{]*?)\b([A-Za-z_]\w*)\s*\(", text, re.M):
        names.add(m.group(2))
print("\n".join(sorted(names)))
PY
[ "$(wc -l <"$tmp/declared")" -gt 100 ] || fail "only $(wc -l <"$tmp/declared") VS_API declarations found"
: >"$tmp/all"
for lib in libvoussoir libvoussoir-record libvoussoir-plot libvoussoir-mpi; do
  so="$build/$lib.so"
  [ -e "$so" ] || { [ "$lib" = libvoussoir-mpi ] && continue; fail "$so missing"; }
  # (the sanitizers' own symbols, __asan*, __odr_asan*, ... in an instrumented build, aside)
  nm -D --defined-only "$so" | awk '{print $NF}' | grep -v '^__\(odr_\)\?\(asan\|ubsan\|lsan\)' |
    sort -u >"$tmp/$lib"
  cat "$tmp/$lib" >>"$tmp/all"
  # (under AddressSanitizer an exported global has its ODR indicator, __odr_asan.NAME, beside it)
  extra=$(comm -23 "$tmp/$lib" "$tmp/declared" |
    grep -v -x -E '(__odr_asan\.)?vs_(record|plot|mpi)_plugin_table' || true)
  [ -z "$extra" ] || fail "$lib.so exports what no installed header declares: $(echo "$extra" | tr "\n" " ")"
  echo "$lib.so: $(wc -l <"$tmp/$lib") symbols, each declared by an installed header"
done
sort -u "$tmp/all" -o "$tmp/all"
missing=$(comm -23 "$tmp/declared" "$tmp/all")
[ -z "$missing" ] || fail "declared with VS_API but exported by no library: $(echo "$missing" | tr "\n" " ")"

# one version
ver=$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")
[ -n "$ver" ] || fail "no CMAKE_PROJECT_VERSION in $build/CMakeCache.txt"
got=$("$build/voussoir" --version | awk '{print $2}')
[ "$got" = "$ver" ] || fail "voussoir --version says $got, CMake $ver"
grep -q "#define VS_VERSION \"$ver\"" "$build/include/voussoir/version.h" || fail "version.h is not $ver"
pc=$(PKG_CONFIG_PATH="$build" pkg-config --modversion voussoir)
[ "$pc" = "$ver" ] || fail "pkg-config --modversion says $pc, CMake $ver"
man=$(sed -n 's/^\.TH VOUSSOIR 1 "[^"]*" "voussoir \([^"]*\)".*/\1/p' "$src/man/voussoir.1")
[ "$man" = "$ver" ] || fail "man/voussoir.1 says $man, CMake $ver"
py=$(sed -n 's/^version = "\(.*\)"/\1/p' "$src/python/pyproject.toml")
[ "$py" = "$ver" ] || fail "python/pyproject.toml says $py, CMake $ver"
pyv=$(sed -n 's/^__version__ = "\(.*\)"/\1/p' "$src/python/voussoir/__init__.py")
[ "$pyv" = "$ver" ] || fail "python/voussoir/__init__.py says $pyv, CMake $ver"
echo "version $ver: the program, version.h, pkg-config, the man page and the Python package agree"
