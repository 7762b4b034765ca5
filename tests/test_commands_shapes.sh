#!/usr/bin/env bash
# Every command on every shape (issue 27): run, plot, the record and its XDMF sidecar, sweep over
# a geometry key, montecarlo with imperfections drawn on the shape, calibrate, for each of the
# generated shapes and a blocks file that `voussoir blocks` wrote; the outputs are checked by
# commands_shapes_check.py against closed forms and the blocks' masses. Small arches (7
# voussoirs) and a short fall keep it to seconds.
# usage: test_commands_shapes.sh VOUSSOIR SOURCE_DIR
set -euo pipefail
vs=$1 src=$2
py=/usr/bin/python3
$py -c "import h5py, numpy" 2>/dev/null ||
  { echo "SKIP: $py lacks h5py/numpy (apt-get install python3-h5py)"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
shapes="circular pointed elliptical basket parabolic catenary file"
for s in $shapes; do
  case $s in
    pointed) geo="eccentricity = 0.3" ;;
    basket) geo=$'rise_mm = 250\nhaunch_deg = 50' ;;
    *) geo="rise_mm = 250" ;;
  esac
  [ "$s" = file ] && continue
  cat > "$s.ini" <<INI
[arch]
shape = $s
span_mm = 600
$geo
thickness_mm = 40
voussoirs = 7
depth_mm = 100
[joints]
kn_N_mm3 = 10
[support]
alpha_deg = 30
[dynamic]
fall_s = 0.3
INI
done
# the pointed arch's blocks, written to a file and read back as arch.shape = file
"$vs" blocks pointed.ini -o pointed_blocks.json
printf '[arch]\nshape = file\nblocks_file = pointed_blocks.json\ndepth_mm = 100\n[joints]\nkn_N_mm3 = 10\n[support]\nalpha_deg = 30\n[dynamic]\nfall_s = 0.3\n' > file.ini

imp="--set imperfections.kn_cov=0.2 --set imperfections.face_mm=0.05 --set imperfections.support_dx_mm=0.5"
for s in $shapes; do
  case $s in
    pointed) vary="--vary arch.eccentricity=0.2,0.4 --vary arch.thickness_mm=38,40" ;;
    file) vary="--vary joints.kn_N_mm3=5,10" ;; # a file's geometry is its own
    *) vary="--vary arch.rise_mm=230,250 --vary arch.thickness_mm=38,40" ;;
  esac
  shape_imp=$imp
  [ "$s" = file ] || shape_imp="$imp --set imperfections.angle_cov=0.05 --set imperfections.thickness_cov=0.03"
  rc=0
  "$vs" run "$s.ini" -q --json -o "$s.h5" > "$s.json" || rc=$?
  [ $rc -eq 0 ] || { echo "FAIL: $s: run exit $rc"; cat "$s.json"; exit 1; }
  # the arch pictures (no charts' python3: exit status 3; test_plot_charts runs the charts)
  rc=0
  VOUSSOIR_PYTHON=/nonexistent/python3 "$vs" plot "$s.h5" -o "${s}_plots" >/dev/null 2>&1 || rc=$?
  [ $rc -eq 3 ] || { echo "FAIL: $s: plot exit $rc"; exit 1; }
  # shellcheck disable=SC2086
  "$vs" sweep "$s.ini" --alpha 30 $vary --set dynamic.fall_s=0 -j 2 -q -o "${s}_sw"
  # shellcheck disable=SC2086
  "$vs" montecarlo "$s.ini" --samples 3 $shape_imp -j 2 -q -o "${s}_mc" >/dev/null
  if [ "$s" != file ]; then
    "$vs" run "$s.ini" -q --first-limit --set imperfections.sample=1 \
      --set imperfections.thickness_cov=0.05 --set imperfections.angle_cov=0.05 -o "${s}_imp.h5" >/dev/null
  fi
  # calibrate to the collapse dz/L the run gave at k_n = 10, then run at the k_n it reports
  target=$($py -c "import json,sys; print('%.4f' % json.load(open(sys.argv[1]))['collapse']['dz_over_L_pct'])" "$s.json")
  "$vs" calibrate "$s.ini" --target-dz-pct "$target" --kn-min 1 --kn-max 100 -q > "${s}_cal.txt" 2>&1 ||
    { echo "FAIL: $s: calibrate"; cat "${s}_cal.txt"; exit 1; }
  kn=$(sed -nE 's/^k_n = ([0-9.eE+-]+) N\/mm\^3 gives.*/\1/p' "${s}_cal.txt")
  "$vs" run "$s.ini" -q --json --no-record --set dynamic.fall_s=0 --kn "$kn" > "${s}_cal.json"
