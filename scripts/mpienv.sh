# shellcheck shell=bash
# Source me (do not run me): exports what Open MPI needs here, from lutmpi/parallel/mpi.env, the one
# place these values live (lutmpi.parallel.mpi.mpirun_env() reads the same file).
# A variable already set in the environment is left as it is.
_lutmpi_env_file="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/lutmpi/parallel/mpi.env"
if [ ! -r "$_lutmpi_env_file" ]; then
  echo "mpienv.sh: cannot read $_lutmpi_env_file" >&2
  return 1 2>/dev/null || exit 1
fi
while IFS= read -r _lutmpi_line || [ -n "$_lutmpi_line" ]; do
  case "$_lutmpi_line" in ''|'#'*) continue ;; esac
  _lutmpi_key="${_lutmpi_line%%=*}"
  if [ -z "${!_lutmpi_key+x}" ]; then
    export "$_lutmpi_key=${_lutmpi_line#*=}"
  fi
done < "$_lutmpi_env_file"
unset _lutmpi_env_file _lutmpi_line _lutmpi_key
