#!/usr/bin/env bash
# Builds a mesh's hierarchy in chunks on this machine with GNU parallel, one chunk per core,
# then joins them — the same three steps a cluster runs (mesh-slurm-array.sh,
# mesh-kubernetes-indexed-job.yaml), with the same result as `simplify --chunks K`:
#
#   INPUT=scan.ply TARGET=1% CHUNKS=8 PLAN_DIR=scan-plan BASE=base.ply bash mesh-parallel.sh
set -euo pipefail
input="${INPUT:?INPUT names the mesh to simplify}"
plan="${PLAN_DIR:-mesh-plan}"
chunks="${CHUNKS:-8}"
asperity simplify plan "$input" --chunks "$chunks" --target-vertices "${TARGET:-1%}" -o "$plan"
seq 0 $((chunks - 1)) | parallel --halt now,fail=1 asperity simplify --plan "$plan" --chunk-index {}
asperity simplify merge "$plan" -o "${BASE:-base.ply}"
