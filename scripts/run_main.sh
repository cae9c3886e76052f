#!/usr/bin/env bash
# The README's main-job command: set everything up, build the paper's default lookup table with MPI,
# then describe it and plot it.
#
#   bash scripts/run_main.sh                                 # paper config, 2 ranks
#   LUTMPI_NP=4 bash scripts/run_main.sh CONFIG OUT.h5       # another config / output / rank count
#
# Output: OUT (default out/paper_table.h5), OUT's description on stdout and in OUT-stem.inspect.txt,
# figures OUT-stem_z_g.png, OUT-stem_roll.png beside it, and the contact-geometry report
# OUT-stem_report/report.md (+ PNGs).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"

config="${1:-configs/paper_s1002_uic60_1in20.toml}"
out="${2:-out/paper_table.h5}"
np="${LUTMPI_NP:-2}"
stem="${out%.h5}"

bash scripts/setup.sh
# shellcheck source=scripts/mpienv.sh
source scripts/mpienv.sh
LUTMPI=.venv/bin/lutmpi
mkdir -p "$(dirname "$out")"

echo "[main] building $out from $config on $np rank(s)"
t0=$SECONDS
# Open MPI 4.1.4 ends a banner with a NUL byte; strip it so logs stay text
timeout -k 30 "${LUTMPI_MAIN_TIMEOUT:-7200}" \
  mpirun -n "$np" "$LUTMPI" build "$config" -o "$out" --force 2>&1 | tr -d '\000'
echo "[main] build took $((SECONDS - t0)) s"

echo "[main] inspect"
"$LUTMPI" inspect "$out" | tee "$stem.inspect.txt"

echo "[main] plots"
for q in z_g roll; do
  "$LUTMPI" plot "$out" "$q" -o "${stem}_$q.png"
  echo "[main] wrote ${stem}_$q.png"
done

echo "[main] report"
"$LUTMPI" report "$out" -o "${stem}_report"
echo "[main] done: $out, $stem.inspect.txt, ${stem}_z_g.png, ${stem}_roll.png, ${stem}_report/report.md"
