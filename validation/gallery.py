#!/usr/bin/env python3
"""Renders the README's gallery: every built-in scene at its own defaults (integrator, spp,
tone curve), scaled to a width of --width pixels, into validation/results/gallery/SCENE.png,
and prints the markdown table the README shows.

    python3 validation/gallery.py [--width 320] [--program build/pathtracer]

Everything comes from `pathtracer --list-scenes` (name, size, spp, integrator, summary), so a new
built-in scene appears here without a change to this script. docs/report/build_report.py
imports render_gallery for the report's gallery.
"""
import argparse
import os
import re
import subprocess
import sys

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


def render_gallery(program, out_dir, width, spp=None, threads=None):
    """Renders every built-in scene at `width` (the height keeps its aspect) into
    out_dir/NAME.png, at its own spp unless `spp` is given. Returns one dict per scene: name,
    width, height, spp, integrator, summary, seconds (render time from the program's summary)."""
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for name, w, h, scene_spp, integrator, summary in list_scenes(str(program)):
        out = os.path.join(out_dir, f"{name}.png")
        # --width alone: the program keeps the scene's aspect ratio.
        cmd = [str(program), name, "--width", str(width), "-o", out]
        cmd += ["--spp", str(spp)] if spp else []
        cmd += ["--threads", str(threads)] if threads else []
        err = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
        seconds = float(re.search(r"time ([0-9.]+) s,", err).group(1))
        rows.append({"name": name, "width": width, "height": round(width * h / w), "spp": spp or scene_spp,
                     "integrator": integrator, "summary": summary, "seconds": seconds, "path": out})
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--width", type=int, default=320, help="width of each render (the height keeps the aspect)")
    p.add_argument("--program", default=os.path.join(ROOT, "build", "pathtracer"))
    p.add_argument("--columns", type=int, default=3, help="images per row of the markdown table")
    args = p.parse_args()
    cells = []
    for g in render_gallery(args.program, OUT, args.width):
        print(f"{g['name']}: {g['width']}x{g['height']}, {g['spp']} spp, {g['integrator']}, {g['seconds']:.1f} s",
              file=sys.stderr)
        rel = os.path.relpath(g["path"], ROOT)
        cells.append(f"![{g['name']}]({rel})<br>`{g['name']}` ({g['integrator']}): {g['summary']}")
    rows = [cells[i:i + args.columns] for i in range(0, len(cells), args.columns)]
    print("| " + " | ".join([" "] * args.columns) + " |")
    print("|" + "---|" * args.columns)
    for row in rows:
        print("| " + " | ".join(row + [" "] * (args.columns - len(row))) + " |")


if __name__ == "__main__":
    main()
