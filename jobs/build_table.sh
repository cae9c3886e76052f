#!/usr/bin/env bash
# Build one lookup table with mpirun on this machine (or an interactive node).
#   NP=2 jobs/build_table.sh configs/paper_s1002_uic60_1in20.toml out/paper.h5 [--force|--resume]
# Calls the CLI only; the Open MPI settings come from scripts/mpienv.sh.
set -euo pipefail
if [ "$#" -lt 2 ]; then
  echo "usage: NP=<ranks> $0 CONFIG.toml OUT.h5 [lutmpi build options]" >&2
  exit 2
fi
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=../scripts/mpienv.sh
source "$here/scripts/mpienv.sh"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
config="$1"; out="$2"; shift 2
np="${NP:-2}"
if ! [[ "$np" =~ ^[1-9][0-9]*$ ]]; then   # mpirun -n 0 would take every slot of the node
  echo "$0: NP must be a number of ranks >= 1, got '$np'" >&2
  exit 2
fi
mkdir -p "$(dirname "$out")"
exec mpirun -n "$np" "$here/.venv/bin/lutmpi" build "$config" -o "$out" "$@"
