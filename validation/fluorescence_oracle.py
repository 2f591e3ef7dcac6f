"""Fluorescence oracle: a flat fluorescent patch under a uniform illuminant, lit and seen
straight, against its closed form from the excitation-emission (Donaldson) matrix.

The patch (material ``fluorescent``, src/model/fluorescence.h) is an infinite plane under a
constant environment of spectral radiance E; the camera looks straight down, so every pixel
sees the plane and the plane sees only the environment. Its radiance is

    L(lo) = kd(lo) E(lo) + integral D(li, lo) E(li) dli,
    D(li, lo) = a(li) Phi e(lo) (li / lo) [li < lo],   a = 1 - 10^(-d eps),   kd = base (1 - a),

and the film's XYZ = integral cmf(l) L(l) dl / integral y_bar(l) dl over 360-830 nm. This script
builds D from the dye tables (spectra/fluorescent_dyes.csv: excitation eps, emission e, 1 nm bins
over the transport range 300-830 nm, as the renderer tabulates them), takes the illuminants D65
and A and the CIE 1931 2 degree observer from colour-science, and compares with renders of each
named dye under D65, A and the 365 nm LED (spectra/uv_lamps.csv): each of X, Y, Z must agree
within 5 standard errors of the image mean (pixels are independent estimates).

    python validation/fluorescence_oracle.py [--spp N] [--program build/pathtracer]
writes validation/results/fluorescence_oracle.md.
"""
from __future__ import annotations

import argparse
import csv
import json
import subprocess
import sys
import tempfile
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore", message='"SciPy" related API')
import colour  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from pfm import read_pfm  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
T_MIN, T_MAX = 300, 830                      # transport range (nm), 1 nm bins
CENTRES = np.arange(T_MIN, T_MAX) + 0.5
DYES = {"fluorescein": 0.925, "rhodamine6g": 0.95, "quinine": 0.546, "stilbene": 0.80}
ILLUMINANTS = ("D65", "A", "led365")
DENSITY, BASE = 1.5, 0.9
Z = 5.0


def read_table(path: Path) -> dict[str, np.ndarray]:
    rows = [r for r in csv.reader(line for line in path.read_text().splitlines() if not line.startswith("#"))]
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}


def interp(table_l: np.ndarray, table_v: np.ndarray, l: np.ndarray) -> np.ndarray:
    return np.interp(l, table_l, table_v)  # linear, ends held: the renderer's piecewise_linear


def illuminant(name: str):
    """E(l) as the scene gives it: CIE tables / 100 (colour-science's datasets), or the lamp."""
    if name == "led365":
        t = read_table(REPO / "spectra" / "uv_lamps.csv")
        return lambda l: interp(t["wavelength_nm"], t["led365"], l)
    sd = colour.SDS_ILLUMINANTS[name]
    return lambda l: interp(sd.wavelengths, sd.values / 100.0, l)


@dataclass
class Dye:
    a: np.ndarray       # absorptance per 1 nm bin
    e: np.ndarray       # emission per nm, sums to 1
    phi: float


def dye(name: str, density: float = DENSITY) -> Dye:
    t = read_table(REPO / "spectra" / "fluorescent_dyes.csv")
    eps = np.maximum(interp(t["wavelength_nm"], t[f"{name}_excitation"], CENTRES), 0)
    a = 1 - 10 ** (-density * eps / eps.max())
    e = np.maximum(interp(t["wavelength_nm"], t[f"{name}_emission"], CENTRES), 0)
    return Dye(a, e / e.sum(), DYES[name])


def radiance(d: Dye, E, l_out: np.ndarray) -> np.ndarray:
    """L(lo) at each of l_out (nm), 360-830."""
    kd = BASE * (1 - interp(CENTRES, d.a, l_out))
    # The re-emitted part: li on a 0.05 nm grid (a within each 1 nm bin, li/lo continuous).
    h = 0.05
    li = np.arange(T_MIN + h / 2, T_MAX, h)
    a_li = d.a[np.clip((li - T_MIN).astype(int), 0, len(d.a) - 1)]
    weighted = a_li * E(li) * li * h                              # a(li) E(li) li dli
    cum = np.concatenate([[0.0], np.cumsum(weighted)])            # integral below each li
    below = cum[np.searchsorted(li, l_out, side="left")]          # li < lo
    e_lo = d.e[np.clip((l_out - T_MIN).astype(int), 0, len(d.e) - 1)]
    return kd * E(l_out) + d.phi * e_lo * below / l_out


def cmf_at(l: np.ndarray) -> np.ndarray:
    """CIE 1931 2 degree CMFs (colour-science, 1 nm over 360-830) linear between entries."""
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(colour.SpectralShape(360, 830, 1))
    return np.stack([np.interp(l, cmfs.wavelengths, cmfs.values[:, k]) for k in range(3)], axis=1)


def oracle_xyz(name: str, illum: str) -> np.ndarray:
    # The film integrates continuous functions; a 0.1 nm grid with the CMFs linear between
    # their 1 nm entries is that integral to well below the render noise.
    return xyz_of(dye(name), illum)


GAMUT_NOTE = ("Luminance factor: Y over the Y of a perfect white under the same light (D65 and A only; above 1 "
              "the colour is brighter than any reflectance can be). Reflectance gamut of an RGB space (D65 only): "
              "its unit cube, the colours of reflectances 0-1 in each primary; a patch is outside when a linear "
              "component of XYZ / Y_white lies outside [0, 1] (colour-science's sRGB and ITU-R BT.2020).")


