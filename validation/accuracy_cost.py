#!/usr/bin/env python3
"""Accuracy against cost of the renderer's knobs (issue 5, second half).

For the scenes ``cornell``, ``cornell-point``, ``colorchecker`` and ``prism`` it
renders a set of points, each one render with one knob moved away from the
defaults (path tracing, 16 spectral bins, 4 wavelengths per path, dispersion
on, unbounded depth), and plots error against render time (log-log):

* ``spp``: samples per pixel 4 ... 1024 at the defaults;
* ``wavelengths-per-path``: 1 (hero alone, no companions) over the same spp
  values (4 is the ``spp`` series; 8 is probed and reported as not measured
  when the program rejects it, which it does today);
* ``spectral-bins``: 4, 8, 16, 32, 64 and exact at ``--bins-spp`` (256), and
  exact over the whole spp sweep (the unbiased curve);
* effects switched off where the program can: ``dispersion`` off (dispersive
  glass gets its mean index) over the spp sweep on scenes whose summary lists
  "dispersion" (``prism``); ``max-depth`` 1, 2, 4 (1 = direct light only) at
  ``--bins-spp`` on the image scenes. ``colorchecker`` is direct environment
  light on coplanar quads: nothing to switch off;
* ``integrator`` bdpt over the spp sweep on the image scenes (and, on a
  dispersive scene, bdpt with dispersion off), if the program has it.

Error
-----
* Image scenes: relMSE = mean over pixels and channels of
  (x - ref)^2 / (ref^2 + 1e-2) (as in ``benchmark.py``) against a reference
  rendered with ``--spectral-bins exact``, 4 wavelengths, dispersion on, at
  ``--reference-spp``, as two halves with different seeds (``prism``'s and
  ``cornell-point``'s with ``--integrator bdpt``: path tracing finds the prism's caustic
  only by chance and the point light's caustic through the glass sphere not at all).
  The halves give the reference's own noise directly:
  relMSE_ref = mean((a - b)^2 / w) / 4, which adds to every measured relMSE;
  the table's error is the measured relMSE minus it (the raw value is shown).
* ``colorchecker``: mean CIEDE2000 over the 24 patches against colour-science's
  exact chart under D65 (reference XYZ, floors and ΔE from ``color_accuracy.py``;
  the patch averages are taken here, from a snapshot of
  ``scenes/colorchecker.json`` that is also what gets rendered). No
  reference render.

Efficiency is 1 / (relMSE * time), and 1 / (dE^2 * time) for the chart (dE
falls as 1/sqrt(time), relMSE as 1/time, so both are constant along a pure
noise curve).

Seeds
-----
A point is the mean of one or more renders with independent seeds. Replicate r
at spp N has seed 1000 + N + 100000 r (replicate 0 is the seed every point had
before replicates existed), and every knob variant at one spp uses the same
seed set, so they are paired: the difference of a 16-bin and an exact render at
the same seeds is mostly the binning bias. A point's error is the mean of its
replicates' errors, with the standard error of that mean (std / sqrt(n)).

Why replicates: on ``prism`` (a caustic seen through and behind a dispersive
prism) a few rare, very bright samples carry nearly all of a render's relMSE,
so the relMSE of ONE render is a heavy-tailed estimate of its expectation: at
341x256 single renders of the path tracer at 4 spp scored from 0.09 to 434 (16
seeds), and bdpt's from 0.58 to 295, which made single-seed curves go up and
down. Such "noisy scenes" (``--noisy-scenes``, default prism) get
``--noisy-seeds`` replicates per spp value of the sweep (default 32 16 4 2 for
4 16 64 256 spp: many where a render is cheap and holds the fewest bright
samples, few where one render already holds many and its relMSE spreads less;
about 1/sqrt(N) overall). The bins and depth points sit at ``--bins-spp``, one
of the sweep's values, and take its count. Every other scene gets ``--seeds``
(default 1). At the report's sizes the 32 16 4 2 replicates add about 250 s of
idle render time to the study (sum of the per-point times of the 2026-12-02
idle run in docs/report/accuracy/accuracy_cost.json, prism's points times
their extra seeds).

A squared bias (in relMSE units) is estimated without the noise as
mean(d1 * d2 / w), d1 and d2 the same-seed differences of the two variants'
mean images at the two largest spp values (independent seeds).

Renders are cached (``--cache-dir``, default ``build/accuracy-cache``) under the
program's version and sha256 and ``--run-tag``: an interrupted run picks up
where it stopped; a rerun for new timings uses a new ``--run-tag``
(references are shared between tags). The cache keeps a copy of the program:
``--program build/accuracy-cache/<version>_<sha>/pathtracer`` remakes the
report from the cache after the build has changed.

    VENV=$(bash validation/setup_venv.sh)
    $VENV/bin/python validation/accuracy_cost.py --quick   # smoke test, ~10 s, into build/accuracy-quick
    $VENV/bin/python validation/accuracy_cost.py                         # full run
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import json
import math
import os
import platform
import shutil
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchmark as bm  # noqa: E402  (read_pfm, parse_summary, machine description)

REPO_ROOT = Path(__file__).resolve().parent.parent

CHART_SCENE = "colorchecker"
CHART_ILLUMINANT = "D65"
ALL_SCENES = ("cornell", "cornell-point", "colorchecker", "prism")
# Every other scene is an image scene (relMSE against a reference). A scene gets the dispersion
# knob when the program lists "dispersion" among its effects.
BIN_VALUES = ("4", "8", "16", "32", "64", "exact")
DEFAULT_BINS = "16"
# Scenes whose reference is rendered with --integrator bdpt: Newton's prism, whose caustic path
# tracing finds only by chance (scenes/README.md; same expected image, far less noise), and
# cornell-point, whose point light's caustic through the glass sphere path tracing cannot find
# at all (a path-traced reference lacks it, and bdpt would read as biased).
BDPT_REFERENCE = ("prism", "glass-spheres", "cornell-point")
DEFAULT_WL = 4

SEED_BASE = 1000          # seed of replicate r at spp N: SEED_BASE + N + SEED_STRIDE * r (paired knobs)
SEED_STRIDE = 100_000     # above any spp, so no two (spp, replicate) pairs share a seed
NOISY_SCENES = ("prism",)  # heavy-tailed relMSE of one render: several seeds per point (see the docstring)
REFERENCE_SEED = 987654321  # halves use this and this + 1

FULL = {
    "height": 64, "chart_height": 80, "spp": [4, 16, 64, 256, 1024], "bins_spp": 256,
    "depths": [1, 2, 4],
    "reference_spp": {"cornell": 16384, "cornell-point": 16384, "prism": 16384},
    "noisy_seeds": [32, 16, 4, 2, 2],
}
QUICK = {
    "height": 24, "chart_height": 40, "spp": [4, 16, 64], "bins_spp": 16, "depths": [1, 2],
    "reference_spp": {"cornell": 512, "cornell-point": 512, "prism": 512},
    "noisy_seeds": [3, 2, 2],
}


def say(*args: object) -> None:
    print(*args, flush=True)


# ------------------------------------------------------------------------------------------
# Configurations and renders


@dataclass(frozen=True)
class Config:
    scene: str
    spp: int
    bins: str = DEFAULT_BINS
    wl: int = DEFAULT_WL
    dispersion: bool = True
    max_depth: int | None = None
    integrator: str = "path"
    rep: int = 0          # replicate: an independent seed at the same spp

    @property
    def seed(self) -> int:
        return SEED_BASE + self.spp + SEED_STRIDE * self.rep

    def key(self) -> str:
        parts = [bm.safe_name(self.scene), f"{self.spp}spp", f"bins{self.bins}", f"wl{self.wl}"]
        if not self.dispersion:
            parts.append("nodisp")
        if self.max_depth is not None:
            parts.append(f"depth{self.max_depth}")
        if self.integrator != "path":
            parts.append(self.integrator)
        return "_".join(parts) + f"_seed{self.seed}"

    def flags(self) -> list[str]:
        f = ["--spp", str(self.spp), "--spectral-bins", self.bins, "--wavelengths-per-path", str(self.wl),
             "--seed", str(self.seed)]
        if not self.dispersion:
            f.append("--no-dispersion")
        if self.max_depth is not None:
            f += ["--max-depth", str(self.max_depth)]
        # Always named: a scene file may choose another integrator than path.
        f += ["--integrator", self.integrator]
        return f


@dataclass
class Point:
    knob: str
    value: str
    config: Config
    time: float = math.nan
    paths_per_s: float = math.nan
    rays_per_s: float = math.nan
    load1: float = math.nan
    cached: bool = False
    wall: float = math.nan       # wall time of the program run, s
    created: str = ""            # when it was rendered
    image: np.ndarray | None = None
    error: float = math.nan      # relMSE minus the reference's noise, or mean dE
    raw: float = math.nan        # relMSE as measured (images) / split-half noise dE (chart)
    max_de: float = math.nan     # chart only
    trimmed: float = math.nan    # images: relMSE without the worst TRIM_FRACTION of the pixels (minus the
                                 # reference's trimmed noise)
    top_share: float = math.nan  # images: share of the relMSE carried by those worst pixels
    # A plotted point is the mean of its replicates (independent seeds; one render if seeds = 1):
    error_se: float = math.nan   # standard error of the mean error (NaN for one seed)
    trimmed_se: float = math.nan
    seeds: int = 1
    replicates: list = field(default_factory=list)   # the single-render Points behind a mean


@dataclass
class Ctx:
    program: bm.Program
    sha: str
    version: str
    threads: int
    cache: Path           # <cache-dir>/<sha12>
    run_dir: Path         # <cache>/<run-tag>
    scratch: Path
    chart_file: Path | None = None   # snapshot of scenes/colorchecker.json
    chart_sha: str = ""
    rendered: int = 0
    render_seconds: float = 0.0


def scene_size(scene: str, args) -> tuple[int, int]:
    """(width, height): the height asked for, the width from the aspect of the scene file's image."""
    h = args.chart_height if scene == CHART_SCENE else args.height
    aspect = 1.0
    try:
        image = json.loads((REPO_ROOT / "scenes" / f"{scene}.json").read_text()).get("image", {})
        aspect = float(image["width"]) / float(image["height"])
    except (OSError, ValueError, KeyError, TypeError, ZeroDivisionError):
        pass
    return max(1, round(h * aspect)), h


