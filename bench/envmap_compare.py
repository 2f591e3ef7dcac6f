#!/usr/bin/env python3
"""Environment-map sampling at equal time (issue 34's performance target; a benchmark, not a test).

The scene: a grey ground, a diffuse sphere and a rough aluminium sphere (GGX alpha 0.1) under a
strongly peaked HDR map, a lat-long image of a dim sky and a small bright sun (about 1 degree
across, most of the map's power), written here as a PFM. Each variant renders for the same
time (--seconds, with --time-limit and one sample per pixel per pass) and is compared with its
renderer's own converged reference (two halves of different seeds, whose difference gives the
reference's own noise, subtracted from every relMSE):

* this program, the map importance sampled (the default), with and without the MIS-compensated
  density (Karlik et al. 2019), and with uniform sampling of the sphere of directions;
* Mitsuba 3's `path` integrator with its `envmap` emitter (llvm_ad_spectral) when --mitsuba-python
  names a Python that has mitsuba: samples per pixel chosen from a timed pilot so that its render
  call takes --seconds.

relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 1e-2); efficiency =
1 / (relMSE * time). Prints a Markdown table with the command that made it (and writes it to
--out if given). Run with nothing else busy on the machine:

    python bench/envmap_compare.py --program build/pathtracer --seconds 10 \
        --mitsuba-python /path/to/venv/bin/python
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

MAP_W, MAP_H = 1024, 512
SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG, SUN_RADIUS_DEG = 30.0, 40.0, 0.5
SUN_RADIANCE = np.array([1.0, 0.92, 0.8]) * 8.0e4
CAMERA = {"position": [0, 1.2, 4.5], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "vfov_degrees": 35}
MAX_DEPTH = 5  # scattering events (Mitsuba's max_depth counts one more)


def sky_map() -> np.ndarray:
    """Linear RGB radiance, (MAP_H, MAP_W, 3), row 0 = top (+Y), Mitsuba's lat-long convention:
    u = atan2(d.x, -d.z) / 2pi, v = acos(d.y) / pi at texel centres."""
    u = (np.arange(MAP_W) + 0.5) / MAP_W
    v = (np.arange(MAP_H) + 0.5) / MAP_H
    phi, theta = 2 * np.pi * u[None, :], np.pi * v[:, None]
    d = np.stack(np.broadcast_arrays(np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)), axis=-1)
    up = np.clip(d[..., 1:2], 0, 1)
    sky = (1 - up) * np.array([0.5, 0.55, 0.65]) + up * np.array([0.12, 0.25, 0.7])
    img = np.where(d[..., 1:2] > 0, sky, np.array([0.1, 0.09, 0.08]))
    el, az = np.radians(SUN_ELEVATION_DEG), np.radians(SUN_AZIMUTH_DEG)
    sun = np.array([np.cos(el) * np.sin(az), np.sin(el), -np.cos(el) * np.cos(az)])
    img[(d @ sun) > np.cos(np.radians(SUN_RADIUS_DEG))] = SUN_RADIANCE
    return img


def write_pfm(path: Path, img: np.ndarray) -> None:
    h, w, _ = img.shape
    path.write_bytes(f"PF\n{w} {h}\n-1\n".encode() + img[::-1].astype("<f4").tobytes())


def map_sun_fraction(img: np.ndarray) -> float:
    sin_theta = np.sin(np.pi * (np.arange(MAP_H) + 0.5) / MAP_H)[:, None]
    y = (img @ np.array([0.2126, 0.7152, 0.0722])) * sin_theta
    return float(y[np.all(img == SUN_RADIANCE, axis=-1)].sum() / y.sum())


def our_scene(map_file: Path, width: int, height: int, background_extra: dict) -> dict:
    return {
        "camera": CAMERA,
        "image": {"width": width, "height": height, "spp": 1},
        "integrator": {"type": "path", "max_depth": MAX_DEPTH},
        "background": {"type": "image", "file": str(map_file), "mapping": "equirect", **background_extra},
        "materials": {
            "ground": {"kd": 0.5},
            "grey": {"kd": 0.7},
            "aluminium": {"type": "conductor", "metal": "Al", "roughness": 0.1},
        },
        "shapes": [
            {"type": "quad", "origin": [-6, 0, 6], "edge1": [12, 0, 0], "edge2": [0, 0, -12], "material": "ground"},
            {"type": "sphere", "center": [-0.7, 0.6, 0], "radius": 0.6, "material": "grey"},
            {"type": "sphere", "center": [0.7, 0.6, 0], "radius": 0.6, "material": "aluminium"},
        ],
    }


MITSUBA_SCRIPT = r"""
import json, sys, time
import numpy as np
import mitsuba as mi
mi.set_variant("llvm_ad_spectral")
a = json.loads(sys.argv[1])
T = mi.ScalarTransform4f
cam = a["camera"]
scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "path", "max_depth": a["max_depth"] + 1},
    "sensor": {"type": "perspective", "fov": cam["vfov_degrees"], "fov_axis": "y",
               "to_world": T().look_at(origin=cam["position"], target=cam["look_at"], up=cam["up"]),
               "film": {"type": "hdrfilm", "width": a["width"], "height": a["height"], "pixel_format": "rgb",
                        "rfilter": {"type": "box"}},
               "sampler": {"type": "independent", "sample_count": 1}},
    "sky": {"type": "envmap", "filename": a["map"]},
    "ground": {"type": "rectangle", "to_world": T().rotate([1, 0, 0], -90).scale(6),
               "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}}},
    "grey": {"type": "sphere", "center": [-0.7, 0.6, 0], "radius": 0.6,
             "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.7, 0.7, 0.7]}}},
    "aluminium": {"type": "sphere", "center": [0.7, 0.6, 0], "radius": 0.6,
                  "bsdf": {"type": "roughconductor", "material": "Al", "distribution": "ggx", "alpha": 0.1}},
})
def render(spp, seed):
    t = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=seed))
    return img, time.perf_counter() - t
