# Sourced by the tests that run the Python package in process: python_runner sets run, the
# command prefix for python3; python_needs skips the test without the modules it imports. A
# sanitizer build's library loads into python3 only after the sanitizers' runtimes: with
# MODE = sanitize they are preloaded, without leak detection (the interpreter does not free
# everything at exit); exit 77 (skip) when CC does not name them.
# usage: python_runner CC [MODE]
python_runner() {
  run=(env)
  if [ "${2:-}" = sanitize ]; then
    local asan ubsan
    asan=$("$1" -print-file-name=libasan.so) ubsan=$("$1" -print-file-name=libubsan.so)
    [ -f "$asan" ] && [ -f "$ubsan" ] ||
      { echo "SKIP: $1 does not name its libasan.so and libubsan.so"; exit 77; }
    run=(env LD_PRELOAD="$asan $ubsan" ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0")
  fi
}

# Exit 77 (skip), saying which, unless $py imports every module named.
# usage: python_needs MODULE...
python_needs() {
  local IFS=,
  "$py" -c "import $*" 2>/dev/null ||
    { echo "SKIP: $py lacks one of $* (.ci/deps installs them)"; exit 77; }
}