def render(ctx: Ctx, scene: str, size: tuple[int, int], flags: list[str], out: Path) -> bm.Run:
    """Render to ``out`` (PFM); returns timings parsed from the program's summary."""
    import subprocess
    w, h = size
    target = scene
    if scene == CHART_SCENE:
        target = str(ctx.chart_file)  # the snapshot of scenes/colorchecker.json (see main)
        flags = flags + ["--color-space", "xyz"]
    cmd = [str(ctx.program.path), target, "--width", str(w), "--height", str(h), "--threads",
           str(ctx.threads), "-o", str(out)] + flags
    cmd_text = " ".join([str(ctx.program.shown)] + cmd[1:])
    if out.exists():
        out.unlink()
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, errors="replace", stdin=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        tail = "\n".join(proc.stderr.strip().splitlines()[-10:])
        raise bm.BenchError(f"{cmd_text}\nexited with status {proc.returncode}; stderr ends:\n{tail}")
    spp = int(flags[flags.index("--spp") + 1])
    t, paths_s, rays_s = bm.parse_summary(proc.stderr, w * h * spp, cmd_text)
    img = bm.read_pfm(out)
    if img.shape != (h, w, 3) or not np.all(np.isfinite(img)):
        raise bm.BenchError(f"{cmd_text}: bad image (shape {img.shape}, finite {np.all(np.isfinite(img))})")
    ctx.rendered += 1
    ctx.render_seconds += wall
    return bm.Run(t, paths_s, rays_s, wall, img)


def store(src: Path, dst: Path) -> None:
    part = dst.with_name(dst.name + ".part")
    shutil.copyfile(src, part)
    os.replace(part, dst)


def measure_point(ctx: Ctx, p: Point, size: tuple[int, int], remaining: str) -> None:
    c = p.config
    stem = f"{c.key()}_{size[0]}x{size[1]}_t{ctx.threads}"
    if c.scene == CHART_SCENE:
        stem += f"_file{ctx.chart_sha[:10]}"
    pfm, meta_path = ctx.run_dir / f"{stem}.pfm", ctx.run_dir / f"{stem}.json"
    if pfm.is_file() and meta_path.is_file():
        try:
            meta = json.loads(meta_path.read_text())
            img = bm.read_pfm(pfm)
            if img.shape == (size[1], size[0], 3):
                p.time, p.paths_per_s, p.rays_per_s = meta["time_s"], meta["paths_per_s"], meta["rays_per_s"]
                p.load1, p.image, p.cached = meta.get("load1", math.nan), img, True
                p.wall, p.created = meta.get("wall_s", math.nan), meta.get("created", "")
                return
        except (OSError, ValueError, KeyError, bm.BenchError):
            pass
    load1 = os.getloadavg()[0]
    tmp = ctx.scratch / "point.pfm"
    run = render(ctx, c.scene, size, c.flags(), tmp)
    store(tmp, pfm)
    meta = {"scene": c.scene, "width": size[0], "height": size[1], "flags": c.flags(), "threads": ctx.threads,
            "time_s": run.time, "wall_s": run.wall, "paths_per_s": run.paths_per_s, "rays_per_s": run.rays_per_s,
            "load1": load1, "program_version": ctx.version, "binary_sha256": ctx.sha,
            "created": datetime.datetime.now().astimezone().isoformat(timespec="seconds")}
    meta_path.write_text(json.dumps(meta, indent=1) + "\n")
    p.time, p.paths_per_s, p.rays_per_s, p.load1, p.image = run.time, run.paths_per_s, run.rays_per_s, load1, run.image
    p.wall, p.created = run.wall, meta["created"]
    say(f"    {p.knob:>20} {p.value:>5} {c.spp:>5} spp: {run.time:7.3f} s  ({run.wall:.1f} s wall, load {load1:.1f}){remaining}")


@dataclass
class Reference:
    image: np.ndarray
    noise: float          # expected relMSE of the reference itself (from its two halves)
    spp: int
    note: str
    noise_trimmed: float = 0.0  # the same, trimmed as the points' trimmed relMSE
    integrator: str = "path"
    wall: float = 0.0           # wall time of its two renders, s


