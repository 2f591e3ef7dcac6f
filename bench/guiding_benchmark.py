#!/usr/bin/env python3
"""Path guiding (Müller et al. 2017, an SD-tree) against plain path tracing at equal time (a
benchmark, not a test).

Scenes (default): bench/guiding/door-ajar.json (a room lit through a door opened a crack),
bench/guiding/window-sun.json (sun and sky through one small window), bench/guiding/prism-room.json
(a prism's rainbow in a dark room, lit through a slit; written by bench/guiding/make_scenes.py)
and the built-in scenes cornell-quad, cornell, cornell-point and glass-spheres. --scenes takes
scene files and built-in names. Every render uses the path integrator (--integrator path: a
scene's own choice, vcm for glass-spheres, is overridden) at --width pixels wide (the height
keeps the scene's aspect ratio unless --height).

Configurations (--configs): "off", "on" or "auto", optionally with the guiding field after a
colon ("on:luminance", "on:spectral"), passed as --guiding MODE [--guiding-field FIELD].
Default: off, on:luminance, on:spectral. The first configuration is the baseline of the gains.
A program without --guiding can still run "off" (then no flag is passed).

Method (equal time, the default). Every render uses one thread (--threads 1) and a fixed spp
(--spp); its CPU time is measured (getrusage of the child: parsing, guiding's training and
everything else included). Both estimators are unbiased, so a render's variance falls as 1/spp
and its error at equal time is relMSE x CPU seconds / budget, the budget being the baseline's
CPU time; the table reports relMSE, the CPU seconds, relMSE scaled to the budget (the "equal
time" column) and the gain over the baseline (its equal-time relMSE over this one's: > 1 is
better). Guiding spends its first samples training the guide, so its error falls faster than
1/spp at first: a fixed-spp render understates it at small spp. --time-budget SECONDS instead
gives every render the program's --time-limit SECONDS (with --pass-spp 1 and a large --spp) and
compares the relMSE directly (the table then gives the spp each render reached).

Reference: a --reference-spp render with guiding off (--reference-integrator, default path;
bdpt, also unbiased, converges the prism's rainbow far sooner) in two halves of different seeds
(--reference-threads threads): their difference gives the reference's own noise, subtracted from
every relMSE. The halves are cached in --reference-dir (default bench/results/guiding-ref/,
ignored by git) under a key of the scene file's bytes and every setting that changes the
image; --refresh-reference renders them again (do so after a change to the renderer). Several
repeats (--repeats, different seeds) run interleaved (off, on, ..., off, on, ...); the table
gives the minimum CPU time and the mean error of the repeats, and `uptime`'s load at the start
and the end.

relMSE = mean over pixels and RGB channels of (x - ref)^2 / (ref^2 + 1e-2).

Chroma noise (for --chroma scenes, default prism-room): the linear sRGB images are converted to
CIELAB (colour-science; XYZ divided by the reference's 99th percentile of Y, the white D65), and
the chroma error is the mean over pixels of ((a* - a*_ref)^2 + (b* - b*_ref)^2) / 2, less the
reference's own (its halves' / 4). Lab is not linear: its equal-time scaling (x CPU / budget)
holds only once the noise is small.

    "$(bash validation/setup_venv.sh)/bin/python" bench/guiding_benchmark.py --program build/pathtracer \\
        --spp 64 --reference-spp 4096 --repeats 2 --out bench/results/guiding.md
    # only some scenes, or at equal wall time:
    ... --scenes bench/guiding/door-ajar.json cornell-quad --time-budget 20
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import resource
import shlex
import subprocess
import sys
import tempfile
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "validation"))
sys.path.insert(0, str(ROOT / "bench"))
from many_lights import load, rel_mse  # noqa: E402
from pfm import read_pfm  # noqa: E402

DEFAULT_SCENES = ["bench/guiding/door-ajar.json", "bench/guiding/window-sun.json", "bench/guiding/prism-room.json",
                  "cornell-quad", "cornell", "cornell-point", "glass-spheres"]
DEFAULT_CONFIGS = ["off", "on:luminance", "on:spectral"]
MODES = ("off", "on", "auto")
FIELDS = ("luminance", "spectral")


@dataclass
class Scene:
    arg: str          # what the program is given: a file path or a built-in name
    label: str        # the scene's name (file name without .json)
    source: Path      # the JSON file (a built-in scene's is scenes/NAME.json)


@dataclass
class Result:
    err: list[float] = field(default_factory=list)
    chroma: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)
    spp: list[int] = field(default_factory=list)


def resolve_scene(arg: str) -> Scene:
    path = Path(arg)
    if path.suffix == ".json":
        if not path.is_file() and (ROOT / path).is_file():
            path = ROOT / path  # the default scenes, from any folder
        if not path.is_file():
            raise SystemExit(f"{arg}: no such scene file")
        return Scene(str(path.resolve()), path.stem, path)
    builtin = ROOT / "scenes" / f"{arg}.json"
    if not builtin.is_file():
        raise SystemExit(f"{arg}: neither a .json file nor a built-in scene (scenes/{arg}.json)")
    return Scene(arg, arg, builtin)


def shown(scene: Scene) -> str:
    """The scene as the table names it: a built-in name, or the file relative to the repository."""
    path = Path(scene.arg)
    if not path.is_absolute():
        return scene.arg
    try:
        return str(path.relative_to(ROOT))
    except ValueError:
        return scene.arg


def config_flags(config: str, has_guiding: bool) -> list[str]:
    """The program's flags for a configuration "MODE" or "MODE:FIELD"."""
    mode, _, fld = config.partition(":")
    if mode not in MODES or (fld and fld not in FIELDS):
        raise SystemExit(f"--configs {config}: expected MODE or MODE:FIELD, MODE one of {MODES}, FIELD one of {FIELDS}")
    if not has_guiding:
        if mode == "off" and not fld:
            return []  # a program from before guiding: it renders without
        raise SystemExit(f"--configs {config}: the program has no --guiding flag (see its --help)")
    return ["--guiding", mode] + (["--guiding-field", fld] if fld else [])


