#!/bin/bash
# Submits a sharded sglab sweep to Slurm: a job array of N shards and the merge job, which starts
# only when every shard succeeded (afterok). Prints the two job ids ("ARRAY MERGE").
#
#   scripts/slurm/submit_sweep.sh N OUT KIND [SWEEP OPTIONS…]
#   e.g. scripts/slurm/submit_sweep.sh 8 results/specular specular
#        scripts/slurm/submit_sweep.sh 4 results/render_sweep render --scene scenes/cornell-glossy.json --vary rsm=16,32
#
# Each shard gets $SGLAB_CPUS CPUs (default 1; the sweep uses exactly those); other sbatch options
# come from the environment as Slurm reads them (SBATCH_PARTITION, SBATCH_TIMELIMIT, …). Run from
# the repository root (the jobs start there); $SGLAB names the binary (default build/bin/sglab).
set -euo pipefail
if [ $# -lt 3 ] || ! [[ $1 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 N OUT KIND [SWEEP OPTIONS…]  (N ≥ 1 shards)" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
n=$1
out=$2
shift 2
array=$(sbatch --parsable --array=0-$((n - 1)) --cpus-per-task="${SGLAB_CPUS:-1}" "$here/sweep_array.sbatch" "$out" "$@")
array=${array%%;*}
merge=$(sbatch --parsable --dependency=afterok:"$array" --kill-on-invalid-dep=yes --cpus-per-task="${SGLAB_CPUS:-1}" \
  "$here/merge.sbatch" "$out")
echo "$array ${merge%%;*}"