def reference(ctx: Ctx, scene: str, size: tuple[int, int], spp: int, integrator: str) -> Reference:
    """Mean of two renders of spp/2 (seeds REFERENCE_SEED, +1): exact bins, 4 wavelengths."""
    half = max(1, spp // 2)
    w, h = size
    stem = f"ref_{bm.safe_name(scene)}_{w}x{h}_{2 * half}spp_exact_wl4_{integrator}_seed{REFERENCE_SEED}"
    pfm_a, pfm_b, meta_path = (ctx.cache / f"{stem}_a.pfm", ctx.cache / f"{stem}_b.pfm",
                               ctx.cache / f"{stem}.json")
    meta = {}
    if meta_path.is_file():
        try:
            meta = json.loads(meta_path.read_text())
        except (OSError, ValueError):
            meta = {}
    halves = []
    for i, path in enumerate((pfm_a, pfm_b)):
        img = None
        if path.is_file() and str(i) in meta.get("halves", {}):
            try:
                img = bm.read_pfm(path)
                if img.shape != (h, w, 3):
                    img = None
            except bm.BenchError:
                img = None
        if img is None:
            say(f"  {scene}: rendering reference half {i + 1}/2 ({w}x{h}, {half} spp, exact bins, {integrator}, "
                f"{ctx.threads} threads) ...")
            tmp = ctx.scratch / "ref.pfm"
            flags = ["--spp", str(half), "--spectral-bins", "exact", "--wavelengths-per-path", "4",
                     "--seed", str(REFERENCE_SEED + i), "--integrator", integrator]
            run = render(ctx, scene, size, flags, tmp)
            store(tmp, path)
            meta.setdefault("halves", {})[str(i)] = {
                "time_s": run.time, "wall_s": run.wall, "paths_per_s": run.paths_per_s, "flags": flags,
                "created": datetime.datetime.now().astimezone().isoformat(timespec="seconds")}
            meta.update({"scene": scene, "width": w, "height": h, "spp": 2 * half, "threads": ctx.threads,
                         "program_version": ctx.version, "binary_sha256": ctx.sha})
            meta_path.write_text(json.dumps(meta, indent=1) + "\n")
            say(f"  {scene}: half {i + 1} took {run.time:.1f} s")
            img = run.image
        halves.append(img)
    a, b = halves
    ref = (a + b) / 2
    total, trimmed, _ = pixel_errors(a, b, w_of(ref))
    took = sum(v.get("time_s", 0) for v in meta.get("halves", {}).values())
    wall = sum(v.get("wall_s", 0) for v in meta.get("halves", {}).values())
    return Reference(ref, total / 4, 2 * half, f"`--integrator {integrator}`, {2 * half} spp, rendered in {took:.0f} s",
                     trimmed / 4, integrator, wall)


def probe(ctx: Ctx, flags: list[str]) -> str | None:
    """None if the program accepts ``flags``, else its error message."""
    import subprocess
    cmd = [str(ctx.program.path), "cornell", "--spp", "1", "--width", "4", "--height", "4", "--quiet",
           "-o", str(ctx.scratch / "probe.pfm")] + flags
    proc = subprocess.run(cmd, capture_output=True, text=True, errors="replace", stdin=subprocess.DEVNULL)
    if proc.returncode == 0:
        return None
    return (proc.stderr.strip().splitlines() or [f"exit status {proc.returncode}"])[-1]


# ------------------------------------------------------------------------------------------
# Plan


def scene_effects(ctx: Ctx, scene: str) -> list[str]:
    """The effects the program lists for ``scene`` in its summary (``effects: a, b, ...``)."""
    import re
    import subprocess
    cmd = [str(ctx.program.path), scene, "--spp", "1", "--width", "4", "--height", "4", "--threads", "1",
           "-o", str(ctx.scratch / "probe.pfm")]
    proc = subprocess.run(cmd, capture_output=True, text=True, errors="replace", stdin=subprocess.DEVNULL)
    if proc.returncode != 0:
        tail = "\n".join(proc.stderr.strip().splitlines()[-5:])
        raise bm.BenchError(f"{' '.join(cmd)} failed ({proc.returncode}):\n{tail}")
    m = re.search(r"^\s*effects:\s*(.*)$", proc.stderr, re.MULTILINE)
    return [e.strip() for e in re.split(r",\s*(?![^()]*\))", m.group(1))] if m else []


def plan(scene: str, args, wavelengths: list[int], integrators: list[str], effects: list[str]) -> list[Point]:
    dispersive = "dispersion" in effects
    image_scene = scene != CHART_SCENE
    pts: list[Point] = []
    for spp in args.spp:
        pts.append(Point("spp", str(spp), Config(scene, spp)))
    for k in wavelengths:
        if k != DEFAULT_WL:
            for spp in args.spp:
                pts.append(Point("wavelengths-per-path", str(k), Config(scene, spp, wl=k)))
    for b in BIN_VALUES:
        pts.append(Point("spectral-bins", b, Config(scene, args.bins_spp, bins=b)))
    # exact over the whole spp sweep: the unbiased curve, and pairs (same seed) with the 16-bin
    # points for the bias estimate
    for spp in args.spp:
        if spp != args.bins_spp:
            pts.append(Point("spectral-bins", "exact", Config(scene, spp, bins="exact")))
    if dispersive:
        for spp in args.spp:
            pts.append(Point("dispersion", "off", Config(scene, spp, dispersion=False)))
    if image_scene:
        for integ in integrators:
            if integ == "path":
                continue
            for spp in args.spp:
                pts.append(Point("integrator", integ, Config(scene, spp, integrator=integ)))
            if dispersive:
                for spp in args.spp:
                    pts.append(Point("dispersion", f"off, {integ}",
                                     Config(scene, spp, dispersion=False, integrator=integ)))
    if image_scene:
        for d in args.depths:
            pts.append(Point("max-depth", str(d), Config(scene, args.bins_spp, max_depth=d)))
    # Replicates: the same seed set for every knob at one spp (paired), independent between spp.
    return [Point(p.knob, p.value, dataclasses.replace(p.config, rep=r))
            for p in pts for r in range(seeds_at(scene, p.config.spp, args))]


def seeds_at(scene: str, spp: int, args) -> int:
    """Independent renders averaged for one point of ``scene`` at ``spp``: --noisy-seeds (one count
    per value of the spp sweep; the last count for any later value) on a noisy scene, else --seeds."""
    if scene not in args.noisy_scenes:
        return args.seeds
    i = args.spp.index(spp) if spp in args.spp else len(args.spp) - 1
    counts = args.noisy_seeds
    return max(args.seeds, counts[min(i, len(counts) - 1)])


def aggregate(points: list[Point]) -> list[Point]:
    """One Point per knob value and configuration (spp, integrator, ...), in the order of first
    appearance: the mean of its replicates' errors, times and images, with the standard error of
    the mean error (std with n − 1 / sqrt(n); NaN for one replicate). The mean image is what a
    render with all the replicates' samples would give (up to the seeds' pattern); the bias
    estimates and image ratios read it."""
    groups: dict[tuple[str, str, Config], list[Point]] = {}
    for p in points:  # by knob too: one render may stand in two series (the default at --bins-spp)
        groups.setdefault((p.knob, p.value, dataclasses.replace(p.config, rep=0)), []).append(p)
    out = []
    for (_, _, config), reps in groups.items():
        first = reps[0]

        def mean(attr: str) -> float:
            vals = [getattr(q, attr) for q in reps]
            return float(np.mean(vals)) if vals else math.nan

        def se(attr: str) -> float:
            vals = [getattr(q, attr) for q in reps]
            return float(np.std(vals, ddof=1) / math.sqrt(len(vals))) if len(vals) > 1 else math.nan

        images = [q.image for q in reps if q.image is not None]
        out.append(Point(
            first.knob, first.value, config, time=mean("time"), paths_per_s=mean("paths_per_s"),
            rays_per_s=mean("rays_per_s"), load1=mean("load1"), cached=all(q.cached for q in reps),
            wall=math.nan, created=min((q.created for q in reps if q.created), default=""),
            image=np.mean(images, axis=0) if images else None, error=mean("error"), raw=mean("raw"),
            max_de=mean("max_de"), trimmed=mean("trimmed"), top_share=mean("top_share"),
            error_se=se("error"), trimmed_se=se("trimmed"), seeds=len(reps), replicates=reps))
    return out


def rises(pts: list[Point], z: float = 2.0) -> list[tuple[Point, Point, float]]:
    """Steps of a curve (sorted by spp) where the mean error rises by more than ``z`` combined
    standard errors: (lower spp point, higher spp point, the rise in standard errors). A
    step between single renders (no standard error) counts when it rises at all."""
    out = []
    for a, b in zip(pts, pts[1:]):
        if not (math.isfinite(a.error) and math.isfinite(b.error)) or b.error <= a.error:
            continue
        se = math.hypot(*(x for x in (a.error_se, b.error_se) if math.isfinite(x))) \
            if any(math.isfinite(x) for x in (a.error_se, b.error_se)) else 0.0
        k = (b.error - a.error) / se if se > 0 else math.inf
        if k > z:
            out.append((a, b, k))
    return out


# ------------------------------------------------------------------------------------------
# Errors


def w_of(ref: np.ndarray) -> np.ndarray:
    return ref * ref + bm.REL_MSE_EPS


@dataclass
class SceneResult:
    scene: str
    size: tuple[int, int]
    points: list[Point]
    ref: Reference | None = None
    chart_scene: dict | None = None     # the parsed snapshot of scenes/colorchecker.json
    title: str = ""                     # set for a derived view (trimmed relMSE)
    extra: dict = field(default_factory=dict)


TRIM_FRACTION = 0.001  # share of the pixels dropped by the trimmed relMSE (at least one pixel)


def pixel_errors(x: np.ndarray, ref: np.ndarray, w: np.ndarray) -> tuple[float, float, float]:
    """(relMSE, relMSE without the worst TRIM_FRACTION of the pixels, share of the relMSE in them).

    Rare paths (a caustic found by chance, a lone wavelength through dispersive glass) put huge
    values in a handful of pixels; those then carry nearly all the relMSE of one render, and
    the trimmed value shows the error of the rest of the image."""
    per_pixel = np.sort(((x - ref) ** 2 / w).sum(axis=2).ravel())
    n = per_pixel.size
    k = max(1, int(TRIM_FRACTION * n))
    total = float(per_pixel.sum())
    top = float(per_pixel[-k:].sum())
    return total / (3 * n), (total - top) / (3 * n), (top / total if total > 0 else 0.0)


def evaluate_images(res: SceneResult) -> None:
    ref = res.ref
    w = w_of(ref.image)
    for p in res.points:
        p.raw, trimmed, p.top_share = pixel_errors(p.image, ref.image, w)
        p.error = p.raw - ref.noise
        p.trimmed = trimmed - ref.noise_trimmed


_ca = None


def color_accuracy():
    global _ca
    if _ca is None:
        import warnings
        warnings.filterwarnings("ignore", message='"SciPy" related API')
        import color_accuracy as ca
        _ca = ca
    return _ca


CHART_MARGIN_PX = 1  # whole pixels dropped inside each patch's edge


def chart_regions(scene: dict, width: int, height: int) -> list[tuple[slice, slice]]:
    """(rows, columns) of the whole pixels inside each patch, in ``color_accuracy.PATCHES`` order.

    Projects each quad with the renderer's pinhole camera (film (0, 0) = top-left corner, y
    down; the quads face the camera, so their images are axis-aligned rectangles)."""
    ca = color_accuracy()
    cam = scene["camera"]
    eye, target = np.array(cam["position"], float), np.array(cam["look_at"], float)
    up = np.array(cam.get("up", [0, 1, 0]), float)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    half_h = math.tan(math.radians(cam.get("vfov_degrees", 40.0)) / 2)
    half_w = half_h * width / height
    by_patch = {}
    for shape in scene["shapes"]:
        kd = scene["materials"][shape["material"]]["kd"]
        if shape["type"] != "quad" or "transform" in shape or kd.get("type") != "colorchecker":
            raise bm.BenchError("the colorchecker scene should hold untransformed colorchecker quads only")
        o, e1, e2 = (np.array(shape[k], float) for k in ("origin", "edge1", "edge2"))
        xs, ys = [], []
        for q in (o, o + e1, o + e2, o + e1 + e2):
            d = q - eye
            depth = d @ forward
            xs.append((d @ right / depth + half_w) / (2 * half_w) * width)
            ys.append((half_h - d @ true_up / depth) / (2 * half_h) * height)
        m = CHART_MARGIN_PX
        c0, c1 = math.ceil(min(xs) - 1e-3) + m, math.floor(max(xs) + 1e-3) - m
        r0, r1 = math.ceil(min(ys) - 1e-3) + m, math.floor(max(ys) + 1e-3) - m
        if c1 - c0 < 2 or r1 - r0 < 2 or c0 < 0 or r0 < 0 or c1 > width or r1 > height:
            raise bm.BenchError(f"patch {kd['patch']} has too few whole pixels at {width}x{height}")
        by_patch[kd["patch"]] = (slice(r0, r1), slice(c0, c1))
    if sorted(by_patch) != sorted(ca.PATCHES):
        raise bm.BenchError("the colorchecker scene should hold one quad per ColorChecker patch")
    return [by_patch[name] for name in ca.PATCHES]


@dataclass
class ChartMeans:
    xyz: np.ndarray      # (24, 3), white Y = 1
    half_a: np.ndarray   # (24, 3) checkerboard halves of each patch
    half_b: np.ndarray
    pixels: int          # pixels of the smallest patch region


def chart_means(image: np.ndarray, scene: dict) -> ChartMeans:
    ca = color_accuracy()
    h, w, _ = image.shape
    image = image * ca.renderer_white_scale(CHART_ILLUMINANT)
    full, a, b, count = [], [], [], []
    for rows, cols in chart_regions(scene, w, h):
        block = image[rows, cols]
        checker = (np.add.outer(np.arange(block.shape[0]), np.arange(block.shape[1])) % 2) == 0
        full.append(block.reshape(-1, 3).mean(axis=0))
        a.append(block[checker].mean(axis=0))
        b.append(block[~checker].mean(axis=0))
        count.append(block.shape[0] * block.shape[1])
    return ChartMeans(np.array(full), np.array(a), np.array(b), min(count))


def evaluate_chart(res: SceneResult) -> None:
    ca = color_accuracy()
    ref_xyz, _ = ca.reference_xyz(CHART_ILLUMINANT)
    for p in res.points:
        m = chart_means(p.image, res.chart_scene)
        de = ca.delta_e(m.xyz, ref_xyz, CHART_ILLUMINANT)
        p.error, p.max_de = float(de.mean()), float(de.max())
        p.raw = float((ca.delta_e(m.half_a, m.half_b, CHART_ILLUMINANT) / 2).mean())
    res.extra["pixels_per_patch"] = chart_means(res.points[0].image, res.chart_scene).pixels


# ------------------------------------------------------------------------------------------
# Reading


def find(res: SceneResult, knob: str, value: str, spp: int) -> Point | None:
    for p in res.points:
        if p.knob == knob and p.value == value and p.config.spp == spp:
            return p
    return None


def default_at(res: SceneResult, spp: int) -> Point | None:
    return find(res, "spp", str(spp), spp) or find(res, "spectral-bins", DEFAULT_BINS, spp)


def base_of(res: SceneResult, p: Point) -> Point | None:
    """What a point is compared with: the defaults at its spp, with its integrator."""
    if p.config.integrator != "path" and p.knob != "integrator":
        return find(res, "integrator", p.config.integrator, p.config.spp)
    return default_at(res, p.config.spp)


def is_chart(res: SceneResult) -> bool:
    return res.scene == CHART_SCENE


def efficiency(res: SceneResult, p: Point) -> float:
    e = p.error ** 2 if is_chart(res) else p.error
    return 1.0 / (e * p.time) if e > 0 and p.time > 0 else math.inf


def fmt(x: float, digits: int = 3) -> str:
    if x is None or not math.isfinite(x):
        return "—" if x is None or math.isnan(x) else ("∞" if x > 0 else "−∞")
    return f"{x:.{digits}g}"


def series(res: SceneResult, knob: str, value: str) -> list[Point]:
    return sorted([p for p in res.points if p.knob == knob and p.value == value], key=lambda p: p.config.spp)


def cross_bias(a1: Point, b1: Point, a2: Point, b2: Point, w: np.ndarray) -> tuple[float, float]:
    """Squared bias of A against B in relMSE units, without the noise: the pairs (a1, b1) and
    (a2, b2) share their seeds within a pair and differ between pairs, so
    E[(a1 - b1)(a2 - b2) / w] is the squared bias alone. Returns (mean, standard error)."""
    prod = ((a1.image - b1.image) * (a2.image - b2.image) / w).ravel()
    return float(prod.mean()), float(prod.std() / math.sqrt(prod.size))


def bins_order(b: str) -> int:
    return 10 ** 6 if b == "exact" else int(b)


def firefly_dominated(res: SceneResult) -> bool:
    shares = [p.top_share for p in res.points if math.isfinite(p.top_share)]
    return bool(shares) and statistics.median(shares) > 0.5


def trimmed_view(res: SceneResult) -> SceneResult:
    """The same scene with the trimmed relMSE as its error."""
    pts = [dataclasses.replace(p, error=p.trimmed, error_se=p.trimmed_se) for p in res.points]
    return SceneResult(res.scene, res.size, pts, res.ref, chart_scene=res.chart_scene,
                       title=f"{res.scene}, trimmed relMSE (worst {TRIM_FRACTION:.1%} of the pixels dropped)")


def with_trimmed(results: list[SceneResult]) -> list[SceneResult]:
    out = []
    for res in results:
        out.append(res)
        if not is_chart(res) and firefly_dominated(res):
            out.append(trimmed_view(res))
    return out


def spp_curves(res: SceneResult) -> dict[tuple[str, str], list[Point]]:
    """The curves drawn against spp: (knob, value) → points sorted by spp ("" for the defaults)."""
    lines: dict[tuple[str, str], list[Point]] = {}
    for p in res.points:
        if p.knob in ("spp", "wavelengths-per-path", "dispersion", "integrator") or \
                (p.knob, p.value) == ("spectral-bins", "exact"):
            lines.setdefault((p.knob, "" if p.knob == "spp" else p.value), []).append(p)
    return {k: sorted(v, key=lambda p: p.config.spp) for k, v in lines.items()}


def reading(results: list[SceneResult], args) -> list[str]:
    out: list[str] = []
    top = max(args.spp)
    S = args.bins_spp
    pair_spp = sorted(args.spp)[-2:]  # the two largest spp values: most bias signal per noise
    for res in results:
        chart = is_chart(res)
        unit = "mean ΔE2000" if chart else "relMSE"
        out.append(f"### {res.title or res.scene}")
        out.append("")
        if not chart and not res.title:
            shares = [p.top_share for p in res.points]
            k = max(1, int(TRIM_FRACTION * res.size[0] * res.size[1]))
            out.append(f"- Share of each render's relMSE in its worst {k} pixel(s) ({TRIM_FRACTION:.1%}): median "
                       f"{statistics.median(shares):.2f}, max {max(shares):.2f}"
                       + (" — a few outlier pixels carry the error, so the relMSE of one render is a poor estimate "
                          "of its expectation (single renders jump by 10× between neighbouring points): each point "
                          "is the mean over its seeds (the `seeds` column) with its standard error, and the trimmed "
                          "relMSE below is steadier" if firefly_dominated(res) else "") + ".")
        if res.title:  # the trimmed view: each render without its worst pixels, which need not fall as 1/N
            out.append("- The trimmed relMSE drops each render's worst pixels (where the rare bright samples "
                       "land), so it is a steadier view of the rest of the image, not the expected error: it need "
                       "not fall as 1/N, and its monotonicity is not checked.")
        steps = [] if res.title else [(key, a, b, z) for key, pts in spp_curves(res).items() for a, b, z in rises(pts)]
        res.extra["rises"] = len(steps)
        if not res.title:
            out.append("- Monotone in spp: " + (
                "every curve's mean error falls from each spp to the next, or rises by less than 2 standard errors."
                if not steps else "; ".join(
                    f"{key[0]} {key[1] or 'default'} rises from {a.config.spp} to {b.config.spp} spp "
                    f"({fmt(a.error)} → {fmt(b.error)}, " + (f"{z:.1f} s.e." if math.isfinite(z) else "single renders")
                    + ")" for key, a, b, z in steps) + "."))
        d_series = [p for p in res.points if p.knob == "spp"]
        exact = series(res, "spectral-bins", "exact")
        # --- efficiency per knob value, relative to the default at the same spp
        out.append(f"- Efficiency 1/({'ΔE²' if chart else 'relMSE'}·time) of the defaults (16 bins, 4 λ/path) "
                   "by spp: " + ", ".join(f"{p.config.spp}: {fmt(efficiency(res, p))}" for p in d_series) + " /s; "
                   "with exact spectra: " + ", ".join(f"{p.config.spp}: {fmt(efficiency(res, p))}" for p in exact)
                   + " /s (constant while noise dominates, falling once a bias floor is reached)")
        rows = []
        for p in res.points:
            if p.knob == "spp" or (p.knob == "spectral-bins" and p.value == DEFAULT_BINS):
                continue
            base = base_of(res, p)
            if base is not None:
                rows.append((p, efficiency(res, p) / efficiency(res, base), p.time / base.time, p.error / base.error))
        if rows:
            out.append("- Against the defaults at the same spp (with the same integrator) (efficiency ×; time ×; error ×):")
            by_knob: dict[tuple[str, str], list] = {}
            for p, er, tr, xr in rows:
                by_knob.setdefault((p.knob, p.value), []).append((p.config.spp, er, tr, xr))
            for (knob, value), lst in sorted(by_knob.items(), key=lambda kv: (kv[0][0], bins_order(kv[0][1]) if kv[0][0] in ("spectral-bins", "max-depth") else 0)):
                cells = "; ".join(f"{spp}: eff ×{fmt(er, 2)} (t ×{fmt(tr, 2)}, err ×{fmt(xr, 2)})"
                                  for spp, er, tr, xr in lst)
                out.append(f"  - {knob} {value}: {cells}")
            at_s = [r for r in rows if r[0].config.spp == S]
            if at_s:
                best = max(at_s, key=lambda r: r[1])
                out.append(f"  - most efficient change at {S} spp: {best[0].knob} {best[0].value} "
                           f"(efficiency ×{fmt(best[1], 2)})")
        # --- binning bias vs noise
        if chart:
            ca = color_accuracy()
            ref_xyz = ca.reference_xyz(CHART_ILLUMINANT)[0]
            floors = {b: float(ca.delta_e(ca.floor_xyz(CHART_ILLUMINANT, int(b)), ref_xyz, CHART_ILLUMINANT).mean())
                      for b in BIN_VALUES[:-1]}
            floor = floors[DEFAULT_BINS]
            p16, pex = default_at(res, S), find(res, "spectral-bins", "exact", S)
            paired = math.nan
            if p16 is not None and pex is not None:
                paired = float(ca.delta_e(chart_means(p16.image, res.chart_scene).xyz,
                                          chart_means(pex.image, res.chart_scene).xyz, CHART_ILLUMINANT).mean())
            ks = [p.raw * math.sqrt(p.config.spp) for p in d_series if p.raw > 0]
            k = statistics.median(ks) if ks else math.nan
            spp_star = (k / floor) ** 2 if floor > 0 else math.inf
            pt = default_at(res, top)
            t_star = spp_star * pt.time / top if pt else math.nan
            res.extra.update(bias16=floor, spp_star=spp_star)
            out.append(f"- Binning: the 16-bin spectra alone are {fmt(floor)} mean ΔE from the exact chart "
                       f"(analytic floor; 16-bin vs exact renders at {S} spp, same seed: {fmt(paired)}). Noise of the "
                       f"patch means (split-half) ≈ {fmt(k)}/√spp ΔE with {res.extra.get('pixels_per_patch')} pixels "
                       f"per patch, so binning dominates noise above ≈ {fmt(spp_star, 2)} spp (≈ {fmt(t_star, 2)} s; "
                       "the crossover scales as 1/pixels per patch).")
            out.append("  - floors by bin count (mean ΔE, the spectra alone): "
                       + ", ".join(f"{b}: {fmt(v, 2)}" for b, v in floors.items())
                       + "; measured at " + f"{S} spp: " + ", ".join(
                           f"{p.value}: {fmt(p.error, 2)}" for p in res.points
                           if p.knob == "spectral-bins" and p.config.spp == S))
        else:
            w = w_of(res.ref.image)
            bias, se = math.nan, math.nan
            pairs = [(default_at(res, n), find(res, "spectral-bins", "exact", n)) for n in pair_spp]
            if len(pair_spp) == 2 and all(a is not None and b is not None for a, b in pairs):
                bias, se = cross_bias(*pairs[0], *pairs[1], w)
            cs = [p.error * p.config.spp for p in exact if p.error > 0]
            c_noise = statistics.median(cs) if cs else math.nan
            res.extra.update(bias16=bias, bias16_se=se, noise_c=c_noise)
            pt = default_at(res, top)
            resolved = math.isfinite(bias) and bias > 2 * se
            if resolved:
                spp_star = c_noise / bias
                res.extra["spp_star"] = spp_star
                out.append(f"- Binning: 16-bin bias ≈ {fmt(bias)} ± {fmt(se, 2)} relMSE (cross product of the "
                           f"same-seed 16-bin − exact differences at {pair_spp[0]} and {pair_spp[1]} spp); noise ≈ "
                           f"{fmt(c_noise)}/spp (median over the exact renders), so binning dominates noise above ≈ "
                           f"{fmt(spp_star, 2)} spp (≈ {fmt(spp_star * pt.time / top, 2)} s at "
                           f"{res.size[0]}x{res.size[1]}).")
            else:
                lim = c_noise / (2 * se) if se > 0 else math.inf
                res.extra["spp_star"] = math.inf
                out.append(f"- Binning: 16-bin bias not resolved ({fmt(bias)} ± {fmt(se, 2)} relMSE, cross product of "
                           f"the same-seed 16-bin − exact differences at {pair_spp[0]} and {pair_spp[1]} spp); noise ≈ "
                           f"{fmt(c_noise)}/spp, so binning stays below noise up to at least ≈ {fmt(lim, 2)} spp.")
            pex = find(res, "spectral-bins", "exact", S)
            paired = {p.value: float(np.mean((p.image - pex.image) ** 2 / w)) for p in res.points
                      if pex is not None and p.knob == "spectral-bins" and p.config.spp == S and p.value != "exact"}
            if paired:
                out.append(f"  - same-seed (N bins − exact)² at {S} spp, each bias plus some noise (an upper bound): "
                           + ", ".join(f"{b}: {fmt(v, 2)}" for b, v in paired.items())
                           + f"; noise of one render at {S} spp ≈ {fmt(c_noise / S, 2)}")
        # --- hero set saving: time ratio for the same noise, the bias (the same 16 bins) removed
        for k in sorted({int(p.value) for p in res.points if p.knob == "wavelengths-per-path"}):
            curve = series(res, "wavelengths-per-path", str(k))
            savings, cells = [], []
            b16 = res.extra.get("bias16", 0.0)
            b16 = b16 if (math.isfinite(b16) and (chart or b16 > 2 * res.extra.get("bias16_se", 0.0))) else 0.0
            for p1 in curve:
                p4 = default_at(res, p1.config.spp)
                if p4 is None:
                    continue
                if chart:   # noise from the split halves, dE^2 ~ 1/time
                    n1, n4 = p1.raw ** 2, p4.raw ** 2
                else:       # relMSE minus the 16-bin bias both share
                    n1, n4 = p1.error - b16, p4.error - b16
                if n1 > 0 and n4 > 0:
                    sv = (n1 * p1.time) / (n4 * p4.time)
                    savings.append(sv)
                    cells.append(f"{p1.config.spp}: ×{fmt(sv, 2)} (noise ×{fmt(n1 / n4, 2)}, t ×{fmt(p1.time / p4.time, 2)})")
            med = statistics.median(savings) if savings else math.nan
            res.extra[f"hero_saving_{k}"] = med
            what = ("split-half noise ΔE², which falls as 1/time; both have the same 16-bin bias"
                    if chart else "relMSE minus the 16-bin bias both share")
            out.append(f"- Hero set: {k} λ/path needs ×{fmt(med, 2)} (median over spp) the render time of 4 λ/path for "
                       f"the same noise ({what}; ratio = noise × time at equal spp): {'; '.join(cells)}.")
        # --- dispersion off: bias it buys (for each integrator measured)
        for value in sorted({p.value for p in res.points if p.knob == "dispersion"}):
            nd = series(res, "dispersion", value)
            cells = []
            for p in nd:
                base = base_of(res, p)
                if base:
                    cells.append(f"{p.config.spp}: err ×{fmt(p.error / base.error, 2)}, t ×{fmt(p.time / base.time, 2)}")
            integ = nd[0].config.integrator
            out.append(f"- Dispersion {value} (mean index) vs dispersion on, both `--integrator {integ}`, against the "
                       f"dispersive reference (error ×, time ×): {'; '.join(cells)}.")
            pairs = [(find(res, "dispersion", value, n), base_of(res, find(res, "dispersion", value, n) or nd[0]))
                     for n in pair_spp]
            if len(pair_spp) == 2 and all(a is not None and b is not None for a, b in pairs):
                bias, se = cross_bias(*pairs[0], *pairs[1], w_of(res.ref.image))
                on = [base_of(res, p) for p in nd]
                cs = [q.error * q.config.spp for q in on if q is not None and q.error > 0]
                c = statistics.median(cs) if cs else math.nan
                res.extra[f"nodisp_bias_{integ}"] = bias
                if bias > 2 * se:
                    out.append(f"  - its bias ≈ {fmt(bias)} ± {fmt(se, 2)} relMSE (cross product of the same-seed "
                               f"off − on differences at {pair_spp[0]} and {pair_spp[1]} spp); the dispersive "
                               f"render's noise ≈ {fmt(c)}/spp, so with `{integ}` switching dispersion off stops "
                               f"paying above ≈ {fmt(c / bias, 2)} spp.")
                else:
                    out.append(f"  - its bias is not resolved ({fmt(bias)} ± {fmt(se, 2)} relMSE): up to {top} spp "
                               f"with `{integ}` dispersion only adds noise to this metric.")
        # --- another integrator than the reference's: do the two converge to the same image?
        for integ in sorted({p.value for p in res.points if p.knob == "integrator"}):
            if chart or res.ref.integrator == integ:
                continue
            q, base = find(res, "integrator", integ, top), default_at(res, top)
            if q is None or base is None:
                continue
            ratio = q.image.mean(axis=(0, 1)) / res.ref.image.mean(axis=(0, 1))
            line = (f"- `--integrator {integ}` against the `{res.ref.integrator}` reference at {top} spp: error "
                    f"×{fmt(q.error / base.error, 2)} that of `{res.ref.integrator}`, mean image / reference "
                    f"(R, G, B) = {', '.join(f'{v:.3f}' for v in ratio)}")
            if q.error > 3 * base.error and np.max(np.abs(ratio - 1)) > 0.01:
                line += (f" — the two integrators converge to different images here; its curve flattens at "
                         f"that difference, not at its own error")
            out.append(line + ".")
        depth = [p for p in res.points if p.knob == "max-depth"]
        if depth:
            base = default_at(res, S)
            out.append(f"- max-depth at {S} spp (error ×, time ×, same-seed (d − unbounded)² relMSE): " + "; ".join(
                f"{p.value}: ×{fmt(p.error / base.error, 2)}, ×{fmt(p.time / base.time, 2)}, "
                f"{fmt(float(np.mean((p.image - base.image) ** 2 / w_of(res.ref.image))), 2)}" for p in depth))
        out.append("")
    return out


# ------------------------------------------------------------------------------------------
# Outputs


def summary(results: list[SceneResult]) -> dict:
    """Every point's numbers as plain data (accuracy_cost.json, read by docs/report/build_report.py)."""
    def num(x: float) -> float | None:
        return x if math.isfinite(x) else None
    return {"scenes": {r.scene: {
        "size": list(r.size),
        "reference": r.ref.note if r.ref is not None else "colour-science (no render)",
        "points": [{"knob": p.knob, "value": p.value, "spp": p.config.spp, "integrator": p.config.integrator,
                    "time": num(p.time), "error": num(p.error), "error_se": num(p.error_se), "seeds": p.seeds,
                    "raw": num(p.raw), "trimmed": num(p.trimmed), "trimmed_se": num(p.trimmed_se),
                    "efficiency": num(efficiency(r, p))} for p in r.points]} for r in results}}


def table(results: list[SceneResult]) -> list[str]:
    lines = ["| scene | knob | value | spp | seeds | time (s) | samples/s | rays/s | error | error s.e. | metric | "
             "raw relMSE / noise ΔE | trimmed relMSE | worst-px share | efficiency (1/s) | load (1 min) |",
             "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: |"]
    for res in results:
        metric = "mean ΔE2000" if is_chart(res) else "relMSE"
        for p in res.points:
            lines.append(f"| {res.scene} | {p.knob} | {p.value} | {p.config.spp} | {p.seeds} | {p.time:.3g} | "
                         f"{p.paths_per_s:.3g} | {p.rays_per_s:.3g} | {fmt(p.error, 4)} | {fmt(p.error_se, 2)} | "
                         f"{metric} | {fmt(p.raw, 4)} | "
                         f"{fmt(p.trimmed, 4)} | {fmt(p.top_share, 2)} | {fmt(efficiency(res, p))} | {fmt(p.load1, 2)} |")
    return lines


def errorbars(ax, pts: list[Point], color) -> None:
    """± 1 standard error of the mean over seeds (points of several seeds only; on log axes the
    lower end is clipped at a tenth of the value, where the bar would cross zero)."""
    pts = [p for p in pts if math.isfinite(p.error_se)]
    if pts:
        lo = [min(p.error_se, 0.9 * p.error) for p in pts]
        ax.errorbar([p.time for p in pts], [p.error for p in pts], yerr=[lo, [p.error_se for p in pts]],
                    fmt="none", ecolor=color, elinewidth=0.9, capsize=2.5, alpha=0.8)


STYLE = {
    ("spp", ""): dict(color="C0", marker="o", ls="-", label="spp sweep (path, 16 bins, 4 λ/path)"),
    ("wavelengths-per-path", "1"): dict(color="C1", marker="s", ls="-", label="1 λ/path (hero alone)"),
    ("wavelengths-per-path", "8"): dict(color="C5", marker="s", ls="-", label="8 λ/path"),
    ("dispersion", "off"): dict(color="C2", marker="^", ls="-", label="dispersion off (mean index)"),
    ("spectral-bins", "exact"): dict(color="C3", marker="D", ls="--", label="--spectral-bins exact"),
    ("integrator", "bdpt"): dict(color="C6", marker="P", ls="-", label="--integrator bdpt"),
    ("dispersion", "off, bdpt"): dict(color="C2", marker="^", ls=":", label="dispersion off, bdpt"),
    ("integrator", "vcm"): dict(color="C9", marker="X", ls="-", label="--integrator vcm"),
    ("dispersion", "off, vcm"): dict(color="C2", marker="^", ls="-.", label="dispersion off, vcm"),
}


def plot(results: list[SceneResult], args, path: Path, title: str, notes: list[str]) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(results)
    cols = 1 if n == 1 else (2 if n <= 4 else 3)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(6.2 * cols, 4.8 * rows), squeeze=False)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    if n < rows * cols:  # the first free panel holds a short key
        axes.ravel()[n].text(0.02, 0.98, "\n".join(notes), va="top", ha="left", fontsize=8,
                             transform=axes.ravel()[n].transAxes, wrap=True)
    for ax, res in zip(axes.ravel(), results):
        chart = is_chart(res)
        for key, pts in spp_curves(res).items():
            pts = sorted([p for p in pts if p.error > 0], key=lambda p: p.config.spp)
            st = STYLE.get(key, dict(marker="o", ls="-", label=f"{key[0]} {key[1]}"))
            line, = ax.plot([p.time for p in pts], [p.error for p in pts], ms=5, lw=1.3, **st)
            errorbars(ax, pts, line.get_color())
            if key == ("spp", ""):
                for p in pts:
                    ax.annotate(str(p.config.spp), (p.time, p.error), textcoords="offset points", xytext=(4, 4),
                                fontsize=7, color="C0")
        bins = [p for p in res.points if p.knob == "spectral-bins" and p.error > 0
                and p.config.spp == args.bins_spp and p.value not in ("exact", DEFAULT_BINS)]
        ax.plot([p.time for p in bins], [p.error for p in bins], "D", color="C3", mfc="none", ms=6, ls="none",
                label=f"--spectral-bins 4, 8, 32, 64 ({args.bins_spp} spp)")
        errorbars(ax, bins, "C3")
        for p in bins:
            ax.annotate(p.value, (p.time, p.error), textcoords="offset points", xytext=(4, -9), fontsize=7, color="C3")
        depth = [p for p in res.points if p.knob == "max-depth" and p.error > 0]
        if depth:
            ax.plot([p.time for p in depth], [p.error for p in depth], "v", color="C4", ms=5, ls="none",
                    label=f"--max-depth 1, 2, 4 ({args.bins_spp} spp)")
            errorbars(ax, depth, "C4")
            for p in depth:
                ax.annotate(f"d{p.value}", (p.time, p.error), textcoords="offset points", xytext=(4, 2),
                            fontsize=7, color="C4")
        b = res.extra.get("bias16", math.nan)
        if math.isfinite(b) and b > 0 and (chart or b > 2 * res.extra.get("bias16_se", 0.0)):
            ax.axhline(b, color="C3", ls="--", lw=0.9, alpha=0.7,
                       label="16-bin floor (analytic)" if chart else "16-bin bias (estimate)")
        ref_noise = (res.ref.noise_trimmed if res.title else res.ref.noise) if res.ref is not None else 0.0
        if ref_noise > 0:
            ax.axhline(ref_noise, color="grey", ls=":", lw=0.9,
                       label=f"reference noise ({res.ref.spp} spp, subtracted)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("render time (s)")
        ax.set_ylabel("mean ΔE2000 vs colour-science" if chart else
                      ("trimmed relMSE vs reference" if res.title else "relMSE vs reference"))
        ax.set_title(f"{res.title or res.scene} ({res.size[0]}x{res.size[1]})", fontsize=9 if res.title else 10)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=6.5, loc="best")
    fig.suptitle(title, fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(path, dpi=100)
    plt.close(fig)


# ------------------------------------------------------------------------------------------


def parse_args(argv):
    p = argparse.ArgumentParser(description="Error against render time of the renderer's knobs "
                                            "(writes accuracy_cost.md, .png and .json).")
    p.add_argument("--program", type=Path, default=None,
                   help="the renderer (default $SPT_PATHTRACER, else build/pathtracer)")
    p.add_argument("--scenes", nargs="+", default=list(ALL_SCENES),
                   help="built-in scenes (default cornell cornell-point colorchecker prism); colorchecker is "
                        "scored in ΔE2000, any other scene in relMSE against its reference")
    p.add_argument("--threads", type=int, default=2, help="threads of every render (default 2)")
    p.add_argument("--plot-per-scene", action="store_true",
                   help="also write each panel of the plot as accuracy_cost_<i>.png, i in panel order")
    p.add_argument("--out", type=Path, default=None,
                   help="folder for accuracy_cost.md and accuracy_cost.png (default validation/results; "
                        "with --quick build/accuracy-quick, so a smoke test never replaces the committed results)")
    p.add_argument("--cache-dir", type=Path, default=REPO_ROOT / "build" / "accuracy-cache")
    p.add_argument("--run-tag", default="main",
                   help="points are cached per tag (references are shared): use a new tag for fresh timings")
    p.add_argument("--quick", action="store_true", help="tiny sizes for the smoke test")
    p.add_argument("--height", type=int,
                   help="image height of cornell, cornell-point, prism; the width follows each scene's aspect "
                        "(default 64; quick 24)")
    p.add_argument("--chart-height", type=int,
                   help="image height of colorchecker, width 3/2 of it (default 80; quick 40)")
    p.add_argument("--spp", type=int, nargs="+", help="spp sweep (default 4 16 64 256 1024; quick 4 16 64)")
    p.add_argument("--bins-spp", type=int, help="spp of the bins and depth points (default 256; quick 16)")
    p.add_argument("--depths", type=int, nargs="*", help="--max-depth values (default 1 2 4; quick 1 2)")
    p.add_argument("--reference-spp", type=int,
                   help="reference spp for every image scene (default: cornell, cornell-point 16384, prism 8192; "
                        "quick 512)")
    p.add_argument("--integrators", nargs="+", default=["path", "bdpt"],
                   help="integrators measured over the spp sweep on the image scenes (default path bdpt; the "
                        "other knobs use path)")
    p.add_argument("--reference-integrator",
                   help="integrator of every reference (default: bdpt for prism, whose caustic path tracing "
                        "finds only by chance, and cornell-point, whose caustic it cannot find; path for cornell)")
    p.add_argument("--seeds", type=int, default=1,
                   help="independent renders averaged per point on every scene (default 1)")
    p.add_argument("--noisy-scenes", nargs="*", default=list(NOISY_SCENES),
                   help="scenes whose single-render relMSE is heavy-tailed (default prism): they get "
                        "--noisy-seeds renders per point")
    p.add_argument("--noisy-seeds", type=int, nargs="+",
                   help="seeds per point on the noisy scenes, one count per --spp value in increasing order "
                        "(the last repeats; default 32 16 4 2 2; quick 3 2 2)")
    p.add_argument("--wavelengths-per-path", dest="wavelengths", type=int, nargs="+", default=[1, 4, 8],
                   help="wavelengths per path to compare (default 1 4 8; values the program rejects are "
                        "reported and skipped)")
    a = p.parse_args(argv)
    preset = QUICK if a.quick else FULL
    if a.out is None:
        a.out = REPO_ROOT / ("build/accuracy-quick" if a.quick else "validation/results")
    a.height = a.height or preset["height"]
    a.chart_height = a.chart_height or preset["chart_height"]
    a.spp = sorted(set(a.spp or preset["spp"]))
    a.bins_spp = a.bins_spp or preset["bins_spp"]
    a.depths = preset["depths"] if a.depths is None else a.depths
    a.noisy_seeds = a.noisy_seeds or preset["noisy_seeds"]
    if a.seeds < 1 or min(a.noisy_seeds) < 1:
        p.error("--seeds and --noisy-seeds: expected counts of at least 1")
    a.ref_spp = {s: a.reference_spp or preset["reference_spp"].get(s, preset["reference_spp"]["cornell"])
                 for s in a.scenes}
    if a.program is None:
        env = os.environ.get("SPT_PATHTRACER")
        a.program = Path(env).expanduser() if env else REPO_ROOT / "build" / "pathtracer"
    if a.bins_spp not in a.spp:
        p.error("--bins-spp must be one of the --spp values")
    a.scenes = list(dict.fromkeys(a.scenes))
    return a


def options_text(argv) -> str:
    """The command line's options for the report, without --program's path (the sha is given)."""
    words = list(sys.argv[1:] if argv is None else argv)
    shown = []
    skip = False
    for w in words:
        if skip:
            skip = False
            continue
        if w == "--program":
            skip = True
            continue
        if w.startswith("--program="):
            continue
        shown.append(w)
    return f"`{' '.join(shown)}`" if shown else "no options"


def main(argv=None) -> int:
    args = parse_args(argv)
    started = time.perf_counter()
    started_at = datetime.datetime.now().astimezone()
    load_start = os.getloadavg()
    src = args.program.resolve()
    if not src.is_file() or not os.access(src, os.X_OK):
        raise bm.BenchError(f"{src} is not an executable file; build it first")
    with tempfile.TemporaryDirectory(prefix="spt-accuracy-") as scratch_name:
        scratch = Path(scratch_name)
        program = bm.Program(scratch / "pathtracer", src)
        shutil.copy2(src, program.path)  # a private copy: a rebuild cannot mix two builds
        sha = bm.sha256_file(program.path)
        version = bm.program_version(program)
        cache = args.cache_dir / f"{bm.safe_name(version)}_{sha[:12]}"
        run_dir = cache / bm.safe_name(args.run_tag)
        run_dir.mkdir(parents=True, exist_ok=True)
        kept = cache / "pathtracer"  # so that the report can be remade from this cache after a rebuild
        if not kept.is_file():
            shutil.copy2(program.path, kept)
        ctx = Ctx(program, sha, version, args.threads, cache, run_dir, scratch)
        chart_scene = None
        if CHART_SCENE in args.scenes:
            # Render a snapshot of the scene file (not the built-in copy), so that the patch
            # regions projected from it always match the image even if the file is edited.
            ctx.chart_file = scratch / f"{CHART_SCENE}.json"
            shutil.copyfile(REPO_ROOT / "scenes" / f"{CHART_SCENE}.json", ctx.chart_file)
            ctx.chart_sha = bm.sha256_file(ctx.chart_file)
            chart_scene = json.loads(ctx.chart_file.read_text())

        machine = (f"{platform.node()}, os.cpu_count() = {os.cpu_count()} ({bm.usable_cpus()} usable), "
                   f"{bm.cpu_model()}, {platform.system()} {platform.release()}")
        say("accuracy against cost")
        say(f"  date     {started_at.isoformat(timespec='seconds')}")
        say(f"  machine  {machine}")
        say(f"  load     {', '.join(f'{v:.2f}' for v in load_start)} (1, 5, 15 min)")
        say(f"  program  {version}, sha256 {sha[:12]} ({src})")
        say(f"  cache    {run_dir}")

        wavelengths, unsupported = [], {}
        for k in dict.fromkeys(args.wavelengths):
            msg = None if k in (1, DEFAULT_WL) else probe(ctx, ["--wavelengths-per-path", str(k)])
            if msg is None:
                wavelengths.append(k)
            else:
                unsupported[f"--wavelengths-per-path {k}"] = msg
                say(f"  note: --wavelengths-per-path {k} is not supported by the program: {msg}")
        integrators = []
        for integ in dict.fromkeys(args.integrators):
            msg = None if integ == "path" else probe(ctx, ["--integrator", integ])
            if msg is None:
                integrators.append(integ)
            else:
                unsupported[f"--integrator {integ}"] = msg
                say(f"  note: --integrator {integ} is not supported by the program: {msg}")
        known = bm.list_scenes(program)
        if known is not None and any(s not in known for s in args.scenes):
            raise bm.BenchError(f"unknown scene(s) {[s for s in args.scenes if s not in known]}; "
                                f"the program has {', '.join(known)}")
        effects = {scene: scene_effects(ctx, scene) for scene in args.scenes}
        ref_integrator = {}
        for scene in args.scenes:
            want = args.reference_integrator or ("bdpt" if scene in BDPT_REFERENCE else "path")
            if want != "path" and probe(ctx, ["--integrator", want]) is not None:
                say(f"  note: reference of {scene}: --integrator {want} not supported, using path")
                want = "path"
            ref_integrator[scene] = want

        results: list[SceneResult] = []
        for scene in args.scenes:
            size = scene_size(scene, args)
            pts = plan(scene, args, wavelengths, integrators, effects[scene])
            # one render per distinct configuration (the default at --bins-spp is in several series)
            unique: dict[Config, Point] = {}
            say(f"{scene} ({size[0]}x{size[1]}, {len(pts)} points; effects: {', '.join(effects[scene]) or '?'})")
            res = SceneResult(scene, size, pts, chart_scene=chart_scene if scene == CHART_SCENE else None)
            if scene != CHART_SCENE:
                res.ref = reference(ctx, scene, size, args.ref_spp[scene], ref_integrator[scene])
                say(f"  reference: {res.ref.note}; its own noise {res.ref.noise:.3g} relMSE")
            # Render spp by spp, every knob at one spp in a row: a change of the machine's load then
            # shifts the points that are compared with each other (same spp) together, rather than
            # one whole series against another.
            order = sorted(range(len(pts)), key=lambda j: (pts[j].config.spp, j))
            for n, i in enumerate(order):
                p = pts[i]
                if p.config in unique:
                    q = unique[p.config]
                    p.time, p.paths_per_s, p.rays_per_s, p.load1, p.image, p.cached = (
                        q.time, q.paths_per_s, q.rays_per_s, q.load1, q.image, q.cached)
                    p.created = q.created  # p.wall stays NaN: one render, counted once
                    continue
                measure_point(ctx, p, size, f"  [{n + 1}/{len(pts)}]")
                unique[p.config] = p
            (evaluate_chart if scene == CHART_SCENE else evaluate_images)(res)
            res.points = aggregate(res.points)   # one point per configuration: the replicates' mean
            results.append(res)

        total = time.perf_counter() - started
        renders = [q for r in results for p in r.points for q in p.replicates]
        loads = [q.load1 for q in renders if math.isfinite(q.load1)]
        views = with_trimmed(results)
        read = reading(views, args)

        cached = sum(1 for q in renders if q.cached)
        walls = [q.wall for q in renders if math.isfinite(q.wall)]
        n_renders, points_wall = len(walls), sum(walls)
        refs_wall = sum(r.ref.wall for r in results if r.ref is not None)
        made = sorted(q.created for q in renders if q.created)
        first_made, last_made = (made[0], made[-1]) if made else ("?", "?")
        header = [
            "# Accuracy against cost",
            "",
            f"Generated by `validation/accuracy_cost.py` ({options_text(argv)}).",
            "",
            f"- date of the renders: {first_made[:10]} (this report: {started_at.isoformat(timespec='seconds')})",
            f"- machine: {machine}",
            "- load: 1-min load average when each point started "
            + (f"min {min(loads):.2f}, median {statistics.median(loads):.2f}, max {max(loads):.2f}" if loads else "—")
            + (f" on {bm.usable_cpus()} cores — the machine was shared, so times are inflated and noisy (±30 % "
               "between neighbouring points); compare within one run only"
               if loads and statistics.median(loads) > bm.usable_cpus() + 0.5 else "")
            + f"; at the start of this report {', '.join(f'{v:.2f}' for v in load_start)} (1, 5, 15 min)",
            f"- program: `{version}`, sha256 `{sha[:16]}`; every render `--threads {args.threads}`; "
            f"time = render time from the program's summary (start-up excluded); samples/s = paths/s "
            f"(one path carries 4 wavelengths by default)",
            "- sizes: " + ", ".join(f"{r.scene} {r.size[0]}x{r.size[1]}" for r in results)
            + (f" ({results[[r.scene for r in results].index(CHART_SCENE)].extra.get('pixels_per_patch')} pixels per patch averaged)"
               if CHART_SCENE in args.scenes else ""),
            f"- seeds: replicate r at N spp has seed {SEED_BASE} + N + {SEED_STRIDE} r; all knobs at one spp share "
            "the seed set (paired); a point is the mean of its replicates, ± its standard error: "
            + "; ".join(f"{r.scene} " + ", ".join(f"{n} spp × {seeds_at(r.scene, n, args)}" for n in args.spp)
                        for r in results),
            f"- renders: {n_renders} distinct points rendered {first_made} … {last_made}, "
            f"{points_wall:.0f} s of program wall time, plus {refs_wall:.0f} s for the references "
            f"(total {(points_wall + refs_wall) / 60:.1f} min); this report took {total:.0f} s, "
            f"{cached} of {len(renders)} renders from the cache (tag `{args.run_tag}`)",
        ]
        if unsupported:
            header.append("- not measured (the program rejects it): " + "; ".join(
                f"`{k}` ({m})" for k, m in unsupported.items()))
        header += ["", "## Error", "",
                   f"- image scenes: {bm.REL_MSE_FORMULA}, against a reference with `--spectral-bins exact`, "
                   "4 λ/path, dispersion on, rendered as two halves with seeds "
                   f"{REFERENCE_SEED} and {REFERENCE_SEED + 1}; the reference's own noise, mean((a−b)²/w)/4 of "
                   "its halves, is subtracted from every relMSE (the raw value is in the table):"]
        for r in results:
            if r.ref is not None:
                header.append(f"  - {r.scene}: reference {r.ref.note}, its noise {r.ref.noise:.3g} relMSE")
        header += [
            "- colorchecker: mean CIEDE2000 of the 24 patch averages against colour-science's exact chart under "
            "D65 (`color_accuracy.py`); the raw column holds the split-half noise estimate (ΔE); no reference render.",
            "- efficiency = 1/(relMSE·time), or 1/(ΔE²·time) for the chart.",
            "- A point with a knob not at its default has every other knob at its default "
            f"(16 bins, 4 λ/path, dispersion on, unbounded depth, spp {args.bins_spp} for bins and depth). "
            f"The 16-bin render at {args.bins_spp} (and {max(args.spp)}) spp appears in both the spp and the bins "
            "series: it is one render.",
            "",
        ]
        md = header + ["## Reading (automatic)", ""] + read + ["## All points", ""] + table(results) + [""]
        args.out.mkdir(parents=True, exist_ok=True)
        md_path, png_path = args.out / "accuracy_cost.md", args.out / "accuracy_cost.png"
        md_path.write_text("\n".join(md))
        (args.out / "accuracy_cost.json").write_text(json.dumps(summary(results), indent=1) + "\n")
        title = (f"Error vs render time — {version} ({sha[:8]}), {os.cpu_count()} cores {bm.cpu_model()}, "
                 f"--threads {args.threads}, {started_at.date().isoformat()}, median load "
                 f"{statistics.median(loads) if loads else math.nan:.1f}")
        ref_spps = sorted({r.ref.spp for r in results if r.ref is not None})
        notes = [
            "How to read",
            "",
            "• a point: mean over independent seeds, bar ± 1 s.e.",
            f"  ({', '.join(args.noisy_scenes)}: {'/'.join(map(str, args.noisy_seeds[:len(args.spp)]))} seeds at "
            f"{'/'.join(map(str, args.spp))} spp; others {args.seeds});",
            "  all knobs at one spp share the seed set",
            "• image scenes: relMSE against a reference (exact spectra,",
            f"  {'/'.join(map(str, ref_spps))} spp) minus the reference's own noise",
            "• colorchecker: mean ΔE2000 against colour-science",
            "• slope −1 (relMSE) or −½ (ΔE): pure noise; a flat tail: a bias floor",
            "• a point below a curve at the same time: a better knob setting",
            f"• trimmed: the worst {TRIM_FRACTION:.1%} of the pixels dropped",
            f"• times: --threads {args.threads}, render time from the program's summary;",
            f"  median load {statistics.median(loads) if loads else math.nan:.1f} on {bm.usable_cpus()} cores"
            + (": expect ±50 % between points" if loads and statistics.median(loads) > bm.usable_cpus() + 0.5 else ""),
            "",
            "Table, reading and caveats: validation/results/accuracy_cost.md",
        ]
        plot(views, args, png_path, title, notes)
        if args.plot_per_scene:  # one legible figure per panel (the report shows these)
            for i, view in enumerate(views):
                plot([view], args, args.out / f"accuracy_cost_{i}.png", "", [])
        say("")
        say("\n".join(read))
        say(f"wrote {md_path} and {png_path} in {total:.0f} s")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except bm.BenchError as e:
        print(f"accuracy_cost.py: error: {e}", file=sys.stderr)
        sys.exit(1)
    except KeyboardInterrupt:
        print("accuracy_cost.py: interrupted (rerun to continue from the cache)", file=sys.stderr)
        sys.exit(130)
