#!/usr/bin/env python3
"""Speed and noise benchmark of the pathtracer program.

For each scene it renders (or reuses from a cache) a high-spp reference image,
then times renders at a few thread counts and measures their error against the
reference:

    relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2)
    efficiency = 1 / (relMSE * time)

and sweeps the sample count (error vs. time) to fit the log-log slope of
relMSE vs. spp, which is about -1 for an unbiased Monte Carlo renderer.

With --baseline OTHER_PROGRAM ("before") each scene is timed with both programs
in interleaved runs (before, after, before, after, ...; same spp, same seeds)
and the table shows both side by side with the ratios after/before. A scene's
reference may be rendered by another integrator (bdpt for the scenes lit by
small area lights, which plain path tracing barely finds) and by another
program (default: the baseline when given), and is made of two half-spp
renders whose difference estimates the reference's own relMSE.

This is a measurement, not a test: it exits non-zero only when something goes
wrong (the program fails, prints no summary, writes a bad image, ...), never
because the numbers are slow.

    bash validation/setup_venv.sh
    .venv/bin/python validation/benchmark.py --quick      # smoke test, ~1 min
    .venv/bin/python validation/benchmark.py              # full run
    .venv/bin/python validation/benchmark.py --baseline /path/to/old/pathtracer   # before/after

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
from pfm import read_pfm  # noqa: F401  (other tools use bm.read_pfm)

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

# cornell-sphere and cornell-quad are scenes/*.json files (issue 13): a program
# that does not have them built in is given the file.
DEFAULT_SCENES = ["cornell", "cornell-point", "cornell-sphere", "cornell-quad"]
# The reference's integrator per scene (others: path). The small area lights of
# these two are found only by hitting them with path tracing (before issue 13);
# bdpt samples them, so its reference converges much faster (at 64 spp on
# cornell-sphere: relMSE about 0.06 per image against about 4 for path).
DEFAULT_REFERENCE_INTEGRATOR = {"cornell-sphere": "bdpt", "cornell-quad": "bdpt"}

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


def run_render(program: Program, scene: str, size: int, spp: int, threads: int, seed: int, out: Path,
               extra: tuple[str, ...] = ()) -> Run:
    """scene: a built-in name or a scene file; extra: more options (e.g. --integrator bdpt)."""
    cmd = [str(program.path), scene, "--spp", str(spp), "--width", str(size), "--height", str(size),
           "-o", str(out), "--threads", str(threads), "--seed", str(seed), *extra]
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


def write_pfm(path: Path, img: np.ndarray) -> None:
    """Write float64 (height, width, 3), top row first, as a little-endian colour PFM."""
    h, w, _ = img.shape
    data = np.ascontiguousarray(img[::-1], dtype="<f4").tobytes()
    path.write_bytes(f"PF\n{w} {h}\n-1.0\n".encode() + data)


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


@dataclass
class Reference:
    image: np.ndarray
    integrator: str
    spp: int
    rel_mse: float  # the reference's own estimated relMSE (nan if unknown)
    shown: str  # the program that rendered it, for messages


def reference_image(program: Program, version: str, binary_sha: str, scene: str, scene_arg: str,
                    integrator: str, size: int, spp: int, cache_dir: Path, threads: int,
                    scratch: Path) -> Reference:
    """The reference of one scene: the spp-weighted mean of two renders of spp/2 (seeds
    REFERENCE_SEED and REFERENCE_SEED+1) by `integrator` of `program`, cached under a name
    holding the scene, size, spp, integrator, seed, version and the binary's sha256.

    Its own relMSE is estimated from the two halves a, b (n_a + n_b = spp paths per pixel):
    E[(a-b)^2] = s^2 (1/n_a + 1/n_b) and the mean's variance is s^2/spp, so
    relMSE(ref) ~ mean((a-b)^2/(ref^2 + eps)) * n_a*n_b/spp^2 (a quarter for equal halves)."""
    stem = (f"ref_{safe_name(scene)}_{size}x{size}_{spp}spp_{safe_name(integrator)}_seed{REFERENCE_SEED}"
            f"_{safe_name(version)}_{binary_sha[:12]}")
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
            noise = meta.get("reference_rel_mse")
            noise = float(noise) if isinstance(noise, (int, float)) else math.nan
            say(f"  {scene}: reusing reference {pfm} (made {made}{took_text}); own relMSE ~ {noise:.3g}")
            return Reference(img, integrator, spp, noise, str(program.shown))

    if spp < 2:
        raise BenchError("--reference-spp must be at least 2 (the reference is two half-spp renders)")
    halves = [(spp // 2, REFERENCE_SEED), (spp - spp // 2, REFERENCE_SEED + 1)]
    say(f"  {scene}: rendering reference, {size}x{size}, {spp} spp ({halves[0][0]} + {halves[1][0]}, "
        f"seeds {REFERENCE_SEED} and {REFERENCE_SEED + 1}), --integrator {integrator}, {threads} thread(s), "
        f"{program.shown} ...")
    cache_dir.mkdir(parents=True, exist_ok=True)
    runs = []
    for i, (n, seed) in enumerate(halves):
        runs.append(run_render(program, scene_arg, size, n, threads, seed, scratch / f"{stem}_{i}.pfm",
                               ("--integrator", integrator)))
    (na, _), (nb, _) = halves
    a, b = runs[0].image, runs[1].image
    img = (a * na + b * nb) / spp
    noise = float(np.mean((a - b) ** 2 / (img * img + REL_MSE_EPS))) * na * nb / (spp * spp)
    render_time = sum(r.time for r in runs)
    wall = sum(r.wall for r in runs)
    meta = {
        "scene": scene, "scene_argument": scene_arg, "width": size, "height": size, "spp": spp,
        "integrator": integrator, "halves": [{"spp": n, "seed": seed} for n, seed in halves],
        "reference_rel_mse": noise,
        "reference_rel_mse_note": "mean((a-b)^2/(ref^2+1e-2)) * n_a*n_b/spp^2, a and b the two halves",
        "threads": threads, "program": str(program.shown), "program_version": version, "binary_sha256": binary_sha,
        "render_time_s": render_time, "wall_time_s": wall, "paths_per_s": size * size * spp / render_time,
        "created": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
    }
    # Write then rename, so an interrupted run never leaves a half-written reference.
    part = cache_dir / f"{stem}.pfm.part"
    write_pfm(part, img)
    os.replace(part, pfm)
    meta_path.write_text(json.dumps(meta, indent=2) + "\n")
    say(f"  {scene}: reference made in {render_time:.1f} s render time ({wall:.1f} s wall, "
        f"{size * size * spp / render_time:.3g} paths/s), own relMSE ~ {noise:.3g} -> {pfm}")
    return Reference(read_pfm(pfm), integrator, spp, noise, str(program.shown))


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
    return measure_interleaved([program], scene, size, spp, threads, seeds, ref, scratch)[0]


def measure_interleaved(programs: list[Program], scene: str, size: int, spp: int, threads: int,
                        seeds: list[int], ref: np.ndarray, scratch: Path) -> list[Measurement]:
    """Each seed renders with every program in turn (A B A B ...), so slow drifts of the
    machine's load affect both alike."""
    ms = [Measurement([], [], [], []) for _ in programs]
    out = scratch / "render.pfm"
    for seed in seeds:
        for program, m in zip(programs, ms):
            run = run_render(program, scene, size, spp, threads, seed, out)
            m.times.append(run.time)
            m.paths_per_s.append(run.paths_per_s)
            m.rays_per_s.append(run.rays_per_s)
            m.rel_mses.append(rel_mse(run.image, ref))
    return ms


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


