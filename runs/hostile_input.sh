#!/usr/bin/env bash
# Hostile input, tried as a hostile user would: each row one input (a case file, an output path,
# a planted link or FIFO, a damaged journal, a shard's table, a pathological case), run in a
# scratch directory with stand-ins only (never the machine's devices), and what came of it: the
# exit status against the one expected, whether the files are as they must be afterwards (a
# planted link's target unchanged, no output directory, the record marked stopped, ...), and
# whether stderr holds a control byte other than the newline. Prints a Markdown table (docs/safety.md, "Hostile input") and exits 1 when
# any row is not as expected.
# usage: runs/hostile_input.sh   (binary: build/voussoir or $VOUSSOIR)
set -uo pipefail
source "$(dirname "$0")/lib.sh"
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"
ref="$here/reference.ini"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
small=(--set arch.voussoirs=11) # a quick arch where the input is not the arch
bad=0

# row WHAT EXPECTED_EXIT CHECK -- COMMAND...: run COMMAND (stdout discarded, stderr kept), then
# CHECK (a shell function returning 0 when the files are as they must be afterwards).
row() {
  local what="$1" want="$2" check="$3"
  shift 4
  local t0 t1 rc clean files ok
  t0=$(date +%s.%N)
  "$@" >/dev/null 2>err.txt </dev/null
  rc=$?
  t1=$(date +%s.%N)
  if LC_ALL=C grep -q $'[\x01-\x09\x0b-\x1f\x7f]' err.txt; then clean="no"; else clean="yes"; fi
  if "$check"; then files="yes"; else files="NO"; fi
  ok="as expected"
  if [ "$rc" != "$want" ] || [ "$files" = NO ] || [ "$clean" = no ]; then
    ok="NOT AS EXPECTED"
    bad=1
  fi
  local msg
  msg="$(head -n 1 err.txt | cut -c1-90 | sed 's/|/\\|/g; s/`//g')"
  printf '| %s | %s (%s) | %.1f | %s | %s | %s | `%s` |\n' "$what" "$rc" "$want" \
    "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')" "$files" "$clean" "$ok" "$msg"
}
nothing() { return 0; }
target_intact() { [ "$(cat target)" = "precious" ]; }
no_dir() { [ ! -e out ]; }
plant() { rm -rf out target; mkdir -p out; echo precious >target; ln -s "$work/target" "out/$1"; }
case_file() { printf '%b' "$1" >case.ini; }

printf '| input | exit (expected) | s | files as they must be | stderr clean | verdict | first line of stderr |\n'
printf '|---|---|---|---|---|---|---|\n'

# --- the case file ---
case_file '[arch]\nra\x1b[2Jdius_mm = 3\n'
row "case: an escape sequence in a key" 2 nothing -- "$bin" run case.ini --no-record -q
case_file '[arch]\nradius_mm = nan\n'
row "case: nan" 2 nothing -- "$bin" run case.ini --no-record -q
case_file '[arch]\nradius_mm = 1e999\n'
row "case: 1e999 (not a double)" 2 nothing -- "$bin" run case.ini --no-record -q
case_file '[arch]\nradius_mm = 0x12c\n'
row "case: hexadecimal" 2 nothing -- "$bin" run case.ini --no-record -q
case_file '[arch]\nvoussoirs = 0\n'
row "case: voussoirs = 0" 2 nothing -- "$bin" run case.ini --no-record -q
case_file '[arch]\nradius_mm = 3\x00\n'
row "case: a NUL byte" 2 nothing -- "$bin" run case.ini --no-record -q
head -c 2000000 /dev/zero | tr '\0' ';' >big.ini
row "case: 2 MB" 2 nothing -- "$bin" run big.ini --no-record -q
mkfifo fifo.ini
row "case: a FIFO (not read, not waited on)" 2 nothing -- "$bin" run fifo.ini --no-record -q
row "--alpha 1e999" 2 nothing -- "$bin" run "$ref" --alpha 1e999 --no-record -q
row "--kn -3" 2 nothing -- "$bin" run "$ref" --kn -3 --no-record -q
row "sweep -j 0" 2 no_dir -- "$bin" sweep "$ref" --alpha 0 -j 0 -o out -q

# --- a blocks file (arch.shape = file) ---
mkfifo fifo.json
case_file '[arch]\nshape = file\nblocks_file = fifo.json\n'
row "blocks file: a FIFO (not read, not waited on)" 2 nothing -- "$bin" run case.ini --no-record -q
printf '{"format": "voussoir-blocks 1", "blocks": [{"name": "L", "support": "left", "polygon": [[-10,0],[0,0],[0,10],[-10,10]]}, {"name": "R", "support": "right", "polygon": [[40,0],[50,0],[50,10],[40,10]]}, {"name": "a", "polygon": [[0,0],[40,0],[40,6],[0,6]]}]}' >partly.json
case_file '[arch]\nshape = file\nblocks_file = partly.json\n'
no_record() { [ ! -e r.h5 ] && [ ! -e r.h5.part ]; }
row "blocks file: edges overlapping partly" 2 no_record -- "$bin" run case.ini -q -o r.h5
printf '{"format": "voussoir-blocks 1", "blocks": [{"name": "a\\u001b[2J", "polygon": []}, {}, {}]}' >esc.json
case_file '[arch]\nshape = file\nblocks_file = esc.json\n'
row "blocks file: an escape sequence in a name" 2 nothing -- "$bin" run case.ini --no-record -q
rm -f target; echo precious >target; ln -sf "$work/target" blocks.json
row "blocks -o a symbolic link" 2 target_intact -- "$bin" blocks "$ref" -o blocks.json

