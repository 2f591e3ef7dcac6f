#!/usr/bin/env python3
"""Writes the path-guiding benchmark scenes of this folder (door-ajar.json, window-sun.json,
prism-room.json): hard cases for a path tracer, where the light that matters arrives through a
small opening after one or more bounces. The geometry is computed here (walls as boxes that
overlap at the corners, so that no light leaks through a seam; the door turned about its
hinge; the prism room turned to the prism's exit beam); the JSON files are the product, each
a plain scene of scenes/README.md. Run after changing anything here:

    python3 bench/guiding/make_scenes.py
"""

from __future__ import annotations

import json
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent


def r(v, nd: int = 5):
    """Rounds numbers (and lists of them) for the file: 1e-5 scene units."""
    if isinstance(v, (list, tuple)):
        return [r(x, nd) for x in v]
    x = round(float(v), nd)
    return 0 if x == 0 else (int(x) if x == int(x) and abs(x) < 1e6 else x)


def box(lo, hi, material: str, transform: dict | None = None) -> dict:
    """An axis-aligned box [lo, hi] as an inline mesh of 12 triangles, counter-clockwise seen
    from outside (then placed by the optional transform)."""
    corners = [[(lo, hi)[i & 1][0], (lo, hi)[(i >> 1) & 1][1], (lo, hi)[(i >> 2) & 1][2]] for i in range(8)]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    faces = [(0, 2, 6, 4), (1, 5, 7, 3), (0, 4, 5, 1), (2, 3, 7, 6), (0, 1, 3, 2), (4, 6, 7, 5)]
    indices = []
    for f in faces:
        p = [corners[i] for i in f]
        e1 = [p[1][k] - p[0][k] for k in range(3)]
        e2 = [p[2][k] - p[0][k] for k in range(3)]
        n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
        out = sum(n[k] * (p[0][k] - centre[k]) for k in range(3))
        if out < 0:
            f = tuple(reversed(f))
        indices += [f[0], f[1], f[2], f[0], f[2], f[3]]
    shape = {"type": "mesh", "positions": r([c for corner in corners for c in corner]), "indices": indices,
             "material": material}
    if transform:
        shape["transform"] = transform
    return shape


def quad(origin, e1, e2, **kw) -> dict:
    return {"type": "quad", "origin": r(origin), "edge1": r(e1), "edge2": r(e2), **kw}


def sphere(c, radius, material) -> dict:
    return {"type": "sphere", "center": r(c), "radius": r(radius), "material": material}


def shell(x0, x1, y0, y1, z0, z1, t: float, material: str, skip: tuple = ()) -> list[dict]:
    """The six walls, thickness t, of the room [x0, x1] x [y0, y1] x [z0, z1] (inside faces on
    those planes), each overlapping its neighbours at the corners. skip: walls left out
    ("-x", "+x", "-y", "+y", "-z", "+z"), to be built with an opening instead."""
    walls = {
        "-y": box([x0 - t, y0 - t, z0 - t], [x1 + t, y0, z1 + t], material),
        "+y": box([x0 - t, y1, z0 - t], [x1 + t, y1 + t, z1 + t], material),
        "-x": box([x0 - t, y0 - t, z0 - t], [x0, y1 + t, z1 + t], material),
        "+x": box([x1, y0 - t, z0 - t], [x1 + t, y1 + t, z1 + t], material),
        "-z": box([x0 - t, y0 - t, z0 - t], [x1 + t, y1 + t, z0], material),
        "+z": box([x0 - t, y0 - t, z1], [x1 + t, y1 + t, z1 + t], material),
    }
    return [w for k, w in walls.items() if k not in skip]


def table(x0, x1, z0, z1, height, material) -> list[dict]:
    leg, top = 0.05, 0.04
    shapes = [box([x0, height - top, z0], [x1, height, z1], material)]
    for x in (x0 + 0.03, x1 - 0.03 - leg):
        for z in (z0 + 0.03, z1 - 0.03 - leg):
            shapes.append(box([x, 0, z], [x + leg, height - top, z + leg], material))
    return shapes


# --- door-ajar ----------------------------------------------------------------------------------

DOOR_DEGREES = 12.0


