#!/usr/bin/env python3
"""cornell-quad against Mitsuba 3's path tracer at equal time (issue 34: "cornell-quad with a
one-sided quad: efficiency against Mitsuba 3's path tracer"; a benchmark, not a test).

The built-in scene `cornell-quad` (scenes/cornell-quad.json) is rebuilt for Mitsuba 3
(llvm_ad_spectral) from the same numbers: the box's infinite planes as two-sided diffuse
rectangles reaching 40 units out of the open front, the spectra tabulated at 1 nm from the same
formulas (sigmoid, Gaussian, 6500 K blackbody normalised at 560 nm), the blue plastic (kd plus
a Fresnel-free mirror of 0.15) as a blend of a diffuse and a perfect mirror, the glass a smooth
dielectric of index 1.5, the light a one-sided rectangle facing down. Both renderers trace
paths without a depth limit (ours: Russian roulette; Mitsuba: max_depth -1, its roulette).

Each renderer is compared with its own converged reference (two halves of different seeds;
their difference estimates the reference's own noise, which is subtracted). Each equal-time
render takes --seconds of render time (ours: the "time" it reports for its render, with
--time-limit; Mitsuba: its render call, spp from a timed pilot, JIT compilation excluded).
relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2); efficiency =
1 / (relMSE * time).

    python bench/cornell_quad_mitsuba.py --program build/pathtracer \\
        --mitsuba-python /path/to/venv/bin/python --seconds 10 --seeds 3 --reference-spp 2048
"""

from __future__ import annotations

import argparse
import json
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "validation"))
from pfm import read_pfm  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))
from envmap_compare import rel_mse  # noqa: E402

MITSUBA_SCRIPT = r"""
import json, sys, time
import numpy as np
import mitsuba as mi
mi.set_variant("llvm_ad_spectral")
a = json.loads(sys.argv[1])
scene = json.loads(open(a["scene"]).read())
lam = np.arange(360.0, 831.0)

def planck(l, t):
    h, c, k = 6.62607015e-34, 2.99792458e8, 1.380649e-23
    l = l * 1e-9
    return 2 * h * c * c / (l ** 5 * np.expm1(h * c / (l * k * t)))

def spectrum(v):
    if isinstance(v, (int, float)):
        vals = np.full_like(lam, float(v))
    elif v["type"] == "gaussian":
        x = (lam - v["center_nm"]) / v["width_nm"]
        vals = v.get("offset", 0) + v.get("scale", 1) * np.exp(-x * x)
    elif v["type"] == "sigmoid":
        vals = v.get("offset", 0) + v.get("scale", 1) / (1 + np.exp(-(lam - v["center_nm"]) / v["width_nm"]))
    elif v["type"] == "blackbody":
        t = v["temperature_k"]
        vals = v.get("scale", 1) * planck(lam, t) / planck(v.get("normalize_nm", 560), t)
    else:
        raise SystemExit("unsupported spectrum " + str(v))
    return vals

def irregular(vals):
    return {"type": "irregular", "wavelengths": ", ".join(f"{l:g}" for l in lam),
            "values": ", ".join(f"{x:.8g}" for x in vals)}

def frame(center, u, v):
    # a rectangle [-1,1]^2 -> center + x u + y v, its normal (local +z) along u x v
    u, v, c = np.array(u, float), np.array(v, float), np.array(center, float)
    n = np.cross(u, v); n /= np.linalg.norm(n)
    m = np.eye(4); m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = u, v, n, c
    return mi.ScalarTransform4f(m)

def material(name):
    m = scene["materials"][name]
    if "kt" in m:
        return {"type": "dielectric", "int_ior": float(m["ior"]), "ext_ior": 1.0}
    kd = spectrum(m["kd"])
    if "ks" in m:
        w = float(m["ks"])
        return {"type": "blendbsdf", "weight": w,
                "bsdf_0": {"type": "diffuse", "reflectance": irregular(kd / (1 - w))},
                "bsdf_1": {"type": "conductor", "material": "none"}}
    return {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": irregular(kd)}}

cam = scene["camera"]
d = {"type": "scene",
     "integrator": {"type": "path", "max_depth": -1},
     "sensor": {"type": "perspective", "fov": cam["vfov_degrees"], "fov_axis": "y",
                "to_world": mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["look_at"], up=cam["up"]),
                "film": {"type": "hdrfilm", "width": a["width"], "height": a["height"], "pixel_format": "rgb",
                         "rfilter": {"type": "box"}},
                "sampler": {"type": "independent", "sample_count": 1}}}
far = 20.0  # the planes reach from z = -1 to z = 2 far - 1 out of the open front
for i, s in enumerate(scene["shapes"]):
    if s["type"] == "plane":
        n, p = np.array(s["normal"], float), np.array(s["point"], float)
        if abs(n[2]) > 0.5:     # the back wall
            shape = {"type": "rectangle", "to_world": frame(p, [1, 0, 0], [0, 1, 0])}
        elif abs(n[0]) > 0.5:   # left or right wall: y and z extents
            shape = {"type": "rectangle", "to_world": frame(p + [0, 0, far - 1], [0, 1, 0], [0, 0, far])}
        else:                   # floor or ceiling: x and z extents
            shape = {"type": "rectangle", "to_world": frame(p + [0, 0, far - 1], [1, 0, 0], [0, 0, far])}
        shape["bsdf"] = material(s["material"])
    elif s["type"] == "sphere":
        shape = {"type": "sphere", "center": s["center"], "radius": s["radius"], "bsdf": material(s["material"])}
    elif s["type"] == "quad":
        o, e1, e2 = (np.array(s[k], float) for k in ("origin", "edge1", "edge2"))
        shape = {"type": "rectangle", "to_world": frame(o + (e1 + e2) / 2, e1 / 2, e2 / 2),
                 "bsdf": {"type": "diffuse", "reflectance": {"type": "spectrum", "value": 0.0}},
                 "emitter": {"type": "area", "radiance": irregular(spectrum(s["emission"]))}}
        if s.get("two_sided", True):
            raise SystemExit("Mitsuba's area lights are one-sided; the scene's quad is two-sided")
    else:
        raise SystemExit("unsupported shape " + s["type"])
    d[f"shape{i}"] = shape
sc = mi.load_dict(d)

def render(spp, seed):
    t = time.perf_counter()
    img = np.array(mi.render(sc, spp=spp, seed=seed))
    return img, time.perf_counter() - t

render(2, 99)  # JIT compilation happens here, outside every timed render
out = {}
if a["seconds"] > 0:
    _, t = render(a["pilot_spp"], 98)
    spp = max(1, round(a["pilot_spp"] * a["seconds"] / t))
else:
    spp = a["spp"]
for i, seed in enumerate(a["seeds"]):
    if spp > 256 and a["seconds"] == 0:  # references in pieces (memory of the LLVM backend)
        acc, t = 0, 0.0
        for k in range(spp // 256):
            img, dt = render(256, seed * 1000 + k)
            acc, t = acc + img, t + dt
        img = acc / (spp // 256)
    else:
        img, t = render(spp, seed)
    np.save(a["out"] + f"_{i}.npy", img[..., :3])
    out[str(i)] = t
print(json.dumps({"spp": spp, "times": out}))
"""


