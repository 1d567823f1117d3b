#!/bin/bash
# The job array's commands as a shell loop, with the variables Slurm would set: each shard of
# shards.sbatch one after another, then merge.sbatch. CI runs it (crates/wedged-cli/tests/
# shards.rs), so the scripts that a cluster runs are the ones tested.
#
#     examples/slurm/local.sh PROBLEM.toml N [wedged enumerate options...]
set -euo pipefail
if [ $# -lt 2 ]; then
    echo "usage: local.sh PROBLEM.toml N [options]" >&2
    exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
problem=$1
n=$2
shift 2
for i in $(seq 1 "$n"); do
    SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=$n bash "$here/shards.sbatch" "$problem" "$@" \
        >/dev/null
done
bash "$here/merge.sbatch"
