#!/usr/bin/env bash
# Builds the report's PDF from the same Markdown GitHub shows: one command on a fresh machine
# (Python 3 with venv; the packages of requirements-pdf.txt come from PyPI into a venv of its own).
#
#   bash docs/report/build_pdf.sh                       # docs/report/README.md → docs/report/report.pdf
#   bash docs/report/build_pdf.sh build/report-quick    # the quick mode's report → build/report-quick/report.pdf
#
# The venv is build/report-pdf-venv (or $SPT_REPORT_VENV); rerunning skips pip when the
# requirements are unchanged.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "${here}/../.." && pwd)"
dir="$(cd "${1:-${here}}" && pwd)"
venv="${SPT_REPORT_VENV:-${root}/build/report-pdf-venv}"
requirements="${here}/requirements-pdf.txt"

[[ -f "${dir}/README.md" ]] || { echo "build_pdf.sh: ${dir}/README.md not found (run build_report.py first)" >&2; exit 2; }
if [[ ! -x "${venv}/bin/python" ]]; then
    echo "build_pdf.sh: creating ${venv}" >&2
    python3 -m venv "${venv}"
fi
stamp="${venv}/.requirements.sha256"
want="$(sha256sum "${requirements}" | cut -d' ' -f1)"
if [[ ! -f "${stamp}" || "$(cat "${stamp}")" != "${want}" ]]; then
    "${venv}/bin/python" -m pip install --quiet --disable-pip-version-check -r "${requirements}"
    echo "${want}" > "${stamp}"
fi
"${venv}/bin/python" "${here}/make_pdf.py" "${dir}/README.md" "${dir}/report.pdf"
