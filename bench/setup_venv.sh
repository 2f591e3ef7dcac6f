#!/usr/bin/env bash
# Creates bench/.venv with numpy and embreex (Embree 4 for Python, used by embree_compare.py
# only: Embree never enters the renderer or its tests) and prints the venv's path.
set -euo pipefail
venv="$(cd "$(dirname "$0")" && pwd)/.venv"
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c 'import embreex, numpy' 2>/dev/null; then
    python3 -m venv "$venv" >&2
    "$venv/bin/pip" install -q numpy embreex >&2
fi
echo "$venv"