render(2, 99)  # JIT compilation happens here, outside every timed render
out = {}
if a["seconds"] > 0:
    _, t = render(a["pilot_spp"], 98)
    spp = max(1, round(a["pilot_spp"] * a["seconds"] / t))
else:
    spp = a["spp"]
for i, seed in enumerate(a["seeds"]):
    img, t = render(spp, seed)
    np.save(a["out"] + f"_{i}.npy", img[..., :3])
    out[str(i)] = t
print(json.dumps({"spp": spp, "times": out}))
"""


def rel_mse(x: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((x - ref) ** 2 / (ref ** 2 + 1e-2)))


def render_ours(program: Path, scene: Path, out: Path, seed: int, *, seconds: float = 0, spp: int = 0,
                threads: int) -> tuple[np.ndarray, float, int]:
    cmd = [str(program), str(scene), "-o", str(out), "--seed", str(seed), "--threads", str(threads)]
    cmd += ["--time-limit", str(seconds), "--pass-spp", "1", "--spp", "1000000"] if seconds else ["--spp", str(spp)]
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    elapsed = time.perf_counter() - t
    if r.returncode != 0:
        raise SystemExit(f"{shlex.join(cmd)} failed:\n{r.stderr}")
    done = re.search(r"(\d+) spp \(of \d+ requested\)", r.stderr)
    return read_pfm(out), elapsed, int(done.group(1)) if done else spp


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--program", type=Path, default=ROOT / "build" / "pathtracer")
    ap.add_argument("--seconds", type=float, default=10.0, help="render time of every equal-time variant")
    ap.add_argument("--reference-spp", type=int, default=2048, help="spp of each half of a reference")
    ap.add_argument("--width", type=int, default=240)
    ap.add_argument("--height", type=int, default=160)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seeds", type=int, default=3, help="equal-time renders per variant")
    ap.add_argument("--mitsuba-python", type=Path, help="a Python with mitsuba 3 (optional)")
    ap.add_argument("--out", type=Path, help="also write the table to this Markdown file")
    args = ap.parse_args(argv)

    work = Path(tempfile.mkdtemp(prefix="envmap_compare_"))
    sky = sky_map()
    map_file = work / "sky.pfm"
    write_pfm(map_file, sky)
    variants = {
        "importance": {},
        "importance, MIS-compensated": {"mis_compensation": True},
        "uniform": {"sampling": "uniform"},
    }
    rows = []
    ref_scene = work / "reference.json"
    ref_scene.write_text(json.dumps(our_scene(map_file, args.width, args.height, {})))
    halves = [render_ours(args.program, ref_scene, work / f"ref{i}.pfm", 1000 + i, spp=args.reference_spp,
                          threads=args.threads)[0] for i in range(2)]
    ref = (halves[0] + halves[1]) / 2
    ref_noise = rel_mse(halves[0], halves[1]) / 4
    for name, extra in variants.items():
        scene = work / f"{name.replace(', ', '_')}.json"
        scene.write_text(json.dumps(our_scene(map_file, args.width, args.height, extra)))
        errs, spps, times = [], [], []
        for s in range(args.seeds):
            img, t, spp = render_ours(args.program, scene, work / "x.pfm", s, seconds=args.seconds, threads=args.threads)
            errs.append(rel_mse(img, ref) - ref_noise)
            spps.append(spp)
            times.append(t)
        rows.append(("this program", name, float(np.mean(spps)), float(np.mean(times)), float(np.mean(errs)),
                     float(np.std(errs))))
        print(rows[-1], flush=True)

    if args.mitsuba_python:
        def mitsuba(seconds: float, spp: int, seeds: list[int], tag: str) -> dict:
            a = {"camera": CAMERA, "max_depth": MAX_DEPTH, "width": args.width, "height": args.height,
                 "map": str(map_file), "seconds": seconds, "spp": spp, "pilot_spp": 16, "seeds": seeds,
                 "out": str(work / tag)}
            r = subprocess.run([str(args.mitsuba_python), "-c", MITSUBA_SCRIPT, json.dumps(a)], capture_output=True,
                               text=True)
            if r.returncode != 0:
                raise SystemExit(f"mitsuba failed:\n{r.stderr}")
            return json.loads(r.stdout.strip().splitlines()[-1])
        mitsuba(0, args.reference_spp, [1000, 1001], "miref")
        mh = [np.load(work / f"miref_{i}.npy") for i in range(2)]
        mref, mnoise = (mh[0] + mh[1]) / 2, rel_mse(mh[0], mh[1]) / 4
        res = mitsuba(args.seconds, 0, list(range(args.seeds)), "mi")
        errs = [rel_mse(np.load(work / f"mi_{i}.npy"), mref) - mnoise for i in range(args.seeds)]
        rows.append(("Mitsuba 3 path + envmap", "its default", float(res["spp"]), float(np.mean(list(res["times"].values()))),
                     float(np.mean(errs)), float(np.std(errs))))
        cross = rel_mse(mref, ref)
    else:
        cross = None

    base = next(r for r in rows if r[1] == "importance")
    lines = [
        "# Environment map sampling at equal time",
        "",
        f"Command: `{shlex.join(['python', 'bench/envmap_compare.py'] + (argv if argv is not None else sys.argv[1:]))}`",
        "",
        f"Scene: {args.width}x{args.height}, path tracing to {MAX_DEPTH} scattering events, {args.seconds:g} s per "
        f"render, {args.threads} threads, mean of {args.seeds} seeds (± their standard deviation). Map "
        f"{MAP_W}x{MAP_H} lat-long, sun {2 * SUN_RADIUS_DEG:g}° across at {SUN_ELEVATION_DEG:g}° elevation carrying "
        f"{100 * map_sun_fraction(sky):.0f} % of the map's power. References: {args.reference_spp} spp x 2 seeds "
        f"per renderer (their own noise, {ref_noise:.2e} for this program, is subtracted).",
        "",
        "Times: this program's whole process (start, reading the map, building its distribution, rendering); "
        "Mitsuba's render call only (its scene loading and JIT compilation are left out).",
        "",
        "| renderer | environment sampling | spp | time (s) | relMSE | efficiency / this program's default |",
        "|---|---|---|---|---|---|",
    ]
    for who, name, spp, t, err, sd in rows:
        eff = (base[4] * base[3]) / (err * t)
        lines.append(f"| {who} | {name} | {spp:.0f} | {t:.1f} | {err:.3e} ± {sd:.1e} | {eff:.2f} |")
    if cross is not None:
        lines += ["", f"The two references against each other: relMSE {cross:.2e} (spectral upsampling, "
                      "materials' data and the ground's extent differ slightly; the table compares noise only)."]
    if args.out:
        args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
