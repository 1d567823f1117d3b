#!/bin/bash
# Submits a sharded enumeration to Slurm: N shard tasks, then the merge once they have all
# ended (whatever their exit codes: a lost shard is named by the merge).
#
#     examples/slurm/submit.sh PROBLEM.toml N [wedged enumerate options...]
#
# Run it from the directory that should hold parts/ and all.json (shared with the nodes).
set -euo pipefail
if [ $# -lt 2 ]; then
    echo "usage: submit.sh PROBLEM.toml N [options]" >&2
    exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
problem=$1
n=$2
shift 2
mkdir -p parts
job=$(sbatch --parsable --array="1-$n" "$here/shards.sbatch" "$problem" "$@")
sbatch --dependency="afterany:$job" "$here/merge.sbatch"