def per_scene(values: list[str], option: str, convert, default) -> tuple[object, dict[str, object]]:
    """'VALUE' sets the default, 'SCENE=VALUE' one scene's value."""
    scenes: dict[str, object] = {}
    for v in values:
        name, eq, val = v.rpartition("=")
        try:
            converted = convert(val)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{option}: bad value {v!r}") from None
        if eq:
            scenes[name] = converted
        else:
            default = converted
    return default, scenes


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(
        description="Time the pathtracer and measure its error against a high-spp reference "
                    "(a measurement, not a test: exits non-zero only on errors).")
    p.add_argument("--program", type=Path, default=None,
                   help="the renderer (\"after\" with --baseline; default: $SPT_PATHTRACER, else "
                        "<repo>/build/pathtracer)")
    p.add_argument("--baseline", type=Path, default=None, metavar="PATH",
                   help="a second pathtracer (\"before\"): each scene is timed with both in interleaved runs "
                        "at equal spp, printed side by side with the ratios after/before")
    p.add_argument("--scenes", nargs="+", default=list(DEFAULT_SCENES),
                   help="built-in scenes, or scene files; a name the programs do not have built in is "
                        f"taken from <repo>/scenes/NAME.json (default {' '.join(DEFAULT_SCENES)})")
    p.add_argument("--size", type=int, default=None,
                   help=f"image width and height (default {DEFAULTS['size']}; --quick: {QUICK['size']})")
    p.add_argument("--spp", type=int, default=None,
                   help=f"samples per pixel of the timed renders (default {DEFAULTS['spp']}; --quick: {QUICK['spp']})")
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts to time (default 1 2)")
    p.add_argument("--reference-spp", nargs="+", default=None, metavar="[SCENE=]N",
                   help=f"samples per pixel of the references: N for every scene, SCENE=N for one "
                        f"(default {DEFAULTS['reference_spp']}; --quick: {QUICK['reference_spp']})")
    p.add_argument("--reference-integrator", nargs="+", default=[], metavar="[SCENE=]NAME",
                   help="integrator of the references (path, bdpt, vcm): NAME for every scene, SCENE=NAME for "
                        "one (default path, and bdpt for "
                        + ", ".join(sorted(DEFAULT_REFERENCE_INTEGRATOR)) + ")")
    p.add_argument("--reference-program", type=Path, default=None, metavar="PATH",
                   help="the program that renders the references (default: --baseline if given, else --program); "
                        "its sha256 is part of the cache key")
    p.add_argument("--references-only", action="store_true",
                   help="make (or check) the references, then stop")
    p.add_argument("--cache-dir", type=Path, default=None,
                   help="where references are kept (default <repo>/build/bench-cache)")
    p.add_argument("--repeats", type=int, default=3,
                   help="runs per configuration; the table shows median and best (default 3)")
    p.add_argument("--sweep-spp", type=int, nargs="*", default=[4, 16, 64, 256],
                   help="spp values of the error-vs-time sweep (default 4 16 64 256; none: no sweep)")
    p.add_argument("--sweep-threads", type=int, default=2, help="threads of the sweep (default 2)")
    p.add_argument("--quick", action="store_true",
                   help=f"smoke-test settings: {QUICK['size']}x{QUICK['size']}, {QUICK['spp']} spp, "
                        f"reference {QUICK['reference_spp']} spp (explicit options still win)")
    a = p.parse_args(argv)
    preset = QUICK if a.quick else DEFAULTS
    for key in ("size", "spp"):
        if getattr(a, key) is None:
            setattr(a, key, preset[key])
    try:
        a.reference_spp_default, a.reference_spp_scene = per_scene(
            a.reference_spp or [], "--reference-spp", int, preset["reference_spp"])
        a.reference_integrator_default, a.reference_integrator_scene = per_scene(
            a.reference_integrator, "--reference-integrator", str, None)
    except argparse.ArgumentTypeError as e:
        p.error(str(e))
    if a.program is None:
        env = os.environ.get("SPT_PATHTRACER")
        a.program = Path(env).expanduser() if env else REPO_ROOT / "build" / "pathtracer"
    if a.reference_program is None:
        a.reference_program = a.baseline if a.baseline is not None else a.program
    if a.cache_dir is None:
        a.cache_dir = REPO_ROOT / "build" / "bench-cache"
    for name in ("size", "spp", "repeats", "sweep_threads"):
        if getattr(a, name) < 1:
            p.error(f"--{name.replace('_', '-')} must be at least 1")
    for name in ("threads", "sweep_spp"):
        if any(v < 1 for v in getattr(a, name)):
            p.error(f"--{name.replace('_', '-')} values must be at least 1")
    if any(v < 2 for v in [a.reference_spp_default, *a.reference_spp_scene.values()]):
        p.error("--reference-spp values must be at least 2 (two half-spp renders)")
    a.threads = list(dict.fromkeys(a.threads))
    a.sweep_spp = sorted(set(a.sweep_spp))
    a.scenes = list(dict.fromkeys(a.scenes))
    return a


