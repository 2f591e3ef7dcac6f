#!/usr/bin/env python3
"""Renders docs/GALLERY.md's images: every built-in scene with its own integrator and tone
curve, converged (--spp-factor times its own spp, at most --width pixels wide) into
docs/gallery/SCENE.png, and small at its own spp into docs/gallery/quick/SCENE.png; prints the
markdown table. Times are CPU seconds over the threads (the wall time on idle cores).

    python3 validation/gallery.py [--width 400] [--spp-factor 4] [--program build/pathtracer] [SCENE...]

Everything comes from `pathtracer --list-scenes` (name, size, spp, integrator, summary), so a new
built-in scene appears here without a change to this script. docs/report/build_report.py
imports render_gallery for the report's gallery.
"""
import argparse
import os
import re
import resource
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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


def cpu_render(program, scene, width, spp, out, threads):
    """Renders and returns the CPU seconds over the threads: the wall time on idle cores, also
    when the machine is shared."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(["nice", "-n", "15", str(program), scene, "--width", str(width), "--spp", str(spp),
                    "--threads", str(threads), "-o", out, "--quiet"], check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime) / threads


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--width", type=int, default=400, help="width of each converged render (at most the scene's)")
    p.add_argument("--spp-factor", type=int, default=4, help="the converged render's spp over the scene's own")
    p.add_argument("--quick-width", type=int, default=160, help="width of the small render at the scene's own spp")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--program", default=os.path.join(ROOT, "build", "pathtracer"))
    p.add_argument("--out", default=os.path.join(ROOT, "docs"), help="writes the images to OUT/gallery/ (the table goes to stdout)")
    p.add_argument("scenes", nargs="*", help="only these scenes (default: every built-in scene)")
    args = p.parse_args()
    from PIL import Image
    folder = os.path.join(args.out, "gallery")
    os.makedirs(os.path.join(folder, "quick"), exist_ok=True)
    rows = []
    for name, w, h, scene_spp, integrator, summary in list_scenes(args.program):
        if args.scenes and name not in args.scenes:
            continue
        width = min(args.width, w)
        big, small = os.path.join(folder, f"{name}.png"), os.path.join(folder, "quick", f"{name}.png")
        t_big = cpu_render(args.program, name, width, args.spp_factor * scene_spp, big, args.threads)
        cpu_render(args.program, name, args.quick_width, scene_spp, small, args.threads)
        for f in (big, small):
            Image.open(f).convert("RGB").save(f, optimize=True)
        # The scene's own size and spp, timed as above: what `pathtracer NAME` takes.
        t_default = t_big / args.spp_factor * (w * h) / (width * round(width * h / w))
        rows.append((name, integrator, summary, width, round(width * h / w), args.spp_factor * scene_spp, t_big,
                     w, h, scene_spp, t_default))
        print(f"{name}: {t_big:.1f} s", file=sys.stderr, flush=True)
    print("| converged | at its defaults | scene |")
    print("|---|---|---|")
    for (name, integrator, summary, width, height, spp, t_big, w, h, scene_spp, t_default) in rows:
        print(f"| ![{name}](gallery/{name}.png) | ![{name} at its defaults](gallery/quick/{name}.png) | "
              f"`{name}` ({integrator}): {summary}.<br>Converged: {width}×{height}, {spp} spp, {t_big:.0f} s."
              f"<br>Defaults (`pathtracer {name}`): {w}×{h}, {scene_spp} spp, about {t_default:.0f} s |")


if __name__ == "__main__":
    main()
