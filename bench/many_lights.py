#!/usr/bin/env python3
"""Many lights: the light BVH against power-proportional light selection at equal time (issue 34;
a benchmark, not a test).

The scene (generated here, written to a temporary folder, never committed: about 1 MB of JSON):
a closed grey hall 48 x 4 x 32 with six diffuse and glossy spheres on the floor, lit only by
--groups emitting meshes of --per-group small one-sided triangles each (default 640 x 16 =
10 240 emitters). Layout "lamps" (default): each mesh is a hanging lamp, its triangles facing
down in a disc of radius 0.3 at a height from 1.3 to 3.5, anywhere over the floor; layout
"scattered": every triangle anywhere on the ceiling or the top metre of a wall, facing into the
room. Each mesh has its own tinted-white RGB colour and radiance (the radiance spans two
decades); the triangles' sizes vary too, so the emitters differ in power and colour. The camera
sees no emitter directly (whose anti-aliasing noise no light selection changes): with lamps it
stands below them and looks down at the floor, with the scattered band it stands below the band.
With --light-selection bvh every triangle is a choice of its own; by power, a point lit by
the few lamps near it still spends most samples on the hundreds far away.

Method. Every render uses one thread (--threads 1) and a fixed spp; its CPU time is measured
(getrusage of the child: the scene's parsing and the BVH build included). Both selections are
unbiased, so a render's variance falls as 1/spp and its error at equal time is
relMSE x CPU seconds / budget; the table reports relMSE, the CPU seconds, and relMSE scaled to
the budget of the power render (the "equal time" column), and the ratio of the two. The
reference is a --reference-spp render by bvh in two halves of different seeds: their
difference gives the reference's own noise, subtracted from every relMSE. Several repeats
(--repeats, different seeds) are run interleaved (power, bvh, power, bvh, ...); the table gives
the minimum CPU time and the mean relMSE of the repeats, and `uptime`'s load at the start and
the end.

relMSE = mean over pixels and RGB channels of (x - ref)^2 / (ref^2 + 1e-2).

    "$(bash validation/setup_venv.sh)/bin/python" bench/many_lights.py --program build/pathtracer \\
        --spp 16 --reference-spp 1024 --repeats 3 [--layout scattered]
"""

from __future__ import annotations

import argparse
import json
import resource
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "validation"))
from pfm import read_pfm  # noqa: E402

ROOM = (48.0, 4.0, 32.0)  # x in [-24, 24], y in [0, 4], z in [-16, 16]