def prepare_program(src: Path, scratch: Path, label: str) -> tuple[Program, str, str, list[str] | None]:
    """A private copy of the program (a rebuild during the benchmark cannot mix two builds in
    one set of numbers), its version, sha256 and built-in scenes."""
    src = src.resolve()
    if not src.is_file() or not os.access(src, os.X_OK):
        raise BenchError(f"{src} is not an executable file; build it with\n"
                         "  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release && cmake --build build -j2")
    program = Program(scratch / f"pathtracer-{label}", src)
    shutil.copy2(src, program.path)
    return program, program_version(program), sha256_file(program.path), list_scenes(program)


def resolve_scene(scene: str, known_lists: list[list[str] | None]) -> tuple[str, str]:
    """(name, argument): the name if every program has it built in, else a scene file
    (given as a path, or <repo>/scenes/NAME.json), passed to every program."""
    path = Path(scene)
    if scene.endswith(".json"):
        if not path.is_file():
            raise BenchError(f"scene file {scene} does not exist")
        return path.stem, str(path.resolve())
    if all(known is None or scene in known for known in known_lists):
        return scene, scene
    file = REPO_ROOT / "scenes" / f"{scene}.json"
    if file.is_file():
        return scene, str(file)
    have = sorted(set.intersection(*(set(k) for k in known_lists if k is not None)))
    raise BenchError(f"unknown scene {scene}: not built into every program and no {file}; "
                     f"built in: {', '.join(have)}")


