#!/usr/bin/env bash
# Submits one render as a Slurm job array (one array task per range of passes) and a merge job
# that runs when every part has succeeded. Needs nothing but the renderer's own commands.
#
#   PATHTRACER=/shared/pathtracer PARTS=16 PARTS_DIR=/shared/parts/myrender \
#       bash submit.sh /shared/out.exr SCENE [render flags...]
#
# PATHTRACER, the scene file and PARTS_DIR must be on a file system every node sees.
# Extra sbatch options (partition, time, account) go in SBATCH_OPTIONS.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
output="$1"
shift
: "${PATHTRACER:?set PATHTRACER to the program on the shared file system}"
: "${PARTS_DIR:?set PARTS_DIR to a shared folder for the partial films}"
parts="${PARTS:-8}"
passes="$("$PATHTRACER" "$@" --print-passes | awk '$1 == "passes" {print $2}')"
(( parts > passes )) && parts="$passes"
mkdir -p "$PARTS_DIR"
printf '%q ' "$@" > "$PARTS_DIR/render_args"   # the render, for every array task
export PATHTRACER PARTS_DIR SPT_PASSES="$passes" SPT_OUTPUT="$output"
# shellcheck disable=SC2086
render_job="$(sbatch --parsable ${SBATCH_OPTIONS:-} --array="0-$((parts - 1))" \
    --export=ALL "$here/render.sbatch")"
# shellcheck disable=SC2086
merge_job="$(sbatch --parsable ${SBATCH_OPTIONS:-} --dependency="afterok:${render_job%%;*}" \
    --export=ALL "$here/merge.sbatch")"
echo "render: job array $render_job ($parts parts of $passes passes); merge: job $merge_job -> $output"
