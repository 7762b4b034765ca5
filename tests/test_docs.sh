#!/usr/bin/env bash
# What the README and the documentation show works as written: their links lead somewhere, and
# their ```sh and ```python blocks run, in order, one session per page, as a user would type them at the root of the source tree
# after the build; the outputs they show are what the commands print. Each page's session runs
# in its own temporary directory (build, runs, examples and docs linked to the tree, a copy of
# python/, HOME a fresh directory, so `~/.local` and `~/.venvs` are temporary), with Debian's
# python3 first on PATH (a fresh Debian 12's) and an environment holding nothing else.
#
# A block's meaning comes from the HTML comment on the line before it (blank lines between
# allowed):
#   (none)                   ```sh and ```python blocks run; any other block is text
#   <!-- not run: WHY -->    shown, not run (the set-up commands, which install packages)
#   <!-- file: NAME -->      the block is written to NAME in the session's directory
#   <!-- output -->          the block is what the previous run block printed (stdout and stderr)
#   <!-- output of: CMD -->  the block is what CMD prints (CMD is run in the session)
#   <!-- as in the README -->  the block is one of the README's (which runs there), not run again
# An output block lists lines in the order they are printed; `...` stands for lines left out,
# and a line ending in `...` for any line that starts with what precedes it.
# Each block runs under `bash -e`; exported variables and the directory carry over to the next.
# (As in any shell, a failure inside an `a && b` list that is not a block's last command does not
# stop the block: keep such lists last.)
# usage: test_docs.sh BUILD_DIR SOURCE_DIR CC [extra compiler/linker flags, e.g. sanitizers]
set -euo pipefail
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd) cc=$(command -v "$3")
shift 3
extra="$*"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
py=/usr/bin/python3
$py -c "import h5py, numpy, matplotlib, venv, ensurepip" 2>/dev/null || {
  echo "SKIP: $py lacks h5py/numpy/matplotlib/venv (.ci/deps installs them)"
  exit 77
}

# A fresh Debian 12's python3 and the C compiler (with the build's sanitizer flags, which a
# program linked to a sanitizer build of the library needs).
mkdir "$tmp/bin"
ln -s "$py" "$tmp/bin/python3"
printf '#!/bin/sh\nexec %q "$@" %s\n' "$cc" "$extra" >"$tmp/bin/cc"
chmod +x "$tmp/bin/cc"

fail() { echo "FAIL: $*" >&2; exit 1; }

# A sanitizer build's library loads into python3 (the package's in-process runs) only after the
# sanitizers' runtimes: the ```python blocks get them preloaded, without leak detection (the
# interpreter does not free everything at exit; the library's leaks are the C tests' concern).
pyenv=""
if [[ " $extra " == *-fsanitize=*address* ]]; then
  asan=$("$cc" -print-file-name=libasan.so) ubsan=$("$cc" -print-file-name=libubsan.so)
  [ -f "$asan" ] && [ -f "$ubsan" ] || fail "$cc does not name its libasan.so and libubsan.so"
  pyenv="env LD_PRELOAD='$asan $ubsan' ASAN_OPTIONS=\${ASAN_OPTIONS:+\$ASAN_OPTIONS:}detect_leaks=0 "
fi

# The blocks of a page as a list: LINE, KIND, ARG, FILE (separated by \037, as ARG may be
# empty), the block's text in FILE.
# KIND: run-sh, run-python, file, output, output-of, as-readme, text.
blocks() { # page dir
  awk -v dir="$2" '
    function flush_marker() { marker = ""; arg = "" }
    BEGIN { inblock = 0; n = 0; flush_marker() }
    inblock && /^```[ \t]*$/ {
      inblock = 0; close(f)
      kind = "text"
      if (marker == "not run") kind = "text"
      else if (marker == "file") kind = "file"
      else if (marker == "output") kind = "output"
      else if (marker == "output of") kind = "output-of"
      else if (marker == "as in the README") kind = "as-readme"
      else if (marker != "") { printf "%d\037bad-marker\037%s\037-\n", start, marker; }
      else if (lang == "sh") kind = "run-sh"
      else if (lang == "python") kind = "run-python"
      printf "%d\037%s\037%s\037%s\n", start, kind, arg, f
      flush_marker(); next
    }
    inblock { print > f; next }
    /^```/ {
      inblock = 1; start = NR; lang = substr($0, 4); sub(/[ \t].*/, "", lang)
      f = sprintf("%s/block%03d", dir, ++n); printf "" > f; next
    }
    /^<!-- .* -->[ \t]*$/ {
      m = $0; sub(/^<!-- */, "", m); sub(/ *-->[ \t]*$/, "", m)
      if (m ~ /^not run:/) { marker = "not run" }
      else if (m ~ /^file: /) { marker = "file"; arg = substr(m, 7) }
      else if (m == "output") { marker = "output" }
      else if (m ~ /^output of: /) { marker = "output of"; arg = substr(m, 12) }
      else if (m == "as in the README") { marker = m }
      else { marker = "unknown marker: " m }
      mline = NR; next
    }
    /^[ \t]*$/ { next }
    marker != "" { printf "%d\037bad-marker\037not followed by a block\037-\n", mline; flush_marker() }
  ' "$1"
}

# The expected lines (FILE) in OUTPUT, in order; `...` lines skipped, a trailing `...` a prefix.
same_output() { # expected output
  awk -v out="$2" '
    function rtrim(s) { sub(/[ \t]+$/, "", s); return s }
    BEGIN { n = 0; while ((getline l < out) > 0) o[++n] = rtrim(l); i = 1 }
    {
      e = rtrim($0)
      if (e == "...") next
      prefix = (e ~ /\.\.\.$/)
      if (prefix) { e = rtrim(substr(e, 1, length(e) - 3)) }
      while (i <= n && !(prefix ? substr(o[i], 1, length(e)) == e : o[i] == e)) i++
      if (i > n) { print "not printed (or not in this order): " $0; exit 1 }
      i++
    }
  ' "$1"
}