def emitter_groups(groups: int, per_group: int, seed: int, layout: str = "lamps") -> list[dict]:
    """The emitting meshes: each a list of one-sided triangles on the ceiling or a wall, just
    inside it, counter-clockwise seen from the room (their front faces it). Layout "lamps": each
    mesh is a hanging lamp, its triangles facing down in a disc of radius 0.3 at a height from
    1.3 to 3.5, anywhere over the floor; "scattered": every triangle anywhere on the ceiling or
    the top metre of a wall, facing into the room."""
    rng = np.random.default_rng(seed)
    hx, hy, hz = ROOM[0] / 2, ROOM[1], ROOM[2] / 2
    # (point on the surface from (a, b) in [0, 1)^2, inward normal)
    surfaces = [
        (lambda a, b: np.array([-hx + 2 * hx * a, hy - 0.01, -hz + 2 * hz * b]), np.array([0.0, -1.0, 0.0])),
        (lambda a, b: np.array([-hx + 2 * hx * a, hy - 1.0 + 0.95 * b, -hz + 0.01]), np.array([0.0, 0.0, 1.0])),
        (lambda a, b: np.array([-hx + 2 * hx * a, hy - 1.0 + 0.95 * b, hz - 0.01]), np.array([0.0, 0.0, -1.0])),
        (lambda a, b: np.array([-hx + 0.01, hy - 1.0 + 0.95 * b, -hz + 2 * hz * a]), np.array([1.0, 0.0, 0.0])),
        (lambda a, b: np.array([hx - 0.01, hy - 1.0 + 0.95 * b, -hz + 2 * hz * a]), np.array([-1.0, 0.0, 0.0])),
    ]
    weights = np.array([0.4, 0.15, 0.15, 0.15, 0.15])
    shapes = []
    for g in range(groups):
        colour = rng.uniform(0.4, 1.0, 3)  # tinted whites: warm, cool, greenish, pinkish
        colour /= colour.max()
        scale = float(10 ** rng.uniform(-0.5, 1.5))
        positions, indices = [], []
        lamp = np.array([rng.uniform(-hx + 0.5, hx - 0.5), rng.uniform(1.3, 3.5), rng.uniform(-hz + 0.5, hz - 0.5)])
        for k in range(per_group):
            if layout == "lamps":
                # A hanging lamp: its triangles facing down, in a disc of radius 0.3.
                n = np.array([0.0, -1.0, 0.0])
                r, phi = 0.3 * np.sqrt(rng.uniform()), rng.uniform(0, 2 * np.pi)
                c = lamp + np.array([r * np.cos(phi), rng.uniform(-0.02, 0.02), r * np.sin(phi)])
            else:
                where, n = surfaces[rng.choice(len(surfaces), p=weights)]
                c = where(*rng.uniform(0, 1, 2))
            t = np.cross(n, [0.0, 1.0, 0.0] if abs(n[1]) < 0.9 else [1.0, 0.0, 0.0])
            t /= np.linalg.norm(t)
            b = np.cross(n, t)  # (t, b, n) right-handed: counter-clockwise in (t, b) faces n
            size = rng.uniform(0.04, 0.12)
            phase = rng.uniform(0, 2 * np.pi)
            for j in range(3):
                angle = phase + 2 * np.pi * j / 3
                positions.extend((c + size * (np.cos(angle) * t + np.sin(angle) * b)).round(5).tolist())
            indices.extend([3 * k, 3 * k + 1, 3 * k + 2])
        shapes.append({"type": "mesh", "positions": positions, "indices": indices, "two_sided": False,
                       "emission": {"type": "rgb", "value": colour.round(4).tolist(), "scale": round(scale, 3)}})
    return shapes


def scene(groups: int, per_group: int, width: int, height: int, seed: int, layout: str = "lamps") -> dict:
    hx, hy, hz = ROOM[0] / 2, ROOM[1], ROOM[2] / 2
    quad = lambda o, e1, e2, m: {"type": "quad", "origin": o, "edge1": e1, "edge2": e2, "material": m}  # noqa: E731
    walls = [
        quad([-hx, 0, -hz], [2 * hx, 0, 0], [0, 0, 2 * hz], "floor"),
        quad([-hx, hy, -hz], [2 * hx, 0, 0], [0, 0, 2 * hz], "wall"),
        quad([-hx, 0, -hz], [2 * hx, 0, 0], [0, hy, 0], "wall"),
        quad([-hx, 0, hz], [2 * hx, 0, 0], [0, hy, 0], "wall"),
        quad([-hx, 0, -hz], [0, hy, 0], [0, 0, 2 * hz], "wall"),
        quad([hx, 0, -hz], [0, hy, 0], [0, 0, 2 * hz], "wall"),
    ]
    spheres = [{"type": "sphere", "center": [x, r, z], "radius": r, "material": m}
               for x, z, r, m in [(-6.0, -4.0, 1.0, "matte"), (-2.0, -6.0, 1.2, "glossy"), (2.5, -2.5, 0.9, "matte"),
                                  (7.0, -5.0, 1.1, "glossy"), (-4.5, 1.5, 0.7, "glossy"), (5.0, 2.0, 0.8, "matte")]]
    # Below the lamps and looking down at the floor (every camera ray goes down: the lamps,
    # which face down, are all above its horizon), or from below the scattered band: the camera
    # sees no emitter directly, whose anti-aliasing noise no light selection changes.
    camera = ({"position": [0, 1.1, 3], "look_at": [0, 0, 1.59], "up": [0, 1, 0], "vfov_degrees": 60}
              if layout == "lamps" else
              {"position": [0, 2.8, hz - 0.5], "look_at": [0, 0, -1], "up": [0, 1, 0], "vfov_degrees": 40})
    return {
        "description": f"bench/many_lights.py: a hall lit by {groups} x {per_group} small one-sided emitting triangles ({layout})",
        "camera": camera,
        "image": {"width": width, "height": height, "spp": 16},
        "materials": {"floor": {"kd": 0.45}, "wall": {"kd": 0.6}, "matte": {"kd": [0.7, 0.6, 0.5]},
                      "glossy": {"type": "plastic", "kd": [0.2, 0.3, 0.5], "roughness": 0.2}},
        "shapes": walls + spheres + emitter_groups(groups, per_group, seed, layout),
    }