def ratio(after: float, before: float) -> str:
    if before == 0 or not math.isfinite(before) or not math.isfinite(after):
        return "-"
    return f"{after / before:.3g}"


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    started = time.perf_counter()

    with tempfile.TemporaryDirectory(prefix="spt-bench-") as scratch_name:
        scratch = Path(scratch_name)
        program, version, binary_sha, known = prepare_program(args.program, scratch, "program")
        baseline = None
        if args.baseline is not None:
            baseline, base_version, base_sha, base_known = prepare_program(args.baseline, scratch, "baseline")
        ref_src = args.reference_program.resolve()
        if baseline is not None and ref_src == baseline.shown:
            ref_program, ref_version, ref_sha = baseline, base_version, base_sha
        elif ref_src == program.shown:
            ref_program, ref_version, ref_sha = program, version, binary_sha
        else:
            ref_program, ref_version, ref_sha, _ = prepare_program(ref_src, scratch, "reference")
        known_lists = [known] + ([base_known] if baseline is not None else [])
        scene_args = dict(resolve_scene(s, known_lists) for s in args.scenes)
        scenes = list(scene_args)
        # SCENE=NAME, else a NAME given for every scene, else DEFAULT_REFERENCE_INTEGRATOR, else path
        ref_integrator = {s: args.reference_integrator_scene.get(
            s, args.reference_integrator_default or DEFAULT_REFERENCE_INTEGRATOR.get(s, "path")) for s in scenes}
        ref_spp = {s: args.reference_spp_scene.get(s, args.reference_spp_default) for s in scenes}

        cpus = usable_cpus()
        say("pathtracer benchmark")
        say(f"  date      {datetime.datetime.now().astimezone().isoformat(timespec='seconds')}")
        say(f"  machine   {platform.node()}, {os.cpu_count()} cores ({cpus} usable), {cpu_model()}")
        try:
            load = ", ".join(f"{v:.2f}" for v in os.getloadavg())
            say(f"  load avg  {load} (1, 5, 15 min, at start)")
        except OSError:
            pass
        say(f"  program   {version} ({program.shown}, sha256 {binary_sha[:12]})" + (" = after" if baseline else ""))
        if baseline is not None:
            say(f"  baseline  {base_version} ({baseline.shown}, sha256 {base_sha[:12]}) = before")
        say(f"  python    {platform.python_version()}, numpy {np.__version__}")
        say(f"  settings  {args.size}x{args.size}, {args.spp} spp, threads {' '.join(map(str, args.threads))}, "
            f"{args.repeats} repeat(s), scenes {' '.join(scenes)}" + (" (--quick)" if args.quick else ""))
        for s in scenes:
            if scene_args[s] != s:
                say(f"  note: {s} is not built into every program: using {scene_args[s]}")
        too_many = [t for t in args.threads + [args.sweep_threads] if t > cpus]
        if too_many:
            say(f"  note: thread count(s) {', '.join(map(str, sorted(set(too_many))))} exceed the {cpus} usable cores")
        say(f"  error     {REL_MSE_FORMULA}")
        say("            efficiency = 1 / (relMSE * median time)")
        say(f"            repeat r uses seed {MEASURE_SEED_BASE}+r (same seeds for every thread count"
            + (" and both programs" if baseline else "") + "); relMSE is the mean over the repeats")
        say("")

        say(f"References ({cpus} threads, program {ref_program.shown}, sha256 {ref_sha[:12]}, cache {args.cache_dir})")
        say("  each is the mean of two half-spp renders a, b (seeds "
            f"{REFERENCE_SEED}, {REFERENCE_SEED + 1}); its own relMSE ~ mean((a-b)^2/(ref^2+1e-2))/4,")
        say("  which a measured relMSE against it contains (a noise floor)")
        refs: dict[str, Reference] = {}
        for scene in scenes:
            refs[scene] = reference_image(ref_program, ref_version, ref_sha, scene, scene_args[scene],
                                          ref_integrator[scene], args.size, ref_spp[scene],
                                          args.cache_dir, cpus, scratch)
        say(fmt_table(["scene", "integrator", "spp", "own relMSE"],
                      [[s, refs[s].integrator, str(refs[s].spp), f"{refs[s].rel_mse:.3g}"] for s in scenes]))
        say("")
        if args.references_only:
            say(f"done in {time.perf_counter() - started:.0f} s (--references-only)")
            return 0

        seeds = [MEASURE_SEED_BASE + r for r in range(args.repeats)]
        if baseline is None:
            say(f"Timings ({args.size}x{args.size}, {args.spp} spp, {args.repeats} run(s) each; "
                "time is the render time the program reports; best = min time / max rate)")
            headers = ["scene", "threads", "spp", "time med", "time best", "paths/s med", "paths/s best",
                       "rays/s med", "rays/s best", "relMSE", "ref share", "efficiency"]
            rows = []
            for scene in scenes:
                for threads in args.threads:
                    m = measure(program, scene_args[scene], args.size, args.spp, threads, seeds,
                                refs[scene].image, scratch)
                    rows.append([scene, str(threads), str(args.spp),
                                 f"{m.time_median:.3f}", f"{min(m.times):.3f}",
                                 f"{statistics.median(m.paths_per_s):.3g}", f"{max(m.paths_per_s):.3g}",
                                 f"{statistics.median(m.rays_per_s):.3g}", f"{max(m.rays_per_s):.3g}",
                                 f"{m.rel_mse:.4g}", f"{refs[scene].rel_mse / m.rel_mse:.2g}", f"{m.efficiency:.4g}"])
                    say(f"  ... {scene}, {threads} thread(s): {m.time_median:.3f} s, relMSE {m.rel_mse:.4g}")
            say("  (time in s, efficiency in 1/s; ref share = the reference's own relMSE / relMSE)")
            say(fmt_table(headers, rows))
            say("")
        else:
            say(f"Before/after ({args.size}x{args.size}, {args.spp} spp, {args.repeats} interleaved run(s) each: "
                "before, after, before, after, ...; same seeds)")
            say("  time med/min in s; paths/s med/max; relMSE mean over the runs; efficiency = 1/(relMSE * median "
                "time) in 1/s; ratio = after/before (paths/s of the medians)")
            headers = ["scene", "thr", "time before", "time after", "paths/s before", "paths/s after", "ratio",
                       "relMSE before", "relMSE after", "ratio", "eff before", "eff after", "ratio", "ref share"]
            rows = []
            for scene in scenes:
                for threads in args.threads:
                    mb, ma = measure_interleaved([baseline, program], scene_args[scene], args.size, args.spp,
                                                 threads, seeds, refs[scene].image, scratch)
                    pb, pa = statistics.median(mb.paths_per_s), statistics.median(ma.paths_per_s)
                    rows.append([scene, str(threads),
                                 f"{mb.time_median:.3f}/{min(mb.times):.3f}", f"{ma.time_median:.3f}/{min(ma.times):.3f}",
                                 f"{pb:.3g}/{max(mb.paths_per_s):.3g}", f"{pa:.3g}/{max(ma.paths_per_s):.3g}",
                                 ratio(pa, pb),
                                 f"{mb.rel_mse:.4g}", f"{ma.rel_mse:.4g}", ratio(ma.rel_mse, mb.rel_mse),
                                 f"{mb.efficiency:.4g}", f"{ma.efficiency:.4g}", ratio(ma.efficiency, mb.efficiency),
                                 f"{refs[scene].rel_mse / min(ma.rel_mse, mb.rel_mse):.2g}"])
                    say(f"  ... {scene}, {threads} thread(s): before {mb.time_median:.3f} s relMSE {mb.rel_mse:.4g}, "
                        f"after {ma.time_median:.3f} s relMSE {ma.rel_mse:.4g}")
            say("  (ref share = the reference's own relMSE / the smaller relMSE of the row)")
            say(fmt_table(headers, rows))
            say("")

        if args.sweep_spp:
            say(f"Error vs. time ({program.shown}, {args.size}x{args.size}, {args.sweep_threads} threads, "
                f"{args.repeats} run(s) per spp)")
            say("  ref share = the reference's own relMSE / relMSE: the part of relMSE that is the reference's noise;")
            say("  'corrected' slope fits relMSE - the reference's own relMSE")
        for scene in scenes if args.sweep_spp else []:
            rows = []
            spps, errs, corrected = [], [], []
            noise = refs[scene].rel_mse if math.isfinite(refs[scene].rel_mse) else 0.0
            for i, spp in enumerate(args.sweep_spp):
                sweep_seeds = [SWEEP_SEED_BASE + 100 * i + r for r in range(args.repeats)]
                m = measure(program, scene_args[scene], args.size, spp, args.sweep_threads, sweep_seeds,
                            refs[scene].image, scratch)
                spps.append(spp)
                errs.append(m.rel_mse)
                corrected.append(m.rel_mse - noise)
                rows.append([str(spp), f"{m.time_median:.3f}", f"{min(m.times):.3f}", f"{m.rel_mse:.4g}",
                             f"{m.rel_mse * spp:.4g}", f"{noise / m.rel_mse:.3f}", f"{m.efficiency:.4g}"])
            say(f"  {scene}")
            say(fmt_table(["spp", "time med", "time best", "relMSE", "relMSE*spp", "ref share", "efficiency"],
                          rows, indent="    "))
            slope = loglog_slope(spps, errs)
            slope_c = loglog_slope(spps, corrected)
            if slope is None:
                say("    slope: needs at least two spp values")
            else:
                slope_c_text = f"{slope_c:.3f}" if slope_c is not None else "n/a"
                say(f"    log-log slope of relMSE vs spp: {slope:.3f} (corrected {slope_c_text}; expected about -1)")
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
