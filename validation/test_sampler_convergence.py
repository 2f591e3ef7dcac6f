"""Smoke test of validation/sampler_convergence.py: ``--quick`` into a temporary file (a few seconds).

Checks that the report has a row per scene and spp with finite positive errors for both
samplers and a slope per scene. The numbers themselves are the full run's job
(results/sampler_convergence.md)."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parent / "sampler_convergence.py"
SCENES = ("cornell", "cornell-point", "cornell-sphere")


def test_quick_run(pathtracer: Path, tmp_path: Path) -> None:
    out = tmp_path / "sampler_convergence.md"
    proc = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--program", str(pathtracer), "--out", str(out)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    md = out.read_text()
    rows = [line.strip("|").split("|") for line in md.splitlines() if line.startswith("| cornell")]
    errors = [r for r in rows if len(r) == 7]
    slopes = [r for r in rows if len(r) == 3]
    assert sorted({r[0].strip() for r in errors}) == sorted(SCENES)
    assert len(errors) == 2 * len(SCENES)  # --quick: 16 and 64 spp
    for r in errors:
        for cell in (r[2], r[3]):
            value = float(cell.split("±")[0])
            assert math.isfinite(value) and value > 0, r
    assert len(slopes) == len(SCENES)