# One page's session.
run_page() { # page
  local page=$1 rel name dir work home line kind arg file n=0 last="" rc t0=$SECONDS
  rel=${page#"$src"/}
  name=${rel//\//_}
  name=${name%.md}
  dir=$tmp/$name
  work=$dir/work
  home=$dir/home
  mkdir -p "$dir/blocks" "$work" "$home"
  ln -s "$build" "$work/build"
  for d in runs examples docs; do ln -s "$src/$d" "$work/$d"; done
  cp -r "$src/python" "$work/python" # pip builds in place; keep the tree clean
  # The session's state: a clean environment, then what the blocks export and where they cd.
  {
    echo "export HOME=$(printf %q "$home") PATH=$(printf %q "$tmp/bin:/usr/local/bin:/usr/bin:/bin")"
    for v in ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS; do
      [ -n "${!v:-}" ] && echo "export $v=$(printf %q "${!v}")"
    done
    [ -n "$extra" ] && echo "export CFLAGS=$(printf %q "$extra") LDFLAGS=$(printf %q "$extra")"
  } >"$dir/env"
  echo "$work" >"$dir/cwd"
  while IFS=$'\037' read -r line kind arg file; do
    case $kind in
      bad-marker) fail "$rel:$line: $arg" ;;
      text) continue ;;
      as-readme)
        local f found=0
        for f in "$tmp/readme-blocks"/block*; do cmp -s "$f" "$file" && found=1; done
        [ $found = 1 ] || fail "$rel:$line: the block is not one of the README's, which run there"
        continue ;;
      file)
        cp "$file" "$(cat "$dir/cwd")/$arg"
        continue ;;
      output)
        [ -n "$last" ] || fail "$rel:$line: an output block with no command before it"
        same_output "$file" "$last" >"$dir/why" ||
          fail "$rel:$line: $(cat "$dir/why"); the command printed:$(printf '\n'; cat "$last")"
        continue ;;
      output-of) printf '%s\n' "$arg" >"$file.cmd" ;;
      run-python) { echo "${pyenv}python3 - <<'VS_DOCS_PYTHON'"; cat "$file"; echo "VS_DOCS_PYTHON"; } >"$file.cmd" ;;
      run-sh) cp "$file" "$file.cmd" ;;
    esac
    n=$((n + 1))
    last=$dir/out$n
    {
      echo "set -e"
      echo ". $(printf %q "$dir/env")"
      echo "cd \"\$(cat $(printf %q "$dir/cwd"))\""
      cat "$file.cmd"
      echo
      echo "export -p >$(printf %q "$dir/env.next")"
      echo "pwd >$(printf %q "$dir/cwd")"
    } >"$file.sh"
    rc=0
    env -i bash "$file.sh" >"$last" 2>&1 </dev/null || rc=$?
    [ $rc -eq 0 ] || fail "$rel:$line: exit status $rc:$(printf '\n'; cat "$file.cmd"; echo ---; tail -n 40 "$last")"
    grep -v -E '^declare -x (OLDPWD|PWD|SHLVL|_)(=|$)' "$dir/env.next" >"$dir/env"
    if [ "$kind" = output-of ]; then
      same_output "$file" "$last" >"$dir/why" ||
        fail "$rel:$line: $(cat "$dir/why"); '$arg' printed:$(printf '\n'; cat "$last")"
    fi
  done < <(blocks "$page" "$dir/blocks")
  echo "$rel: $n blocks run ($((SECONDS - t0)) s)"
}

# The links between the pages: every relative link's file exists, and its #anchor is a heading
# there (GitHub's anchors: the heading in lower case, punctuation but - and _ dropped, blanks -).
perl -e '
  use File::Basename qw(dirname);
  my (%anchors, $bad);
  sub anchors {
    my ($f) = @_;
    return $anchors{$f} if $anchors{$f};
    my (%a, $in);
    open(my $h, "<", $f) or return {};
    while (<$h>) {
      $in = !$in if /^```/;
      next if $in;
      if (/^#+\s+(.*?)\s*$/) { my $s = lc $1; $s =~ s/[^\w\- ]//g; $s =~ s/ /-/g; $a{$s} = 1 }
    }
    return $anchors{$f} = \%a;
  }
  for my $page (@ARGV) {
    open(my $h, "<", $page) or die "$page: $!";
    my ($in, $n) = (0, 0);
    while (my $l = <$h>) {
      $n++;
      $in = !$in if $l =~ /^```/;
      next if $in;
      while ($l =~ /\]\(([^)\s]+)\)/g) {
        my $t = $1;
        next if $t =~ m{^[a-z]+:};
        my ($file, $anchor) = split /#/, $t, 2;
        my $target = $file eq "" ? $page : $file =~ m{^/} ? $file : dirname($page) . "/$file";
        if (!-e $target) { print "FAIL: $page:$n: link $t: no such file\n"; $bad++; next }
        next unless defined $anchor && $target =~ /\.md$/;
        $bad++, print "FAIL: $page:$n: link $t: no such heading\n" unless anchors($target)->{$anchor};
      }
    }
  }
  exit($bad ? 1 : 0);
' "$src/README.md" "$src"/docs/*.md >&2 || exit 1

mkdir "$tmp/readme-blocks"
blocks "$src/README.md" "$tmp/readme-blocks" >/dev/null
pages=("$src/README.md" "$src"/docs/*.md)
for page in "${pages[@]}"; do
  run_page "$page"
done
echo "docs: ok"
