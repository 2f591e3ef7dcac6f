#!/usr/bin/env python3
"""Renders the README's gallery: every built-in scene at its own defaults (integrator, spp,
tone curve), scaled to a width of --width pixels, into validation/results/gallery/SCENE.png,
and prints the markdown table the README shows.

    python3 validation/gallery.py [--width 320] [--program build/pathtracer]

Everything comes from `pathtracer --list-scenes` (name, size, spp, integrator, summary), so a new
built-in scene appears here without a change to this script.
"""
import argparse
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "validation", "results", "gallery")


def list_scenes(program):
    """[(name, width, height, spp, integrator, summary)] from --list-scenes."""
    scenes = []
    for line in subprocess.run([program, "--list-scenes"], check=True, capture_output=True,
                               text=True).stdout.splitlines():
        name, size, spp, _, integrator, summary = line.split(None, 5)
        w, h = map(int, size.split("x"))
        scenes.append((name, w, h, int(spp), integrator, summary))
    return scenes


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--width", type=int, default=320, help="width of each render (the height keeps the aspect)")
    p.add_argument("--program", default=os.path.join(ROOT, "build", "pathtracer"))
    p.add_argument("--columns", type=int, default=3, help="images per row of the markdown table")
    args = p.parse_args()
    os.makedirs(OUT, exist_ok=True)
    cells = []
    for name, w, h, spp, integrator, summary in list_scenes(args.program):
        out = os.path.join(OUT, f"{name}.png")
        t0 = time.perf_counter()
        # --width alone: the program keeps the scene's aspect ratio.
        subprocess.run([args.program, name, "--width", str(args.width), "--quiet", "-o", out], check=True)
        took = time.perf_counter() - t0
        print(f"{name}: {args.width}x{round(args.width * h / w)}, {spp} spp, {integrator}, {took:.1f} s",
              file=sys.stderr)
        rel = os.path.relpath(out, ROOT)
        cells.append(f"![{name}]({rel})<br>`{name}` ({integrator}): {summary}")
    rows = [cells[i:i + args.columns] for i in range(0, len(cells), args.columns)]
    print("| " + " | ".join([" "] * args.columns) + " |")
    print("|" + "---|" * args.columns)
    for row in rows:
        print("| " + " | ".join(row + [" "] * (args.columns - len(row))) + " |")


if __name__ == "__main__":
    main()
