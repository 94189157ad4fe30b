#!/usr/bin/env bash
# Runs every tile of an asperity terrain plan as a Slurm job array: array task K runs
# tile K (Slurm sets SLURM_ARRAY_TASK_ID).
#
#   asperity terrain plan --size 4097 --tile-size 1025 --seed 7 -o world   # 16 tiles
#   PLAN_DIR=world sbatch --array=0-15 slurm-array.sh
#
# The array must cover the plan's tiles (0 to the tile count − 1). A rerun of a failed
# array skips the tiles already complete.
#SBATCH --job-name=asperity-terrain
#SBATCH --array=0-15
#SBATCH --cpus-per-task=2
#SBATCH --mem=2G
#SBATCH --time=00:30:00
set -euo pipefail
exec asperity terrain --plan "${PLAN_DIR:-world}"