# --- output paths ---
rm -rf out target; echo precious >target; ln -s "$work/target" link.h5
row "run -o a symbolic link" 2 target_intact -- "$bin" run "$ref" "${small[@]}" --first-limit -q -o link.h5
mkfifo out.h5
row "run -o a FIFO" 2 nothing -- "$bin" run "$ref" "${small[@]}" --first-limit -q -o out.h5
row "run -o with an escape sequence" 2 nothing -- "$bin" run "$ref" --first-limit -q -o $'r\x1b[2J.h5'
row "run -o a:b.h5 (ParaView splits at ':')" 2 nothing -- "$bin" run "$ref" --first-limit -q -o a:b.h5
row "run -o of 252 bytes" 2 nothing -- "$bin" run "$ref" --first-limit -q -o "$(printf 'x%.0s' {1..249}).h5"
row "run --csv naming the case file" 2 nothing -- "$bin" run "$ref" --no-record -q --csv "$ref"
plant summary.csv.tmp
row "sweep: a link at summary.csv.tmp" 2 target_intact -- "$bin" sweep "$ref" "${small[@]}" --alpha 0 --first-limit -q -o out
plant run_0001.json.part
row "sweep: a link at run_0001.json.part" 2 target_intact -- "$bin" sweep "$ref" "${small[@]}" --alpha 0 --first-limit -q -o out
plant samples.csv.part
row "montecarlo: a link at samples.csv.part" 2 target_intact -- "$bin" montecarlo "$ref" "${small[@]}" --samples 2 -q -o out
plant montecarlo.manifest.part
row "montecarlo: a link at montecarlo.manifest.part" 2 target_intact -- "$bin" montecarlo "$ref" "${small[@]}" --samples 2 -q -o out
deep="d"; for k in 1 2 3 4 5 6; do deep="$deep/$(printf "$k%.0s" {1..200})"; done; mkdir -p "$deep"
deep_clean() { [ -z "$(find d -type f)" ]; }
row "montecarlo -o of 1209 bytes (was cut at 1200)" 2 deep_clean -- "$bin" montecarlo "$ref" "${small[@]}" --samples 2 -q -o "$deep/out"
rm -rf out target

# --- studies: the directory lock, damaged journals ---
# the first study is held on its run 2 until the file `release` exists (VS_FAULT_HOLD, the tests'
# hook; VS_FAULT_HELD: made once it holds)
VS_FAULT_HOLD=2 VS_FAULT_RELEASE="$work/release" VS_FAULT_HELD="$work/held.flag" \
  "$bin" sweep "$ref" "${small[@]}" --alpha 0,30 --first-limit -q -j 1 -o held >/dev/null 2>&1 &
first=$!
for _ in $(seq 1 3000); do [ -e held.flag ] && break; sleep 0.02; done
held_same() { [ -e held/sweep.journal ]; }
row "a second study in the directory of one under way" 2 held_same -- "$bin" montecarlo "$ref" "${small[@]}" --samples 2 -q -o held
touch release; wait "$first"
"$bin" sweep "$ref" "${small[@]}" --alpha 0,30 --first-limit -q -o sw >/dev/null 2>&1
cp sw/summary.csv whole.csv
# flip a byte in the first row of the journal (its checksum then fails)
python3 - sw/sweep.journal <<'EOF'
import sys
p = sys.argv[1]
b = bytearray(open(p, 'rb').read())
b[b.index(b'\n') + 10] ^= 0x55
open(p, 'wb').write(b)
EOF
same_table() { cmp -s <(cut -d, -f1-8 sw/summary.csv) <(cut -d, -f1-8 whole.csv); }
row "sweep --resume: a journal row with a flipped byte (runs again)" 0 same_table -- "$bin" sweep "$ref" "${small[@]}" --alpha 0,30 --first-limit -q -o sw --resume

# --- merge: a shard's table ---
mkdir -p shard
"$bin" montecarlo "$ref" "${small[@]}" --samples 2 -q -o shard >/dev/null 2>&1
cp shard/samples.csv good.csv
sed -i '1s/voussoirs=11/voussoirs=0/' shard/samples.csv
row "merge: shard header voussoirs=0" 2 no_dir -- "$bin" merge shard -o out
cp good.csv shard/samples.csv; sed -i '1s/max_mm=[0-9.e+]*/max_mm=nan/' shard/samples.csv
row "merge: shard header max_mm=nan" 2 no_dir -- "$bin" merge shard -o out
cp good.csv shard/samples.csv; sed -i '3s/collapse/collapsed/' shard/samples.csv
row "merge: a row's status not montecarlo's" 2 no_dir -- "$bin" merge shard -o out
rm shard/samples.csv; mkfifo shard/samples.csv
row "merge: the table a FIFO (not waited on)" 2 no_dir -- "$bin" merge shard -o out

# --- a run that would not end ---
stopped() { h5dump -a /status endless.h5 2>/dev/null | grep -q 'stopped: wall-time limit'; }
row "an endless fall (fall.step_ms=0.001, dynamic.fall_s=1e6) with --max-wall-s 2" 130 stopped -- \
  "$bin" run "$ref" --set fall.step_ms=0.001 --set dynamic.fall_s=1e6 --max-wall-s 2 -q -o endless.h5
exit "$bad"
