"""Smoke test of validation/accuracy_cost.py: ``--quick`` into a temporary folder (~15 s).

Checks that the table and the plot are written, that every scene has rows for
every knob, that the errors are finite, and (loosely) that the error falls
with spp. The numbers themselves are not judged: that is the full run's job.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parent / "accuracy_cost.py"
SCENES = ("cornell", "cornell-point", "colorchecker", "prism")
BINS = {"4", "8", "16", "32", "64", "exact"}


def table_rows(md: str) -> list[dict[str, str]]:
    lines = md.split("## All points", 1)[1].strip().splitlines()
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    rows = []
    for line in lines[2:]:
        if not line.startswith("|"):
            break
        rows.append(dict(zip(header, (c.strip() for c in line.strip("|").split("|")))))
    return rows


def test_quick_run(pathtracer: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    proc = subprocess.run(
        [sys.executable, str(SCRIPT), "--quick", "--program", str(pathtracer), "--out", str(out),
         "--cache-dir", str(tmp_path / "cache")],
        capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]

    md_path, png_path = out / "accuracy_cost.md", out / "accuracy_cost.png"
    assert png_path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    md = md_path.read_text()
    assert "os.cpu_count()" in md and "load average" in md and "## Reading (automatic)" in md

    rows = table_rows(md)
    for scene in SCENES:
        mine = [r for r in rows if r["scene"] == scene]
        knobs = {r["knob"] for r in mine}
        expected = {"spp", "wavelengths-per-path", "spectral-bins"}
        if scene != "colorchecker":
            expected.add("max-depth")
        if scene == "prism":
            expected.add("dispersion")
        assert expected <= knobs, (scene, knobs)
        assert {r["value"] for r in mine if r["knob"] == "spectral-bins"} == BINS
        for r in mine:
            for col in ("time (s)", "samples/s", "error", "raw relMSE / noise ΔE"):
                assert math.isfinite(float(r[col])), (scene, r)
            assert float(r["time (s)"]) > 0 and float(r["samples/s"]) > 0
        sweep = sorted(((int(r["spp"]), float(r["error"])) for r in mine if r["knob"] == "spp"))
        assert len(sweep) >= 3
        # loosely: the largest spp has a clearly smaller error than the smallest
        assert sweep[-1][1] < 0.7 * sweep[0][1], (scene, sweep)
    # 8 wavelengths per path: measured if the program accepts it, else reported as not measured
    assert ("wavelengths-per-path | 8 |" in md) or ("--wavelengths-per-path 8" in md)
