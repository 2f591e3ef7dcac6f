"""The committed report (docs/report/) describes the program in this tree: build_report.py records
a sha256 of its inputs (the renderer's source, spectra, scenes, build files, the report's own
scripts and template, and what it reads from validation/ and bench/) in results.json and
README.md; this test recomputes it. After any change to those inputs the report must be rebuilt
(docs/report/README.md says how) and committed with its PDF."""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
REPORT_DIR = ROOT / "docs" / "report"


@pytest.fixture(scope="module")
def build_report():
    sys.path.insert(0, str(REPORT_DIR))
    try:
        return importlib.import_module("build_report")
    finally:
        sys.path.remove(str(REPORT_DIR))


def test_committed_report_was_built_from_this_tree(build_report):
    results = json.loads((REPORT_DIR / "results.json").read_text())
    run = results["run"]
    recorded = run.get("inputs_sha256")
    current = build_report.inputs_sha256(ROOT)
    assert recorded == current, (
        f"docs/report/ was built from other inputs (recorded sha256 {recorded}, this tree's {current}): "
        "rebuild it (build_report.py, then build_pdf.sh, as docs/report/README.md says) and commit it")
    assert run["mode"] == "full"
    assert run.get("earlier_sections") == [], "some sections were taken from an earlier run (--from-results)"
    assert f"Inputs sha256: {current}" in (REPORT_DIR / "README.md").read_text()
    pdf = REPORT_DIR / "report.pdf"
    assert pdf.is_file() and pdf.read_bytes()[:5] == b"%PDF-", "docs/report/report.pdf is missing"
    assert pdf.stat().st_size > 100_000


def _tree(tmp_path: Path) -> Path:
    for rel, text in {"src/a.cpp": "int a;\n", "scenes/s.json": "{}\n", "CMakeLists.txt": "project(x)\n",
                      "docs/report/report.md.in": "{{x}}\n", "docs/report/README.md": "out\n",
                      "validation/test_other.py": "\n"}.items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(text)
    return tmp_path


def test_hash_follows_every_input_and_no_output(build_report, tmp_path):
    """Planted changes: editing, adding or renaming an input changes the hash; editing an output
    (the generated README.md) or a file the report does not read does not."""
    root = _tree(tmp_path)
    base = build_report.inputs_sha256(root)
    assert base == build_report.inputs_sha256(root)
    (root / "docs/report/README.md").write_text("rebuilt\n")
    (root / "validation/test_other.py").write_text("changed\n")
    (root / "src/__pycache__").mkdir()
    (root / "src/__pycache__/x.pyc").write_bytes(b"\0")
    assert build_report.inputs_sha256(root) == base
    for change in (lambda: (root / "src/a.cpp").write_text("int b;\n"),
                   lambda: (root / "scenes/t.json").write_text("{}\n"),
                   lambda: (root / "src/a.cpp").rename(root / "src/b.cpp"),
                   lambda: (root / "docs/report/report.md.in").write_text("{{y}}\n")):
        change()
        now = build_report.inputs_sha256(root)
        assert now != base
        base = now
