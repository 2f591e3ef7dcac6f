#!/usr/bin/env python3
"""Load time and peak memory of a large environment map (issue 34: "a map of 8k x 4k texels
loads and builds its distribution in seconds, with peak memory in the note"; a benchmark, not a
test).

Writes a W x H lat-long PFM (default 8192 x 4096, 402 MB) of a sky gradient with a sun, every
texel multiplied by its own random factor so that nearly every colour is distinct (as in a
photograph: no two neighbours share a fit), then renders a 4 x 4 image at 1 spp lit by it with
each --program, interleaved, --runs times, under `/usr/bin/time -v`. Reports per program the
minimum wall time and peak resident memory, the "scene loaded in" time the program prints, and
the load average. The map is written to a temporary folder and deleted afterwards. --portal
names a window in front of the sphere as the map's portal (its distribution is built at load).

    python bench/envmap_load.py --program build/pathtracer [--program other/pathtracer] --runs 5 [--portal]
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np


def write_map(path: Path, w: int, h: int) -> None:
    """Linear RGB, PFM rows bottom to top; built in bands of rows to bound this script's memory."""
    rng = np.random.default_rng(7)
    el, az = np.radians(30.0), np.radians(40.0)
    sun = np.array([np.cos(el) * np.sin(az), np.sin(el), -np.cos(el) * np.cos(az)])
    u = (np.arange(w) + 0.5) / w
    phi = 2 * np.pi * u
    with open(path, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1\n".encode())
        band = 256
        for top in reversed(range(0, h, band)):  # PFM: the bottom row first
            rows = np.arange(top, min(top + band, h))
            theta = np.pi * (rows + 0.5) / h
            st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
            d = np.stack(np.broadcast_arrays(st * np.sin(phi), ct, -st * np.cos(phi)), axis=-1)
            up = np.clip(d[..., 1:2], 0, 1)
            sky = (1 - up) * np.array([0.5, 0.55, 0.65]) + up * np.array([0.12, 0.25, 0.7])
            img = np.where(d[..., 1:2] > 0, sky, np.array([0.1, 0.09, 0.08]))
            img = img * rng.uniform(0.7, 1.3, size=img.shape)
            img[(d @ sun) > np.cos(np.radians(0.5))] = np.array([1.0, 0.92, 0.8]) * 8.0e4
            f.write(img[::-1].astype("<f4").tobytes())


def run(program: Path, scene: Path, threads: int) -> dict:
    cmd = ["/usr/bin/time", "-v", str(program), str(scene), "--spp", "1", "--threads", str(threads),
           "-o", str(scene.with_suffix(".pfm"))]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{r.stderr}")
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", r.stderr)
    seconds = (int(wall.group(1) or 0) * 60 + int(wall.group(2))) * 60 + float(wall.group(3))
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", r.stderr).group(1))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1)) / 1024
    load = re.search(r"scene loaded in ([\d.]+) s", r.stderr)
    return {"wall": seconds, "user": user, "rss": rss, "load": float(load.group(1)) if load else float("nan"),
            "loadavg": os.getloadavg()[0]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--program", type=Path, action="append", required=True, help="repeat to compare programs")
    ap.add_argument("--width", type=int, default=8192)
    ap.add_argument("--height", type=int, default=4096)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--portal", action="store_true", help="sample the map through a portal")
    ap.add_argument("--keep", type=Path, help="write the map here and keep it (default: a temporary folder)")
    args = ap.parse_args(argv)

    work = Path(tempfile.mkdtemp(prefix="envmap_load_"))
    try:
        map_file = args.keep or work / "map.pfm"
        if not map_file.exists():
            write_map(map_file, args.width, args.height)
        scene = work / "scene.json"
        background = {"type": "image", "file": str(map_file.resolve()), "mapping": "equirect"}
        if args.portal:  # a 2 x 1 window in the plane z = -2, its front (-z) facing away from the sphere
            background["portal"] = {"origin": [-1, 0, -2], "edge1": [0, 1, 0], "edge2": [2, 0, 0]}
        scene.write_text(json.dumps({
            "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "vfov_degrees": 35},
            "image": {"width": 4, "height": 4, "spp": 1},
            "background": background,
            "materials": {"grey": {"kd": 0.5}},
            "shapes": [{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "grey"}],
        }))
        results: dict[Path, list[dict]] = {p: [] for p in args.program}
        for i in range(args.runs):
            for p in args.program:
                r = run(p, scene, args.threads)
                results[p].append(r)
                print(f"run {i} {p}: {r}", flush=True)
        print(f"\nmap {args.width}x{args.height}{' with a portal' if args.portal else ''}, {args.threads} threads, "
              f"min of {args.runs} interleaved runs")
        print("| program | wall (s) | user (s) | scene loaded in (s) | peak RSS (MiB) | load average (1 min) |")
        print("|---|---:|---:|---:|---:|---|")
        for p, rs in results.items():
            print(f"| {p} | {min(r['wall'] for r in rs):.2f} | {min(r['user'] for r in rs):.2f} | "
                  f"{min(r['load'] for r in rs):.2f} | {min(r['rss'] for r in rs):.0f} | "
                  f"{min(r['loadavg'] for r in rs):.1f}–{max(r['loadavg'] for r in rs):.1f} |")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