def rel_mse(x: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((x - ref) ** 2 / (ref ** 2 + 1e-2)))


def render(program: Path, scene_file: Path, out: Path, selection: str, spp: int, seed: int,
           threads: int = 1, extra: list[str] | None = None) -> tuple[np.ndarray, float]:
    """The image and the CPU seconds (user + system) of the render."""
    cmd = [str(program), str(scene_file), "-o", str(out), "--spp", str(spp), "--seed", str(seed),
           "--threads", str(threads), "--light-selection", selection, "--quiet"] + (extra or [])
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"{shlex.join(cmd)} failed:\n{r.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return read_pfm(out), cpu


def load() -> str:
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--program", type=Path, default=ROOT / "build" / "pathtracer")
    ap.add_argument("--groups", type=int, default=640)
    ap.add_argument("--per-group", type=int, default=16)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--spp", type=int, default=16, help="spp of each compared render")
    ap.add_argument("--reference-spp", type=int, default=1024, help="spp of the reference (two halves)")
    ap.add_argument("--reference-threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--layout", choices=["lamps", "scattered"], default="lamps",
                    help="lamps: each mesh a lamp of its triangles (default); scattered: triangles anywhere")
    ap.add_argument("--max-depth", type=int, help="scattering events per path (default unbounded; 1: direct light)")
    ap.add_argument("--keep", type=Path, help="write the scene here too")
    ap.add_argument("--out", type=Path, help="also write the table here")
    args = ap.parse_args(argv)

    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        scene_file = tmp / "many_lights.json"
        text = json.dumps(scene(args.groups, args.per_group, args.width, args.height, 1, args.layout))
        scene_file.write_text(text)
        if args.keep:
            args.keep.write_text(text)
        load_start = load()
        extra = ["--max-depth", str(args.max_depth)] if args.max_depth is not None else []
        half = args.reference_spp // 2
        halves = [render(args.program, scene_file, tmp / f"ref{i}.pfm", "bvh", half, 1000 + i,
                         args.reference_threads, extra)[0] for i in range(2)]
        ref = 0.5 * (halves[0] + halves[1])
        ref_noise = rel_mse(halves[0], halves[1]) / 4
        results: dict[str, dict[str, list[float]]] = {s: {"err": [], "cpu": []} for s in ("power", "bvh")}
        for rep in range(args.repeats):
            for selection in ("power", "bvh"):
                img, cpu = render(args.program, scene_file, tmp / f"{selection}{rep}.pfm", selection, args.spp,
                                  10 + rep, 1, extra)
                results[selection]["err"].append(rel_mse(img, ref) - ref_noise)
                results[selection]["cpu"].append(cpu)
        load_end = load()

    budget = min(results["power"]["cpu"])
    rows = []
    for selection in ("power", "bvh"):
        err = float(np.mean(results[selection]["err"]))
        cpu = min(results[selection]["cpu"])
        rows.append((selection, err, cpu, err * cpu / budget))
    cmd = "python bench/many_lights.py " + shlex.join(argv if argv is not None else sys.argv[1:])
    lines = [
        f"`{cmd}`",
        "",
        f"{args.groups * args.per_group} emitters ({args.groups} meshes x {args.per_group} triangles, {args.layout}), "
        f"{args.width}x{args.height}, {args.spp} spp per render, 1 thread; reference {args.reference_spp} spp "
        f"(bvh; its own noise {ref_noise:.2e} subtracted); {args.repeats} interleaved repeats.",
        f"Load at start: `{load_start}`; at end: `{load_end}`.",
        "",
        "| selection | relMSE | CPU s (min) | relMSE at equal time |",
        "|---|---|---|---|",
    ]
    for selection, err, cpu, equal in rows:
        lines.append(f"| {selection} | {err:.4g} | {cpu:.2f} | {equal:.4g} |")
    lines.append("")
    lines.append(f"bvh: {rows[0][3] / rows[1][3]:.1f}x lower relMSE than power at equal CPU time.")
    table = "\n".join(lines)
    print(table)
    if args.out:
        args.out.write_text(table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
