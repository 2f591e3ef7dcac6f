#!/usr/bin/env bash
# Create (if missing) the validation virtual environment and install
# validation/requirements.txt into it. Idempotent: when the venv already holds
# exactly these requirements (same file hash, same interpreter) pip is skipped.
#
#   bash validation/setup_venv.sh            # venv at <repo>/.venv
#   SPT_VENV=/some/dir bash validation/setup_venv.sh
#   PYTHON=python3.12 bash validation/setup_venv.sh   # interpreter for a new venv
#
# The venv path is the only thing printed on stdout; progress goes to stderr.
set -euo pipefail

script_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo_root="$(cd "${script_dir}/.." && pwd)"
requirements="${script_dir}/requirements.txt"
venv="${SPT_VENV:-${repo_root}/.venv}"
python="${PYTHON:-python3}"

if [[ ! -x "${venv}/bin/python" ]]; then
    echo "setup_venv: creating ${venv}" >&2
    "${python}" -m venv "${venv}"
fi
venv="$(cd "${venv}" && pwd)"
venv_python="${venv}/bin/python"

stamp="${venv}/.spt-requirements.stamp"
want="$(
    {
        sha256sum "${requirements}" | cut -d' ' -f1
        "${venv_python}" -c 'import sys; print(sys.version)'
    } | sha256sum | cut -d' ' -f1
)"

if [[ -f "${stamp}" && "$(cat "${stamp}")" == "${want}" ]]; then
    echo "setup_venv: requirements already installed" >&2
else
    echo "setup_venv: installing ${requirements}" >&2
    rm -f "${stamp}"
    "${venv_python}" -m pip install --quiet --disable-pip-version-check \
        -r "${requirements}" >&2
    echo "${want}" > "${stamp}"
fi

echo "${venv}"