def door_ajar() -> dict:
    # One building, x in [-2, 2], y in [0, 2.5]: the camera's room z in [-2, 2], the lamp's room
    # z in [-5, -2.1], a wall z in [-2.1, -2] between them with a doorway x in [0.6, 1.5],
    # y in [0, 2.05]. The door (0.92 x 2.05 x 0.04) is hinged at x = 1.5 on the camera's side of
    # the wall and opened DOOR_DEGREES into the camera's room: its free edge stands about 16 cm
    # from the jamb, and light leaves the wedge between door and wall through that slit (and
    # over the door's top edge) towards -x only. The lamp, on the lamp room's wall x = -2 facing
    # +x, therefore cannot shine through the slit: its light reaches the camera's room after a
    # bounce off the lamp room's walls (mostly the wall x = 2 it faces), and the camera sees
    # it after at least two bounces (the bright wedge on the floor), most of the room after
    # three or more.
    t = 0.1
    shapes = [
        box([-2 - t, -t, -5 - t], [2 + t, 0, 2 + t], "floor"),
        box([-2 - t, 2.5, -5 - t], [2 + t, 2.5 + t, 2 + t], "wall"),
        box([-2 - t, -t, -5 - t], [-2, 2.5 + t, 2 + t], "wall"),
        box([2, -t, -5 - t], [2 + t, 2.5 + t, 2 + t], "wall"),
        box([-2 - t, -t, -5 - t], [2 + t, 2.5 + t, -5], "wall"),
        box([-2 - t, -t, 2], [2 + t, 2.5 + t, 2 + t], "wall"),
        # the dividing wall around the doorway
        box([-2, 0, -2.1], [0.6, 2.5, -2.0], "wall"),
        box([1.5, 0, -2.1], [2, 2.5, -2.0], "wall"),
        box([0.6, 2.05, -2.1], [1.5, 2.5, -2.0], "wall"),
        # the door: in its own frame x in [-0.9, 0.02] (2 cm inside the jamb at the hinge),
        # z in [0, 0.04], turned about the hinge line x = 1.5, z = -2
        box([-0.9, 0, 0], [0.02, 2.05, 0.04], "door",
            {"rotate": {"axis": [0, 1, 0], "degrees": DOOR_DEGREES}, "translate": [1.5, 0, -2.0]}),
        # the lamp: on the lamp room's wall x = -2, facing +x (one-sided)
        quad([-1.95, 0.9, -4.3], [0, 0.8, 0], [0, 0, 1.2], two_sided=False,
             emission={"type": "blackbody", "temperature_k": 4000, "scale": 900}),
        # the lamp room: a cupboard (its floor and walls are what the slit sees)
        box([1.2, 0, -4.95], [1.95, 1.9, -4.3], "wood"),
    ]
    # the camera's room: a table with a glossy ball and a box, a rough copper ball, a plastic cube
    shapes += table(-1.3, -0.1, -1.1, -0.3, 0.75, "wood")
    shapes += [
        sphere([-0.95, 0.9, -0.7], 0.15, "red plastic"),
        box([-0.55, 0.75, -0.85], [-0.3, 1.0, -0.6], "white"),
        sphere([0.45, 0.3, -0.2], 0.3, "copper"),
        box([-1.9, 0, 0.2], [-1.2, 0.45, 1.1], "blue plastic"),
        box([1.55, 0, -1.0], [1.95, 1.6, 0.4], "wood"),  # a wardrobe by the right wall
    ]
    return {
        "description": f"Veach's door ajar (bench/guiding/make_scenes.py): a closed room lit only through a door opened {DOOR_DEGREES:g} degrees into it from a second room, whose lamp faces away from the slit, so every light path to the camera bounces at least twice (once in each room); a table with a glossy ball and a box, a rough copper ball, a plastic bench. A path-guiding benchmark (bench/guiding_benchmark.py).",
        "summary": "door ajar: a room lit through a crack from the next room's bounced light",
        "camera": {"position": [-1.55, 1.55, 1.85], "look_at": [0.35, 0.7, -1.6], "up": [0, 1, 0], "vfov_degrees": 60},
        "image": {"width": 320, "height": 240, "spp": 64},
        "materials": {
            "wall": {"kd": 0.7},
            "floor": {"kd": [0.45, 0.33, 0.22]},
            "door": {"kd": 0.75},
            "wood": {"type": "plastic", "kd": [0.35, 0.2, 0.1], "roughness": 0.15},
            "white": {"kd": 0.8},
            "red plastic": {"type": "plastic", "kd": [0.6, 0.05, 0.04], "roughness": 0.05},
            "blue plastic": {"type": "plastic", "kd": [0.1, 0.2, 0.5], "roughness": 0.3},
            "copper": {"type": "conductor", "metal": "Cu", "roughness": 0.15},
        },
        "shapes": shapes,
    }


# --- window-sun ---------------------------------------------------------------------------------

