#!/usr/bin/env bash
# Submits one render as a Slurm job array (one array task per range of passes) and a merge job
# that runs when every part has succeeded. Needs nothing but the renderer's own commands.
#
#   PATHTRACER=/shared/pathtracer PARTS=16 PARTS_DIR=/shared/parts/myrender \
#       bash submit.sh /shared/out.exr SCENE [render flags...]
#
# PATHTRACER, the scene file and PARTS_DIR must be on a file system every node sees.
# Extra sbatch options (partition, time, account) go in SBATCH_OPTIONS.
#
# Everything a task needs is stored in PARTS_DIR (the render's arguments in render_args; the
# program, pass count, part count, output and folder in job; the merge job's id in merge_job),
# so a task is rerun with PARTS_DIR alone: see rerun.sh.
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
PARTS_DIR="$(cd "$PARTS_DIR" && pwd)"
printf '%q ' "$@" > "$PARTS_DIR/render_args"   # the render, for every array task
# The part count is stored, not taken from SLURM_ARRAY_TASK_COUNT: a rerun of task K alone
# (an array of one task) must render the passes of part K of this split.
{
    printf 'PATHTRACER=%q\n' "$(realpath -s "$(command -v "$PATHTRACER")")"
    printf 'SPT_PASSES=%q\nSPT_PARTS=%q\n' "$passes" "$parts"
    printf 'SPT_OUTPUT=%q\n' "$output"
    printf 'SPT_WORKDIR=%q\n' "$PWD"   # relative scene and output paths are from here
} > "$PARTS_DIR/job"
# shellcheck disable=SC2086
render_job="$(sbatch --parsable ${SBATCH_OPTIONS:-} --array="0-$((parts - 1))" \
    --export="ALL,PARTS_DIR=$PARTS_DIR" "$here/render.sbatch")"
# shellcheck disable=SC2086
merge_job="$(sbatch --parsable ${SBATCH_OPTIONS:-} --dependency="afterok:${render_job%%;*}" \
    --export="ALL,PARTS_DIR=$PARTS_DIR" "$here/merge.sbatch")"
echo "${merge_job%%;*}" > "$PARTS_DIR/merge_job"
echo "render: job array $render_job ($parts parts of $passes passes); merge: job $merge_job -> $output"