done
# an axis over a key the shape does not read is refused (exit 2, nothing written)
for bad in "file.ini --vary arch.thickness_mm=30,40" "circular.ini --vary arch.eccentricity=0.1" \
           "circular.ini --vary arch.radius_mm=300" "pointed.ini --vary arch.rise_mm=200"; do
  rc=0
  # shellcheck disable=SC2086
  "$vs" sweep $bad --alpha 0 -q -o refused 2>refused.txt || rc=$?
  { [ $rc -eq 2 ] && [ ! -e refused ] && grep -q "arch\." refused.txt; } ||
    { echo "FAIL: sweep $bad: exit $rc, $(cat refused.txt)"; exit 1; }
done

# both supports: the left one moves outward at half the right one's rate; the tables' travel
# columns and dz/L, dx/L (of the relative displacement), and the shards of a montecarlo merged
two="--set support.left_alpha_deg=90 --set support.left_rate_mm_s=0.02"
# shellcheck disable=SC2086
"$vs" sweep pointed.ini --alpha 0,30 $two --set dynamic.fall_s=0 -j 2 -q -o two_sw >/dev/null
mc="pointed.ini --samples 4 --set imperfections.kn_cov=0.2 $two -j 2 -q"
# shellcheck disable=SC2086
{ "$vs" montecarlo $mc -o two_mc && "$vs" montecarlo $mc --shard 1/2 -o two_s1 &&
  "$vs" montecarlo $mc --shard 2/2 -o two_s2 && "$vs" merge two_s1 two_s2 -o two_merged; } >/dev/null
# calibrate to the spreading dx/L with the right support settling (alpha = 0): the left one's
# outward travel is the spreading
# shellcheck disable=SC2086
"$vs" calibrate pointed.ini --target-dx-pct 4 --set support.alpha_deg=0 $two --kn-min 1 --kn-max 100 -q > two_cal.txt 2>&1 ||
  { echo "FAIL: calibrate to dx/L with the left support moving"; cat two_cal.txt; exit 1; }
kn=$(sed -nE 's/^k_n = ([0-9.eE+-]+) N\/mm\^3 gives.*/\1/p' two_cal.txt)
# shellcheck disable=SC2086
"$vs" run pointed.ini -q --json --no-record --set dynamic.fall_s=0 --set support.alpha_deg=0 $two --kn "$kn" > two_cal.json
# a table written before the travel columns and the header's span and motion still merges
mkdir old_s1
sed -E '1s/ L_mm=.*//; 2,$s/(,[^,]*){5}$//' two_s1/samples.csv > old_s1/samples.csv
# with a sample that failed and one that did not collapse (their travel: nan)
printf '4,failed,nan,nan,nan,nan,0,,,,,,,the cause\n6,max_displacement,1.5,nan,nan,nan,0,,,,,,,\n' >> old_s1/samples.csv
"$vs" merge old_s1 -o old_merged >/dev/null
"$vs" merge old_merged -o old_again >/dev/null

# shellcheck disable=SC2086
$py "$src/tests/commands_shapes_check.py" "$tmp" $shapes