def window_sun() -> dict:
    # A closed room x in [-2, 2], y in [0, 2.6], z in [-2.5, 2.5], walls 15 cm thick, with one
    # window of 0.7 x 0.7 in its wall x = -2 (y in [1, 1.7], z in [-1, -0.3]). The sun, 30
    # degrees high towards -x (a little towards -z), shines through it onto the floor in the
    # middle of the room; the sky through the window and the sunlit ground outside light the
    # rest. The camera stands in the corner beside the window wall and looks across the room:
    # the window is out of view.
    x0, x1, y0, y1, z0, z1, t = -2.0, 2.0, 0.0, 2.6, -2.5, 2.5, 0.15
    wy0, wy1, wz0, wz1 = 1.0, 1.7, -1.0, -0.3
    shapes = [{"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "ground"}]
    shapes += shell(x0, x1, y0, y1, z0, z1, t, "wall", skip=("-x", "-y"))
    shapes += [
        box([x0, y0, z0], [x1, y0 + 0.02, z1], "floor"),  # the room's floor on the ground
        # the wall x = -2 around the window
        box([x0 - t, y0, z0 - t], [x0, wy0, z1 + t], "wall"),
        box([x0 - t, wy1, z0 - t], [x0, y1 + t, z1 + t], "wall"),
        box([x0 - t, wy0, z0 - t], [x0, wy1, wz0], "wall"),
        box([x0 - t, wy0, wz1], [x0, wy1, z1 + t], "wall"),
        # furniture
        box([0.7, 0, -2.45], [1.95, 0.45, -1.85], "fabric"),   # a bench against the back wall
        box([0.7, 0.45, -2.45], [1.95, 0.9, -2.3], "fabric"),
        sphere([1.3, 0.35, 0.6], 0.35, "glossy white"),
        sphere([0.4, 0.25, 1.4], 0.25, "gold"),
        box([1.6, 0, 1.2], [1.95, 1.2, 2.2], "wall"),          # a shelf by the right wall
    ]
    shapes += table(-0.9, 0.3, -2.4, -1.7, 0.72, "wood")
    return {
        "description": "A closed room lit by the spectral sun and sky (Hosek-Wilkie, turbidity 3) through one 0.7 x 0.7 window (bench/guiding/make_scenes.py): the sun, 30 degrees high, makes a patch on the floor; everything else the camera sees is lit through the window after one or more bounces. A path-guiding benchmark (bench/guiding_benchmark.py).",
        "summary": "a room lit by sun and sky through one small window",
        "camera": {"position": [-1.7, 1.6, 2.2], "look_at": [1.0, 0.5, -1.2], "up": [0, 1, 0], "vfov_degrees": 55},
        "image": {"width": 320, "height": 240, "spp": 64},
        "background": {"type": "sky", "sun_elevation_degrees": 30, "sun_azimuth_degrees": 195,
                       "turbidity": 3, "ground_albedo": 0.3, "scale": 30},
        "materials": {
            "ground": {"kd": 0.3},
            "wall": {"kd": 0.75},
            "floor": {"kd": [0.5, 0.36, 0.22]},
            "wood": {"type": "plastic", "kd": [0.35, 0.2, 0.1], "roughness": 0.15},
            "fabric": {"kd": [0.2, 0.35, 0.3]},
            "glossy white": {"type": "plastic", "kd": 0.8, "roughness": 0.05},
            "gold": {"type": "conductor", "metal": "Au", "roughness": 0.2},
        },
        "shapes": shapes,
    }


# --- prism-room ---------------------------------------------------------------------------------

def prism_room() -> dict:
    # scenes/prism.json's optics in a closed dark room: the SF11 prism (side 0.5, height 1) at
    # the origin turned to minimum deviation, a white lamp in a black box whose face x = -0.5651
    # has a vertical slit; the dispersed beam lands on the room's white back wall (the plane of
    # prism.json's screen). The room is turned so that this wall is one of its walls. Nothing
    # else emits: the rest of the room is lit by what the rainbow, the beam's spill and the
    # prism's reflections send back.
    S0 = (0.07606, -1.34798)               # a point of prism.json's screen (x, z)
    u = (1.0992, 0.48156)
    n_u = math.hypot(*u)
    u = (u[0] / n_u, u[1] / n_u)           # along the wall
    nrm = (-u[1], u[0])                    # the wall's normal, towards the prism

    def world(a, b):
        return [S0[0] + a * u[0] + b * nrm[0], S0[1] + a * u[1] + b * nrm[1]]

    A0, A1, B1, H = -2.4, 2.8, 3.9, 2.6    # the room in the wall's frame: a along, b out of it

    def wall(a0, b0, a1, b1, y0, y1, material):
        p, q = world(a0, b0), world(a1, b1)
        return quad([p[0], y0, p[1]], [q[0] - p[0], 0, q[1] - p[1]], [0, y1 - y0, 0], material=material)

    c00, c10, c11, c01 = world(A0, 0), world(A1, 0), world(A1, B1), world(A0, B1)
    shapes = [
        {"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor"},
        wall(A0, 0, A1, 0, 0, H, "white"),     # the back wall: the rainbow's
        wall(A1, 0, A1, B1, 0, H, "grey"),
        wall(A1, B1, A0, B1, 0, H, "grey"),
        wall(A0, B1, A0, 0, 0, H, "grey"),
        quad([c00[0], H, c00[1]], [c10[0] - c00[0], 0, c10[1] - c00[1]], [c01[0] - c00[0], 0, c01[1] - c00[1]],
             material="grey"),
        {"type": "mesh", "file": "../../scenes/prism.ply", "material": "flint",
         "transform": {"scale": [0.2886751345948129, 0.5, 0.2886751345948129],
                       "rotate": {"axis": [0, 1, 0], "degrees": 33.1713}, "translate": [0, 0.5, 0]}},
    ]
    # The lamp box x in [-2.3, -0.5651], z in [-0.3, 0.5], y in [0, 1.15]; the slit in its face
    # x = -0.5651: z in [0.1038, 0.1538], y in [0.05, 1.0] (prism.json's slit is 3.5 cm wide and
    # open above; this one is 5 cm wide, so that a path from the wall finds the lamp more often).
    X, xb, za, zb, yt = -0.5651, -2.3, -0.3, 0.5, 1.15
    s0, s1, sy0, sy1 = 0.0938, 0.1538, 0.05, 1.0
    shapes += [
        quad([X, 0, za], [0, 0, s0 - za], [0, yt, 0], material="black"),
        quad([X, 0, s1], [0, 0, zb - s1], [0, yt, 0], material="black"),
        quad([X, 0, s0], [0, 0, s1 - s0], [0, sy0, 0], material="black"),
        quad([X, sy1, s0], [0, 0, s1 - s0], [0, yt - sy1, 0], material="black"),
        quad([xb, 0, za], [0, 0, zb - za], [0, yt, 0], material="black"),
        quad([xb, 0, za], [X - xb, 0, 0], [0, yt, 0], material="black"),
        quad([xb, 0, zb], [X - xb, 0, 0], [0, yt, 0], material="black"),
        quad([xb, yt, za], [X - xb, 0, 0], [0, 0, zb - za], material="black"),
        # the lamp: 8 cm wide, 0.9 tall, 1.2 behind the slit, facing it (one-sided)
        quad([X - 1.2, 0.05, s0 - 0.01], [0, 0.9, 0], [0, 0, 0.08], two_sided=False,
             emission={"type": "illuminant", "name": "D65", "scale": 2500}),
    ]
    return {
        "description": "Newton's prism in a dark room (bench/guiding/make_scenes.py; the optics of scenes/prism.json): a white lamp in a black box shines through a 5 cm slit into an SF11 prism at minimum deviation, which fans the beam into a rainbow on the room's white wall; nothing else emits, the room is lit only by light that came through the prism and the slit. The path tracer finds the lamp from the wall only when a diffuse bounce passes back through the prism and the slit: a path-guiding benchmark (bench/guiding_benchmark.py), also of colour noise.",
        "summary": "a prism's rainbow in a dark room, lit only through a slit",
        "camera": {"position": [0.45, 1.6, 2.0], "look_at": [0.45, 0.55, -0.8], "up": [0, 1, 0], "vfov_degrees": 55},
        "image": {"width": 320, "height": 240, "spp": 64},
        "materials": {
            "floor": {"kd": 0.5},
            "white": {"kd": 0.85},
            "grey": {"kd": 0.6},
            "black": {"kd": 0},
            "flint": {"kt": 1, "ior": {"type": "glass", "name": "SF11"}},
        },
        "shapes": shapes,
    }


def dump(scene: dict) -> str:
    """The scene as JSON: one line per shape and per material, the rest indented."""
    lines = ["{"]
    items = list(scene.items())
    for i, (k, v) in enumerate(items):
        comma = "," if i + 1 < len(items) else ""
        if k == "shapes":
            lines.append(f'  "shapes": [')
            lines += [f"    {json.dumps(s, ensure_ascii=False)}{',' if j + 1 < len(v) else ''}" for j, s in enumerate(v)]
            lines.append(f"  ]{comma}")
        elif k == "materials":
            lines.append('  "materials": {')
            ms = list(v.items())
            lines += [f"    {json.dumps(m)}: {json.dumps(d)}{',' if j + 1 < len(ms) else ''}" for j, (m, d) in enumerate(ms)]
            lines.append(f"  }}{comma}")
        else:
            lines.append(f"  {json.dumps(k)}: {json.dumps(v, ensure_ascii=False)}{comma}")
    lines.append("}")
    return "\n".join(lines) + "\n"


def main() -> None:
    for name, make in (("door-ajar", door_ajar), ("window-sun", window_sun), ("prism-room", prism_room)):
        path = HERE / f"{name}.json"
        path.write_text(dump(make()))
        print(path)


if __name__ == "__main__":
    main()
