#!/usr/bin/env python3
"""Builds the report: renders every figure, measures every number it quotes, and writes

    OUT/figures/*.png   the figures (compressed PNG)
    OUT/results.json    every number the text quotes (and the machine, date and commit)
    OUT/README.md       docs/report/report.md.in with each {{key}} replaced from results.json

Full mode (OUT = docs/report, the committed report; about half an hour on 2 idle cores, run it
on an idle machine):

    VENV=$(bash validation/setup_venv.sh)
    $VENV/bin/python docs/report/build_report.py

Quick mode (CI: tiny sizes, about a minute; OUT = build/report-quick, the tree stays clean). It
checks that every figure is produced and that every key the text names has a value:

    $VENV/bin/python docs/report/build_report.py --quick

A stage that fails does not stop the others (the run then exits 1 naming it, without writing
README.md); `--only SECTION` (repeatable) re-runs that section and takes every other section's
numbers from its cached results (build/report-cache/<mode>/<program sha>/sections/, keyed by the
settings and the program's hash); with `--from-results docs/report/results.json` a section without
cached results takes its numbers from that earlier run instead, and the text names the run (so
one stage can be re-run on another machine). `--estimate FRACTION` renders every stage at that fraction of
its spp into a cache of its own and prints each stage's projected time on idle cores (from the
renders' CPU time, which other processes hardly change); it writes no report, and with --only
it estimates those sections alone.

The renderer is $SPT_PATHTRACER, else build/pathtracer (or --program). Renders are cached
under build/report-cache/<program sha> by their command line, so rebuilding the text after an
edit renders nothing again. Reuses validation/ as modules: accuracy_cost.py (the
accuracy-versus-time study), color_accuracy.py (the colour checker against colour-science),
gallery.py (the gallery) and bdpt_compare.py (relMSE).
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
import resource
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPORT_DIR = Path(__file__).resolve().parent
ROOT = REPORT_DIR.parent.parent
sys.path.insert(0, str(ROOT / "validation"))
import accuracy_cost  # noqa: E402
import bdpt_compare  # noqa: E402
import benchmark  # noqa: E402
import color_accuracy  # noqa: E402
import gallery  # noqa: E402

# Every size, sample count and time of a run. Full: about half an hour on 2 idle cores, sized
# with `--estimate 0.015625` (2026-12-02, commit 03217f3's renderer, on the loaded 2-core VM; its
# CPU time per path matched the idle 1-thread throughput of parallel_strategies.md). Projected
# render seconds on idle cores, stage by stage (a shared reference counts where it is first
# rendered): convergence 403, materials 94, lights 91, gi 70, point_caustic 45, extensions 183,
# colour 49, accuracy 774, gallery 94: 1803 s, an upper bound (a vcm render's fixed cost per pass
# is scaled up with its spp). A reference has 8-16× the samples of the largest count compared
# with it; its own noise is measured (two halves) and subtracted.
# The accuracy stage took 514 s on the idle machine (2026-12-02 07:39 run). Its prism points
# then became means over 32/16/4/2 seeds at 4/16/64/256 spp and its chart 256 pixels high:
# about +250 s and +30 s by that run's per-point times, so about 13 min idle. `--only accuracy
# --estimate 0.125` (2026-12-02, 16/8/4/2 seeds, 80-pixel chart, on the shared machine with a
# load of 13-20: CPU time inflated) projected 773 s.
# Quick: the pipeline in about a minute.
FULL = {
    "size": 256, "threads": 2,
    "conv_spp": [1, 4, 16, 64, 256],
    "ref_spp": {"cornell": 4096, "cornell-sphere": 4096, "cornell-quad": 2048, "cornell-point": 2048},
    "material_spp": 32, "material_ref_spp": 512, "equal_seconds": 10.0,
    "effects_size": 512, "effects_spp": 256,
    "caustic_seconds": 15.0, "prism_ref_spp": 2048,
    "extension_spp": 256, "integrators_spp": 64, "gallery_width": 320, "gallery_spp": None,
    "chart_spp": 128, "chart_exact_spp": 1024, "chart_size": None, "chart_bins": (4, 8, 16, 32, 64),
    "accuracy_cost": ["--height", "256", "--chart-height", "256", "--spp", "4", "16", "64", "256", "--bins-spp", "64",
                      "--reference-spp", "1024", "--integrators", "path", "bdpt", "vcm",
                      "--wavelengths-per-path", "1", "4", "--noisy-scenes", "prism", "--noisy-seeds", "32", "16", "4", "2"],
}
QUICK = {
    "size": 32, "threads": 2,
    "conv_spp": [1, 2, 4, 8, 16],
    "ref_spp": {"cornell": 128, "cornell-sphere": 128, "cornell-quad": 128, "cornell-point": 128},
    "material_spp": 4, "material_ref_spp": 64, "equal_seconds": 0.3,
    "effects_size": 48, "effects_spp": 8,
    "caustic_seconds": 0.3, "prism_ref_spp": 64,
    "extension_spp": 4, "integrators_spp": 2, "gallery_width": 32, "gallery_spp": 2,
    "chart_spp": 4, "chart_exact_spp": 0, "chart_size": None, "chart_bins": (16,),
    "accuracy_cost": ["--quick", "--scenes", "cornell-point", "--integrators", "path", "bdpt", "vcm",
                      "--spp", "4", "16", "--bins-spp", "16", "--seeds", "2",
                      "--depths", "1", "--wavelengths-per-path", "4"],
}

# A reference must hold all the light transport of its scene. Path tracing does wherever every
# light has an area (each path has a non-zero density), and costs the least per sample; the point
# light's caustic through the glass of `cornell-point` has density zero for it, so that reference
# is bdpt's (which connects light subpaths through the glass to the camera).
def reference_integrator(scene: str) -> str:
    return "bdpt" if scene == "cornell-point" else "path"


def canonical_reference(r: "Renderer", p: dict, scene: str) -> tuple[np.ndarray, float]:
    """The long reference of a canonical scene at the report's size, shared by every section
    (the render cache makes the second request a file read)."""
    return r.reference(scene, width=p["size"], height=p["size"], spp=p["ref_spp"][scene],
                       integrator=reference_integrator(scene))


def ratio(a: float, b: float) -> float:
    """a / b, or NaN where b is 0 (quick mode's tiny renders can time as 0 s or score 0)."""
    return a / b if b else math.nan


def say(*args: object) -> None:
    print(*args, flush=True)


# ------------------------------------------------------------------------------------------
# Rendering (cached by command line)


@dataclass
class Render:
    image: np.ndarray     # linear RGB (H, W, 3) from the PFM
    png: Path             # the program's developed 8-bit image
    seconds: float        # render time from the program's summary
    spp: int              # samples per pixel reached (--time-limit may stop earlier)


class Renderer:
    """Runs the program, caching each render by its command line under the program's sha.

    With `fraction` < 1 (--estimate) every render runs at that fraction of its spp (time limits
    likewise) into a cache of its own, and `projected` adds up what the full render would take
    on idle cores: its CPU time scaled to the full spp, divided by the threads (CPU time, unlike
    wall time, hardly depends on what else the machine runs), or its time limit."""

    def __init__(self, program: Path, cache: Path, threads: int, fraction: float = 1.0):
        self.program = program
        self.sha = benchmark.sha256_file(program)
        self.version = subprocess.run([str(program), "--version"], capture_output=True, text=True,
                                      check=True).stdout.strip()
        self.fraction = fraction
        self.cache = cache / (self.sha[:12] + ("" if fraction == 1 else f"-estimate-{fraction:g}"))
        self.cache.mkdir(parents=True, exist_ok=True)
        self.threads = threads
        self.seconds = 0.0
        self.projected = 0.0
        self._counted: set[str] = set()

    def render(self, scene: str | Path, *, width: int, height: int | None = None, spp: int = 16,
               seed: int = 0, integrator: str | None = None, time_limit: float | None = None,
               extra: tuple[str, ...] = ()) -> Render:
        """One render of a built-in scene (name) or scene file (Path), cached by its command."""
        run_spp = spp if time_limit is not None else max(1, round(spp * self.fraction))
        flags = ["--width", str(width)] + (["--height", str(height)] if height else [])
        flags += ["--spp", str(run_spp), "--seed", str(seed), "--threads", str(self.threads)]
        if integrator:
            flags += ["--integrator", integrator]
        if time_limit is not None:
            flags += ["--time-limit", f"{time_limit * self.fraction:g}"]
        flags += list(extra)
        scene_id = Path(scene).read_text() if isinstance(scene, Path) else scene
        key = hashlib.sha256(json.dumps([scene_id, flags]).encode()).hexdigest()[:20]
        pfm, png, meta = (self.cache / f"{key}.{ext}" for ext in ("pfm", "png", "json"))
        if not meta.is_file():
            cmd = [str(self.program), str(scene), *flags, "-o", str(pfm), "-o", str(png)]
            cpu0 = child_cpu_seconds()
            run = subprocess.run(cmd, capture_output=True, text=True)
            cpu = child_cpu_seconds() - cpu0
            if run.returncode != 0:
                raise RuntimeError(f"{' '.join(cmd)} failed ({run.returncode}):\n{run.stderr}")
            seconds = float(re.search(r"time ([0-9.]+) s,", run.stderr).group(1))
            stopped = re.search(r"stopped by --time-limit \S+ s after (\d+) of", run.stderr)
            meta.write_text(json.dumps({"seconds": seconds, "spp": int(stopped.group(1)) if stopped else run_spp,
                                        "cpu_seconds": cpu, "command": cmd[1:]}))
            self.seconds += seconds
        m = json.loads(meta.read_text())
        if key not in self._counted:
            self._counted.add(key)
            self.projected += (time_limit if time_limit is not None
                               else m.get("cpu_seconds", 0.0) * spp / run_spp / self.threads)
        return Render(bdpt_compare.read_pfm(str(pfm)), png, m["seconds"], m["spp"])

    def reference(self, scene: str | Path, *, width: int, spp: int, integrator: str,
                  height: int | None = None) -> tuple[np.ndarray, float]:
        """(reference image, its own relMSE noise): two halves with different seeds; the noise
        of their mean is mean((a − b)²/w)/4 (as accuracy_cost.py's references)."""
        a, b = (self.render(scene, width=width, height=height, spp=max(1, spp // 2), seed=987654321 + i,
                            integrator=integrator).image for i in (0, 1))
        ref = (a + b) / 2
        return ref, float(np.mean((a - b) ** 2 / accuracy_cost.w_of(ref)) / 4)


def child_cpu_seconds() -> float:
    """User + system CPU time of the finished child processes so far."""
    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


def rel_mse(x: np.ndarray, ref: np.ndarray, noise: float = 0.0) -> float:
    """relMSE against a reference, less the reference's own noise (which adds to every value)."""
    return bdpt_compare.rel_mse(x, ref) - noise


def slope_reading(slope: float, se: float) -> str:
    """What a fitted relMSE slope says: noise alone gives −1; flatter means an error that does not
    fall with N (a bias floor)."""
    if not (math.isfinite(slope) and math.isfinite(se)) or se == 0:
        return "too few points to tell"
    z = (slope + 1) / se
    if abs(z) <= 2:
        return "consistent with −1 (pure noise)"
    return f"{'flatter' if z > 0 else 'steeper'} than −1 by {abs(z):.1f} s.e." + (" (a bias floor)" if z > 0 else "")


def loglog_fit(x: list[float], y: list[float]) -> tuple[float, float]:
    """Least-squares slope of log y on log x and its standard error."""
    lx, ly = np.log10(x), np.log10(y)
    A = np.vstack([lx, np.ones_like(lx)]).T
    (slope, icept), *_ = np.linalg.lstsq(A, ly, rcond=None)
    if len(lx) < 3:
        return float(slope), math.nan
    res = ly - (slope * lx + icept)
    se = math.sqrt(float(res @ res) / (len(lx) - 2) / float(((lx - lx.mean()) ** 2).sum()))
    return float(slope), se


# ------------------------------------------------------------------------------------------
# Figures


def load_png(path: Path) -> np.ndarray:
    from PIL import Image
    return np.asarray(Image.open(path).convert("RGB"))


def save_figure(fig, path: Path) -> None:
    """Saves a matplotlib figure as a palette-free, maximally compressed PNG."""
    import matplotlib.pyplot as plt
    from PIL import Image
    fig.savefig(path, dpi=100)
    plt.close(fig)
    Image.open(path).convert("RGB").save(path, optimize=True)


def panels(path: Path, images: list[np.ndarray], titles: list[str], inset: tuple[float, ...] | None = None,
           insets: list[tuple[float, ...]] | None = None) -> None:
    """Renders side by side, titled; with `inset` (x, y, w, h as fractions of the image) or
    one per image in `insets`, a second row shows that box magnified (nearest neighbour) and
    the box is drawn on the render."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.patches as patches
    import matplotlib.pyplot as plt
    boxes = insets or ([inset] * len(images) if inset else None)
    rows = 2 if boxes else 1
    aspect = images[0].shape[0] / images[0].shape[1]
    fig, axes = plt.subplots(rows, len(images), figsize=(2.8 * len(images), 2.8 * aspect * rows + 0.5),
                             squeeze=False)
    for i, (img, title) in enumerate(zip(images, titles)):
        ax = axes[0][i]
        ax.imshow(img, interpolation="nearest")
        ax.set_title(title, fontsize=8)
        ax.axis("off")
        if boxes:
            h, w = img.shape[:2]
            x, y, bw, bh = boxes[i]
            x0, y0 = int(x * w), int(y * h)
            x1, y1 = max(x0 + 1, int((x + bw) * w)), max(y0 + 1, int((y + bh) * h))
            ax.add_patch(patches.Rectangle((x0 - 0.5, y0 - 0.5), x1 - x0, y1 - y0, fill=False, ec="yellow", lw=1))
            axes[1][i].imshow(img[y0:y1, x0:x1], interpolation="nearest")
            axes[1][i].axis("off")
    fig.tight_layout()
    save_figure(fig, path)


# ------------------------------------------------------------------------------------------
# Sections: each renders what it needs and returns its numbers


def convergence(r: Renderer, p: dict, figs: Path) -> dict:
    """relMSE against spp on log–log axes, the fitted slope ± standard error per scene and
    integrator. cornell-point's reference is bdpt's, so path tracing's missing caustic shows
    as a floor."""
    import matplotlib.pyplot as plt
    out = {}
    series = [("cornell", "path"), ("cornell-point", "path"), ("cornell-point", "bdpt"), ("cornell-sphere", "path")]
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for scene, integ in series:
        ref, noise = canonical_reference(r, p, scene)
        pts, pngs = [], []
        for spp in p["conv_spp"]:
            x = r.render(scene, width=p["size"], height=p["size"], spp=spp, seed=1000 + spp, integrator=integ)
            pts.append((spp, rel_mse(x.image, ref, noise), x.seconds))
            pngs.append(x.png)
        if (scene, integ) in (("cornell", "path"), ("cornell-sphere", "path")):
            # What the numbers look like: the same scene at each spp, side by side.
            panels(figs / f"convergence_{scene}.png", [load_png(f) for f in pngs],
                   [f"{s} spp, {t:.2f} s, relMSE {e:.3g}" for s, e, t in pts])
        good = [(s, e) for s, e, _ in pts if e > 0]
        slope, se = loglog_fit([s for s, _ in good], [e for _, e in good]) if len(good) >= 2 else (math.nan, math.nan)
        name = f"{scene}/{integ}"
        out[name] = {"scene": scene, "integrator": integ, "slope": slope, "slope_se": se,
                     "reading": slope_reading(slope, se),
                     "reference": f"{reference_integrator(scene)}, {p['ref_spp'][scene]} spp",
                     "reference_noise": noise, "spp": [s for s, _, _ in pts], "relmse": [e for _, e, _ in pts],
                     "seconds": [t for _, _, t in pts],
                     "relmse_max_spp": pts[-1][1], "relmse_min_spp": pts[0][1]}
        ax.loglog([s for s, _ in good], [e for _, e in good], "o-",
                  label=f"{scene}, {integ}: slope {slope:.2f} ± {se:.2f}")
    s0 = p["conv_spp"]
    first = out["cornell/path"]["relmse"][0]
    ax.loglog(s0, [first * s0[0] / s for s in s0], "k:", lw=1, label="1/N")
    ax.set_xlabel("samples per pixel N")
    ax.set_ylabel("relMSE against the reference")
    ax.set_title(f"Convergence, {p['size']}×{p['size']}", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, figs / "convergence.png")
    out["spp_min"], out["spp_max"] = min(p["conv_spp"]), max(p["conv_spp"])
    out["spp_range"] = f"{out['spp_min']}–{out['spp_max']}"
    out["ref_spp"] = ", ".join(f"`{s}` {reference_integrator(s)} {n}" for s, n in p["ref_spp"].items())
    return out


MATERIALS = {
    "diffuse": {"kd": 0.75},
    "plastic": {"type": "plastic", "kd": 0.75},
    "rough metal": {"type": "conductor", "metal": "Al", "roughness": 0.35},
    "mirror metal": {"type": "conductor", "metal": "Al"},
    "glass": {"type": "dielectric", "ior": 1.5},
}


def material_scene(material: dict, folder: Path, name: str) -> Path:
    """cornell-quad with one sphere of `material` in the middle (same light, same walls)."""
    scene = json.loads((ROOT / "scenes" / "cornell-quad.json").read_text())
    scene["description"] = scene["summary"] = f"report: a {name} sphere in cornell-quad"
    scene["materials"]["probe"] = material
    scene["shapes"] = [s for s in scene["shapes"] if s["type"] != "sphere"]
    scene["shapes"].append({"type": "sphere", "center": [0, -0.55, 0], "radius": 0.45, "material": "probe"})
    path = folder / f"material-{name.replace(' ', '-')}.json"
    path.write_text(json.dumps(scene, indent=1))
    return path


def materials(r: Renderer, p: dict, figs: Path, scratch: Path) -> dict:
    """Equal spp, one sphere per material under a small quad light: relMSE of the whole image
    and of the sphere's pixels, time, efficiency."""
    out, imgs, titles = {}, [], []
    n = p["size"]
    rows = []
    for name, mat in MATERIALS.items():
        scene = material_scene(mat, scratch, name)
        ref, noise = r.reference(scene, width=n, height=n, spp=p["material_ref_spp"], integrator="path")
        x = r.render(scene, width=n, height=n, spp=p["material_spp"], seed=7, integrator="path")
        e = rel_mse(x.image, ref, noise)
        # The sphere's pixels: a box around its image (centre (0, −0.55, 0), radius 0.45).
        box = (slice(int(0.52 * n), int(0.92 * n)), slice(int(0.3 * n), int(0.7 * n)))
        e_sphere = float(np.mean((x.image[box] - ref[box]) ** 2 / accuracy_cost.w_of(ref[box])))
        out[name] = {"relmse": e, "relmse_sphere": e_sphere, "seconds": x.seconds, "reference_noise": noise,
                     "efficiency": ratio(1.0, e * x.seconds) if e > 0 else math.inf}
        rows.append(f"| {name} | {e:.4g} | {e_sphere:.4g} | {x.seconds:.2f} | {out[name]['efficiency']:.3g} | "
                    f"{noise:.2g} |")
        imgs.append(load_png(x.png))
        titles.append(f"{name}: relMSE {e:.3g}")
    base = out["diffuse"]["relmse"]
    for name in out:
        out[name]["vs_diffuse"] = out[name]["relmse"] / base if base > 0 else math.nan
    panels(figs / "materials.png", imgs, titles, inset=(0.3, 0.52, 0.4, 0.4))
    out["table"] = "\n".join(["| sphere | relMSE (image) | relMSE (sphere box) | time (s) | 1/(relMSE·time) | "
                              "reference's own relMSE |", "|---|---:|---:|---:|---:|---:|"] + rows)
    out["spp"], out["ref_spp"] = p["material_spp"], p["material_ref_spp"]
    return out


def lights(r: Renderer, p: dict, figs: Path) -> dict:
    """Point, sphere and quad light of the same power at equal render time (path tracing)."""
    out, imgs, titles = {}, [], []
    n = p["size"]
    for scene in ("cornell-point", "cornell-sphere", "cornell-quad"):
        ref, noise = canonical_reference(r, p, scene)
        x = r.render(scene, width=n, height=n, spp=1_000_000, seed=11, integrator="path",
                     time_limit=p["equal_seconds"], extra=("--pass-spp", "1"))
        e = rel_mse(x.image, ref, noise)
        out[scene] = {"relmse": e, "spp": x.spp, "seconds": x.seconds, "reference_noise": noise}
        imgs.append(load_png(x.png))
        titles.append(f"{scene}: {x.spp} spp in {x.seconds:.1f} s\nrelMSE {e:.3g}")
    panels(figs / "lights_equal_time.png", imgs, titles)
    out["seconds"] = p["equal_seconds"]
    return out


# Boxes (x, y, w, h as fractions) of the canonical Cornell box's features.
SHADOW_BOX = (0.18, 0.72, 0.36, 0.26)     # under the plastic sphere
BLEED_BOX = (0.0, 0.55, 0.3, 0.45)        # the red wall's light on the floor and the sphere
CAUSTIC_BOX = (0.58, 0.84, 0.34, 0.16)      # the floor under the glass sphere


def gi_effects(r: Renderer, p: dict, figs: Path) -> dict:
    n, spp = p["effects_size"], p["effects_spp"]
    shots = [("hard shadows", "cornell-point", "path", SHADOW_BOX),
             ("soft shadows", "cornell-quad", "path", SHADOW_BOX),
             ("colour bleeding", "cornell", "path", BLEED_BOX),
             ("caustic (area light)", "cornell", "path", CAUSTIC_BOX)]
    out, imgs, titles = {}, [], []
    for label, scene, integ, box in shots:
        x = r.render(scene, width=n, height=n, spp=spp, seed=3, integrator=integ)
        out[label] = {"scene": scene, "integrator": integ, "seconds": x.seconds, "spp": spp}
        imgs.append(load_png(x.png))
        titles.append(f"{label}\n{scene}, {integ}, {x.seconds:.1f} s")
    panels(figs / "gi_effects.png", imgs, titles, insets=[s[3] for s in shots])
    out["size"], out["spp"] = n, spp
    return out


def point_caustic(r: Renderer, p: dict, figs: Path) -> dict:
    """cornell-point at equal time with path, bdpt and vcm: the point light's caustic through
    the glass sphere. Mean luminance of the caustic box against bdpt's reference."""
    n = p["size"]
    ref, noise = canonical_reference(r, p, "cornell-point")
    x0, y0, bw, bh = CAUSTIC_BOX
    box = (slice(int(y0 * n), int((y0 + bh) * n)), slice(int(x0 * n), int((x0 + bw) * n)))
    lum = np.array([0.2126, 0.7152, 0.0722])
    out = {"reference_box_luminance": float((ref[box] @ lum).mean())}
    imgs, titles = [], []
    for integ in ("path", "bdpt", "vcm"):
        extra = ("--pass-spp", "1") if integ != "vcm" else ()
        x = r.render("cornell-point", width=n, height=n, spp=1_000_000, seed=5, integrator=integ,
                     time_limit=p["caustic_seconds"], extra=extra)
        e = rel_mse(x.image, ref, noise)
        box_lum = float((x.image[box] @ lum).mean())
        out[integ] = {"relmse": e, "spp": x.spp, "seconds": x.seconds, "box_luminance": box_lum,
                      "box_ratio": ratio(box_lum, out["reference_box_luminance"])}
        imgs.append(load_png(x.png))
        titles.append(f"{integ}: {x.spp} spp, {x.seconds:.1f} s\nrelMSE {e:.3g}, caustic box {out[integ]['box_ratio']:.0%}")
    panels(figs / "point_caustic.png", imgs, titles, inset=CAUSTIC_BOX)
    out["seconds"], out["size"] = p["caustic_seconds"], n
    return out


def supports(r: Renderer, flags: list[str], scene: str = "cornell") -> bool:
    """Whether the program accepts these flags for `scene` (a one-pixel render)."""
    run = subprocess.run([str(r.program), scene, "--width", "1", "--height", "1", "--spp", "1", "--quiet",
                          "-o", str(r.cache / "probe.pfm"), *flags], capture_output=True, text=True)
    return run.returncode == 0


def extensions(r: Renderer, p: dict, figs: Path) -> dict:
    """Side-by-side comparisons where the program has a switch for the extension."""
    n, spp = p["size"], p["extension_spp"]
    out = {}

    # Parallel tiles: the same image on 1 and 2 threads.
    t = {}
    for threads in (1, 2):
        saved, r.threads = r.threads, threads
        t[threads] = r.render("cornell", width=n, height=n, spp=spp, seed=21)
        r.threads = saved
    panels(figs / "threads.png", [load_png(t[1].png), load_png(t[2].png)],
           [f"1 thread: {t[1].seconds:.2f} s", f"2 threads: {t[2].seconds:.2f} s (same image, bit for bit)"])
    out["threads"] = {"seconds_1": t[1].seconds, "seconds_2": t[2].seconds,
                      "speedup": ratio(t[1].seconds, t[2].seconds),
                      "identical": "yes" if np.array_equal(t[1].image, t[2].image) else "no"}

    # BVH: a mesh scene with its tree and with every triangle tested in a loop (--no-bvh), at
    # an eighth of the spp (the loop is slow); the tree changes no hit, so the images are equal.
    bvh_spp = max(1, spp // 8)
    b = {on: r.render("liquid-glass", width=n, height=n, spp=bvh_spp, seed=23, extra=() if on else ("--no-bvh",))
         for on in (True, False)}
    panels(figs / "bvh.png", [load_png(b[True].png), load_png(b[False].png)],
           [f"BVH: {b[True].seconds:.2f} s", f"no BVH (--no-bvh): {b[False].seconds:.2f} s"])
    out["bvh"] = {"spp": bvh_spp, "seconds_on": b[True].seconds, "seconds_off": b[False].seconds,
                  "speedup": ratio(b[False].seconds, b[True].seconds),
                  "identical": "yes" if np.array_equal(b[True].image, b[False].image) else "no"}

    # Hero wavelengths: 1 against 4 wavelengths per path, equal spp (cornell's reference).
    ref, noise = canonical_reference(r, p, "cornell")
    wl = {k: r.render("cornell", width=n, height=n, spp=spp, seed=22, extra=("--wavelengths-per-path", str(k)))
          for k in (1, 4)}
    out["hero"] = {f"relmse_{k}": rel_mse(x.image, ref, noise) for k, x in wl.items()}
    out["hero"].update({f"seconds_{k}": x.seconds for k, x in wl.items()})
    out["hero"]["ratio"] = ratio(out["hero"]["relmse_1"], out["hero"]["relmse_4"])
    panels(figs / "hero_wavelengths.png", [load_png(wl[1].png), load_png(wl[4].png)],
           [f"1 wavelength/path: relMSE {out['hero']['relmse_1']:.3g}",
            f"4 (hero + 3): relMSE {out['hero']['relmse_4']:.3g}"], inset=(0.3, 0.3, 0.4, 0.3))

    # Light sampling on a small sphere light: BSDF sampling alone, light sampling alone, MIS.
    ref, noise = canonical_reference(r, p, "cornell-sphere")
    ls = {m: r.render("cornell-sphere", width=n, height=n, spp=spp, seed=23, extra=("--light-sampling", m))
          for m in ("bsdf", "light", "mis")}
    out["light_sampling"] = {m: {"relmse": rel_mse(x.image, ref, noise), "seconds": x.seconds} for m, x in ls.items()}
    panels(figs / "light_sampling.png", [load_png(x.png) for x in ls.values()],
           [f"--light-sampling {m}: relMSE {out['light_sampling'][m]['relmse']:.3g}, {x.seconds:.1f} s"
            for m, x in ls.items()])

    # Special next-event strategies, each against its absence at equal spp: the plane light's
    # sampler on cornell (its light is the whole ceiling) and specular chains through the glass
    # and shiny spheres on cornell-sphere (the caustics of a small light).
    for key, scene, flag in (("plane_nee", "cornell", "--plane-nee"), ("caustic_nee", "cornell-sphere", "--caustic-nee")):
        if not supports(r, [flag, "off"], scene=scene):
            out[key] = {"available": "no"}
            continue
        ref, noise = canonical_reference(r, p, scene)
        runs = {v: r.render(scene, width=n, height=n, spp=spp, seed=29, extra=(flag, v)) for v in ("off", "on")}
        res = {v: {"relmse": rel_mse(x.image, ref, noise), "seconds": x.seconds} for v, x in runs.items()}
        res.update({"available": "yes", "relmse_ratio": ratio(res["off"]["relmse"], res["on"]["relmse"]),
                    "time_ratio": ratio(res["on"]["seconds"], res["off"]["seconds"]),
                    "efficiency_ratio": ratio(res["off"]["relmse"] * res["off"]["seconds"],
                                              res["on"]["relmse"] * res["on"]["seconds"])})
        out[key] = res
        panels(figs / f"{key}.png", [load_png(x.png) for x in runs.values()],
               [f"{flag} {v}: {x.seconds:.1f} s, relMSE {res[v]['relmse']:.3g}" for v, x in runs.items()])

    # Dispersion on and off: prism with the scene's integrator.
    w = p["size"]
    dp = {on: r.render("prism", width=w, spp=spp, seed=24, extra=() if on else ("--no-dispersion",))
          for on in (True, False)}
    out["dispersion"] = {"seconds_on": dp[True].seconds, "seconds_off": dp[False].seconds}
    panels(figs / "dispersion.png", [load_png(dp[True].png), load_png(dp[False].png)],
           [f"dispersion (Sellmeier BK7), {dp[True].seconds:.1f} s", f"--no-dispersion, {dp[False].seconds:.1f} s"])

    # bdpt and vcm on a caustic seen through glass (equal time; bdpt reference).
    ref, noise = r.reference("prism", width=w, spp=p["prism_ref_spp"], integrator="bdpt")
    pv = {}
    for integ in ("path", "bdpt", "vcm"):
        extra = ("--pass-spp", "1") if integ != "vcm" else ()
        pv[integ] = r.render("prism", width=w, spp=1_000_000, seed=25, integrator=integ,
                             time_limit=p["equal_seconds"], extra=extra)
    out["prism_integrators"] = {i: {"relmse": rel_mse(x.image, ref, noise), "spp": x.spp, "seconds": x.seconds,
                                    "relmse_trimmed": bdpt_compare.rel_mse_trimmed(x.image, ref)}
                                for i, x in pv.items()}
    for i in ("bdpt", "vcm"):
        out["prism_integrators"][i]["gain"] = ratio(out["prism_integrators"]["path"]["relmse"],
                                                    out["prism_integrators"][i]["relmse"])
    panels(figs / "prism_integrators.png", [load_png(x.png) for x in pv.values()],
           [f"{i}: {x.spp} spp, {x.seconds:.1f} s, relMSE {out['prism_integrators'][i]['relmse']:.3g}"
            for i, x in pv.items()])

    # The sampler: independent random numbers against Owen-scrambled Sobol, equal spp.
    if supports(r, ["--sampler", "sobol"]):
        ref, noise = canonical_reference(r, p, "cornell")
        sm = {s: r.render("cornell", width=n, height=n, spp=spp, seed=26, extra=("--sampler", s))
              for s in ("independent", "sobol")}
        out["sampler"] = {s: {"relmse": rel_mse(x.image, ref, noise), "seconds": x.seconds} for s, x in sm.items()}
        ind, sob = out["sampler"]["independent"], out["sampler"]["sobol"]
        out["sampler"].update({"available": "yes", "relmse_ratio": ratio(ind["relmse"], sob["relmse"]),
                               "time_ratio": ratio(sob["seconds"], ind["seconds"]),
                               "efficiency_ratio": ratio(ind["relmse"] * ind["seconds"], sob["relmse"] * sob["seconds"])})
        panels(figs / "sampler.png", [load_png(x.png) for x in sm.values()],
               [f"--sampler {s}: relMSE {out['sampler'][s]['relmse']:.3g}, {x.seconds:.1f} s" for s, x in sm.items()])
    else:
        out["sampler"] = {"available": "no"}

    # The wavefront schedule against tiles: same image, time per pass.
    if supports(r, ["--schedule", "wavefront"]):
        wf = {s: r.render("cornell", width=n, height=n, spp=spp, seed=27, extra=("--schedule", s))
              for s in ("tiles", "wavefront")}
        out["wavefront"] = {"seconds_tiles": wf["tiles"].seconds, "seconds_wavefront": wf["wavefront"].seconds,
                            "time_ratio": ratio(wf["wavefront"].seconds, wf["tiles"].seconds),
                            "identical": "yes" if np.array_equal(wf["tiles"].image, wf["wavefront"].image) else "no"}
    else:
        out["wavefront"] = {"time_ratio": math.nan, "identical": "not in this program"}

    # Which integrators the program accepts for a scene with a medium, and with motion blur.
    for key, scene in (("media", "cornell-fog"), ("motion", "motion")):
        ok = [i for i in ("path", "bdpt", "vcm") if supports(r, ["--integrator", i], scene=scene)]
        out[key] = {"integrators": ", ".join(f"`{i}`" for i in ok) or "none",
                    "refused": ", ".join(f"`{i}`" for i in ("path", "bdpt", "vcm") if i not in ok) or "none"}

    # Textures, rough glass and a homogeneous medium in every integrator that accepts them: each
    # integrator's mean luminance against path tracing's (same expected image where path tracing
    # samples all the light; the ratio's distance from 1 is then noise or a bias). prism-haze's
    # spot light reaches the haze behind the prism only through the glass, which path tracing
    # cannot sample (section 3): its ratio measures the light the path tracer misses.
    lum = np.array([0.2126, 0.7152, 0.0722])
    for key, scene, size in (("textured", "textured", n), ("frosted", "frosted-glass", n),
                             ("haze", "prism-haze", n)):
        integs = [i for i in ("path", "bdpt", "vcm") if i == "path" or supports(r, ["--integrator", i], scene=scene)]
        imgs = {i: r.render(scene, width=size, spp=p["integrators_spp"], seed=28, integrator=i) for i in integs}
        means = {i: float((x.image @ lum).mean()) for i, x in imgs.items()}
        out[key] = {f"{i}_vs_path": ratio(means[i], means["path"]) for i in integs if i != "path"}
        out[key]["path_vs_bdpt"] = ratio(means["path"], means["bdpt"]) if "bdpt" in means else math.nan
        out[key]["integrators"] = ", ".join(f"`{i}`" for i in integs)
        out[key].update({f"seconds_{i}": x.seconds for i, x in imgs.items()})
        panels(figs / f"{key}_integrators.png", [load_png(x.png) for x in imgs.values()],
               [f"{i}: {x.seconds:.1f} s, mean / path {ratio(means[i], means['path']):.3f}" for i, x in imgs.items()])
    # Depth of field and motion blur: the scene as it is against a copy with the effect switched
    # off in its camera (aperture 0: a pinhole; shutter closed to one instant), at equal spp with
    # the scene's own integrator.
    scratch = figs.parent / "scenes"
    for key, scene, camera, labels in (
            ("dof", "bokeh", {"aperture_radius": 0.0}, ("pinhole (aperture_radius 0)", "thin lens, as in the scene")),
            ("motion_blur", "motion", {"shutter": [0.0, 0.0]}, ("shutter [0, 0]: one instant", "shutter [0, 1]"))):
        off = r.render(scene_variant(scene, camera, scratch), width=n, spp=p["integrators_spp"], seed=5)
        on = r.render(scene, width=n, spp=p["integrators_spp"], seed=5)
        out[key] = {"seconds_off": off.seconds, "seconds_on": on.seconds, "time_ratio": ratio(on.seconds, off.seconds)}
        panels(figs / f"{key}.png", [load_png(off.png), load_png(on.png)],
               [f"{labels[0]}: {off.seconds:.1f} s", f"{labels[1]}: {on.seconds:.1f} s"])
    out["spp"], out["integrators_spp"] = spp, p["integrators_spp"]
    return out


def scene_variant(name: str, camera: dict, folder: Path) -> Path:
    """A copy of scenes/<name>.json with these camera keys replaced, written to `folder`; the files
    it names (meshes, textures) by absolute path, so that the copy loads from anywhere."""
    scene = json.loads((ROOT / "scenes" / f"{name}.json").read_text())
    scene["camera"].update(camera)

    def absolute(node):
        if isinstance(node, dict):
            return {k: (str(ROOT / "scenes" / v) if k == "file" and isinstance(v, str) else absolute(v))
                    for k, v in node.items()}
        if isinstance(node, list):
            return [absolute(v) for v in node]
        return node

    path = folder / f"{name}-variant-{hashlib.sha256(json.dumps(camera).encode()).hexdigest()[:8]}.json"
    path.write_text(json.dumps(absolute(scene), indent=1) + "\n")
    return path


def gallery_section(r: Renderer, p: dict, figs: Path) -> dict:
    """Every built-in scene at its own spp and integrator, `gallery_width` wide."""
    folder = figs / "gallery"
    folder.mkdir(exist_ok=True)
    lines = ["| render | scene | size | spp | integrator | time (s) |", "|---|---|---|---|---|---:|"]
    times = {}
    for name, w, h, scene_spp, integrator, summary in gallery.list_scenes(str(r.program)):
        width = p["gallery_width"]
        spp = p["gallery_spp"] or scene_spp
        x = r.render(name, width=width, spp=spp, seed=0, integrator=integrator)
        shutil.copyfile(x.png, folder / f"{name}.png")
        save_png_optimized(folder / f"{name}.png")
        times[name] = x.seconds
        lines.append(f"| ![{name}](figures/gallery/{name}.png) | `{name}`: {summary} | "
                     f"{width}×{round(width * h / w)} | {x.spp} | {integrator} | {x.seconds:.1f} |")
    return {"table": "\n".join(lines), "count": len(times), "times": times}


def scaled(spp: int, fraction: float) -> int:
    return max(1, round(spp * fraction))


def colour_section(r: Renderer, p: dict, figs: Path) -> dict:
    w, h = p["chart_size"] or (None, None)
    cpu0 = child_cpu_seconds()
    f = r.fraction
    results = [color_accuracy.evaluate(r.program, ill, scaled(p["chart_spp"], f), bin_counts=p["chart_bins"],
                                       exact_spp=scaled(p["chart_exact_spp"], f) if p["chart_exact_spp"] else None,
                                       width=w, height=h)
               for ill in color_accuracy.SCENES]
    # Its renders use every core (the program's default threads): CPU time over the cores.
    r.projected += (child_cpu_seconds() - cpu0) / f / (os.cpu_count() or 1)
    color_accuracy.plot(results, figs / "color_accuracy.png")
    save_png_optimized(figs / "color_accuracy.png")
    out = {}
    lines = ["| illuminant | bins | mean ΔE2000 | max ΔE2000 | floor of the bins (mean) |", "|---|---|---:|---:|---:|"]
    for res in results:
        d = {"exact_mean": res.exact.render_mean, "exact_max": res.exact.render_max, "exact_spp": res.exact.spp}
        for b, br in res.bins.items():
            d[f"bins_{b}_mean"] = br.render_mean
            d[f"bins_{b}_floor"] = br.floor_mean
            lines.append(f"| {res.illuminant} | {b} | {br.render_mean:.3f} | {br.render_max:.3f} | {br.floor_mean:.3f} |")
        out[res.illuminant] = d
    out["table"] = "\n".join(lines)
    out["spp"] = p["chart_spp"]
    return out


def scaled_accuracy_argv(argv: list[str], fraction: float) -> tuple[list[str], float]:
    """accuracy_cost.py's arguments with every spp scaled by about `fraction` (kept distinct, so
    the study renders as many points), into a cache and output folder of their own; and the
    fraction of the samples this keeps (sweep plus reference), which the CPU time scales back by."""
    a = accuracy_cost.parse_args(argv)
    spp = [max(1, round(s * fraction)) for s in a.spp]
    for i in range(1, len(spp)):
        spp[i] = max(spp[i], spp[i - 1] + 1)
    bins = spp[a.spp.index(a.bins_spp)]
    ref = max(2, round(max(a.ref_spp.values()) * fraction))
    out = [w for w in argv]
    for flag in ("--spp", "--bins-spp", "--reference-spp", "--out", "--cache-dir", "--run-tag"):
        if flag in out:
            i = out.index(flag) + 1
            while i < len(out) and not out[i].startswith("--"):
                del out[i]
            del out[i - 1]
    tag = f"estimate-{fraction:g}"
    # Each spp value is rendered with as many seeds as in the full run (the counts go by position
    # in the sweep), so weigh it by its mean seed count over the scenes.
    seeds = [sum(accuracy_cost.seeds_at(sc, n, a) for sc in a.scenes) / len(a.scenes) for n in a.spp]
    kept = (sum(w * n for w, n in zip(seeds, spp)) + ref) / (sum(w * n for w, n in zip(seeds, a.spp))
                                                             + max(a.ref_spp.values()))
    return out + ["--spp", *map(str, spp), "--bins-spp", str(bins), "--reference-spp", str(ref),
                  "--out", str(a.out.parent / f"accuracy-{tag}"), "--cache-dir", str(a.cache_dir),
                  "--run-tag", tag], kept


def save_png_optimized(path: Path) -> None:
    from PIL import Image
    Image.open(path).convert("RGB").save(path, optimize=True)


def accuracy_section(r: Renderer, p: dict, figs: Path, cache: Path) -> dict:
    """validation/accuracy_cost.py with every integrator against bdpt references."""
    folder = figs.parent / "accuracy"
    argv = p["accuracy_cost"] + ["--plot-per-scene", "--program", str(r.program), "--out", str(folder),
                                 "--cache-dir", str(cache / "accuracy-cost")]
    fraction = 1.0
    if r.fraction != 1:  # --estimate: every spp (sweep, bins, references) at about the fraction
        argv, fraction = scaled_accuracy_argv(argv, r.fraction)
        folder = Path(argv[argv.index("--out") + 1])
    cpu0 = child_cpu_seconds()
    accuracy_cost.main(argv)
    r.projected += (child_cpu_seconds() - cpu0) / fraction / p["threads"]
    # One copy of the plot, with the other figures (accuracy/ keeps the study's table and data).
    shutil.move(folder / "accuracy_cost.png", figs / "accuracy_cost.png")
    save_png_optimized(figs / "accuracy_cost.png")
    # The text shows the panels one by one, each legible at the page's width.
    panel_lines = []
    for i, panel in enumerate(sorted(folder.glob("accuracy_cost_*.png"), key=lambda f: int(f.stem.rsplit("_", 1)[1]))):
        shutil.move(panel, figs / f"accuracy_cost_{i}.png")
        save_png_optimized(figs / f"accuracy_cost_{i}.png")
        panel_lines.append(f"![error against render time, panel {i + 1}](figures/accuracy_cost_{i}.png)")
    data = json.loads((folder / "accuracy_cost.json").read_text())
    # Per scene and integrator: the spp sweep at the defaults (path's is the knob "spp").
    lines = ["| scene | integrator | reference | spp | seeds | time (s) | error ± s.e. | efficiency | slope of error vs spp |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    out = {"scenes": {}}
    rises = []  # steps of a curve where the mean error rises by more than 2 standard errors
    for scene, s in data["scenes"].items():
        out["scenes"][scene] = {}
        for integ in ("path", "bdpt", "vcm"):
            pts = sorted((q for q in s["points"] if (q["knob"] == "spp" and integ == "path")
                          or (q["knob"] == "integrator" and q["value"] == integ)), key=lambda q: q["spp"])
            if not pts:
                continue
            good = [q for q in pts if q["error"] and q["error"] > 0]
            slope, se = loglog_fit([q["spp"] for q in good], [q["error"] for q in good]) if len(good) >= 2 \
                else (math.nan, math.nan)
            last = pts[-1]
            for a, b in zip(pts, pts[1:]):
                if a["error"] is None or b["error"] is None or b["error"] <= a["error"]:
                    continue
                bar = math.hypot(a.get("error_se") or 0.0, b.get("error_se") or 0.0)
                if bar == 0 or b["error"] - a["error"] > 2 * bar:
                    rises.append(f"{scene}/{integ} {a['spp']}→{b['spp']} spp")
            out["scenes"][scene][integ] = {"spp": last["spp"], "time": last["time"], "error": last["error"],
                                           "error_se": last.get("error_se"), "seeds": last.get("seeds", 1),
                                           "efficiency": last["efficiency"], "slope": slope, "slope_se": se}
            bar = last.get("error_se")
            lines.append(f"| {scene} | {integ} | {s['reference']} | {last['spp']} | {last.get('seeds', 1)} | "
                         f"{last['time'] or math.nan:.2f} | {last['error'] or math.nan:.3g}"
                         + (f" ± {bar:.2g}" if bar is not None else "") + f" | {last['efficiency'] or math.nan:.3g} | "
                         f"{slope:.2f} ± {se:.2f} |")
    out["table"] = "\n".join(lines)
    best, flatter = [], []
    for scene, by_integ in out["scenes"].items():
        ranked = sorted(((v["efficiency"] or 0.0, integ) for integ, v in by_integ.items()), reverse=True)
        if len(ranked) > 1:
            best.append(f"`{scene}` {ranked[0][1]} ({ranked[0][0]:.3g}/s; next {ranked[1][1]}, {ranked[1][0]:.3g}/s)")
        for integ, v in by_integ.items():
            target = -0.5 if scene == accuracy_cost.CHART_SCENE else -1.0
            if math.isfinite(v["slope_se"]) and v["slope"] - target > 2 * v["slope_se"]:
                flatter.append(f"`{scene}` {integ} ({v['slope']:.2f} ± {v['slope_se']:.2f})")
    out["best"] = "; ".join(best) or "—"
    out["flatter"] = ", ".join(flatter) or "none"
    out["monotone"] = ("every curve of this table falls from each spp to the next, or rises by less than two "
                       "standard errors" if not rises else
                       "these steps rise by more than two standard errors: " + ", ".join(rises))
    out["report"] = "accuracy/accuracy_cost.md"
    args = accuracy_cost.parse_args(argv)
    out["height"], out["chart_height"] = args.height, args.chart_height
    out["reference_spp"] = ", ".join(sorted({str(v) for v in args.ref_spp.values()}))
    noisy = [sc for sc in args.noisy_scenes if sc in args.scenes]
    others = f"{args.seeds} seed{'s' if args.seeds != 1 else ''} per point"
    out["seeds_note"] = (
        "; ".join(f"`{sc}` averages " + ", ".join(f"{accuracy_cost.seeds_at(sc, n, args)} at {n}" for n in args.spp)
                  + " spp" for sc in noisy)
        + " (many seeds where a render is cheap and holds few of the bright samples, few where one render "
        f"already holds many and its relMSE spreads less), the other scenes {others}" if noisy
        else f"every scene {others}")
    out["figures"] = "\n\n".join(panel_lines) or "![error against render time](figures/accuracy_cost.png)"
    return out


# ------------------------------------------------------------------------------------------
# The text


KEY = re.compile(r"\{\{\s*([\w./ -]+?)\s*(?::\s*([^}]*?))?\s*\}\}")


def lookup(results: dict, dotted: str):
    value = results
    for part in dotted.split("."):
        value = value[part]
    return value


def fill_template(template: str, results: dict) -> str:
    """{{a.b.c}} or {{a.b.c:.3g}} → the value from results (formatted); every key must exist."""
    missing = []

    def replace(m: re.Match) -> str:
        try:
            value = lookup(results, m.group(1))
        except (KeyError, TypeError):
            missing.append(m.group(1))
            return m.group(0)
        return format(value, m.group(2)) if m.group(2) else str(value)

    text = KEY.sub(replace, template)
    if missing:
        raise SystemExit(f"build_report.py: report.md.in names keys that results.json lacks: {', '.join(missing)}")
    return text


def check_figures(text: str, out: Path) -> None:
    refs = re.findall(r"\]\((figures/[^)]+)\)", text)
    absent = [f for f in refs if not (out / f).is_file()]
    if absent:
        raise SystemExit(f"build_report.py: the text shows figures that were not produced: {', '.join(absent)}")


def strip_private(d):
    if isinstance(d, dict):
        return {k: strip_private(v) for k, v in d.items() if not k.startswith("_")}
    return d


def git_commit() -> str:
    try:
        sha = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                             check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                               capture_output=True, text=True).stdout.strip()
        return sha[:12] + (" (with uncommitted changes)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown (not a git checkout)"


# What the report is built from: the renderer's source and data, the report's own scripts and
# template, and the validation modules and measurement files it reads. Its outputs (README.md,
# results.json, figures/, report.pdf) are not inputs, so committing them keeps the hash.
# validation/test_report_current.py compares the hash recorded in docs/report/results.json with
# the tree's: a report built from another program fails it.
REPORT_INPUTS = ("src", "spectra", "scenes", "CMakeLists.txt", "cmake",
                 "docs/report/build_report.py", "docs/report/report.md.in", "docs/report/make_pdf.py",
                 "docs/report/build_pdf.sh", "docs/report/requirements-pdf.txt",
                 "validation/accuracy_cost.py", "validation/bdpt_compare.py", "validation/benchmark.py",
                 "validation/color_accuracy.py", "validation/gallery.py",
                 "validation/results/parallel_strategies.md", "bench/README.md")


def input_files(root: Path) -> list[str]:
    """The report's input files under `root` (relative, sorted): the files git tracks there, or in
    a tree that is not a git checkout every file but Python caches."""
    try:
        listed = subprocess.run(["git", "ls-files", "-z", "--", *REPORT_INPUTS], cwd=root, capture_output=True,
                                check=True).stdout.decode()
        if listed:
            return sorted(f for f in listed.split("\0") if f and (root / f).is_file())
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for entry in REPORT_INPUTS:
        path = root / entry
        if path.is_file():
            files.append(entry)
        elif path.is_dir():
            files += [f.relative_to(root).as_posix() for f in path.rglob("*")
                      if f.is_file() and "__pycache__" not in f.parts and f.suffix != ".pyc"]
    return sorted(files)


def inputs_sha256(root: Path = ROOT) -> str:
    """sha256 over the report's input files: each relative path and its contents."""
    h = hashlib.sha256()
    for rel in input_files(root):
        data = (root / rel).read_bytes()
        h.update(f"{rel}\0{len(data)}\0".encode())
        h.update(data)
    return h.hexdigest()


def measured_files(r: Renderer, p: dict, figs: Path) -> dict:
    """Numbers the report quotes from measurements committed elsewhere (timings that need an
    idle machine and an external library): the parallel strategies' table and the BVH against
    Embree. Read from the files at build time, so the text follows them."""
    out = {}
    text = (ROOT / "validation" / "results" / "parallel_strategies.md").read_text()
    rows = {}
    header = None
    for line in text.splitlines():
        cells = [c.strip().strip("*") for c in line.strip().strip("|").split("|")]
        if line.startswith("| variant"):
            header = cells
        elif header and line.startswith("|") and not line.startswith("|---") and len(cells) == len(header):
            rows[cells[0]] = dict(zip(header[1:], (float(c) for c in cells[1:])))
    tiles, wave = rows["tiles 32, mutex"], rows["wavefront, mutex"]
    measured = re.search(r"\*\*Measured at ([^*]*?)\*\*", text)
    out["parallel"] = {"note": measured.group(1).rstrip(".:") if measured else "see the file",
                       "tiles_cornell_1": tiles["cornell 1T"], "tiles_cornell_2": tiles["cornell 2T"],
                       "wavefront_cornell_1": wave["cornell 1T"], "wavefront_cornell_2": wave["cornell 2T"],
                       "pixel_cornell_2": rows["tiles pixel, mutex"]["cornell 2T"],
                       "scaling_cornell": ratio(tiles["cornell 2T"], tiles["cornell 1T"]),
                       "wavefront_vs_tiles": {k: ratio(wave[k], tiles[k]) for k in tiles},
                       "wavefront_vs_tiles_range": "{:.2f}–{:.2f}".format(
                           min(ratio(wave[k], tiles[k]) for k in tiles), max(ratio(wave[k], tiles[k]) for k in tiles))}
    # bench/README.md: one block per mesh, "N triangles (name)", then "build: ... (ours/Embree Rx)"
    # and "SET  T thread(s): ... ours/Embree R".
    text = (ROOT / "bench" / "README.md").read_text()
    lines = ["| mesh | triangles | build time | camera 1T | camera 2T | diffuse 1T | diffuse 2T | shadow 1T | shadow 2T |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    meshes = {}
    for block in re.split(r"\n(?=\d+ triangles \()", text)[1:]:
        head = re.match(r"(\d+) triangles \(([^)]+)\)", block)
        build = re.search(r"build: .*\(ours/Embree ([0-9.]+)x\)", block)
        rays = dict(((m.group(1), m.group(2)), float(m.group(3))) for m in
                    re.finditer(r"(camera|diffuse|shadow)\s+(\d) threads?\s*:.*ours/Embree ([0-9.]+)", block))
        if not (head and build and len(rays) == 6):
            continue
        name = head.group(2) if head.group(2) != "generated" else f"generated {head.group(1)}"
        meshes[name] = {"triangles": int(head.group(1)), "build": float(build.group(1)),
                        **{f"{k}_{t}": v for (k, t), v in rays.items()}}
        lines.append(f"| {name} | {int(head.group(1)):,} | {float(build.group(1)):.2f} | " +
                     " | ".join(f"{rays[(k, t)]:.2f}" for k in ("camera", "diffuse", "shadow") for t in ("1", "2")) + " |")
    measured = re.search(r"Measured at ([^\n]*\n[^\n]*)", text)

    def spread(cols: tuple[str, ...], names=None) -> str:
        vals = [m[c] for n, m in meshes.items() if names is None or n in names for c in cols]
        return f"{min(vals):.2f}–{max(vals):.2f}" if vals else "—"

    large = [n for n, m in meshes.items() if m["triangles"] >= 200_000]
    cells = [(m[f"{k}_{t}"], n, k, t) for n, m in meshes.items() for k in ("camera", "diffuse", "shadow")
             for t in ("1", "2")]
    low, high = min(cells), max(cells)
    out["embree_summary"] = {
        "camera_2": spread(("camera_2",)), "camera_1": spread(("camera_1",)),
        "incoherent_1": spread(("diffuse_1", "shadow_1")),
        "incoherent_2_large": spread(("diffuse_2", "shadow_2"), large),
        "large_meshes": ", ".join(large), "build": spread(("build",)),
        "lowest": f"{low[0]:.2f} ({low[2]} rays, {low[3]} thread{'s' if low[3] != '1' else ''}, {low[1]})",
        "highest": f"{high[0]:.2f} ({high[2]} rays, {high[3]} thread{'s' if high[3] != '1' else ''}, {high[1]})",
    } if meshes else {}
    out["embree"] = {"table": "\n".join(lines), "meshes": meshes,
                     "note": " ".join(measured.group(1).replace("*", "").split()).rstrip(":,")
                     if measured else "see bench/README.md"}
    return out


SECTIONS = {
    "convergence": convergence,
    "materials": lambda r, p, figs, ctx: materials(r, p, figs, ctx["scratch"]),
    "lights": lights,
    "gi": gi_effects,
    "point_caustic": point_caustic,
    "extensions": extensions,
    "files": measured_files,
    "colour": colour_section,
    "accuracy": lambda r, p, figs, ctx: accuracy_section(r, p, figs, ctx["cache"]),
    "gallery": gallery_section,
}
NEEDS_CONTEXT = ("materials", "accuracy")


def settings_hash(p: dict, r: Renderer) -> str:
    """What a section's cached results depend on: the settings and the program (binary hash)."""
    return hashlib.sha256(json.dumps([p, r.sha, r.fraction], default=str).encode()).hexdigest()[:16]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="tiny sizes (CI): checks every figure and number is made")
    ap.add_argument("--out", type=Path, help="output folder (default docs/report; with --quick build/report-quick)")
    ap.add_argument("--program", type=Path, help="the renderer (default $SPT_PATHTRACER, else build/pathtracer)")
    ap.add_argument("--cache-dir", type=Path, default=ROOT / "build" / "report-cache")
    ap.add_argument("--only", action="append", choices=list(SECTIONS), metavar="SECTION",
                    help="re-run this section (repeatable); every other section's numbers come from its cached "
                         f"results of an earlier run with the same settings and program. Sections: {', '.join(SECTIONS)}")
    ap.add_argument("--from-results", type=Path, metavar="RESULTS_JSON",
                    help="with --only: a section without cached results of these settings and program takes its "
                         "numbers from this results.json of an earlier run (e.g. the committed "
                         "docs/report/results.json); the report then names that run's date, commit and program "
                         "for those sections")
    ap.add_argument("--estimate", type=float, metavar="FRACTION",
                    help="render every stage at FRACTION of its spp (and time limits) into a cache of its own and "
                         "print what each stage would take on idle cores (CPU time scaled up); writes no report")
    a = ap.parse_args(argv)
    if a.estimate is not None and not 0 < a.estimate <= 1:
        ap.error(f"--estimate: expected a fraction in (0, 1], got {a.estimate}")
    if a.from_results is not None and not a.only:
        ap.error("--from-results: only with --only (the sections not re-run take their numbers from it)")
    earlier = json.loads(a.from_results.read_text()) if a.from_results is not None else None
    p = QUICK if a.quick else FULL
    mode = "quick" if a.quick else "full"
    out = a.out or (ROOT / "build" / "report-quick" if a.quick else REPORT_DIR)
    if a.estimate is not None:
        out = a.out or (ROOT / "build" / f"report-estimate-{mode}")
    program = (a.program or Path(os.environ.get("SPT_PATHTRACER") or ROOT / "build" / "pathtracer")).resolve()
    if not os.access(program, os.X_OK):
        ap.error(f"--program: {program} is not an executable file; build the renderer first")
    figs = out / "figures"
    figs.mkdir(parents=True, exist_ok=True)
    scratch = out / "scenes"
    scratch.mkdir(exist_ok=True)
    cache = a.cache_dir / mode
    r = Renderer(program, cache, p["threads"], a.estimate or 1.0)
    section_cache = r.cache / "sections"
    section_cache.mkdir(exist_ok=True)
    tag = settings_hash(p, r)
    ctx = {"scratch": scratch, "cache": cache}
    started = time.perf_counter()
    results: dict = {"run": {
        "mode": mode,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "commit": git_commit(), "program": r.version, "program_sha256": r.sha[:16],
        "inputs_sha256": inputs_sha256(),
        "machine": f"{benchmark.cpu_model()}, {os.cpu_count()} logical CPUs, {platform.system()} {platform.release()}",
        "threads": p["threads"], "size": p["size"],
    }}
    stage_seconds, projected, failed, from_earlier = {}, {}, [], []
    for name, step in SECTIONS.items():
        cached = section_cache / f"{name}-{tag}.json"
        if a.only and name not in a.only:
            if a.estimate:  # an estimate of some sections writes no report: nothing to fill in
                continue
            if not cached.is_file() and earlier is not None and name in earlier:
                results[name] = earlier[name]
                stage_seconds[name] = earlier["run"].get("stage_seconds", {}).get(name, 0.0)
                from_earlier.append(name)
                say(f"== {name}: from {a.from_results} ({earlier['run'].get('date')}, commit "
                    f"{earlier['run'].get('commit')})")
                continue
            if not cached.is_file():
                raise SystemExit(f"build_report.py: --only: no cached results of section '{name}' for these "
                                 f"settings and this program; run it too (--only {name}), pass --from-results, "
                                 "or run without --only")
            saved = json.loads(cached.read_text())
            results[name], stage_seconds[name] = saved["results"], saved["seconds"]
            say(f"== {name}: cached ({saved['seconds']:.1f} s when it ran)")
            continue
        t0, p0 = time.perf_counter(), r.projected
        say(f"== {name}")
        try:
            results[name] = step(r, p, figs, ctx) if name in NEEDS_CONTEXT else step(r, p, figs)
        except Exception as e:  # noqa: BLE001 - one failed stage must not cost the others
            failed.append(name)
            say(f"   FAILED: {type(e).__name__}: {e}")
            continue
        stage_seconds[name] = time.perf_counter() - t0
        projected[name] = r.projected - p0
        cached.write_text(json.dumps({"results": strip_private(results[name]), "seconds": stage_seconds[name]},
                                     default=float) + "\n")
        say(f"   {stage_seconds[name]:.1f} s" + (f" (projected on idle cores at full spp: {projected[name]:.0f} s)"
                                               if a.estimate else ""))
    shutil.rmtree(scratch, ignore_errors=True)
    say("\nwall time per stage (s):")
    for name, t in stage_seconds.items():
        say(f"  {name:14s} {t:8.1f}" + (f"   projected {projected[name]:8.0f}" if name in projected and a.estimate else ""))
    if a.estimate:
        total = sum(projected.values())
        say(f"  {'total':14s} {sum(stage_seconds.values()):8.1f}   projected {total:8.0f} s = {total / 60:.1f} min "
            f"(renders only; CPU time of the renders at fraction {a.estimate:g}, scaled by 1/{a.estimate:g}, "
            f"over {p['threads']} threads)")
        (out / "estimate.json").write_text(json.dumps({"fraction": a.estimate, "projected_seconds": projected,
                                                        "stage_seconds": stage_seconds}, indent=1) + "\n")
    if failed:
        say(f"\nbuild_report.py: failed stage(s): {', '.join(failed)}; the others are cached: rerun with "
            + " ".join(f"--only {f}" for f in failed))
        return 1
    if a.estimate:
        return 0
    results["run"]["stage_seconds"] = {k: round(v, 1) for k, v in stage_seconds.items()}
    # Which sections' numbers come from an earlier run (--from-results): the text names it.
    results["run"]["earlier_sections"] = from_earlier
    results["run"]["provenance"] = "" if not from_earlier else (
        f" The sections {', '.join(from_earlier)} keep the numbers and figures of an earlier run: "
        f"{earlier['run'].get('date')}, commit `{earlier['run'].get('commit')}`, program sha256 "
        f"`{earlier['run'].get('program_sha256')}`, on {earlier['run'].get('machine')}.")
    results["run"]["stage_list"] = ", ".join(f"{k} {v / 60:.1f}" for k, v in stage_seconds.items()) + " min"
    results["run"]["minutes"] = sum(stage_seconds.values()) / 60
    results["run"]["this_invocation_minutes"] = (time.perf_counter() - started) / 60
    results = strip_private(results)
    (out / "results.json").write_text(json.dumps(results, indent=1, default=float) + "\n")
    text = fill_template((REPORT_DIR / "report.md.in").read_text(), results)
    check_figures(text, out)
    (out / "README.md").write_text(text)
    say(f"wrote {out / 'README.md'}, {out / 'results.json'} and {len(list(figs.rglob('*.png')))} figures "
        f"in {results['run']['this_invocation_minutes']:.1f} min (stages: {results['run']['minutes']:.1f} min)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
