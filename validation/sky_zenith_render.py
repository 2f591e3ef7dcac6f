#!/usr/bin/env python3
"""The zenith chromaticity of the renderer's Hosek-Wilkie sky, measured from renders: a camera
at the origin looking straight up (2 degree field, no sun, nothing in view) rendered as CIE XYZ
(--color-space xyz, PFM), for a few sun elevations; printed beside the model's own CIE XYZ
dataset's values (validation/results/sky_zenith_xyz.txt, from validation/sky_zenith_xyz.py).

Usage: python3 validation/sky_zenith_render.py PATH/TO/pathtracer
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from pfm import read_pfm

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = [(5, 3), (15, 3), (30, 3), (45, 3), (60, 3), (85, 3)]


def reference():
    out = {}
    with open(os.path.join(HERE, "results", "sky_zenith_xyz.txt")) as f:
        for line in f:
            if line.startswith("#"):
                continue
            v = line.split()
            out[(int(v[0]), int(v[1]))] = (float(v[3]), float(v[4]))
    return out


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    program = os.path.abspath(sys.argv[1])
    ref = reference()
    print("# sun_elevation_deg turbidity  x y (render)  x y (XYZ dataset)  distance")
    with tempfile.TemporaryDirectory() as tmp:
        for elevation, turbidity in CASES:
            scene = {
                "camera": {"position": [0, 0, 0], "look_at": [0, 1, 0], "up": [0, 0, -1], "vfov_degrees": 2},
                "image": {"width": 8, "height": 8, "spp": 64},
                "background": {"type": "sky", "sun_elevation_degrees": elevation, "turbidity": turbidity,
                               "ground_albedo": 0.1, "sun": False},
                "materials": {"g": {"kd": 0.5}},
                "shapes": [{"type": "sphere", "center": [0, -100, 0], "radius": 1, "material": "g"}],
            }
            path = os.path.join(tmp, "zenith.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            out = os.path.join(tmp, "zenith.pfm")
            subprocess.run([program, path, "--color-space", "xyz", "--quiet", "-o", out], check=True)
            xyz = read_pfm(out).reshape(-1, 3).mean(axis=0)
            x, y = xyz[0] / xyz.sum(), xyz[1] / xyz.sum()
            rx, ry = ref[(elevation, turbidity)] if (elevation, turbidity) in ref else (float("nan"),) * 2
            print(f"{elevation} {turbidity}  {x:.4f} {y:.4f}  {rx:.4f} {ry:.4f}  {np.hypot(x - rx, y - ry):.4f}")


if __name__ == "__main__":
    main()