def gamut(xyz: np.ndarray, illum: str) -> tuple[str, str]:
    """(luminance factor, the RGB spaces whose reflectance cube the colour lies outside)."""
    if illum == "led365":
        return "-", "-"
    l = np.arange(360.05, 830, 0.1)
    y = cmf_at(l)[:, 1]
    white_y = (illuminant(illum)(l) * y).sum() / y.sum()
    beta = f"{xyz[1] / white_y:.3f}"
    if illum != "D65":
        return beta, "-"
    out = []
    for space, label in (("sRGB", "sRGB"), ("ITU-R BT.2020", "Rec.2020")):
        cs = colour.RGB_COLOURSPACES[space]
        # XYZ relative to the spectral D65 white, taken as the space's own white (no adaptation).
        rgb = colour.XYZ_to_RGB(xyz / white_y, cs, illuminant=cs.whitepoint, apply_cctf_encoding=False)
        if rgb.min() < -1e-6 or rgb.max() > 1 + 1e-6:
            out.append(label)
    return beta, ", ".join(out) if out else "neither"


def xyz_of(d: Dye, illum: str) -> np.ndarray:
    l = np.arange(360.05, 830, 0.1)
    cmf = cmf_at(l)
    L = radiance(d, illuminant(illum), l)
    return (L[:, None] * cmf).sum(axis=0) / cmf[:, 1].sum()


def scene_json(name: str, illum: str) -> dict:
    background = ({"type": "uv_lamp", "name": "led365"} if illum == "led365"
                  else {"type": "illuminant", "name": illum})
    return {
        "camera": {"position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, 1], "vfov_degrees": 20},
        "background": background,
        "materials": {"patch": {"type": "fluorescent", "dye": name, "density": DENSITY, "base": BASE}},
        "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "patch"}],
    }


def render_xyz(program: Path, name: str, illum: str, spp: int, size: int, seed: int = 1):
    """(mean XYZ, standard error) over the image's pixels."""
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "patch.json"
        scene.write_text(json.dumps(scene_json(name, illum)))
        out = Path(tmp) / "patch.pfm"
        cmd = [str(program), str(scene), "--spp", str(spp), "--width", str(size), "--height", str(size),
               "--color-space", "xyz", "--seed", str(seed), "--quiet", "-o", str(out)]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
        px = read_pfm(out).reshape(-1, 3)
    return px.mean(axis=0), px.std(axis=0, ddof=1) / np.sqrt(len(px))


def compare(program: Path, name: str, illum: str, spp: int, size: int):
    want = oracle_xyz(name, illum)
    got, se = render_xyz(program, name, illum, spp, size)
    z = np.abs(got - want) / np.maximum(se, 1e-12)
    return want, got, se, z


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--program", type=Path, default=REPO / "build" / "pathtracer")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--size", type=int, default=32)
    ap.add_argument("--out", type=Path, default=REPO / "validation" / "results" / "fluorescence_oracle.md")
    args = ap.parse_args()
    lines = ["# Fluorescence oracle: flat patch, closed form vs render", "",
             f"`python validation/fluorescence_oracle.py --spp {args.spp} --size {args.size}` "
             f"(density {DENSITY}, base {BASE}; pass: |render - oracle| <= {Z} standard errors in X, Y and Z).", "",
             GAMUT_NOTE, "",
             "| dye | illuminant | oracle XYZ | render XYZ | standard error | max z | re-emitted share of Y "
             "| luminance factor | outside the reflectance gamut of |",
             "|---|---|---|---|---|---|---|---|---|"]
    ok = True
    for name in DYES:
        for illum in ILLUMINANTS:
            want, got, se, z = compare(args.program, name, illum, args.spp, args.size)
            d = dye(name)
            reflected_only = Dye(d.a, d.e, 0.0)
            l = np.arange(360.05, 830, 0.1)
            y = cmf_at(l)[:, 1]
            E = illuminant(illum)
            share = 1 - (radiance(reflected_only, E, l) * y).sum() / max((radiance(d, E, l) * y).sum(), 1e-30)
            beta, outside = gamut(want, illum)
            passed = bool(np.all(z <= Z))
            ok &= passed
            fmt = lambda v: "(" + ", ".join(f"{x:.5g}" for x in v) + ")"  # noqa: E731
            lines.append(f"| {name} | {illum} | {fmt(want)} | {fmt(got)} | {fmt(se)} | {z.max():.2f}"
                         f"{'' if passed else ' FAIL'} | {share:.3f} | {beta} | {outside} |")
            print(lines[-1], flush=True)
    lines += ["", "## The chart's patches (scenes/fluorescent-chart.json, base 0.9, under D65; closed form only)", "",
              "| dye | density | quantum yield | oracle XYZ | luminance factor | outside the reflectance gamut of |",
              "|---|---|---|---|---|---|"]
    for name in DYES:
        for density, phi in ((1.0, None), (3.0, None), (3.0, 0.0)):
            d = dye(name, density)
            if phi is not None:
                d = Dye(d.a, d.e, phi)
            want = xyz_of(d, "D65")
            beta, outside = gamut(want, "D65")
            lines.append(f"| {name} | {density:g} | {d.phi:g} | ({', '.join(f'{x:.4g}' for x in want)}) "
                         f"| {beta} | {outside} |")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
