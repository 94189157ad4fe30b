#!/usr/bin/env bash
# Runs every tile of an asperity terrain plan on this machine with GNU parallel, one job
# per core: PLAN_DIR=world ./parallel.sh
set -euo pipefail
plan="${PLAN_DIR:-world}"
tiles=$(grep -c '"index"' "$plan/plan.json")
seq 0 $((tiles - 1)) | parallel --halt now,fail=1 asperity terrain --plan "$plan" --tile-index {}
