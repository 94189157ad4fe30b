#!/usr/bin/env bash
# Builds every chunk of an asperity mesh plan as a Slurm job array: array task K builds
# chunk K (Slurm sets SLURM_ARRAY_TASK_ID). Then one job joins them.
#
#   asperity simplify plan scan.ply --chunks 16 --target-vertices 0.1% -o scan-plan
#   jobid=$(PLAN_DIR=scan-plan sbatch --parsable --array=0-15 mesh-slurm-array.sh)
#   sbatch --dependency=afterok:$jobid --wrap 'asperity simplify merge scan-plan -o base.ply'
#
# The array must cover the plan's chunks (0 to the chunk count − 1). A rerun of a failed
# array skips the chunks already complete. A chunk needs about 400 bytes per face of its
# part (plan.json: "faces"); the merge reads the whole input again.
#SBATCH --job-name=asperity-mesh-chunk
#SBATCH --array=0-15
#SBATCH --cpus-per-task=2
#SBATCH --mem=8G
#SBATCH --time=01:00:00
set -euo pipefail
exec asperity simplify --plan "${PLAN_DIR:-mesh-plan}"
