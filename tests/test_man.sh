#!/usr/bin/env bash
# The man page and the case-file reference against the program:
#  - every command `voussoir --help` lists has its synopsis line and its entry under COMMANDS;
#  - every option that `voussoir --help` and each command's `--help` print is under OPTIONS;
#  - every case key of the program's own table (CASE_KEYS prints it: section, key, unit,
#    default, allowed range) is named in its section's paragraph of the man page's CASE FILES,
#    and has its row in docs/case-file.md with that unit, default and range, and that table has
#    no other key;
#  - groff reads the page without a warning (when groff is installed).
# usage: test_man.sh VOUSSOIR CASE_KEYS SOURCE_DIR
set -euo pipefail
vs=$1 keys=$2 src=$3
man=$src/man/voussoir.1
ref=$src/docs/case-file.md
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
errors=0
bad() { echo "FAIL: $*" >&2; errors=$((errors + 1)); }

# The page's text without its font escapes; a section of it (from .SH NAME to the next .SH).
sed -e 's/\\-/-/g' -e 's/\\f[BIRP]//g' -e 's/\\e/\\/g' "$man" >"$tmp/man"
section() { awk -v s="$1" '/^\.SH / { on = ($0 == ".SH " s); next } on' "$tmp/man"; }
# The options a text names: --long-name, or -x standing alone (not the -E of I-E-E).
options() { perl -ne 'print "$1\n" while /(?<![\w-])(--[a-z][a-z0-9-]*|-[a-zA-Z])(?![\w-])/g'; }
has_word() { perl -e '$w = quotemeta shift; local $/; exit !(<STDIN> =~ /(?<![\w-])$w(?![\w-])/)' -- "$1"; }

"$vs" --help >"$tmp/help"
commands=$(sed -n 's/^ *\(usage:\)\? *voussoir \([a-z][a-z]*\) .*/\2/p' "$tmp/help" | sort -u)
[ "$(wc -w <<<"$commands")" -ge 6 ] || bad "voussoir --help lists only: $commands"
section SYNOPSIS >"$tmp/synopsis"
section COMMANDS >"$tmp/commands"
section OPTIONS >"$tmp/options"
for c in $commands; do
  grep -qx "\.B voussoir $c" "$tmp/synopsis" || bad "man page: no synopsis of 'voussoir $c'"
  grep -A1 -x '\.TP' "$tmp/commands" | grep -qx "\.B $c" || bad "man page: '$c' not under COMMANDS"
  "$vs" "$c" --help >"$tmp/help.$c" || bad "voussoir $c --help: exit status $?"
done
for h in "$tmp"/help*; do
  what=${h#"$tmp"/help}
  what="voussoir ${what#.}${what:+ }--help"
  for o in $(options <"$h" | sort -u); do
    has_word "$o" <"$tmp/options" || bad "man page: option $o ($what) not under OPTIONS"
  done
done

# The case keys: the man page's paragraph of each section, the reference's row of each key.
# (fields separated by \037: a unit may be empty, which tab-separated read would skip)
"$keys" | tr '\t' '\037' >"$tmp/keys"
[ "$(wc -l <"$tmp/keys")" -ge 40 ] || bad "case_keys printed $(wc -l <"$tmp/keys") keys"
section "CASE FILES" >"$tmp/casefiles"
# Numbers in one form (%.6g) so that 1e6, 1e+06 and 1000000 compare equal; backticks dropped.
canon() {
  perl -pe 's/`//g; s/(?<![\w.])([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(?![\w.])/sprintf("%.6g", $1)/ge'
}
awk -F'|' '/^\| `\[/ {
  for (i = 2; i <= 6; i++) { gsub(/^ +| +$/, "", $i) }
  gsub(/[`\[\]]/, "", $2); gsub(/`/, "", $3); print $2 "\037" $3 "\037" $4 "\037" $5 "\037" $6
}' "$ref" >"$tmp/rows"
while IFS=$'\037' read -r sec key unit def allowed; do
  awk -v s=".B [$sec]" '/^\.TP$/ { getline; on = ($0 == s); next } /^\.(PP|SH)/ { on = 0 } on' \
    "$tmp/casefiles" >"$tmp/para"
  [ -s "$tmp/para" ] || bad "man page: no [$sec] under CASE FILES"
  has_word "$key" <"$tmp/para" || bad "man page: $sec.$key not in [$sec] under CASE FILES"
  row=$(awk -F'\037' -v s="$sec" -v k="$key" '$1 == s && $2 == k' "$tmp/rows")
  if [ -z "$row" ]; then
    bad "docs/case-file.md: no row for $sec.$key"
    continue
  fi
  IFS=$'\037' read -r _ _ dunit ddef dallowed <<<"$row"
  [ "$dunit" = "${unit:-–}" ] || bad "docs/case-file.md: $sec.$key: unit '$dunit', the program's '${unit:-–}'"
  [ "$(canon <<<"$ddef")" = "$(canon <<<"$def")" ] ||
    bad "docs/case-file.md: $sec.$key: default '$ddef', the program's '$def'"
  want=$(canon <<<"$allowed") got=$(canon <<<"$dallowed")
  [ "$got" = "$want" ] || [ "${got#"$want, "}" != "$got" ] ||
    bad "docs/case-file.md: $sec.$key: allowed '$dallowed', the program's '$allowed'"
done <"$tmp/keys"
while IFS=$'\037' read -r sec key _; do
  awk -F'\037' -v s="$sec" -v k="$key" '$1 == s && $2 == k { f = 1 } END { exit !f }' "$tmp/keys" ||
    bad "docs/case-file.md: $sec.$key is not a key of the program"
done <"$tmp/rows"

if command -v groff >/dev/null; then
  groff -man -ww -z "$man" 2>"$tmp/groff" && [ ! -s "$tmp/groff" ] || bad "groff: $(cat "$tmp/groff")"
fi
[ $errors -eq 0 ] || exit 1
echo "man page and case-file reference: $(wc -w <<<"$commands") commands, $(cat "$tmp"/help* | options | sort -u | wc -l) options, $(wc -l <"$tmp/keys") keys"
