#!/usr/bin/env python3
"""A room lit through a window: the environment map sampled with and without a portal at equal
time (issue 34's portals; a benchmark, not a test).

The scene: a closed white room [-1, 1]^3 with a window of 0.8 x 0.6 in its wall z = -1, a grey
ball and a rough aluminium ball inside, under bench/envmap_compare.py's map (a dim sky and a
small bright sun that shines in through the window; with --no-sun the sky alone). The same
scene is rendered with the map sampled over the whole sphere (importance sampling of the map,
the default) and with the window named as the map's portal, each for --seconds, and compared
with a converged reference of the scene without the portal (two halves of different seeds;
their difference gives the reference's own noise, subtracted from every relMSE). relMSE and
efficiency = 1 / (relMSE * time) as in envmap_compare.py. Run with nothing else busy on the machine:

    python bench/portal_compare.py --program build/pathtracer --seconds 10
"""

from __future__ import annotations

import argparse
import json
import shlex
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from envmap_compare import SUN_RADIANCE, rel_mse, render_ours, sky_map, write_pfm  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
WINDOW = {"origin": [-0.2, 0.0, -1.0], "edge1": [0, 0.6, 0], "edge2": [0.8, 0, 0]}  # front: -z, outside


def room_scene(map_file: Path, width: int, height: int, portal: bool) -> dict:
    def quad(origin, e1, e2, material="white"):
        return {"type": "quad", "origin": origin, "edge1": e1, "edge2": e2, "material": material}

    # The wall z = -1 around the window x in [-0.2, 0.6], y in [0, 0.6].
    walls = [quad([-1, -1, -1], [2, 0, 0], [0, 0, 2]), quad([-1, 1, -1], [2, 0, 0], [0, 0, 2]),
             quad([-1, -1, -1], [0, 2, 0], [0, 0, 2]), quad([1, -1, -1], [0, 2, 0], [0, 0, 2]),
             quad([-1, -1, 1], [2, 0, 0], [0, 2, 0]),
             quad([-1, -1, -1], [2, 0, 0], [0, 1, 0]), quad([-1, 0.6, -1], [2, 0, 0], [0, 0.4, 0]),
             quad([-1, 0, -1], [0.8, 0, 0], [0, 0.6, 0]), quad([0.6, 0, -1], [0.4, 0, 0], [0, 0.6, 0])]
    background = {"type": "image", "file": str(map_file), "mapping": "equirect"}
    if portal:
        background["portal"] = WINDOW
    return {
        "camera": {"position": [0.7, 0.3, 0.9], "look_at": [-0.4, -0.6, -0.3], "up": [0, 1, 0], "vfov_degrees": 75},
        "image": {"width": width, "height": height, "spp": 1},
        "integrator": {"type": "path", "max_depth": 6},
        "background": background,
        "materials": {"white": {"kd": 0.7}, "grey": {"kd": 0.5},
                      "aluminium": {"type": "conductor", "metal": "Al", "roughness": 0.1}},
        "shapes": walls + [{"type": "sphere", "center": [-0.3, -0.65, 0.1], "radius": 0.35, "material": "grey"},
                           {"type": "sphere", "center": [0.45, -0.75, -0.35], "radius": 0.25, "material": "aluminium"}],
    }


def overcast(img: np.ndarray) -> np.ndarray:
    """The map without its sun: the sun's texels take the sky's colour at the horizon."""
    out = img.copy()
    out[np.all(img == SUN_RADIANCE, axis=-1)] = np.array([0.5, 0.55, 0.65])
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--program", type=Path, default=ROOT / "build" / "pathtracer")
    ap.add_argument("--seconds", type=float, default=10.0, help="render time of each equal-time variant")
    ap.add_argument("--reference-spp", type=int, default=4096, help="spp of each half of the reference")
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3, help="equal-time renders per variant (seeds differ)")
    ap.add_argument("--no-sun", action="store_true",
                    help="the sky alone (the sun's texels given the sky's colour at the horizon): an overcast day")
    ap.add_argument("--out", type=Path, help="also write the table here")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp_name:
        tmp = Path(tmp_name)
        map_file = tmp / "sky.pfm"
        write_pfm(map_file, overcast(sky_map()) if a.no_sun else sky_map())
        scenes = {}
        for name, portal in (("whole sphere", False), ("portal", True)):
            scenes[name] = tmp / f"{'portal' if portal else 'sphere'}.json"
            scenes[name].write_text(json.dumps(room_scene(map_file, a.width, a.height, portal)))
        halves = [render_ours(a.program, scenes["whole sphere"], tmp / f"ref{i}.pfm", 1000 + i, spp=a.reference_spp,
                              threads=a.threads)[0] for i in range(2)]
        reference = 0.5 * (halves[0] + halves[1])
        ref_noise = 0.25 * rel_mse(halves[0], halves[1])  # the error of their mean
        rows = []
        # Interleaved: one render of each variant per round.
        results = {name: [] for name in scenes}
        for r in range(a.repeats):
            for name, scene in scenes.items():
                img, t, spp = render_ours(a.program, scene, tmp / "x.pfm", 10 + r, seconds=a.seconds, threads=a.threads)
                results[name].append((rel_mse(img, reference) - ref_noise, t, spp))
        for name, runs in results.items():
            err = float(np.mean([x[0] for x in runs]))
            t = float(np.mean([x[1] for x in runs]))
            spp = int(np.mean([x[2] for x in runs]))
            rows.append((name, spp, t, err, 1 / (err * t)))
        base = rows[0][4]
        lines = ["| sampling | spp in the time | time (s) | relMSE | efficiency | vs whole sphere |", "|---|---|---|---|---|---|"]
        for name, spp, t, err, eff in rows:
            lines.append(f"| {name} | {spp} | {t:.1f} | {err:.3e} | {eff:.3g} | {eff / base:.2f}x |")
        cmd = "python bench/portal_compare.py " + shlex.join(argv if argv is not None else sys.argv[1:])
        text = "\n".join(lines) + f"\n\nReference: 2 x {a.reference_spp} spp; relMSE less its noise ({ref_noise:.2e}).\n`{cmd}`\n"
        print(text)
        if a.out:
            a.out.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
