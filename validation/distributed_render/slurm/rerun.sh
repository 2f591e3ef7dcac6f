#!/usr/bin/env bash
# Reruns failed array tasks of a render that submit.sh submitted, and its merge:
#
#   bash rerun.sh PARTS_DIR K [K...]
#
# A failed task leaves the merge job pending for ever (its afterok dependency can no longer be
# met). This cancels that merge job (its id is in PARTS_DIR/merge_job), submits tasks K... as
# a new array (each renders part K of the stored split: PARTS_DIR/job) and a new merge job
# that runs when they succeed. Extra sbatch options go in SBATCH_OPTIONS, as for submit.sh.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if (( $# < 2 )); then
    echo "usage: bash rerun.sh PARTS_DIR K [K...]   (K: the array tasks to render again)" >&2
    exit 2
fi
PARTS_DIR="$(cd "$1" && pwd)"
shift
[[ -f "$PARTS_DIR/job" ]] || { echo "rerun.sh: $PARTS_DIR/job is missing: not a folder submit.sh filled" >&2; exit 2; }
tasks="$(IFS=,; echo "$*")"
if [[ -f "$PARTS_DIR/merge_job" ]]; then
    scancel "$(cat "$PARTS_DIR/merge_job")" || true   # already gone: nothing to cancel
fi
# shellcheck disable=SC2086
render_job="$(sbatch --parsable ${SBATCH_OPTIONS:-} --array="$tasks" \
    --export="ALL,PARTS_DIR=$PARTS_DIR" "$here/render.sbatch")"
# shellcheck disable=SC2086
merge_job="$(sbatch --parsable ${SBATCH_OPTIONS:-} --dependency="afterok:${render_job%%;*}" \
    --export="ALL,PARTS_DIR=$PARTS_DIR" "$here/merge.sbatch")"
echo "${merge_job%%;*}" > "$PARTS_DIR/merge_job"
echo "render: tasks $tasks as job array $render_job; merge: job $merge_job"
