#!/bin/sh
# Runs the loess drained triaxial point inputs (inputs/point/loess_<model>_s*.toml) through
# `stratum point` and plots them with tools/plot_triaxial.py into docs/figures/loess_<model>_{q,ev}.png.
# Usage: tools/loess_triaxial.sh [MODEL] [STRATUM]   (MODEL defaults to duncan_chang,
#        STRATUM to build/release/bin/stratum); run from the repository root.
set -eu
model=${1:-duncan_chang}
stratum=${2:-build/release/bin/stratum}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
set --
for f in inputs/point/loess_"$model"_s*.toml; do
  s=$(basename "$f" .toml | sed 's/.*[_s]0*\([0-9]*\)$/\1/')
  "$stratum" point "$f" --out "$work/$s.csv" > /dev/null
  set -- "$@" "$work/$s.csv" "sigma_3 = $s kPa"
done
# matplotlib: the first python3 on the PATH that has it, else the system one; PYTHON overrides.
py=${PYTHON:-python3}
"$py" -c "import matplotlib" 2> /dev/null || py=/usr/bin/python3
"$py" tools/plot_triaxial.py --out "docs/figures/loess_$model" \
  --title "Loess, $model, drained triaxial (CID)" "$@"
