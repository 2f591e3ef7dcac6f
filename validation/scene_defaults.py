#!/usr/bin/env python3
"""Measures what every built-in scene's own defaults give: the render time of its default
sample count, and the relMSE of that sample count against a render with 16x the samples.

    python3 validation/scene_defaults.py [--program build/pathtracer] [--width 80] [SCENE...]

relMSE is a per-pixel quantity, so both renders are made at a reduced size (--width, default 80
pixels) with the scene's own spp and 16x that spp, different seeds; the reference's time, scaled
by the ratio of pixel counts, is the time of the full-size default render (it is
what the table reports as "time at defaults": CPU seconds divided by --threads, which is the
wall time on idle cores and stays meaningful on a shared machine). relMSE = mean over pixels and channels of
(x - ref)^2 / (ref^2 + 0.01), as validation/benchmark.py. Prints a markdown table.
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "validation"))
from gallery import list_scenes  # noqa: E402
from pfm import read_pfm  # noqa: E402


def render(program, scene, width, spp, seed, out, threads):
    cmd = ["nice", "-n", "15", program, scene, "--width", str(width), "--spp", str(spp),
           "--seed", str(seed), "--threads", str(threads), "-o", out]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    # CPU seconds over the threads: the wall time on idle cores, also on a shared machine.
    return (after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime) / threads


def rel_mse(x, ref):
    return float(np.mean((x - ref) ** 2 / (ref ** 2 + 1e-2)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--program", default=os.path.join(ROOT, "build", "pathtracer"))
    ap.add_argument("--width", type=int, default=80,
                    help="render width of both measurement renders (the height keeps the aspect)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("scenes", nargs="*", help="built-in scene names or scene files (default: every built-in scene)")
    args = ap.parse_args()
    listed = {s[0]: s for s in list_scenes(args.program)}
    names = args.scenes or list(listed)
    print("| scene | integrator | size, spp | time at defaults (s) | relMSE vs 16x spp |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            if name in listed:
                _, w, h, spp, integrator, _ = listed[name]
            else:
                import json
                d = json.load(open(name))
                w, h, spp = d["image"]["width"], d["image"]["height"], d["image"]["spp"]
                integrator = d.get("integrator", "path")
            a, b = os.path.join(tmp, "a.pfm"), os.path.join(tmp, "b.pfm")
            render(args.program, name, args.width, spp, 1, a, args.threads)
            t_ref = render(args.program, name, args.width, 16 * spp, 2, b, args.threads)
            x, ref = read_pfm(a), read_pfm(b)
            e = rel_mse(x, ref)
            t_full = t_ref / 16 * (w * h) / (ref.shape[0] * ref.shape[1])
            print(f"| `{os.path.basename(name)}` | {integrator} | {w}x{h}, {spp} | {t_full:.1f} | {e:.4f} |", flush=True)


if __name__ == "__main__":
    main()
