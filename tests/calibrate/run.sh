#!/usr/bin/env bash
# `stratum calibrate` through the command line (CTest: calibrate.cli).
#
#   run.sh <stratum exe> <plugin dir> <tests/calibrate dir> <work dir> [mpiexec]
#
# 1. c and phi of the strip footing (footing_c_phi.toml) on one process: exit 0, the result files,
#    the true values (10 kPa, 30 degrees) inside the 95 % intervals of parameters.csv;
# 2. the same under `mpiexec -n 3 --oversubscribe`: parameters.csv, residuals.csv and
#    jacobian.csv byte-identical to 1.;
# 3. killed (SIGKILL after 8 journaled runs), then run again into the same folder: it takes
#    those runs from the journal and ends with the files of 1., byte for byte;
# 4. bad input: exit 1, one located line, no output folder;
# 5. --print-scene prints the scene at the start values.
# Without [mpiexec] (a build without MPI) part 2 runs on one process.
set -euo pipefail

if [[ $# -lt 4 ]]; then
  echo "usage: $0 <stratum exe> <plugin dir> <tests/calibrate dir> <work dir> [mpiexec]" >&2
  exit 2
fi
exe=$1
export STRATUM_PLUGIN_PATH=$2
here=$(cd "$3" && pwd)
work=$4
mpi=${5:-}
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
# Open MPI refuses root unless told (CI containers run as root).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rm -rf "$work"
mkdir -p "$work"

fail() {
  echo "calibrate test FAILED: $*" >&2
  exit 1
}
study=$here/footing_c_phi.toml

# 1. one process
"$exe" calibrate "$study" --out "$work/one" >"$work/one.out" 2>"$work/one.err" || fail "1 process: exit $? ($(tail -3 "$work/one.err"))"
for f in journal.csv parameters.csv correlation.csv singular_values.csv jacobian.csv residuals.csv report.md \
  fitted_footing.csv best/history/footing.csv; do
  [[ -s "$work/one/$f" ]] || fail "1 process: no $f"
done
# The truth inside the 95 % intervals (columns ci95_low, ci95_high).
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  $1 == "c" { ok_c = $col["ci95_low"] < 10 && 10 < $col["ci95_high"] && $col["determined"] == "true" }
  $1 == "phi" { ok_phi = $col["ci95_low"] < 30 && 30 < $col["ci95_high"] && $col["determined"] == "true" }
  END { exit !(ok_c && ok_phi) }' "$work/one/parameters.csv" || fail "truth outside the intervals: $(cat "$work/one/parameters.csv")"
grep -q "strongly correlated" "$work/one/report.md" || fail "report.md does not name the c-phi correlation"
echo "1 process: ok"

# 2. three processes
if [[ -n "$mpi" ]]; then
  "$mpi" -n 3 --oversubscribe "$exe" calibrate "$study" --out "$work/three" >"$work/three.out" 2>"$work/three.err" ||
    fail "3 processes: exit $? ($(tail -3 "$work/three.err"))"
  grep -q "3 processes" "$work/three.err" || fail "not run on 3 processes: $(head -1 "$work/three.err")"
else
  "$exe" calibrate "$study" --out "$work/three" >"$work/three.out" 2>"$work/three.err" || fail "second run: exit $?"
fi
for f in parameters.csv residuals.csv jacobian.csv correlation.csv; do
  cmp "$work/one/$f" "$work/three/$f" || fail "$f differs between 1 and 3 processes"
done
echo "3 processes: ok, the same result files"

# 3. killed, resumed
set +e
STRATUM_CALIBRATE_KILL_AFTER=8 "$exe" calibrate "$study" --out "$work/killed" >/dev/null 2>&1
rc=$?
set -e
[[ $rc -eq 137 ]] || fail "the kill hook did not kill (exit $rc)"
[[ ! -e "$work/killed/parameters.csv" ]] || fail "parameters.csv written by a killed calibration"
kept=$(grep -vc '^#' "$work/killed/journal.csv")
((kept >= 8)) || fail "journal after the kill: $kept runs, expected at least 8"
"$exe" calibrate "$study" --out "$work/killed" >"$work/resumed.out" 2>"$work/resumed.err" || fail "resume: exit $?"
grep -q "$kept runs in the journal" "$work/resumed.err" || fail "resume message: $(head -1 "$work/resumed.err")"
# Every distinct run once: those of the killed start and those run now make the uninterrupted set.
total=$(grep -vc '^#' "$work/one/journal.csv")
grep -Eq "runs: [0-9]+ asked for, $((total - kept)) run now, [1-9][0-9]* answered from the journal" "$work/resumed.out" ||
  fail "resume did not take the journal's $kept runs (uninterrupted: $total): $(grep runs: "$work/resumed.out")"
for f in parameters.csv residuals.csv jacobian.csv; do
  cmp "$work/one/$f" "$work/killed/$f" || fail "resumed $f differs from the uninterrupted one"
done
echo "killed and resumed: ok ($kept runs reused)"

# 4. bad input: bounds reversed
sed "s|\.\./\.\./inputs|$here/../../inputs|; s|footing_reaction.csv|$here/footing_reaction.csv|; s/^lower = 5.0/lower = 50.0/" \
  "$study" >"$work/bad.toml"
set +e
"$exe" calibrate "$work/bad.toml" --out "$work/bad" >"$work/bad.out" 2>"$work/bad.err"
rc=$?
set -e
[[ $rc -eq 1 ]] || fail "bad input: exit $rc"
[[ $(wc -l <"$work/bad.err") -eq 1 ]] || fail "bad input: not one line: $(cat "$work/bad.err")"
grep -Eq "^stratum: .*bad\.toml:[0-9]+:9 \[\[parameters\]\] 2 lower = 50 must be below upper = 45" "$work/bad.err" ||
  fail "bad input: $(cat "$work/bad.err")"
[[ ! -e "$work/bad" ]] || fail "bad input: an output folder was made"
echo "bad input: ok ($(cat "$work/bad.err"))"

# 5. --print-scene
"$exe" calibrate "$study" --print-scene >"$work/scene.toml" || fail "--print-scene: exit $?"
grep -q "^c = 16" "$work/scene.toml" && grep -q "^phi = 24" "$work/scene.toml" && grep -q "^psi = 24" "$work/scene.toml" ||
  fail "--print-scene: start values missing"
echo "print-scene: ok"