def render_ours(program: Path, out: Path, seed: int, args, *, seconds: float = 0, spp: int = 0):
    cmd = [str(program), str(ROOT / "scenes" / "cornell-quad.json"), "-o", str(out), "--seed", str(seed), "--threads", str(args.threads),
           "--width", str(args.width), "--height", str(args.height)]
    cmd += ["--time-limit", str(seconds), "--pass-spp", "1", "--spp", "1000000"] if seconds else ["--spp", str(spp)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"{shlex.join(cmd)} failed:\n{r.stderr}")
    done = re.search(r"(\d+) spp", r.stderr)
    t = float(re.search(r"time ([\d.]+) s", r.stderr).group(1))
    return read_pfm(out), t, int(done.group(1)) if done else spp


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--program", type=Path, default=ROOT / "build" / "pathtracer")
    ap.add_argument("--mitsuba-python", type=Path, required=True, help="a Python with mitsuba 3")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--reference-spp", type=int, default=2048, help="spp of each half of a reference")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--height", type=int, default=128)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="cornell_quad_mitsuba_"))
    scene_json = ROOT / "scenes" / "cornell-quad.json"

    halves = [render_ours(args.program, work / f"ref{i}.pfm", 1000 + i, args, spp=args.reference_spp)[0]
              for i in range(2)]
    ref, noise = (halves[0] + halves[1]) / 2, rel_mse(halves[0], halves[1]) / 4
    rows = []
    errs, spps, times = [], [], []
    for s in range(args.seeds):
        img, t, spp = render_ours(args.program, work / "x.pfm", s, args, seconds=args.seconds)
        errs.append(rel_mse(img, ref) - noise), spps.append(spp), times.append(t)
    rows.append(("this program (path)", np.mean(spps), np.mean(times), errs, noise))

    def mitsuba(seconds: float, spp: int, seeds: list[int], tag: str) -> dict:
        a = {"scene": str(scene_json), "width": args.width, "height": args.height, "seconds": seconds, "spp": spp,
             "pilot_spp": 16, "seeds": seeds, "out": str(work / tag)}
        r = subprocess.run([str(args.mitsuba_python), "-c", MITSUBA_SCRIPT, json.dumps(a)], capture_output=True,
                           text=True)
        if r.returncode != 0:
            raise SystemExit(f"mitsuba failed:\n{r.stderr}")
        return json.loads(r.stdout.strip().splitlines()[-1])
    mitsuba(0, args.reference_spp, [1000, 1001], "miref")
    mh = [np.load(work / f"miref_{i}.npy") for i in range(2)]
    mref, mnoise = (mh[0] + mh[1]) / 2, rel_mse(mh[0], mh[1]) / 4
    res = mitsuba(args.seconds, 0, list(range(args.seeds)), "mi")
    merrs = [rel_mse(np.load(work / f"mi_{i}.npy"), mref) - mnoise for i in range(args.seeds)]
    rows.append(("Mitsuba 3 (path)", res["spp"], np.mean(list(res["times"].values())), merrs, mnoise))

    base = rows[1]
    lines = [f"Command: `{shlex.join(['python', 'bench/cornell_quad_mitsuba.py'] + (argv if argv is not None else sys.argv[1:]))}`",
             "", f"cornell-quad {args.width}x{args.height}, {args.threads} threads, {args.seconds:g} s renders, "
             f"mean of {args.seeds} seeds; references {args.reference_spp} spp x 2 per renderer.", "",
             "| renderer | spp | render time (s) | relMSE | reference noise | efficiency / Mitsuba 3 |",
             "|---|---:|---:|---:|---:|---:|"]
    for who, spp, t, e, nz in rows:
        eff = (np.mean(base[3]) * base[2]) / (np.mean(e) * t)
        lines.append(f"| {who} | {spp:.0f} | {t:.2f} | {np.mean(e):.3e} ± {np.std(e):.1e} | {nz:.1e} | {eff:.2f} |")
    lines += ["", f"The two references against each other: relMSE {rel_mse(mref, ref):.2e} (spectral upsampling and "
                  "colour pipelines differ; the table compares noise only)."]
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