SUMMARY = re.compile(r": (\d+)x(\d+), (\d+) spp")


def render(program: Path, scene: Scene, out: Path, spp: int, seed: int, threads: int,
           extra: list[str]) -> tuple[np.ndarray, float, int]:
    """The image, the CPU seconds (user + system) of the render and the spp it rendered."""
    cmd = [str(program), scene.arg, "-o", str(out), "--spp", str(spp), "--seed", str(seed),
           "--threads", str(threads)] + extra
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"{shlex.join(cmd)} failed (status {r.returncode}):\n{r.stderr}{r.stdout}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    m = SUMMARY.search(r.stdout + r.stderr)
    return read_pfm(out), cpu, int(m.group(3)) if m else spp


class Lab:
    """CIELAB of linear sRGB images, scaled so that the reference's 99th percentile of Y is white."""

    def __init__(self, ref: np.ndarray):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import colour  # noqa: PLC0415 (only the chroma needs it)
        self.colour = colour
        self.space = colour.RGB_COLOURSPACES["sRGB"]
        y = self.xyz(ref)[..., 1]
        self.white = max(float(np.percentile(y, 99)), 1e-6)

    def xyz(self, img: np.ndarray) -> np.ndarray:
        return self.colour.RGB_to_XYZ(img, self.space, apply_cctf_decoding=False)

    def ab(self, img: np.ndarray) -> np.ndarray:
        lab = self.colour.XYZ_to_Lab(np.maximum(self.xyz(img), 0) / self.white, self.space.whitepoint)
        return lab[..., 1:]

    def error(self, img: np.ndarray, ref_ab: np.ndarray) -> float:
        return float(np.mean((self.ab(img) - ref_ab) ** 2))  # mean of Δa*², Δb*²: their sum / 2


def reference(args, scene: Scene, common: list[str], has_guiding: bool) -> tuple[list[np.ndarray], bool, str]:
    """The two halves of the reference (cached), whether they came from the cache, its integrator."""
    integrator = args.reference_integrator.get(scene.label, args.reference_integrator.get("", "path"))
    half = args.reference_spp // 2
    ref_common = list(common)
    i = ref_common.index("--integrator")
    ref_common[i + 1] = integrator
    if integrator == "path" and has_guiding:
        ref_common += ["--guiding", "off"]
    key_text = json.dumps({"scene": hashlib.sha256(scene.source.read_bytes()).hexdigest(), "arg": scene.arg,
                           "args": ref_common, "spp": half, "seeds": [1000, 1001]})
    key = hashlib.sha256(key_text.encode()).hexdigest()[:12]
    folder = args.reference_dir / f"{scene.label}-{key}"
    files = [folder / f"half{i}.pfm" for i in range(2)]
    if not args.refresh_reference and all(f.is_file() for f in files):
        return [read_pfm(f) for f in files], True, integrator
    folder.mkdir(parents=True, exist_ok=True)
    cpu = []
    for i, f in enumerate(files):
        print(f"reference {scene.label}: half {i + 1} of 2, {half} spp ({integrator}) ...", file=sys.stderr, flush=True)
        cpu.append(render(args.program, scene, f, half, 1000 + i, args.reference_threads, ref_common)[1])
    version = subprocess.run([str(args.program), "--version"], capture_output=True, text=True).stdout.strip()
    meta = {"scene": scene.arg, "source": str(scene.source), "integrator": integrator, "spp_per_half": half,
            "seeds": [1000, 1001], "threads": args.reference_threads, "args": ref_common, "cpu_seconds": cpu,
            "program": str(args.program), "version": version}
    (folder / "meta.json").write_text(json.dumps(meta, indent=1) + "\n")
    return [read_pfm(f) for f in files], False, integrator


