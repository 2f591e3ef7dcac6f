#!/usr/bin/env python3
"""Builds the report: renders every figure, measures every number it quotes, and writes

    OUT/figures/*.png   the figures (compressed PNG)
    OUT/results.json    every number the text quotes (and the machine, date and commit)
    OUT/README.md       docs/report/report.md.in with each {{key}} replaced from results.json

Full mode (OUT = docs/report, the committed report; hours on 2 cores, run it on an idle machine):

    VENV=$(bash validation/setup_venv.sh)
    $VENV/bin/python docs/report/build_report.py

Quick mode (CI: tiny sizes, about a minute; OUT = build/report-quick, the tree stays clean). It
checks that every figure is produced and that every key the text names has a value:

    $VENV/bin/python docs/report/build_report.py --quick

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

# Every size, sample count and time of a run. Quick: the pipeline in about a minute.
FULL = {
    "size": 256, "threads": 2,
    "conv_spp": [1, 4, 16, 64, 256, 1024], "ref_spp": 16384,
    "material_spp": 64, "material_ref_spp": 4096, "equal_seconds": 30.0,
    "effects_size": 512, "effects_spp": 1024,
    "caustic_seconds": 60.0, "caustic_ref_spp": 16384,
    "extension_spp": 256, "gallery_width": 512, "gallery_spp": None,
    "chart_spp": 128, "chart_exact_spp": 2048, "chart_size": None, "chart_bins": (4, 8, 16, 32, 64),
    "accuracy_cost": ["--height", "256", "--integrators", "path", "bdpt", "vcm",
                      "--reference-integrator", "bdpt"],
}
QUICK = {
    "size": 32, "threads": 2,
    "conv_spp": [1, 2, 4, 8, 16], "ref_spp": 128,
    "material_spp": 4, "material_ref_spp": 64, "equal_seconds": 0.3,
    "effects_size": 48, "effects_spp": 8,
    "caustic_seconds": 0.3, "caustic_ref_spp": 64,
    "extension_spp": 4, "gallery_width": 32, "gallery_spp": 2,
    "chart_spp": 4, "chart_exact_spp": 0, "chart_size": None, "chart_bins": (16,),
    "accuracy_cost": ["--quick", "--scenes", "cornell-point", "--integrators", "path", "bdpt", "vcm",
                      "--reference-integrator", "bdpt", "--spp", "4", "16", "--bins-spp", "16",
                      "--depths", "1", "--wavelengths-per-path", "4"],
}

# A reference must hold all the light transport of its scene: bdpt does (it connects to point
# lights through glass, which path tracing cannot); `cornell` is lit by an emitting infinite
# plane that bdpt reaches by camera paths only, so there both are path tracing.
def reference_integrator(scene: str) -> str:
    return "path" if scene == "cornell" else "bdpt"


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
    def __init__(self, program: Path, cache: Path, threads: int):
        self.program = program
        self.sha = benchmark.sha256_file(program)
        self.version = subprocess.run([str(program), "--version"], capture_output=True, text=True,
                                      check=True).stdout.strip()
        self.cache = cache / self.sha[:12]
        self.cache.mkdir(parents=True, exist_ok=True)
        self.threads = threads
        self.seconds = 0.0

    def render(self, scene: str | Path, *, width: int, height: int | None = None, spp: int = 16,
               seed: int = 0, integrator: str | None = None, time_limit: float | None = None,
               extra: tuple[str, ...] = ()) -> Render:
        """One render of a built-in scene (name) or scene file (Path), cached by its command."""
        flags = ["--width", str(width)] + (["--height", str(height)] if height else [])
        flags += ["--spp", str(spp), "--seed", str(seed), "--threads", str(self.threads)]
        if integrator:
            flags += ["--integrator", integrator]
        if time_limit is not None:
            flags += ["--time-limit", str(time_limit)]
        flags += list(extra)
        scene_id = Path(scene).read_text() if isinstance(scene, Path) else scene
        key = hashlib.sha256(json.dumps([scene_id, flags]).encode()).hexdigest()[:20]
        pfm, png, meta = (self.cache / f"{key}.{ext}" for ext in ("pfm", "png", "json"))
        if not meta.is_file():
            cmd = [str(self.program), str(scene), *flags, "-o", str(pfm), "-o", str(png)]
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                raise RuntimeError(f"{' '.join(cmd)} failed ({run.returncode}):\n{run.stderr}")
            seconds = float(re.search(r"time ([0-9.]+) s,", run.stderr).group(1))
            stopped = re.search(r"stopped by --time-limit \S+ s after (\d+) of", run.stderr)
            meta.write_text(json.dumps({"seconds": seconds, "spp": int(stopped.group(1)) if stopped else spp,
                                        "command": cmd[1:]}))
            self.seconds += seconds
        m = json.loads(meta.read_text())
        return Render(bdpt_compare.read_pfm(str(pfm)), png, m["seconds"], m["spp"])

    def reference(self, scene: str | Path, *, width: int, spp: int, integrator: str,
                  height: int | None = None) -> tuple[np.ndarray, float]:
        """(reference image, its own relMSE noise): two halves with different seeds; the noise
        of their mean is mean((a − b)²/w)/4 (as accuracy_cost.py's references)."""
        a, b = (self.render(scene, width=width, height=height, spp=max(1, spp // 2), seed=987654321 + i,
                            integrator=integrator).image for i in (0, 1))
        ref = (a + b) / 2
        return ref, float(np.mean((a - b) ** 2 / accuracy_cost.w_of(ref)) / 4)


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
    refs = {}
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for scene, integ in series:
        if scene not in refs:
            refs[scene] = r.reference(scene, width=p["size"], height=p["size"], spp=p["ref_spp"],
                                      integrator=reference_integrator(scene))
        ref, noise = refs[scene]
        pts = []
        for spp in p["conv_spp"]:
            x = r.render(scene, width=p["size"], height=p["size"], spp=spp, seed=1000 + spp, integrator=integ)
            pts.append((spp, rel_mse(x.image, ref, noise), x.seconds))
        good = [(s, e) for s, e, _ in pts if e > 0]
        slope, se = loglog_fit([s for s, _ in good], [e for _, e in good]) if len(good) >= 2 else (math.nan, math.nan)
        name = f"{scene}/{integ}"
        out[name] = {"scene": scene, "integrator": integ, "slope": slope, "slope_se": se,
                     "reading": slope_reading(slope, se),
                     "reference": f"{reference_integrator(scene)}, {p['ref_spp']} spp",
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
    out["_refs"] = refs
    out["spp_min"], out["spp_max"] = min(p["conv_spp"]), max(p["conv_spp"])
    out["spp_range"] = f"{out['spp_min']}–{out['spp_max']}"
    out["ref_spp"] = p["ref_spp"]
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
        ref, noise = r.reference(scene, width=n, height=n, spp=p["material_ref_spp"], integrator="bdpt")
        x = r.render(scene, width=n, height=n, spp=p["material_spp"], seed=7, integrator="path")
        e = rel_mse(x.image, ref, noise)
        # The sphere's pixels: a box around its image (centre (0, −0.55, 0), radius 0.45).
        box = (slice(int(0.52 * n), int(0.92 * n)), slice(int(0.3 * n), int(0.7 * n)))
        e_sphere = float(np.mean((x.image[box] - ref[box]) ** 2 / accuracy_cost.w_of(ref[box])))
        out[name] = {"relmse": e, "relmse_sphere": e_sphere, "seconds": x.seconds,
                     "efficiency": ratio(1.0, e * x.seconds) if e > 0 else math.inf}
        rows.append(f"| {name} | {e:.4g} | {e_sphere:.4g} | {x.seconds:.2f} | {out[name]['efficiency']:.3g} |")
        imgs.append(load_png(x.png))
        titles.append(f"{name}: relMSE {e:.3g}")
    base = out["diffuse"]["relmse"]
    for name in out:
        out[name]["vs_diffuse"] = out[name]["relmse"] / base if base > 0 else math.nan
    panels(figs / "materials.png", imgs, titles, inset=(0.3, 0.52, 0.4, 0.4))
    out["table"] = "\n".join(["| sphere | relMSE (image) | relMSE (sphere box) | time (s) | 1/(relMSE·time) |",
                              "|---|---:|---:|---:|---:|"] + rows)
    out["spp"], out["ref_spp"] = p["material_spp"], p["material_ref_spp"]
    return out


def lights(r: Renderer, p: dict, figs: Path, refs: dict) -> dict:
    """Point, sphere and quad light of the same power at equal render time (path tracing)."""
    out, imgs, titles = {}, [], []
    n = p["size"]
    for scene in ("cornell-point", "cornell-sphere", "cornell-quad"):
        if scene not in refs:
            refs[scene] = r.reference(scene, width=n, height=n, spp=p["ref_spp"], integrator="bdpt")
        ref, noise = refs[scene]
        x = r.render(scene, width=n, height=n, spp=1_000_000, seed=11, integrator="path",
                     time_limit=p["equal_seconds"], extra=("--pass-spp", "1"))
        e = rel_mse(x.image, ref, noise)
        out[scene] = {"relmse": e, "spp": x.spp, "seconds": x.seconds}
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
    n = p["effects_size"]
    ref, noise = r.reference("cornell-point", width=n, height=n, spp=p["caustic_ref_spp"], integrator="bdpt")
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


def supports(r: Renderer, flags: list[str]) -> bool:
    """Whether the program accepts these flags (a one-pixel render)."""
    run = subprocess.run([str(r.program), "cornell", "--width", "1", "--height", "1", "--spp", "1", "--quiet",
                          "-o", str(r.cache / "probe.pfm"), *flags], capture_output=True, text=True)
    return run.returncode == 0


def extensions(r: Renderer, p: dict, figs: Path, refs: dict) -> dict:
    """Side-by-side comparisons where the program has a switch for the extension."""
    n, spp = p["size"], p["extension_spp"]
    out = {}

    # Parallel tiles: the same image on 1 and 2 threads.
    t = {}
    for threads in (1, 2):
        saved, r.threads = r.threads, threads
        t[threads] = r.render("cornell", width=n, height=n, spp=spp, seed=21)
        r.threads = saved
    out["threads"] = {"seconds_1": t[1].seconds, "seconds_2": t[2].seconds,
                      "speedup": ratio(t[1].seconds, t[2].seconds),
                      "identical": "yes" if np.array_equal(t[1].image, t[2].image) else "no"}

    # Hero wavelengths: 1 against 4 wavelengths per path, equal spp (cornell's reference).
    ref, noise = refs["cornell"]
    wl = {k: r.render("cornell", width=n, height=n, spp=spp, seed=22, extra=("--wavelengths-per-path", str(k)))
          for k in (1, 4)}
    out["hero"] = {f"relmse_{k}": rel_mse(x.image, ref, noise) for k, x in wl.items()}
    out["hero"].update({f"seconds_{k}": x.seconds for k, x in wl.items()})
    out["hero"]["ratio"] = ratio(out["hero"]["relmse_1"], out["hero"]["relmse_4"])
    panels(figs / "hero_wavelengths.png", [load_png(wl[1].png), load_png(wl[4].png)],
           [f"1 wavelength/path: relMSE {out['hero']['relmse_1']:.3g}",
            f"4 (hero + 3): relMSE {out['hero']['relmse_4']:.3g}"], inset=(0.3, 0.3, 0.4, 0.3))

    # Light sampling on a small sphere light: BSDF sampling alone, light sampling alone, MIS.
    ref, noise = refs["cornell-sphere"]
    ls = {m: r.render("cornell-sphere", width=n, height=n, spp=spp, seed=23, extra=("--light-sampling", m))
          for m in ("bsdf", "light", "mis")}
    out["light_sampling"] = {m: {"relmse": rel_mse(x.image, ref, noise), "seconds": x.seconds} for m, x in ls.items()}
    panels(figs / "light_sampling.png", [load_png(x.png) for x in ls.values()],
           [f"--light-sampling {m}: relMSE {out['light_sampling'][m]['relmse']:.3g}, {x.seconds:.1f} s"
            for m, x in ls.items()])

    # Dispersion on and off: prism with the scene's integrator.
    w = p["size"]
    dp = {on: r.render("prism", width=w, spp=spp, seed=24, extra=() if on else ("--no-dispersion",))
          for on in (True, False)}
    out["dispersion"] = {"seconds_on": dp[True].seconds, "seconds_off": dp[False].seconds}
    panels(figs / "dispersion.png", [load_png(dp[True].png), load_png(dp[False].png)],
           [f"dispersion (Sellmeier BK7), {dp[True].seconds:.1f} s", f"--no-dispersion, {dp[False].seconds:.1f} s"])

    # bdpt and vcm on a caustic seen through glass (equal time; bdpt reference).
    ref, noise = r.reference("prism", width=w, spp=p["caustic_ref_spp"], integrator="bdpt")
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

    # The sampler (issue of its own): compared when the program has the flag.
    if supports(r, ["--sampler", "sobol"]):
        ref, noise = refs["cornell"]
        sm = {s: r.render("cornell", width=n, height=n, spp=spp, seed=26, extra=("--sampler", s))
              for s in ("independent", "sobol") if supports(r, ["--sampler", s])}
        out["sampler"] = {s: {"relmse": rel_mse(x.image, ref, noise), "seconds": x.seconds} for s, x in sm.items()}
        panels(figs / "sampler.png", [load_png(x.png) for x in sm.values()],
               [f"--sampler {s}: relMSE {out['sampler'][s]['relmse']:.3g}" for s in sm])
        out["sampler"]["available"] = "yes"
    else:
        out["sampler"] = {"available": "not in the program this report was built with"}
    return out


def gallery_section(r: Renderer, p: dict, figs: Path) -> dict:
    folder = figs / "gallery"
    rows = gallery.render_gallery(r.program, folder, p["gallery_width"], spp=p["gallery_spp"],
                                  threads=r.threads)
    lines = ["| render | scene | size | spp | integrator | time (s) |", "|---|---|---|---|---|---:|"]
    for g in rows:
        lines.append(f"| ![{g['name']}](figures/gallery/{g['name']}.png) | `{g['name']}`: {g['summary']} | "
                     f"{g['width']}×{g['height']} | {g['spp']} | {g['integrator']} | {g['seconds']:.1f} |")
    return {"table": "\n".join(lines), "count": len(rows),
            "times": {g["name"]: g["seconds"] for g in rows}}


def colour_section(r: Renderer, p: dict, figs: Path) -> dict:
    w, h = p["chart_size"] or (None, None)
    results = [color_accuracy.evaluate(r.program, ill, p["chart_spp"], bin_counts=p["chart_bins"],
                                       exact_spp=p["chart_exact_spp"] or None, width=w, height=h)
               for ill in color_accuracy.SCENES]
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


def save_png_optimized(path: Path) -> None:
    from PIL import Image
    Image.open(path).convert("RGB").save(path, optimize=True)


def accuracy_section(r: Renderer, p: dict, figs: Path, cache: Path) -> dict:
    """validation/accuracy_cost.py with every integrator against bdpt references."""
    folder = figs.parent / "accuracy"
    argv = p["accuracy_cost"] + ["--program", str(r.program), "--out", str(folder),
                                 "--cache-dir", str(cache / "accuracy-cost")]
    accuracy_cost.main(argv)
    # One copy of the plot, with the other figures (accuracy/ keeps the study's table and data).
    shutil.move(folder / "accuracy_cost.png", figs / "accuracy_cost.png")
    save_png_optimized(figs / "accuracy_cost.png")
    data = json.loads((folder / "accuracy_cost.json").read_text())
    # Per scene and integrator: the spp sweep at the defaults (path's is the knob "spp").
    lines = ["| scene | integrator | reference | spp | time (s) | error | efficiency | slope of error vs spp |",
             "|---|---|---|---:|---:|---:|---:|---:|"]
    out = {"scenes": {}}
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
            out["scenes"][scene][integ] = {"spp": last["spp"], "time": last["time"], "error": last["error"],
                                           "efficiency": last["efficiency"], "slope": slope, "slope_se": se}
            lines.append(f"| {scene} | {integ} | {s['reference']} | {last['spp']} | {last['time'] or math.nan:.2f} | "
                         f"{last['error'] or math.nan:.3g} | {last['efficiency'] or math.nan:.3g} | "
                         f"{slope:.2f} ± {se:.2f} |")
    out["table"] = "\n".join(lines)
    out["report"] = "accuracy/accuracy_cost.md"
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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="tiny sizes (CI): checks every figure and number is made")
    ap.add_argument("--out", type=Path, help="output folder (default docs/report; with --quick build/report-quick)")
    ap.add_argument("--program", type=Path, help="the renderer (default $SPT_PATHTRACER, else build/pathtracer)")
    ap.add_argument("--cache-dir", type=Path, default=ROOT / "build" / "report-cache")
    a = ap.parse_args(argv)
    p = QUICK if a.quick else FULL
    out = a.out or (ROOT / "build" / "report-quick" if a.quick else REPORT_DIR)
    program = (a.program or Path(os.environ.get("SPT_PATHTRACER") or ROOT / "build" / "pathtracer")).resolve()
    if not os.access(program, os.X_OK):
        ap.error(f"--program: {program} is not an executable file; build the renderer first")
    figs = out / "figures"
    figs.mkdir(parents=True, exist_ok=True)
    scratch = out / "scenes"
    scratch.mkdir(exist_ok=True)
    r = Renderer(program, a.cache_dir / ("quick" if a.quick else "full"), p["threads"])
    started = time.perf_counter()
    results: dict = {"run": {
        "mode": "quick" if a.quick else "full",
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "commit": git_commit(), "program": r.version,
        "machine": f"{benchmark.cpu_model()}, {os.cpu_count()} logical CPUs, {platform.system()} {platform.release()}",
        "threads": p["threads"], "size": p["size"],
    }}
    steps = [
        ("convergence", lambda: convergence(r, p, figs)),
        ("materials", lambda: materials(r, p, figs, scratch)),
        ("lights", lambda: lights(r, p, figs, results["convergence"]["_refs"])),
        ("gi", lambda: gi_effects(r, p, figs)),
        ("point_caustic", lambda: point_caustic(r, p, figs)),
        ("extensions", lambda: extensions(r, p, figs, results["convergence"]["_refs"])),
        ("colour", lambda: colour_section(r, p, figs)),
        ("accuracy", lambda: accuracy_section(r, p, figs, a.cache_dir / ("quick" if a.quick else "full"))),
        ("gallery", lambda: gallery_section(r, p, figs)),
    ]
    for name, step in steps:
        t0 = time.perf_counter()
        say(f"== {name}")
        results[name] = step()
        say(f"   {time.perf_counter() - t0:.1f} s")
    results["run"]["minutes"] = (time.perf_counter() - started) / 60
    results = strip_private(results)
    (out / "results.json").write_text(json.dumps(results, indent=1, default=float) + "\n")
    text = fill_template((REPORT_DIR / "report.md.in").read_text(), results)
    check_figures(text, out)
    (out / "README.md").write_text(text)
    shutil.rmtree(scratch)
    say(f"wrote {out / 'README.md'}, {out / 'results.json'} and {len(list(figs.rglob('*.png')))} figures "
        f"in {results['run']['minutes']:.1f} min")
    return 0


if __name__ == "__main__":
    sys.exit(main())
