#!/usr/bin/env python3
"""Speed and noise benchmark of the pathtracer program.

For each scene it renders (or reuses from a cache) a high-spp reference image,
then times renders at a few thread counts and measures their error against the
reference:

    relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)
    efficiency = 1 / (relMSE * time)

and sweeps the sample count (error vs. time) to fit the log-log slope of
relMSE vs. spp, which is about -1 for an unbiased Monte Carlo renderer.

This is a measurement, not a test: it exits non-zero only when something goes
wrong (the program fails, prints no summary, writes a bad image, ...), never
because the numbers are slow.

    bash validation/setup_venv.sh
    .venv/bin/python validation/benchmark.py --quick      # smoke test, ~1 min
    .venv/bin/python validation/benchmark.py              # full run

See validation/README.md ("Benchmark") for what is measured and how.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent

REL_MSE_EPS = 1e-2
REL_MSE_FORMULA = "relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)"

# Seeds. Repeat r of a measured render uses MEASURE_SEED_BASE + r (the same
# seeds for every thread count, so thread counts render comparable images);
# the spp sweep uses its own seeds per spp so the points are independent; the
# reference uses a seed no measured render uses.
MEASURE_SEED_BASE = 1
SWEEP_SEED_BASE = 1000
REFERENCE_SEED = 987654321

QUICK = {"size": 64, "spp": 16, "reference_spp": 1024}
DEFAULTS = {"size": 256, "spp": 64, "reference_spp": 16384}

SUMMARY_RE = re.compile(
    r"^\s*time\s+(?P<time>\S+)\s+s,\s+(?P<paths>\S+)\s+paths/s,\s+(?P<rays>\S+)\s+rays/s",
    re.MULTILINE,
)


class BenchError(Exception):
    """A failure that makes the benchmark meaningless (exit status 1)."""


def say(*args: object) -> None:
    print(*args, flush=True)


# --------------------------------------------------------------------------
# Images


def read_pfm(path: Path) -> np.ndarray:
    """Read a colour PFM ("PF") file; returns float64 (height, width, 3), top row first."""
    data = path.read_bytes()
    # Header: three whitespace-separated tokens, then exactly one whitespace byte.
    tokens: list[bytes] = []
    pos = 0
    while len(tokens) < 4:
        while pos < len(data) and data[pos : pos + 1].isspace():
            pos += 1
        start = pos
        while pos < len(data) and not data[pos : pos + 1].isspace():
            pos += 1
        if start == pos:
            raise BenchError(f"{path}: truncated PFM header")
        tokens.append(data[start:pos])
    pos += 1  # the single whitespace byte after the scale
    magic, w_tok, h_tok, scale_tok = tokens
    if magic != b"PF":
        raise BenchError(f"{path}: not a colour PFM file (magic {magic!r})")
    try:
        width, height, scale = int(w_tok), int(h_tok), float(scale_tok)
    except ValueError as e:
        raise BenchError(f"{path}: bad PFM header: {e}") from None
    if width <= 0 or height <= 0 or scale == 0 or not math.isfinite(scale):
        raise BenchError(f"{path}: bad PFM header ({width} x {height}, scale {scale})")
    dtype = "<f4" if scale < 0 else ">f4"
    count = width * height * 3
    if len(data) - pos != count * 4:
        raise BenchError(f"{path}: {len(data) - pos} bytes of pixels, expected {count * 4} for {width}x{height}")
    img = np.frombuffer(data, dtype=dtype, count=count, offset=pos).reshape(height, width, 3)
    return img[::-1].astype(np.float64)  # PFM rows go bottom to top


def rel_mse(img: np.ndarray, ref: np.ndarray) -> float:
    if img.shape != ref.shape:
        raise BenchError(f"image shape {img.shape} differs from reference shape {ref.shape}")
    return float(np.mean((img - ref) ** 2 / (ref * ref + REL_MSE_EPS)))


def check_image(img: np.ndarray, path: Path, size: int) -> None:
    if img.shape != (size, size, 3):
        raise BenchError(f"{path}: image is {img.shape[1]}x{img.shape[0]}, expected {size}x{size}")
    if not np.all(np.isfinite(img)):
        raise BenchError(f"{path}: image has {int(np.sum(~np.isfinite(img)))} non-finite values")


# --------------------------------------------------------------------------
# Running the program


@dataclass
class Run:
    time: float  # render time, s (see run_render for the precision)
    paths_per_s: float
    rays_per_s: float
    wall: float  # wall-clock time of the whole process, s
    image: np.ndarray


_warned_time = False


def parse_summary(stderr: str, n_paths: int, cmd_text: str) -> tuple[float, float, float]:
    """(time, paths/s, rays/s) from the summary the program prints on stderr.

    The summary prints the time with 2 decimals (+-5 ms) but paths/s with 3
    significant digits (+-0.5 %), so for renders under 1 s the time is taken
    as paths / (paths/s) when that agrees with the printed time.
    """
    global _warned_time
    m = SUMMARY_RE.search(stderr)
    if not m:
        tail = "\n".join(stderr.strip().splitlines()[-10:])
        raise BenchError(f"no 'time ... s, ... paths/s, ... rays/s' line in the output of\n  {cmd_text}\nstderr ends:\n{tail}")
    try:
        t, paths_s, rays_s = (float(m.group(k)) for k in ("time", "paths", "rays"))
    except ValueError:
        raise BenchError(f"cannot parse the summary line {m.group(0).strip()!r}") from None
    if not all(math.isfinite(v) and v >= 0 for v in (t, paths_s, rays_s)) or paths_s == 0:
        raise BenchError(f"implausible summary line {m.group(0).strip()!r}")
    derived = n_paths / paths_s
    if t < 1.0:
        if abs(derived - t) <= 0.0051 + 0.006 * derived:
            t = derived
        elif not _warned_time:
            _warned_time = True
            say(f"  note: paths/s x time != width*height*spp ({m.group(0).strip()!r}); using the printed time")
    if t <= 0:
        raise BenchError(f"render time is 0 in {m.group(0).strip()!r}; use a larger --size or --spp")
    return t, paths_s, rays_s


@dataclass
class Program:
    path: Path  # the private copy that is run
    shown: Path  # the path the user gave, for messages


def run_render(program: Program, scene: str, size: int, spp: int, threads: int, seed: int, out: Path) -> Run:
    cmd = [str(program.path), scene, "--spp", str(spp), "--width", str(size), "--height", str(size),
           "-o", str(out), "--threads", str(threads), "--seed", str(seed)]
    cmd_text = " ".join([str(program.shown)] + cmd[1:])
    if out.exists():
        out.unlink()
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, errors="replace", stdin=subprocess.DEVNULL)
    except OSError as e:
        raise BenchError(f"cannot run {cmd_text}: {e}") from None
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        tail = "\n".join(proc.stderr.strip().splitlines()[-10:])
        raise BenchError(f"{cmd_text}\nexited with status {proc.returncode}; stderr ends:\n{tail}")
    t, paths_s, rays_s = parse_summary(proc.stderr, size * size * spp, cmd_text)
    if not out.is_file():
        raise BenchError(f"{cmd_text}\ndid not write {out}")
    img = read_pfm(out)
    check_image(img, out, size)
    return Run(t, paths_s, rays_s, wall, img)


def program_version(program: Program) -> str:
    try:
        proc = subprocess.run([str(program.path), "--version"], capture_output=True, text=True,
                              errors="replace", stdin=subprocess.DEVNULL, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise BenchError(f"cannot run {program.shown} --version: {e}") from None
    version = proc.stdout.strip() or proc.stderr.strip()
    if proc.returncode != 0 or not version:
        raise BenchError(f"{program.shown} --version failed (status {proc.returncode}): {version[:200]!r}")
    return version.splitlines()[0]


def list_scenes(program: Program) -> list[str] | None:
    try:
        proc = subprocess.run([str(program.path), "--list-scenes"], capture_output=True, text=True,
                              errors="replace", stdin=subprocess.DEVNULL, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return None
    if proc.returncode != 0:
        return None
    return proc.stdout.split()


def sha256_file(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


# --------------------------------------------------------------------------
# Machine description


def cpu_model() -> str:
    try:
        text = Path("/proc/cpuinfo").read_text(errors="replace")
    except OSError:
        text = ""
    for key in ("model name", "Model", "Hardware", "cpu model", "Processor"):
        m = re.search(rf"^{re.escape(key)}\s*:\s*(.+)$", text, re.MULTILINE)
        if m and m.group(1).strip():
            return m.group(1).strip()
    return platform.processor() or platform.machine() or "unknown"


def usable_cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


# --------------------------------------------------------------------------
# Reference images


def safe_name(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._+-]+", "_", text).strip("_") or "x"


def reference_image(program: Program, version: str, binary_sha: str, scene: str, size: int, spp: int,
                    cache_dir: Path, threads: int, scratch: Path) -> np.ndarray:
    stem = f"ref_{safe_name(scene)}_{size}x{size}_{spp}spp_seed{REFERENCE_SEED}_{safe_name(version)}"
    pfm = cache_dir / f"{stem}.pfm"
    meta_path = cache_dir / f"{stem}.json"
    if pfm.is_file():
        try:
            img = read_pfm(pfm)
            check_image(img, pfm, size)
        except BenchError as e:
            say(f"  {scene}: cached reference unusable ({e}); rendering it again")
        else:
            meta = {}
            try:
                meta = json.loads(meta_path.read_text())
            except (OSError, ValueError):
                pass
            made = meta.get("created", "?")
            took = meta.get("render_time_s")
            took_text = f", took {took:.1f} s to render" if isinstance(took, (int, float)) else ""
            say(f"  {scene}: reusing reference {pfm} (made {made}{took_text})")
            if meta.get("binary_sha256") not in (None, binary_sha):
                say(f"  {scene}: note: that reference was made by a different build of '{version}' "
                    f"(sha256 {str(meta.get('binary_sha256'))[:12]}); delete it if the image should have changed")
            return img

    say(f"  {scene}: rendering reference, {size}x{size}, {spp} spp, {threads} thread(s), seed {REFERENCE_SEED} ...")
    cache_dir.mkdir(parents=True, exist_ok=True)
    tmp = scratch / f"{stem}.pfm"
    run = run_render(program, scene, size, spp, threads, REFERENCE_SEED, tmp)
    meta = {
        "scene": scene, "width": size, "height": size, "spp": spp, "seed": REFERENCE_SEED,
        "threads": threads, "program_version": version, "binary_sha256": binary_sha,
        "render_time_s": run.time, "wall_time_s": run.wall, "paths_per_s": run.paths_per_s,
        "rays_per_s": run.rays_per_s,
        "created": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
    }
    # Copy then rename, so an interrupted run never leaves a half-written reference.
    part = cache_dir / f"{stem}.pfm.part"
    shutil.copyfile(tmp, part)
    os.replace(part, pfm)
    meta_path.write_text(json.dumps(meta, indent=2) + "\n")
    say(f"  {scene}: reference made in {run.time:.1f} s render time ({run.wall:.1f} s wall, "
        f"{run.paths_per_s:.3g} paths/s) -> {pfm}")
    return run.image


# --------------------------------------------------------------------------
# Measurements


@dataclass
class Measurement:
    times: list[float]
    paths_per_s: list[float]
    rays_per_s: list[float]
    rel_mses: list[float]

    @property
    def time_median(self) -> float:
        return statistics.median(self.times)

    @property
    def rel_mse(self) -> float:
        return statistics.fmean(self.rel_mses)

    @property
    def efficiency(self) -> float:
        return 1.0 / (self.rel_mse * self.time_median) if self.rel_mse > 0 else math.inf


def measure(program: Program, scene: str, size: int, spp: int, threads: int, seeds: list[int],
            ref: np.ndarray, scratch: Path) -> Measurement:
    m = Measurement([], [], [], [])
    out = scratch / "render.pfm"
    for seed in seeds:
        run = run_render(program, scene, size, spp, threads, seed, out)
        m.times.append(run.time)
        m.paths_per_s.append(run.paths_per_s)
        m.rays_per_s.append(run.rays_per_s)
        m.rel_mses.append(rel_mse(run.image, ref))
    return m


def fmt_table(headers: list[str], rows: list[list[str]], indent: str = "  ") -> str:
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(headers)]
    lines = [indent + "  ".join(h.rjust(w) for h, w in zip(headers, widths)),
             indent + "  ".join("-" * w for w in widths)]
    lines += [indent + "  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in rows]
    return "\n".join(lines)


def loglog_slope(x: list[float], y: list[float]) -> float | None:
    pts = [(math.log(a), math.log(b)) for a, b in zip(x, y) if a > 0 and b > 0]
    if len(pts) < 2 or len({p[0] for p in pts}) < 2:
        return None
    lx, ly = np.array(pts).T
    return float(np.polyfit(lx, ly, 1)[0])


# --------------------------------------------------------------------------


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(
        description="Time the pathtracer and measure its error against a high-spp reference "
                    "(a measurement, not a test: exits non-zero only on errors).")
    p.add_argument("--program", type=Path, default=None,
                   help="the renderer (default: $SPT_PATHTRACER, else <repo>/build/pathtracer)")
    p.add_argument("--scenes", nargs="+", default=["cornell", "cornell-point"], help="built-in scenes")
    p.add_argument("--size", type=int, default=None,
                   help=f"image width and height (default {DEFAULTS['size']}; --quick: {QUICK['size']})")
    p.add_argument("--spp", type=int, default=None,
                   help=f"samples per pixel of the timed renders (default {DEFAULTS['spp']}; --quick: {QUICK['spp']})")
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts to time (default 1 2)")
    p.add_argument("--reference-spp", type=int, default=None,
                   help=f"samples per pixel of the reference (default {DEFAULTS['reference_spp']}; "
                        f"--quick: {QUICK['reference_spp']})")
    p.add_argument("--cache-dir", type=Path, default=None,
                   help="where references are kept (default <repo>/build/bench-cache)")
    p.add_argument("--repeats", type=int, default=3,
                   help="runs per configuration; the table shows median and best (default 3)")
    p.add_argument("--sweep-spp", type=int, nargs="+", default=[4, 16, 64, 256],
                   help="spp values of the error-vs-time sweep (default 4 16 64 256)")
    p.add_argument("--sweep-threads", type=int, default=2, help="threads of the sweep (default 2)")
    p.add_argument("--quick", action="store_true",
                   help=f"smoke-test settings: {QUICK['size']}x{QUICK['size']}, {QUICK['spp']} spp, "
                        f"reference {QUICK['reference_spp']} spp (explicit options still win)")
    a = p.parse_args(argv)
    preset = QUICK if a.quick else DEFAULTS
    for key, value in preset.items():
        if getattr(a, key) is None:
            setattr(a, key, value)
    if a.program is None:
        env = os.environ.get("SPT_PATHTRACER")
        a.program = Path(env).expanduser() if env else REPO_ROOT / "build" / "pathtracer"
    if a.cache_dir is None:
        a.cache_dir = REPO_ROOT / "build" / "bench-cache"
    for name in ("size", "spp", "reference_spp", "repeats", "sweep_threads"):
        if getattr(a, name) < 1:
            p.error(f"--{name.replace('_', '-')} must be at least 1")
    for name in ("threads", "sweep_spp"):
        if any(v < 1 for v in getattr(a, name)):
            p.error(f"--{name.replace('_', '-')} values must be at least 1")
    a.threads = list(dict.fromkeys(a.threads))
    a.sweep_spp = sorted(set(a.sweep_spp))
    a.scenes = list(dict.fromkeys(a.scenes))
    return a


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    started = time.perf_counter()
    program_src = args.program.resolve()
    if not program_src.is_file() or not os.access(program_src, os.X_OK):
        raise BenchError(f"{program_src} is not an executable file; build it with\n"
                         "  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build -j2")

    with tempfile.TemporaryDirectory(prefix="spt-bench-") as scratch_name:
        scratch = Path(scratch_name)
        # Run a private copy, so a rebuild of the program during the benchmark
        # cannot mix two builds in one set of numbers.
        program = Program(scratch / "pathtracer", program_src)
        shutil.copy2(program_src, program.path)
        binary_sha = sha256_file(program.path)
        version = program_version(program)
        known = list_scenes(program)
        if known is not None:
            unknown = [s for s in args.scenes if s not in known]
            if unknown:
                raise BenchError(f"unknown scene(s) {', '.join(unknown)}; the program has: {', '.join(known)}")

        cpus = usable_cpus()
        say("pathtracer benchmark")
        say(f"  date      {datetime.datetime.now().astimezone().isoformat(timespec='seconds')}")
        say(f"  machine   {platform.node()}, {os.cpu_count()} cores ({cpus} usable), {cpu_model()}")
        try:
            load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
            say(f"  load avg  {load} (1, 5, 15 min, at start)")
        except OSError:
            pass
        say(f"  program   {version} ({program_src}, sha256 {binary_sha[:12]})")
        say(f"  python    {platform.python_version()}, numpy {np.__version__}")
        say(f"  settings  {args.size}x{args.size}, {args.spp} spp, threads {' '.join(map(str, args.threads))}, "
            f"{args.repeats} repeat(s), reference {args.reference_spp} spp, scenes {' '.join(args.scenes)}"
            + (" (--quick)" if args.quick else ""))
        too_many = [t for t in args.threads + [args.sweep_threads] if t > cpus]
        if too_many:
            say(f"  note: thread count(s) {', '.join(map(str, sorted(set(too_many))))} exceed the {cpus} usable cores")
        say(f"  error     {REL_MSE_FORMULA}")
        say("            efficiency = 1 / (relMSE * median time)")
        say(f"            repeat r uses seed {MEASURE_SEED_BASE}+r (same seeds for every thread count); "
            "relMSE is the mean over the repeats")
        say("")

        say(f"References ({args.reference_spp} spp, {cpus} threads, cache {args.cache_dir})")
        refs = {}
        for scene in args.scenes:
            refs[scene] = reference_image(program, version, binary_sha, scene, args.size, args.reference_spp,
                                          args.cache_dir, cpus, scratch)
        say("")

        say(f"Timings ({args.size}x{args.size}, {args.spp} spp, {args.repeats} run(s) each; "
            "time is the render time the program reports; best = min time / max rate)")
        headers = ["scene", "threads", "spp", "time med", "time best", "paths/s med", "paths/s best",
                   "rays/s med", "rays/s best", "relMSE", "efficiency"]
        rows = []
        seeds = [MEASURE_SEED_BASE + r for r in range(args.repeats)]
        for scene in args.scenes:
            for threads in args.threads:
                m = measure(program, scene, args.size, args.spp, threads, seeds, refs[scene], scratch)
                rows.append([scene, str(threads), str(args.spp),
                             f"{m.time_median:.3f}", f"{min(m.times):.3f}",
                             f"{statistics.median(m.paths_per_s):.3g}", f"{max(m.paths_per_s):.3g}",
                             f"{statistics.median(m.rays_per_s):.3g}", f"{max(m.rays_per_s):.3g}",
                             f"{m.rel_mse:.4g}", f"{m.efficiency:.4g}"])
                say(f"  ... {scene}, {threads} thread(s): {m.time_median:.3f} s, relMSE {m.rel_mse:.4g}")
        say("  (time in s, efficiency in 1/s)")
        say(fmt_table(headers, rows))
        say("")

        say(f"Error vs. time ({args.size}x{args.size}, {args.sweep_threads} threads, {args.repeats} run(s) per spp, "
            f"reference {args.reference_spp} spp)")
        say("  ref share = spp/(spp+ref spp): the part of relMSE expected from the reference's own noise;")
        say("  'corrected' slope fits relMSE * (1 - ref share)")
        for scene in args.scenes:
            rows = []
            spps, errs, corrected = [], [], []
            for i, spp in enumerate(args.sweep_spp):
                sweep_seeds = [SWEEP_SEED_BASE + 100 * i + r for r in range(args.repeats)]
                m = measure(program, scene, args.size, spp, args.sweep_threads, sweep_seeds, refs[scene], scratch)
                share = spp / (spp + args.reference_spp)
                spps.append(spp)
                errs.append(m.rel_mse)
                corrected.append(m.rel_mse * (1 - share))
                rows.append([str(spp), f"{m.time_median:.3f}", f"{min(m.times):.3f}", f"{m.rel_mse:.4g}",
                             f"{m.rel_mse * spp:.4g}", f"{share:.3f}", f"{m.efficiency:.4g}"])
            say(f"  {scene}")
            say(fmt_table(["spp", "time med", "time best", "relMSE", "relMSE*spp", "ref share", "efficiency"],
                          rows, indent="    "))
            slope = loglog_slope(spps, errs)
            slope_c = loglog_slope(spps, corrected)
            if slope is None:
                say("    slope: needs at least two spp values")
            else:
                say(f"    log-log slope of relMSE vs spp: {slope:.3f} (corrected {slope_c:.3f}; expected about -1)")
        say("")
        say(f"done in {time.perf_counter() - started:.0f} s")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except BenchError as e:
        print(f"benchmark.py: error: {e}", file=sys.stderr)
        sys.exit(1)
    except KeyboardInterrupt:
        print("benchmark.py: interrupted", file=sys.stderr)
        sys.exit(130)