def parse_reference_integrator(text: str) -> dict[str, str]:
    """"bdpt" (every scene) or "prism-room:bdpt,glass-spheres:bdpt" (per scene; others path)."""
    out: dict[str, str] = {}
    for item in text.split(","):
        name, _, integrator = item.rpartition(":")
        if integrator not in ("path", "bdpt"):
            raise SystemExit(f"--reference-integrator {text}: {integrator!r} is not path or bdpt (unbiased)")
        out[name] = integrator
    return out


def fmt(x: float) -> str:
    return f"{x:.4g}"


def gain(x: float) -> str:
    return "n/a" if np.isnan(x) else f"{x:.2f}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--program", type=Path, default=ROOT / "build" / "pathtracer")
    ap.add_argument("--scenes", nargs="+", default=DEFAULT_SCENES, help="scene files and built-in scene names")
    ap.add_argument("--configs", nargs="+", default=DEFAULT_CONFIGS,
                    help="off | on | auto, each optionally :luminance or :spectral (the first is the baseline)")
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, help="default: the scene's aspect ratio")
    ap.add_argument("--spp", type=int, default=64, help="spp of each compared render (equal-time mode)")
    ap.add_argument("--time-budget", type=float, metavar="SECONDS",
                    help="instead: every render gets --time-limit SECONDS (one thread); relMSE compared directly")
    ap.add_argument("--pass-spp", type=int, default=1, help="with --time-budget: the program's --pass-spp")
    ap.add_argument("--reference-spp", type=int, default=4096, help="spp of the reference (two halves)")
    ap.add_argument("--reference-threads", type=int, default=2)
    ap.add_argument("--reference-integrator", type=parse_reference_integrator, default={"": "path"},
                    help="path (default) or bdpt, for every scene or per scene: prism-room:bdpt,glass-spheres:bdpt")
    ap.add_argument("--reference-dir", type=Path, default=ROOT / "bench" / "results" / "guiding-ref")
    ap.add_argument("--refresh-reference", action="store_true", help="render the references again")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--max-depth", type=int, help="scattering events per path (default: unbounded)")
    ap.add_argument("--chroma", nargs="*", default=["prism-room"],
                    help="scenes (names) whose CIELAB chroma error is reported; 'all' for every scene")
    ap.add_argument("--keep-images", type=Path, help="keep every render's PFM in this folder")
    ap.add_argument("--out", type=Path, help="also write the tables here")
    args = ap.parse_args(argv)
    if len(set(args.configs)) != len(args.configs):
        raise SystemExit(f"--configs {' '.join(args.configs)}: each configuration once")
    if args.reference_spp < 2 or args.spp < 1 or args.repeats < 1:
        raise SystemExit("--reference-spp must be at least 2, --spp and --repeats at least 1")

    help_text = subprocess.run([str(args.program), "--help"], capture_output=True, text=True).stdout
    has_guiding = "--guiding" in help_text
    flags = {c: config_flags(c, has_guiding) for c in args.configs}
    scenes = [resolve_scene(s) for s in args.scenes]
    common = ["--integrator", "path", "--width", str(args.width)]
    common += ["--height", str(args.height)] if args.height else []
    common += ["--max-depth", str(args.max_depth)] if args.max_depth is not None else []
    timed = ["--time-limit", str(args.time_budget), "--pass-spp", str(args.pass_spp)] if args.time_budget else []
    spp = 1000000 if args.time_budget else args.spp  # with a time limit: the most it may render
    if args.keep_images:
        args.keep_images.mkdir(parents=True, exist_ok=True)

    cmd = "python bench/guiding_benchmark.py " + shlex.join(argv if argv is not None else sys.argv[1:])
    lines = [f"`{cmd}`", ""]
    if not has_guiding:
        lines += ["The program has no --guiding flag: \"off\" renders with its defaults.", ""]
    lines += [f"Load at start: `{load()}`.", ""]
    summary: list[tuple[str, dict[str, float]]] = []
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = args.keep_images or Path(tmp_name)
        for scene in scenes:
            halves, cached, integrator = reference(args, scene, common, has_guiding)
            ref = 0.5 * (halves[0] + halves[1])
            ref_noise = rel_mse(halves[0], halves[1]) / 4
            chroma = "all" in args.chroma or scene.label in args.chroma
            if chroma:
                lab = Lab(ref)
                ref_ab = lab.ab(ref)
                ab0, ab1 = lab.ab(halves[0]), lab.ab(halves[1])
                chroma_noise = float(np.mean((ab0 - ab1) ** 2)) / 4
            results = {c: Result() for c in args.configs}
            for rep in range(args.repeats):
                for c in args.configs:
                    out = tmp / f"{scene.label}-{c.replace(':', '-')}-{rep}.pfm"
                    img, cpu, done = render(args.program, scene, out, spp, 10 + rep, 1, common + flags[c] + timed)
                    r = results[c]
                    r.err.append(rel_mse(img, ref) - ref_noise)
                    r.cpu.append(cpu)
                    r.spp.append(done)
                    if chroma:
                        r.chroma.append(lab.error(img, ref_ab) - chroma_noise)
                    print(f"{scene.label} {c} repeat {rep + 1}: relMSE {r.err[-1]:.4g}, {cpu:.2f} CPU s, {done} spp",
                          file=sys.stderr, flush=True)

            base = args.configs[0]
            budget = min(results[base].cpu)
            h, w = ref.shape[:2]
            mode = (f"each render --time-limit {args.time_budget:g} s (--pass-spp {args.pass_spp})" if args.time_budget
                    else f"{args.spp} spp per render")
            lines += [f"### {scene.label}", "",
                      f"`{shown(scene)}`, {w}x{h}, {mode}, 1 thread, {args.repeats} interleaved repeats; reference "
                      f"{args.reference_spp} spp ({integrator}, guiding off{', cached' if cached else ''}), its own "
                      f"relMSE {ref_noise:.3g} subtracted" + (f", its own chroma error {chroma_noise:.3g}" if chroma else "")
                      + ".", ""]
            if args.time_budget:
                head = "| config | relMSE | CPU s (min) | spp (mean) | gain |"
                sep = "|---|---|---|---|---|"
            else:
                head = "| config | relMSE | CPU s (min) | relMSE at equal time | gain |"
                sep = "|---|---|---|---|---|"
            if chroma:
                head += " chroma error | chroma at equal time |" if not args.time_budget else " chroma error |"
                sep += "---|---|" if not args.time_budget else "---|"
            lines += [head, sep]
            equal: dict[str, float] = {}
            for c in args.configs:
                r = results[c]
                err, cpu = float(np.mean(r.err)), min(r.cpu)
                equal[c] = err if args.time_budget else err * cpu / budget
            # (a relMSE at or below 0: the reference's own noise is as large; no gain can be given)
            gains = {c: equal[base] / equal[c] if equal[c] > 0 and equal[base] > 0 else float("nan")
                     for c in args.configs}
            for c in args.configs:
                r = results[c]
                err, cpu = float(np.mean(r.err)), min(r.cpu)
                middle = f"{np.mean(r.spp):.0f}" if args.time_budget else fmt(equal[c])
                row = f"| {c} | {fmt(err)} | {cpu:.2f} | {middle} | {gain(gains[c])} |"
                if chroma:
                    ch = float(np.mean(r.chroma))
                    row += f" {fmt(ch)} |" if args.time_budget else f" {fmt(ch)} | {fmt(ch * cpu / budget)} |"
                lines.append(row)
            lines.append("")
            summary.append((scene.label, gains))

    if len(scenes) > 1 and len(args.configs) > 1:
        lines += ["### Gains at equal time (baseline's relMSE over each configuration's)", "",
                  "| scene | " + " | ".join(args.configs) + " |", "|---|" + "---|" * len(args.configs)]
        for label, gains in summary:
            lines.append(f"| {label} | " + " | ".join(gain(gains[c]) for c in args.configs) + " |")
        lines.append("")
    lines.append(f"Load at end: `{load()}`.")
    table = "\n".join(lines)
    print(table)
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
