"""Tests of validation/accuracy_cost.py.

The smoke test runs ``--quick`` into a temporary folder (~20 s): the table and the plot are
written, every scene has rows for every knob, the errors are finite, the noisy scene's points
average several seeds with a standard error, and (loosely) the error falls with spp. The numbers
themselves are not judged: that is the full run's job.

The seed plan, the mean over seeds and the monotonicity check are tested on their own, without
renders: knob variants at one spp share their seeds (paired), replicates and spp values never
share one, the mean and its standard error are those of the replicates, and a planted rise of
more than two standard errors is reported while a smaller one is not.
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parent / "accuracy_cost.py"
sys.path.insert(0, str(SCRIPT.parent))
import accuracy_cost as ac  # noqa: E402
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
    assert md.count("- Monotone in spp:") == len(SCENES)

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
            # quick: prism is the noisy scene, 3 seeds at 4 spp and 2 above; the others one seed
            seeds = int(r["seeds"])
            assert seeds == ((3 if r["spp"] == "4" else 2) if scene == "prism" else 1), (scene, r)
            assert (r["error s.e."] == "—") == (seeds == 1), (scene, r)
            if seeds > 1:
                assert float(r["error s.e."]) >= 0, (scene, r)
        sweep = sorted(((int(r["spp"]), float(r["error"])) for r in mine if r["knob"] == "spp"))
        assert len(sweep) >= 3
        # loosely: the largest spp has a clearly smaller error than the smallest
        assert sweep[-1][1] < 0.7 * sweep[0][1], (scene, sweep)
    # 8 wavelengths per path: measured if the program accepts it, else reported as not measured
    assert ("wavelengths-per-path | 8 |" in md) or ("--wavelengths-per-path 8" in md)


def quick_args(*extra: str):
    return ac.parse_args(["--quick", *extra])


def test_seed_plan_is_paired_across_knobs_and_independent_across_spp_and_replicates() -> None:
    args = quick_args("--scenes", "prism", "cornell")
    effects = ["dispersion"]
    pts = ac.plan("prism", args, [1, 4], ["path", "bdpt"], effects)
    by_spp: dict[int, dict[tuple, set[int]]] = {}
    for p in pts:
        variant = (p.knob, p.value)
        by_spp.setdefault(p.config.spp, {}).setdefault(variant, set()).add(p.config.seed)
    seed_sets = {}
    for spp, variants in by_spp.items():
        sets = list(variants.values())
        assert all(s == sets[0] for s in sets), (spp, variants)  # paired: one seed set per spp
        assert len(sets[0]) == ac.seeds_at("prism", spp, args)
        assert ac.SEED_BASE + spp in sets[0]                     # replicate 0 keeps the old seed
        seed_sets[spp] = sets[0]
    spps = sorted(seed_sets)
    for i, a in enumerate(spps):
        for b in spps[i + 1:]:
            assert not (seed_sets[a] & seed_sets[b]), (a, b)      # independent between spp values
    assert [ac.seeds_at("prism", n, args) for n in args.spp] == [3, 2, 2]
    assert {ac.seeds_at("cornell", n, args) for n in args.spp} == {1}
    # two points share a configuration only where the default at --bins-spp stands in two series
    shared = {p.config for p in pts if sum(q.config == p.config for q in pts) > 1}
    assert shared == {ac.Config("prism", args.bins_spp, rep=r) for r in range(ac.seeds_at("prism", args.bins_spp, args))}
    # ... and the mean over seeds keeps both series' points
    assert len(ac.aggregate(pts)) == len({(p.knob, p.value, p.config.spp, p.config.integrator,
                                           p.config.dispersion, p.config.max_depth) for p in pts})


def fake(value: float, rep: int, spp: int = 4, image: float = 0.0) -> "ac.Point":
    p = ac.Point("spp", str(spp), ac.Config("prism", spp, rep=rep), time=1.0 + rep, error=value, raw=value,
                 trimmed=value / 2, top_share=0.5, image=np.full((2, 2, 3), image))
    p.replicates = []
    return p


def test_aggregate_is_the_mean_and_its_standard_error() -> None:
    errors = [1.0, 2.0, 6.0]
    pts = [fake(e, r, image=float(r)) for r, e in enumerate(errors)] + [fake(5.0, 0, spp=16)]
    out = ac.aggregate(pts)
    assert [(p.config.spp, p.seeds) for p in out] == [(4, 3), (16, 1)]
    mean = out[0]
    assert mean.error == pytest.approx(3.0)
    assert mean.error_se == pytest.approx(np.std(errors, ddof=1) / math.sqrt(3))
    assert mean.trimmed == pytest.approx(1.5)
    assert mean.time == pytest.approx(2.0)
    assert np.allclose(mean.image, 1.0)            # the replicates' mean image
    assert mean.config.rep == 0 and len(mean.replicates) == 3
    assert math.isnan(out[1].error_se)             # one seed: no standard error


def point(spp: int, error: float, se: float) -> "ac.Point":
    return dataclasses.replace(fake(error, 0, spp=spp), error_se=se)


def test_rises_reports_only_rises_beyond_two_standard_errors() -> None:
    falling = [point(4, 10.0, 3.0), point(16, 3.0, 1.0), point(64, 1.0, 0.2)]
    assert ac.rises(falling) == []
    within = [point(4, 10.0, 3.0), point(16, 14.0, 3.0)]    # +4 against a combined s.e. of 4.2
    assert ac.rises(within) == []
    planted = [point(4, 1.0, 0.1), point(16, 3.0, 0.5), point(64, 0.5, 0.1)]  # +2 against 0.51
    (a, b, z), = ac.rises(planted)
    assert (a.config.spp, b.config.spp) == (4, 16) and z > 3
    single = [point(4, 1.0, math.nan), point(16, 1.5, math.nan)]  # single renders: any rise counts
    assert len(ac.rises(single)) == 1
