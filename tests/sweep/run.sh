#!/usr/bin/env bash
# `stratum sweep` through the command line (CTest: sweep.cli).
#
#   run.sh <stratum exe> <plugin dir> <tests/sweep dir> <work dir> [mpiexec]
#
# 1. the study tests/sweep/lhs.toml on one process: exit 0, "3 failed" on stdout and the
#    failing samples as rows (status failed, the reason naming the Poisson's ratio);
# 2. the same under `mpiexec -n 3 --oversubscribe`: samples.csv byte-identical to 1.;
# 3. killed and resumed: SIGKILL after 4 journal records (one process), then after 3 more
#    (mpiexec -n 2), then a plain rerun: every index exactly once in the journal and
#    samples.csv byte-identical to 1.;
# 4. the study changed under an existing journal: exit 1 with one line saying so;
# 5. a bad study file: exit 1, one located line (file:line:col), no output folder.
# Without [mpiexec] (a build without MPI) the MPI parts run on one process instead.
set -euo pipefail

if [[ $# -lt 4 ]]; then
  echo "usage: $0 <stratum exe> <plugin dir> <tests/sweep dir> <work dir> [mpiexec]" >&2
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
  echo "sweep test FAILED: $*" >&2
  exit 1
}
par() { # par N ARGS...: N MPI processes, or one when there is no MPI
  local n=$1
  shift
  if [[ -n "$mpi" ]]; then "$mpi" -n "$n" --oversubscribe "$@"; else "$@"; fi
}

# 1. one process
"$exe" sweep "$here/lhs.toml" --out "$work/one" >"$work/one.out" 2>"$work/one.err" || fail "1 process: exit $?"
grep -q "3 failed" "$work/one.out" || fail "1 process: no failure count on stdout: $(cat "$work/one.out")"
[[ $(grep -c ',failed,"' "$work/one/samples.csv") -eq 3 ]] || fail "expected 3 failed rows"
grep ',failed,"' "$work/one/samples.csv" | grep -q 'nu = 0.5.* is outside' || fail "failed row without its reason"
[[ $(grep -c ',converged,$' "$work/one/samples.csv") -eq 7 ]] || fail "expected 7 converged rows"
[[ $(wc -l <"$work/one/samples.csv") -eq 11 ]] || fail "samples.csv: expected header + 10 rows"
cut -d, -f1 "$work/one/samples.csv" | tail -n +2 | tr '\n' ' ' | grep -qx '0 1 2 3 4 5 6 7 8 9 ' ||
  fail "samples.csv not ordered by index"
echo "1 process: ok"

# 2. three processes
par 3 "$exe" sweep "$here/lhs.toml" --out "$work/three" >"$work/three.out" 2>"$work/three.err" ||
  fail "3 processes: exit $? ($(cat "$work/three.err"))"
cmp "$work/one/samples.csv" "$work/three/samples.csv" || fail "samples.csv differs between 1 and 3 processes"
[[ -z "$mpi" ]] || grep -q "on 3 processes" "$work/three.out" || fail "not run on 3 processes: $(cat "$work/three.out")"
echo "3 processes: ok, samples.csv identical"

# 3. killed twice, resumed
set +e
STRATUM_SWEEP_KILL_AFTER=4 "$exe" sweep "$here/lhs.toml" --out "$work/killed" >/dev/null 2>&1
rc=$?
set -e
[[ $rc -eq 137 ]] || fail "the kill hook did not kill (exit $rc)"
[[ ! -e "$work/killed/samples.csv" ]] || fail "samples.csv written by a killed study"
[[ $(grep -vc '^#' "$work/killed/journal.csv") -eq 4 ]] || fail "journal after the first kill: expected 4 rows"
set +e
if [[ -n "$mpi" ]]; then
  "$mpi" -n 2 --oversubscribe -x STRATUM_SWEEP_KILL_AFTER=3 "$exe" sweep "$here/lhs.toml" --out "$work/killed" \
    >/dev/null 2>&1
else
  STRATUM_SWEEP_KILL_AFTER=3 "$exe" sweep "$here/lhs.toml" --out "$work/killed" >/dev/null 2>&1
fi
rc=$?
set -e
[[ $rc -ne 0 ]] || fail "the second kill did not kill"
[[ $(grep -vc '^#' "$work/killed/journal.csv") -eq 7 ]] || fail "journal after the second kill: expected 7 rows"
"$exe" sweep "$here/lhs.toml" --out "$work/killed" >"$work/resumed.out" 2>"$work/resumed.err" ||
  fail "resume: exit $?"
grep -q "7 of 10 samples are in the journal, 3 to run" "$work/resumed.err" || fail "resume message: $(cat "$work/resumed.err")"
grep -q "3 run now" "$work/resumed.out" || fail "resume ran more than the missing samples"
dups=$(grep -v '^#' "$work/killed/journal.csv" | cut -d, -f1 | sort | uniq -d)
[[ -z "$dups" && $(grep -vc '^#' "$work/killed/journal.csv") -eq 10 ]] || fail "journal: not every sample once"
cmp "$work/one/samples.csv" "$work/killed/samples.csv" || fail "resumed samples.csv differs from the uninterrupted one"
echo "killed and resumed: ok"

# 4. the study changed under the journal
sed "s|\.\./\.\./inputs|$here/../../inputs|; s/seed = 7/seed = 8/" "$here/lhs.toml" >"$work/changed.toml"
"$exe" sweep "$work/changed.toml" --out "$work/changed" >/dev/null 2>&1 || fail "changed study, first run"
sed -i 's/seed = 8/seed = 9/' "$work/changed.toml"
set +e
"$exe" sweep "$work/changed.toml" --out "$work/changed" >/dev/null 2>"$work/changed.err"
rc=$?
set -e
[[ $rc -eq 1 && $(wc -l <"$work/changed.err") -eq 1 ]] || fail "changed study: exit $rc, $(cat "$work/changed.err")"
grep -q "written by another study" "$work/changed.err" || fail "changed study: $(cat "$work/changed.err")"
echo "changed study: ok"

# 5. a bad study file
set +e
"$exe" sweep "$here/bad.toml" --out "$work/bad" >"$work/bad.out" 2>"$work/bad.err"
rc=$?
set -e
[[ $rc -eq 1 ]] || fail "bad study: exit $rc"
[[ $(wc -l <"$work/bad.err") -eq 1 ]] || fail "bad study: not one line: $(cat "$work/bad.err")"
grep -Eq "^stratum: .*bad\.toml:7:8 .*path 'materials\.sand\.E': no key 'sand' in \[materials\]; keys: concrete, soil" \
  "$work/bad.err" || fail "bad study: $(cat "$work/bad.err")"
[[ ! -e "$work/bad" ]] || fail "bad study: an output folder was made"
echo "bad study: ok ($(cat "$work/bad.err"))"
