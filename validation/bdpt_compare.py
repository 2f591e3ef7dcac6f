#!/usr/bin/env python3
"""Equal-time comparison of the path tracer, bdpt and vcm (bdpt with vertex merging; issue 7).

For each scene named on the command line: a long bdpt reference (cached in build/), then each
integrator for --seconds seconds (the program's --time-limit, in 1-spp passes), relative MSE
against the reference, side-by-side PNGs (path | bdpt | vcm) in validation/results/ and a
markdown table. The reference is unbiased bdpt, so vcm's merging blur counts as error.

    python3 validation/bdpt_compare.py prism glass-spheres [--seconds 60] [--size 512]

relMSE = mean over pixels and RGB channels of (x - ref)^2 / (ref^2 + 1e-2).
Needs numpy and the built program (build/pathtracer).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time
import zlib

import numpy as np
from pfm import read_pfm  # noqa: F401  (the report reads renders through it)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXE = os.path.join(ROOT, "build", "pathtracer")
RESULTS = os.path.join(ROOT, "validation", "results")
CACHE = os.path.join(ROOT, "build", "bdpt_reference")
INTEGRATORS = ("path", "bdpt", "vcm")


def render(scene, integrator, size, spp, out, threads, seed=0):
    cmd = [EXE, scene, "--integrator", integrator, "--width", str(size), "--height", str(size),
           "--spp", str(spp), "--threads", str(threads), "--seed", str(seed), "-o", out, "--quiet"]
    start = time.monotonic()
    subprocess.run(cmd, check=True)
    return time.monotonic() - start


def render_for(scene, integrator, size, seconds, out, threads, seed=0):
    """Renders whole 1-spp passes until the next would end after `seconds` (--time-limit);
    returns (spp, render seconds) as the program reports them. (vcm's passes are always one
    sample.)"""
    cmd = [EXE, scene, "--integrator", integrator, "--width", str(size), "--height", str(size),
           "--spp", "1000000", "--time-limit", str(seconds)] + (["--pass-spp", "1"] if integrator != "vcm" else []) + [
           "--threads", str(threads), "--seed", str(seed), "-o", out]
    err = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
    spp = int(re.search(r"stopped by --time-limit \S+ s after (\d+) of", err).group(1))
    secs = float(re.search(r"time ([0-9.]+) s", err).group(1))
    return spp, secs


def rel_mse(x, ref):
    return float(np.mean((x - ref) ** 2 / (ref ** 2 + 1e-2)))


def rel_mse_trimmed(x, ref, drop=1e-4):
    """relMSE without the worst `drop` fraction of pixels (0.01 %: 26 pixels at 512²). Paths
    that neither integrator samples well (on `prism`: the floor caustic seen through the
    glass, specular-diffuse-specular) appear as a few huge isolated pixels whose squares
    dominate the plain mean; this figure shows the error of the rest of the image."""
    e = np.sort(((x - ref) ** 2 / (ref ** 2 + 1e-2)).mean(axis=2).ravel())
    return float(e[: int(round(len(e) * (1 - drop)))].mean())


def write_png(path, rgb):
    """sRGB 8-bit PNG from linear RGB (clipped), numpy + zlib only."""
    a = np.clip(rgb, 0, 1)
    a = np.where(a <= 0.0031308, 12.92 * a, 1.055 * a ** (1 / 2.4) - 0.055)
    img = (a * 255 + 0.5).astype(np.uint8)
    h, w, _ = img.shape
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(h))

    def chunk(tag, body):
        c = tag + body
        return len(body).to_bytes(4, "big") + c + zlib.crc32(c).to_bytes(4, "big")

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", w.to_bytes(4, "big") + h.to_bytes(4, "big") + b"\x08\x02\x00\x00\x00")
    png += chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reference-seconds", type=float, default=1800,
                    help="time budget of the bdpt reference (rendered once, cached)")
    args = ap.parse_args()
    os.makedirs(RESULTS, exist_ok=True)
    os.makedirs(CACHE, exist_ok=True)
    rows = {}
    for scene in args.scenes:
        name = os.path.splitext(os.path.basename(scene))[0]
        ref_path = os.path.join(CACHE, f"{name}_{args.size}_ref.pfm")
        if not os.path.exists(ref_path):
            tmp = os.path.join(CACHE, f"{name}_bdpt_calib.pfm")  # calibration: spp per second
            spp = max(16, int(4 / render(scene, "bdpt", args.size, 4, tmp, args.threads, seed=99)
                              * args.reference_seconds))
            print(f"{name}: reference, bdpt {spp} spp", file=sys.stderr)
            render(scene, "bdpt", args.size, spp, ref_path, args.threads, seed=12345)
        ref = read_pfm(ref_path)
        images, result = {}, {}
        for integ in INTEGRATORS:
            out = os.path.join(CACHE, f"{name}_{integ}.pfm")
            spp, t = render_for(scene, integ, args.size, args.seconds, out, args.threads, seed=1)
            images[integ] = read_pfm(out)
            result[integ] = (spp, t, rel_mse(images[integ], ref), rel_mse_trimmed(images[integ], ref))
        rows[name] = {"size": args.size, "seconds": args.seconds, **result}
        gap = np.ones((args.size, 8, 3))
        side = np.concatenate([images["path"], gap, images["bdpt"], gap, images["vcm"]], axis=1)
        write_png(os.path.join(RESULTS, f"{name}_path_bdpt_vcm.png"), side)
        write_png(os.path.join(RESULTS, f"{name}_reference.png"), ref)
    # Rows of scenes not rendered this time are kept from earlier runs.
    store = os.path.join(RESULTS, "bdpt_compare.json")
    all_rows = json.load(open(store)) if os.path.exists(store) else {}
    all_rows.update(rows)
    with open(store, "w") as f:
        json.dump(all_rows, f, indent=1, sort_keys=True)
    lines = ["| scene | size, s | integrator | spp | seconds | relMSE | trimmed | path relMSE / this | trimmed |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name, r in sorted(all_rows.items()):
        p = r["path"]
        for integ in INTEGRATORS:
            if integ not in r:
                continue
            x = r[integ]
            lines.append(f"| {name} | {r['size']}², {r['seconds']:g} | {integ} | {x[0]} | {x[1]:.1f} | {x[2]:.4g} | "
                         f"{x[3]:.4g} | {p[2] / x[2]:.2f}× | {p[3] / x[3]:.1f}× |")
    lines.append("")
    lines.append("relMSE = mean of (x − ref)²/(ref² + 0.01) over pixels and RGB against an unbiased bdpt "
                 "reference; trimmed: without the 0.01 % worst pixels. Equal time by --time-limit on 2 threads.")
    table = "\n".join(lines) + "\n"
    with open(os.path.join(RESULTS, "bdpt_compare.md"), "w") as f:
        f.write(table)
    print(table)


if __name__ == "__main__":
    main()
