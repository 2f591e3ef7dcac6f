"""Colour accuracy of the renderer on the ColorChecker, against colour-science.

Renders the scenes ``scenes/colorchecker.json`` (CIE D65),
``scenes/colorchecker-a.json`` (CIE illuminant A), ``scenes/colorchecker-f11.json``
(CIE F11, a tri-band fluorescent lamp) and ``scenes/colorchecker-led.json`` (CIE LED-B3,
a phosphor-converted white LED; all four also built in), and the D65 file with its
background renamed to CIE F2 and F7 (fluorescent lamps), with ``--color-space xyz`` for
``--spectral-bins`` 4, 8, 16, 32, 64 and ``exact``, averages the central pixels of each of
the 24 patches and compares them in CIELAB (CIEDE2000) with colour-science's own
computation of the same patches. F2, F7, F11 and LED-B3 have lines a few nm wide (their
tables are at 5 nm): "spiky light".

What is compared
----------------
Each patch is a Lambertian quad lit only by a constant environment of the
illuminant S and coplanar with the other patches, so its radiance is exactly
rho(lambda) * S(lambda) (no interreflection).

* **Reference** (``reference_xyz``): the Ohta reflectances
  (``colour.SDS_COLOURCHECKERS['ColorChecker N Ohta']``) and the illuminant
  (``colour.SDS_ILLUMINANTS``), both aligned to 360-830 nm at 1 nm with
  ``colour.LinearInterpolator`` and constant extrapolation, integrated by
  ``colour.sd_to_XYZ(..., method='Integration')`` with the CIE 1931 2 degree
  observer at 1 nm (Y = 100 for the perfect reflector; divided by 100 here).
  Linear interpolation, not Sprague or cubic, because the renderer's named
  table sources are piecewise linear between the tabulated points and held
  constant outside them: the reference must describe the same spectrum, or
  the difference of interpolants (a few hundredths of Delta E) would be
  counted as renderer error.
* **Rendered** (``patch_means``): the renderer's XYZ is
  integral(rho * k S * cmf) / integral(y_bar) (its film divides by integral(y_bar);
  ``renderer_scale`` k is 1/100 for D65 and A, tables of 100 at 560 nm, and 1/luminance
  for the lamps with lines). It is scaled by integral(y_bar) / integral(k S * y_bar),
  1 nm sums of the same tables, so that the perfect white has Y = 1 exactly as in the
  reference.
* **Exact integral** (``film_xyz``): what the exact mode converges to, the integral of
  the same piecewise-linear functions (Simpson per 1 nm interval, exact for them). Under
  light with 5 nm lines colour-science's 1 nm sums differ from it by 0.004-0.0055 mean
  Delta E (F11: 0.015 max), which is the quadrature's error, not the renderer's; the exact
  mode is checked against both.
* **Representation floor** (``floor_xyz``): for N bins, rho and S are
  replaced by what the renderer stores (``binned``): the least-squares
  projection of the piecewise-linear table onto the look-up's basis
  (``project_onto_bins``, as src/spectral/spectrum.cpp; float32) at the bin
  centres 380 + (i + 0.5) * 400 / N, linear between centres and held constant
  beyond the first and last centre.
  rho_b * S_b is integrated with the CMFs at 1 nm over 360-830 nm and scaled
  with the white of the *true* illuminant. This is the error of N bins
  alone; the renderer's N-bin render must be within 0.02 mean Delta E of it (N >= 16).

The renderer integrates the continuous product of its piecewise-linear spectra and CMFs
(Monte Carlo); under D65 and A the 1 nm sums above differ from that integral by at most
0.004 Delta E (0.0016 mean) for the reference and 0.003 for the floors, measured on a
0.01 nm grid (under the lamps with lines: ``film_xyz``).
colour-science 0.4.7's default alignment (Sprague for these reflectances, linear for D65
and A) would instead move the reference by 0.015-0.02 mean, 0.044 max.

Lab for all three uses ``colour.XYZ_to_Lab`` with the white point xy of the
reference perfect white under the same illuminant (so Lab is relative to the
illuminant's own white), and ``colour.delta_E(method='CIE 2000')``.

Binned modes use a control variate (at ``--spiky-spp`` under the lamps with lines, where it
helps less: the exact render's noise there is the lines', which the bins smooth away). Every
render of one illuminant at one spp uses the
same seed, so each pixel sample draws the same wavelengths whatever the spectra (a diffuse
patch under a uniform environment consumes its random numbers identically), and

    render(N) - render(exact) + reference

estimates the N-bin render's expected XYZ with the noise of the *difference* of the two
spectra only. Its expectation is that of render(N) as long as exact mode is unbiased, which
the separate exact-mode check (``--exact-spp``, its own seed) verifies against the
reference directly. The raw render(N) is reported as well.

Noise is measured in every render: the pixels of each patch's central region are split in a
checkerboard into two halves (every pixel has its own random stream, so the halves are
independent); the Delta E between the two half means, divided by 2, estimates the Delta E
noise of the full mean (each half has twice its variance, their difference four times). With
``--seed-check`` the exact mode is rendered again with another seed and the Delta E between
the two renders is reported (expected about sqrt(2) times the noise of one render).

What spiky light costs (``exact_cost``, ``--cost-spp``): the exact mode at several spp
against ``film_xyz``, so its Delta E is Monte Carlo error alone, per illuminant.

Run::

    .venv/bin/python validation/color_accuracy.py --exact-spp 1024   # writes validation/results/

Outputs ``color_accuracy.md`` (tables) and ``color_accuracy.png`` (plot) in ``--out``.
``validation/test_color_accuracy.py`` asserts the criteria with the functions below (at
lower spp).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np
from pfm import read_pfm  # noqa: F401  (re-exported for the tests)

warnings.filterwarnings("ignore", message='"SciPy" related API')
import colour  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent
SCENES_DIR = REPO_ROOT / "scenes"

BIN_COUNTS: tuple[int | str, ...] = (4, 8, 16, 32, 64, "exact")
# illuminant name (the scene's) -> built-in scene: daylight, a tungsten lamp, and light with
# lines a few nm wide (a tri-band fluorescent lamp, a phosphor-converted white LED)
SCENES = {"D65": "colorchecker", "A": "colorchecker-a", "F11": "colorchecker-f11",
          "LED-B3": "colorchecker-led"}
# illuminants rendered from the D65 scene's file with only its background renamed (the script
# measures them too; they are no built-in scenes)
DERIVED = ("F2", "F7")
ILLUMINANTS = tuple(SCENES) + DERIVED
# the scene's illuminant name -> colour-science's key (where they differ)
COLOUR_KEYS = {"F2": "FL2", "F7": "FL7", "F11": "FL11"}
# the illuminants the renderer sets to 1 at 560 nm (tables of 100 there); the others it sets
# to luminance 1 (src/scene/spectrum_parser.cpp)
AT_560 = ("D65", "A")

DEFAULT_SPP = 128        # binned renders and the exact control (one seed)
# The same under light with lines: the control variate render(N) - render(exact) + reference
# helps little there (the exact render's noise comes from the lines, which N bins smooth away),
# so its noise at 128 spp (0.013-0.018 mean Delta E under F11 for N >= 16) would blur the 0.02
# that the binned modes are held to; at 512 it is 0.002.
DEFAULT_SPIKY_SPP = 256
SPIKY = ("F2", "F7", "F11", "LED-B3")   # light with lines a few nm wide
DEFAULT_COST_SPP = (16, 64, 256)  # the exact mode's noise against spp (--cost-spp; 1024: the check)
DEFAULT_EXACT_SPP = 2048  # the exact-mode check (its own seed)
DEFAULT_SEED = 1
MARGIN_PX = 1  # pixels dropped inside each patch's edge

SHAPE = colour.SpectralShape(360, 830, 1)  # the renderer's sampled range and its CMF table
WAVELENGTHS = SHAPE.wavelengths
BIN_MIN, BIN_MAX = 380.0, 780.0  # the renderer's binned range (src/spectral/spectrum.h)

CHECKER = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]
# Scene/material names are colour-science's patch names lower-cased, each run of other
# characters turned into one '_' (as in spectra/colorchecker.csv).
PATCHES: dict[str, str] = {re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_"): name
                           for name in CHECKER}


# ---------------------------------------------------------------------------------------
# Spectra and the colour-science reference
# ---------------------------------------------------------------------------------------

@lru_cache(maxsize=None)
def cmfs() -> colour.MultiSpectralDistributions:
    """CIE 1931 2 degree CMFs at 1 nm over 360-830 nm (the renderer's table)."""
    return colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(SHAPE)


def align_linear(sd: colour.SpectralDistribution) -> colour.SpectralDistribution:
    """``sd`` at 1 nm over 360-830 nm: linear between its points, constant outside them."""
    return sd.copy().align(SHAPE, interpolator=colour.LinearInterpolator,
                           extrapolator=colour.Extrapolator,
                           extrapolator_kwargs={"method": "Constant", "left": None, "right": None})


def illuminant_sd(name: str) -> colour.SpectralDistribution:
    return colour.SDS_ILLUMINANTS[COLOUR_KEYS.get(name, name)]


def renderer_scale(illuminant: str) -> float:
    """Factor from the table's values to the renderer's illuminant: 1/100 for the tables of 100
    at 560 nm, else 1/luminance, with the luminance as the renderer computes it
    (``cie_luminance``: 1 nm sums of y_bar times the table over 360-830 nm, over the sum of
    y_bar)."""
    if illuminant in AT_560:
        return 0.01
    y_bar = cmfs().values[:, 1]
    return float(np.sum(y_bar) / np.sum(_table(illuminant_sd(illuminant))(WAVELENGTHS) * y_bar))


@lru_cache(maxsize=None)
def reference_xyz(illuminant: str) -> tuple[np.ndarray, np.ndarray]:
    """(XYZ of the 24 patches (24, 3), XYZ of the perfect white), Y_white = 1.

    colour-science's ``sd_to_XYZ(method='Integration')`` on the linearly aligned SDs.
    """
    observer = cmfs()
    light = align_linear(illuminant_sd(illuminant))
    xyz = np.array([colour.sd_to_XYZ(align_linear(CHECKER[name]), observer, light,
                                     method="Integration") for name in PATCHES.values()])
    white = colour.sd_to_XYZ(colour.sd_ones(SHAPE), observer, light, method="Integration")
    return xyz / 100.0, white / 100.0


def reference_xyz_numpy(illuminant: str) -> np.ndarray:
    """The same as ``reference_xyz`` with plain numpy (np.interp, 1 nm sums): a cross-check."""
    cmf = cmfs().values
    s = _table(illuminant_sd(illuminant))(WAVELENGTHS)
    rho = np.array([_table(CHECKER[name])(WAVELENGTHS) for name in PATCHES.values()])
    return (rho * s) @ cmf / np.sum(s * cmf[:, 1])


def _table(sd: colour.SpectralDistribution):
    """The renderer's table source: piecewise linear through the points, ends held."""
    wl, v = np.asarray(sd.wavelengths, float), np.asarray(sd.values, float)
    return lambda lam: np.interp(lam, wl, v)


def project_onto_bins(sd: colour.SpectralDistribution, bins: int) -> np.ndarray:
    """The renderer's bin values (src/spectral/spectrum.cpp): least-squares projection of the
    table onto the look-up's basis (hats between bin centres, end ones held flat) over
    380-780 nm, from 64 midpoint samples per bin, clamped to the range of a 0.5 nm scan; float32."""
    width = (BIN_MAX - BIN_MIN) / bins
    k = np.arange(bins * 64)
    f = _table(sd)(BIN_MIN + (k + 0.5) * width / 64)
    if bins == 1:
        return np.array([f.mean()], dtype=np.float32).astype(float)
    x = (k + 0.5) / 64 - 0.5
    step = width / 64
    b = np.zeros(bins)
    left, right = x <= 0, x >= bins - 1
    mid = ~(left | right)
    b[0] += f[left].sum() * step
    b[-1] += f[right].sum() * step
    i = np.floor(x[mid]).astype(int)
    t = x[mid] - i
    np.add.at(b, i, (1 - t) * f[mid] * step)
    np.add.at(b, i + 1, t * f[mid] * step)
    gram = np.diag(np.full(bins, 2 * width / 3)) + np.diag(np.full(bins - 1, width / 6), 1) \
        + np.diag(np.full(bins - 1, width / 6), -1)
    gram[0, 0] = gram[-1, -1] = 5 * width / 6
    scan = _table(sd)(np.arange(BIN_MIN, BIN_MAX + 0.25, 0.5))  # range for the clamp, as in C++
    c = np.clip(np.linalg.solve(gram, b), scan.min(), scan.max())
    return c.astype(np.float32).astype(float)


def binned(sd: colour.SpectralDistribution, bins: int, lam: np.ndarray = WAVELENGTHS) -> np.ndarray:
    """What the renderer evaluates for ``sd`` with ``bins`` bins, at wavelengths ``lam``.

    Bin values: ``project_onto_bins`` (as the renderer's), stored as float32; look-up: linear
    between centres, constant beyond the first and last centre (np.interp holds the ends).
    """
    width = (BIN_MAX - BIN_MIN) / bins
    centres = BIN_MIN + (np.arange(bins) + 0.5) * width
    values = project_onto_bins(sd, bins)
    if bins == 1:
        return np.full(np.shape(lam), values[0])
    return np.interp(lam, centres, values)


def floor_xyz(illuminant: str, bins: int) -> np.ndarray:
    """XYZ (24, 3) of the N-bin spectra, white of the true illuminant at Y = 1."""
    cmf = cmfs().values
    sd = illuminant_sd(illuminant)
    s_true = _table(sd)(WAVELENGTHS)
    s_b = binned(sd, bins)
    rho_b = np.array([binned(CHECKER[name], bins) for name in PATCHES.values()])
    return (rho_b * s_b) @ cmf / np.sum(s_true * cmf[:, 1])


def renderer_white_scale(illuminant: str) -> float:
    """Factor from the renderer's XYZ to Y_white = 1.

    The renderer's illuminant is the table times ``renderer_scale`` (1/100 for the tables of 100
    at 560 nm) and its film divides by integral(y_bar), so its perfect white has
    Y = integral(S k y_bar) / integral(y_bar); both integrals as 1 nm sums, like the
    reference's normalisation (1 for the illuminants of luminance 1, up to rounding)."""
    y_bar = cmfs().values[:, 1]
    s = _table(illuminant_sd(illuminant))(WAVELENGTHS) * renderer_scale(illuminant)
    return float(np.sum(y_bar) / np.sum(s * y_bar))


@lru_cache(maxsize=None)
def film_xyz(illuminant: str) -> tuple[np.ndarray, np.ndarray]:
    """(XYZ of the 24 patches (24, 3), XYZ of the background) that exact-mode renders converge
    to, in ``patch_means``'s units (Y_white = 1 by the 1 nm sums): the exact integrals of the
    renderer's continuous functions, not colour-science's 1 nm sums.

    The film estimates integral(rho(l) S(l) cmf(l) dl) / integral(y_bar(l) dl) over 360-830 nm
    with rho and S linear between their table points (5 nm, ends held) and the CMFs linear
    between their 1 nm entries (src/spectral/observer.h). On each 1 nm interval all three are
    linear, so the integrand is a cubic and Simpson's rule is exact. For D65 and A this differs
    from the 1 nm sums of ``reference_xyz`` by 0.0016 and 0.0013 mean Delta E (about 2e-6 in
    the white's Y); under light with lines 5 nm wide by 0.004-0.005 (F11: 0.0054 mean, 0.015
    max), the reference's quadrature error, not the renderer's. The background's z-test and the
    exact mode's check against the integral compare with this."""
    cmf = cmfs().values
    edges = WAVELENGTHS.astype(float)
    mids = 0.5 * (edges[:-1] + edges[1:])
    s = _table(illuminant_sd(illuminant))
    rho = [_table(CHECKER[name]) for name in PATCHES.values()] + [lambda lam: np.ones_like(lam)]

    def simpson(f_edges, f_mids):  # exact for cubics on each 1 nm interval
        return np.sum(f_edges[:-1] + 4 * f_mids + f_edges[1:], axis=0) / 6

    cmf_mid = 0.5 * (cmf[:-1] + cmf[1:])  # the linear CMFs at the interval midpoints
    light = np.array([simpson((r(edges) * s(edges))[:, None] * cmf, (r(mids) * s(mids))[:, None] * cmf_mid)
                      for r in rho])
    y_integral = simpson(cmf[:, 1], cmf_mid[:, 1])
    xyz = light * renderer_scale(illuminant) / y_integral * renderer_white_scale(illuminant)
    return xyz[:-1], xyz[-1]


def film_white_xyz(illuminant: str) -> np.ndarray:
    """XYZ (Y_white = 1 units) that the film's background pixels converge to (``film_xyz``).
    Under D65 and A it differs from the Lab white (1 nm sums) by about 2e-6 in Y and 1.5e-5 in
    Z: far below any Delta E that matters, but above the background's standard error once the
    sampler stratifies wavelengths (Sobol at 1024 spp: about 2e-7 of Y), so the z-test compares
    with this."""
    return film_xyz(illuminant)[1]


@lru_cache(maxsize=None)
def white_xy(illuminant: str) -> np.ndarray:
    return colour.XYZ_to_xy(reference_xyz(illuminant)[1])


def lab(xyz: np.ndarray, illuminant: str) -> np.ndarray:
    return colour.XYZ_to_Lab(xyz, white_xy(illuminant))


def delta_e(xyz_a: np.ndarray, xyz_b: np.ndarray, illuminant: str) -> np.ndarray:
    return np.asarray(colour.delta_E(lab(xyz_a, illuminant), lab(xyz_b, illuminant),
                                     method="CIE 2000"))


# ---------------------------------------------------------------------------------------
# Rendering and patch averages
# ---------------------------------------------------------------------------------------

def scene_name(illuminant: str) -> str:
    """The built-in scene of the illuminant, or a name for the derived scene file."""
    return SCENES.get(illuminant) or f"colorchecker-{illuminant.lower()}"


def scene_file(illuminant: str) -> Path:
    """The scene file (derived illuminants: the D65 scene's, which ``scene_text`` rewrites)."""
    return SCENES_DIR / f"{SCENES[illuminant if illuminant in SCENES else 'D65']}.json"


def scene_text(illuminant: str) -> str:
    """The JSON text rendered for the illuminant: its scene file, or for a derived illuminant the
    D65 scene's with only the background's name replaced."""
    text = scene_file(illuminant).read_text()
    if illuminant in SCENES:
        return text
    old = '"background": {"type": "illuminant", "name": "D65"}'
    if text.count(old) != 1:
        raise ValueError(f"{scene_file(illuminant)}: expected one background {old}")
    return text.replace(old, f'"background": {{"type": "illuminant", "name": "{illuminant}"}}')


def scene_json(illuminant: str) -> dict:
    return json.loads(scene_text(illuminant))


def scene_image_size(illuminant: str) -> tuple[int, int]:
    image = scene_json(illuminant)["image"]
    return int(image["width"]), int(image["height"])


def patch_boxes(illuminant: str, width: int, height: int) -> dict[str, tuple[float, ...]]:
    """patch name -> (x0, x1, y0, y1): the patch's extent on the film in pixels.

    Projects each quad of the scene file with the renderer's pinhole camera
    (src/render/camera.h): film (0, 0) is the top-left corner, x right, y down."""
    scene = scene_json(illuminant)
    cam = scene["camera"]
    eye, target = np.array(cam["position"], float), np.array(cam["look_at"], float)
    up = np.array(cam.get("up", [0, 1, 0]), float)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    half_h = np.tan(np.radians(cam.get("vfov_degrees", 40.0)) / 2)
    half_w = half_h * width / height
    boxes = {}
    for shape in scene["shapes"]:
        if shape["type"] != "quad" or "transform" in shape:
            raise ValueError("the colorchecker scenes hold untransformed quads only")
        o, e1, e2 = (np.array(shape[k], float) for k in ("origin", "edge1", "edge2"))
        xs, ys = [], []
        for p in (o, o + e1, o + e2, o + e1 + e2):
            d = p - eye
            depth = d @ forward
            xs.append((d @ right / depth + half_w) / (2 * half_w) * width)
            ys.append((half_h - d @ true_up / depth) / (2 * half_h) * height)
        boxes[shape["material"]] = (min(xs), max(xs), min(ys), max(ys))
    if sorted(boxes) != sorted(PATCHES):
        raise ValueError(f"{scene_file(illuminant)}: expected one quad per ColorChecker patch")
    return boxes


def patch_regions(illuminant: str, width: int, height: int,
                  margin: int = MARGIN_PX) -> dict[str, tuple[slice, slice]]:
    """patch name -> (row slice, column slice) of the pixels that lie wholly inside the
    patch, ``margin`` pixels in from its edges (the quads face the camera squarely, so
    their images are axis-aligned rectangles)."""
    regions = {}
    for name, (x0, x1, y0, y1) in patch_boxes(illuminant, width, height).items():
        c0, c1 = int(np.ceil(x0 - 1e-3)) + margin, int(np.floor(x1 + 1e-3)) - margin
        r0, r1 = int(np.ceil(y0 - 1e-3)) + margin, int(np.floor(y1 + 1e-3)) - margin
        if c1 - c0 < 2 or r1 - r0 < 2 or c0 < 0 or r0 < 0 or c1 > width or r1 > height:
            raise ValueError(f"patch {name} has too few whole pixels at {width}x{height}")
        regions[name] = (slice(r0, r1), slice(c0, c1))
    return regions


def background_mask(illuminant: str, width: int, height: int) -> np.ndarray:
    """Boolean (height, width): pixels at least one pixel away from every patch (the gaps and
    the border), where the camera sees the constant background, the illuminant itself."""
    mask = np.ones((height, width), bool)
    for x0, x1, y0, y1 in patch_boxes(illuminant, width, height).values():
        c0, c1 = max(int(np.floor(x0)) - 1, 0), int(np.ceil(x1)) + 1
        r0, r1 = max(int(np.floor(y0)) - 1, 0), int(np.ceil(y1)) + 1
        mask[r0:r1, c0:c1] = False
    if not mask.any():
        raise ValueError(f"no background pixels at {width}x{height}")
    return mask


def render(program: Path, illuminant: str, bins: int | str, spp: int, seed: int,
           out: Path, width: int | None = None, height: int | None = None) -> float:
    """Render the ColorChecker scene file of ``illuminant`` to the PFM ``out`` (XYZ).

    The file (not the built-in copy; for a derived illuminant its text beside ``out``) is
    rendered, so the patch regions projected from it always match the image. Returns the wall
    time in seconds."""
    scene = scene_file(illuminant)
    if illuminant not in SCENES:
        scene = out.parent / f"{scene_name(illuminant)}.json"
        scene.write_text(scene_text(illuminant))
    # The program's default sampler (what users get).
    command = [str(program), str(scene), "--spp", str(spp),
               "--spectral-bins", str(bins), "--color-space", "xyz", "--seed", str(seed),
               "--quiet", "-o", str(out)]
    if width:
        command += ["--width", str(width), "--height", str(height)]
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({result.returncode}):\n{result.stderr}")
    return time.perf_counter() - start


@dataclass
class PatchMeans:
    xyz: np.ndarray          # (24, 3) mean over each patch's central pixels, Y_white = 1
    half_a: np.ndarray       # (24, 3) mean over the "black" squares of a checkerboard
    half_b: np.ndarray       # (24, 3) ... and over the "white" squares
    background: np.ndarray   # (3,) mean over the background pixels, Y_white = 1
    background_se: np.ndarray  # (3,) its standard error (pixel spread / sqrt(pixels))
    pixels: int              # pixels per patch (the smallest region)
    seconds: float = 0.0


def patch_means(image: np.ndarray, illuminant: str) -> PatchMeans:
    """Average each patch's central pixels of an XYZ image; scaled so that Y_white = 1."""
    height, width, _ = image.shape
    regions = patch_regions(illuminant, width, height)
    image = image * renderer_white_scale(illuminant)
    full, a, b, count = [], [], [], []
    for name in PATCHES:
        rows, cols = regions[name]
        block = image[rows, cols]
        checker = (np.add.outer(np.arange(block.shape[0]), np.arange(block.shape[1])) % 2) == 0
        full.append(block.reshape(-1, 3).mean(axis=0))
        a.append(block[checker].mean(axis=0))
        b.append(block[~checker].mean(axis=0))
        count.append(block.shape[0] * block.shape[1])
    background = image[background_mask(illuminant, width, height)]
    return PatchMeans(np.array(full), np.array(a), np.array(b), background.mean(axis=0),
                      background.std(axis=0, ddof=1) / np.sqrt(len(background)), min(count))


def render_patch_means(program: Path, illuminant: str, bins: int | str, spp: int, seed: int,
                       workdir: Path, width: int | None = None,
                       height: int | None = None) -> PatchMeans:
    out = workdir / f"{scene_name(illuminant)}_{bins}_{spp}spp_seed{seed}.pfm"
    seconds = render(program, illuminant, bins, spp, seed, out, width, height)
    means = patch_means(read_pfm(out), illuminant)
    means.seconds = seconds
    return means


# ---------------------------------------------------------------------------------------
# Evaluation
# ---------------------------------------------------------------------------------------

@dataclass
class BinResult:
    """One bin count under one illuminant. Delta E arrays hold the 24 patches."""
    bins: int | str
    spp: int
    render_de: np.ndarray          # render vs reference
    noise_de: np.ndarray           # split-half estimate of the render's noise
    floor_de: np.ndarray           # N-bin spectra vs reference (zeros for exact)
    cv_de: np.ndarray | None       # render - exact render (same seed) + reference, vs reference
    cv_noise_de: np.ndarray | None  # split-half noise of that estimate
    seconds: float

    @property
    def render_mean(self) -> float:
        return float(self.render_de.mean())

    @property
    def render_max(self) -> float:
        return float(self.render_de.max())

    @property
    def floor_mean(self) -> float:
        return float(self.floor_de.mean())

    @property
    def floor_max(self) -> float:
        return float(self.floor_de.max())

    @property
    def noise_mean(self) -> float:
        return float(self.noise_de.mean())

    @property
    def excess_mean(self) -> float:
        """Render mean minus floor mean: what the renderer adds (noise included)."""
        return self.render_mean - self.floor_mean

    @property
    def cv_mean(self) -> float:
        return float(self.cv_de.mean())

    @property
    def cv_excess_mean(self) -> float:
        """The same with the control-variate estimate (little noise)."""
        return self.cv_mean - self.floor_mean

    @property
    def cv_noise_mean(self) -> float:
        return float(self.cv_noise_de.mean())


@dataclass
class IlluminantResult:
    illuminant: str
    width: int
    height: int
    pixels_per_patch: int
    bins: dict = field(default_factory=dict)   # bin count -> BinResult (all at one spp, one seed)
    exact: BinResult | None = None             # the exact-mode check (its own spp and seed)
    background_de: float = 0.0                 # background pixels vs the illuminant's white
    background_z: np.ndarray | None = None     # (3,) (background - film_white_xyz) / standard error
    seed_check: np.ndarray | None = None       # exact: Delta E between two seeds, per patch
    exact_vs_film: np.ndarray | None = None    # exact check vs ``film_xyz`` (the exact integral)


def evaluate(program: Path, illuminant: str, spp: int = DEFAULT_SPP, seed: int = DEFAULT_SEED,
             bin_counts=BIN_COUNTS, exact_spp: int | None = None, seed_check: bool = False,
             width: int | None = None, height: int | None = None) -> IlluminantResult:
    """Render every bin count (and exact mode) at ``spp`` with the same ``seed`` and compare
    with the reference and the floors.

    The same seed gives every render the same wavelengths in every pixel sample (a diffuse
    patch under a uniform environment draws its random numbers the same way whatever its
    spectrum), so render(N) - render(exact) + reference estimates the N-bin render's expected
    XYZ with far less noise than render(N) alone: a control variate whose expectation, the
    reference, is what the exact-mode check verifies.

    ``exact_spp`` (default ``spp``): the exact-mode check uses its own render at that spp with
    seed + 1, independent of the control variate; ``seed_check`` renders it again with
    seed + 2 and reports the Delta E between the two.
    """
    ref, white = reference_xyz(illuminant)
    w, h = (width, height) if width else scene_image_size(illuminant)
    counts = list(bin_counts) + ([] if "exact" in bin_counts else ["exact"])
    with tempfile.TemporaryDirectory(prefix="color_accuracy_") as tmp:
        work = Path(tmp)
        renders = {b: render_patch_means(program, illuminant, b, spp, seed, work, width, height)
                   for b in counts}
        control = renders["exact"]
        result = IlluminantResult(illuminant, w, h, control.pixels)
        for b in counts:
            m = renders[b]
            floor = (np.zeros(len(PATCHES)) if b == "exact"
                     else delta_e(floor_xyz(illuminant, b), ref, illuminant))
            cv = cv_noise = None
            if b != "exact":
                cv = delta_e(m.xyz - control.xyz + ref, ref, illuminant)
                cv_noise = delta_e(m.half_a - control.half_a + ref,
                                   m.half_b - control.half_b + ref, illuminant) / 2
            result.bins[b] = BinResult(b, spp, delta_e(m.xyz, ref, illuminant),
                                       delta_e(m.half_a, m.half_b, illuminant) / 2, floor,
                                       cv, cv_noise, m.seconds)
        if exact_spp is None or (exact_spp == spp and not seed_check):
            result.exact = result.bins["exact"]
            first = control
        else:
            first = render_patch_means(program, illuminant, "exact", exact_spp, seed + 1, work,
                                       width, height)
            result.exact = BinResult("exact", exact_spp, delta_e(first.xyz, ref, illuminant),
                                     delta_e(first.half_a, first.half_b, illuminant) / 2,
                                     np.zeros(len(PATCHES)), None, None, first.seconds)
        result.exact_vs_film = delta_e(first.xyz, film_xyz(illuminant)[0], illuminant)
        result.background_de = float(delta_e(first.background, white, illuminant))
        result.background_z = (first.background - film_white_xyz(illuminant)) / first.background_se
        if seed_check:
            second = render_patch_means(program, illuminant, "exact", result.exact.spp, seed + 2,
                                        work, width, height)
            result.seed_check = delta_e(first.xyz, second.xyz, illuminant)
    return result


# ---------------------------------------------------------------------------------------
# Reports
# ---------------------------------------------------------------------------------------

def _label(bins) -> str:
    return "exact" if bins == "exact" else str(bins)


def text_table(r: IlluminantResult) -> str:
    lines = [f"Illuminant {r.illuminant}: {r.width}x{r.height}, {r.pixels_per_patch} px/patch, "
             f"background vs white: Delta E {r.background_de:.4f}, "
             f"z-scores XYZ {np.array2string(r.background_z, precision=2)}",
             f"{'bins':>6} {'spp':>5} {'mean':>8} {'max':>8} {'floor':>8} {'fl.max':>8} "
             f"{'excess':>8} {'noise':>7} {'cv.exc':>8} {'cv.nse':>7}"]
    rows = [b for b in r.bins.values() if b.bins != "exact"] + [r.exact]
    for b in rows:
        cv = (f"{b.cv_excess_mean:+8.4f} {b.cv_noise_mean:7.4f}" if b.cv_de is not None
              else f"{'':>8} {'':>7}")
        lines.append(f"{_label(b.bins):>6} {b.spp:5d} {b.render_mean:8.4f} {b.render_max:8.4f} "
                     f"{b.floor_mean:8.4f} {b.floor_max:8.4f} {b.excess_mean:+8.4f} "
                     f"{b.noise_mean:7.4f} {cv}")
    if r.exact_vs_film is not None:
        lines.append(f"  exact vs the exact integral (film_xyz): Delta E mean "
                     f"{r.exact_vs_film.mean():.4f} max {r.exact_vs_film.max():.4f}")
    if r.seed_check is not None:
        lines.append(f"  exact, two seeds: Delta E mean {r.seed_check.mean():.4f} "
                     f"max {r.seed_check.max():.4f}")
    return "\n".join(lines)


@dataclass
class CostPoint:
    """One exact-mode render of the cost study."""
    illuminant: str
    spp: int
    de: np.ndarray     # (24,) vs film_xyz: the exact integral, so Monte Carlo error alone
    noise: float       # split-half noise estimate, mean over the patches
    seconds: float

    @property
    def mean(self) -> float:
        return float(self.de.mean())


def exact_cost(program: Path, illuminant: str, spps=DEFAULT_COST_SPP, seed: int = DEFAULT_SEED,
               width: int | None = None, height: int | None = None) -> list[CostPoint]:
    """Exact mode at each spp (one seed), against the exact integral of its spectra
    (``film_xyz``): the Delta E is Monte Carlo error alone, so the spp at which it falls below
    a target is what the illuminant's spectrum costs in samples."""
    target = film_xyz(illuminant)[0]
    points = []
    with tempfile.TemporaryDirectory(prefix="color_accuracy_cost_") as tmp:
        for spp in spps:
            m = render_patch_means(program, illuminant, "exact", spp, seed, Path(tmp), width, height)
            points.append(CostPoint(illuminant, spp, delta_e(m.xyz, target, illuminant),
                                    float((delta_e(m.half_a, m.half_b, illuminant) / 2).mean()),
                                    m.seconds))
    return points


def cost_markdown(points: list[CostPoint]) -> list[str]:
    illuminants = list(dict.fromkeys(p.illuminant for p in points))
    spps = sorted({p.spp for p in points})
    at = {(p.illuminant, p.spp): p for p in points}
    lines = ["## What spiky light costs: exact mode against samples per pixel", "",
             "Exact mode against the exact integral of its own spectra (`film_xyz`; the"
             " largest spp is the exact-mode check above, with its own seed),"
             " so each ΔE is Monte Carlo error alone: mean ΔE2000 over the 24 patches, and the"
             " render's wall time (240x160, shared machine).", "",
             "| spp | " + " | ".join(illuminants) + " |",
             "| ---: | " + " | ".join("---:" for _ in illuminants) + " |"]
    for spp in spps:
        lines.append(f"| {spp} | " + " | ".join(
            f"{at[i, spp].mean:.4f} ({at[i, spp].seconds:.1f} s)" if (i, spp) in at else "—"
            for i in illuminants) + " |")
    lines.append("")
    return lines


def markdown(results: list[IlluminantResult], program: Path, seed: int, total_seconds: float,
             cost: list[CostPoint] | None = None) -> str:
    version = subprocess.run([str(program), "--version"], capture_output=True,
                             text=True).stdout.strip()
    first = results[0]
    spps = ", ".join(f"{r.illuminant} {next(iter(r.bins.values())).spp}" for r in results)
    scenes = ", ".join(f"`{scene_name(r.illuminant)}` ({r.illuminant})" for r in results)
    lines = [
        "# Colour accuracy on the ColorChecker",
        "",
        "Generated by `validation/color_accuracy.py` (criteria asserted by"
        " `validation/test_color_accuracy.py`).",
        "",
        f"- Program: `{version}`, `--color-space xyz`, scenes {scenes} at"
        f" {first.width}x{first.height}; " + ", ".join(f"`{scene_name(i)}`" for i in DERIVED) +
        " are `scenes/colorchecker.json` with only the background's illuminant renamed (no"
        " built-in scenes).",
        f"- Binned modes and the control exact render, spp: {spps}; seed {seed} (the same seed"
        f" for all, so the same wavelengths in every sample); exact-mode check:"
        f" {first.exact.spp} spp, seed {seed if first.exact is first.bins['exact'] else seed + 1}.",
        f"- Each patch is averaged over its central {first.pixels_per_patch} pixels"
        f" ({MARGIN_PX} px in from its edges). All renders took {total_seconds:.0f} s"
        f" ({os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the end).",
        "",
        "ΔE is CIEDE2000 against colour-science: `colour.sd_to_XYZ(method='Integration')`, CIE 1931"
        " 2°, 1 nm over 360–830 nm, reflectance and illuminant aligned with `LinearInterpolator`"
        " and constant extrapolation (what the renderer's table sources are), Lab relative to the"
        " illuminant's white. D65 and A are their tables / 100 (1 at 560 nm) in the renderer,"
        " F2, F7, F11 (CIE 15:2004) and LED-B3 (CIE 015:2018) their tables at luminance 1.",
        "",
        "- *exact vs integral*: the exact-mode check against the exact integral of the same"
        " piecewise-linear spectra (`film_xyz`, Simpson per 1 nm interval, exact for them) instead"
        " of colour-science's 1 nm sums: under light with 5 nm lines the sums themselves are off"
        " by 0.004–0.0055 mean ΔE (F11: 0.015 max), which the exact mode's ΔE against"
        " colour-science carries.",
        "- *floor*: the same integration of the N-bin spectra (bin-centre samples, linear"
        " between centres, ends held), the error of the representation alone.",
        "- *render − floor*: mean ΔE of the render minus mean ΔE of the floor: what the"
        " renderer adds, Monte Carlo noise included.",
        "- *noise*: Monte Carlo noise of the render's patch means in ΔE (split-half estimate).",
        "- *CV*: the render minus the exact render of the same seed plus the reference (a control"
        " variate: nearly noise-free estimate of the N-bin render's expected colour);"
        " *CV − floor* is what the test bounds (0.02 for N ≥ 16, 0.05 for N = 4, 8).",
        "- *time*: wall time of the render (a shared machine: for ratios only).",
        "",
    ]
    for r in results:
        lines += [f"## Illuminant {r.illuminant} (scene `{scene_name(r.illuminant)}`)", "",
                  "| bins | spp | mean ΔE | max ΔE | floor mean | floor max | render − floor |"
                  " noise | CV mean | CV − floor | CV noise | time (s) |",
                  "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
        rows = [b for b in r.bins.values() if b.bins != "exact"] + [r.exact]
        for b in rows:
            cv = ((f"{b.cv_mean:.4f}", f"{b.cv_excess_mean:+.4f}", f"{b.cv_noise_mean:.4f}")
                  if b.cv_de is not None else ("—", "—", "—"))
            lines.append(f"| {_label(b.bins)} | {b.spp} | {b.render_mean:.4f} | {b.render_max:.4f} |"
                         f" {b.floor_mean:.4f} | {b.floor_max:.4f} | {b.excess_mean:+.4f} |"
                         f" {b.noise_mean:.4f} | {cv[0]} | {cv[1]} | {cv[2]} | {b.seconds:.1f} |")
        if r.exact_vs_film is not None:
            lines += ["", f"Exact vs integral: ΔE mean {r.exact_vs_film.mean():.4f}, max"
                          f" {r.exact_vs_film.max():.4f} (the exact-mode check against `film_xyz`)."]
        z = ", ".join(f"{v:+.2f}" for v in r.background_z)
        lines += ["", f"Background pixels (the illuminant seen directly, exact check render) vs"
                      f" the illuminant's white: ΔE {r.background_de:.4f}; (mean − the film's"
                      f" expected white, `film_white_xyz`) / standard error for X, Y, Z: {z}."]
        if r.seed_check is not None:
            lines.append(f"Exact mode rendered again with seed {seed + 2}: ΔE between the two"
                         f" renders mean {r.seed_check.mean():.4f}, max {r.seed_check.max():.4f}"
                         f" (≈ √2 × the noise of one render).")
        lines.append("")
    columns = [(r, b) for r in results for b in list(r.bins.values()) if b.bins == 16]
    columns += [(r, r.exact) for r in results]
    lines += cost_markdown(cost) if cost else []
    lines += ["## Per patch: ΔE of the render (16 bins and exact)", "",
              "| patch | " + " | ".join(f"{r.illuminant} {_label(b.bins)}" for r, b in columns) + " |",
              "| --- | " + " | ".join("---:" for _ in columns) + " |"]
    for i, name in enumerate(PATCHES.values()):
        lines.append(f"| {name} | " + " | ".join(f"{b.render_de[i]:.3f}" for _, b in columns) + " |")
    lines += ["", "Criteria of the test (D65, A, F11, LED-B3): exact mean ≤ 0.02 and max ≤ 0.05"
              " against colour-science, and mean ≤ 0.004 against the exact integral; each binned"
              " mode's CV mean within 0.02 of its floor mean for N ≥ 16 (0.05 for N = 4, 8);"
              " 16 bins mean ≤ 0.5 under D65 and A.", ""]
    return "\n".join(lines)


def plot(results: list[IlluminantResult], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cols = len(results) if len(results) <= 3 else (len(results) + 1) // 2
    rows = (len(results) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.8 * cols, 4.4 * rows), sharey=True,
                             squeeze=False)
    for ax in axes.flat[len(results):]:
        ax.set_visible(False)
    for ax, r in zip(axes.flat, results):
        binned_results = [b for b in r.bins.values() if b.bins != "exact"]
        x = [b.bins for b in binned_results]
        xe = max(x) * 2
        ax.plot(x, [b.floor_mean for b in binned_results], "-", color="C0", lw=6, alpha=0.25,
                label="floor mean (N-bin spectra alone)")
        ax.plot(x, [b.floor_max for b in binned_results], "-", color="C1", lw=6, alpha=0.25,
                label="floor max")
        ax.plot(x + [xe], [b.render_mean for b in binned_results] + [r.exact.render_mean], "o-",
                color="C0", label="render mean")
        ax.plot(x + [xe], [b.render_max for b in binned_results] + [r.exact.render_max], "s-",
                color="C1", label="render max")
        ax.plot(x, [b.cv_mean for b in binned_results], "+", color="k", ms=10,
                label="render mean, control variate")
        ax.plot(x + [xe], [b.noise_mean for b in binned_results] + [r.exact.noise_mean], "x:",
                color="grey", label="noise of the render (mean)")
        ax.axhline(0.02, color="grey", lw=0.8, ls="--")
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xticks(x + [xe], [str(b) for b in x] + ["exact"])
        ax.minorticks_off()
        ax.set_xlabel("--spectral-bins")
        ax.set_title(f"ColorChecker, illuminant {r.illuminant}")
        ax.grid(True, which="major", alpha=0.3)
    for row in axes:
        row[0].set_ylabel("CIEDE2000 vs colour-science")
    axes[0][0].legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from conftest import pathtracer_location

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--program", type=Path, default=pathtracer_location(),
                        help="renderer (default $SPT_PATHTRACER or build/pathtracer)")
    parser.add_argument("--spp", type=int, default=DEFAULT_SPP,
                        help="samples per pixel of the binned renders and the exact control"
                             f" (default {DEFAULT_SPP})")
    parser.add_argument("--spiky-spp", type=int, default=DEFAULT_SPIKY_SPP,
                        help=f"the same under {', '.join(SPIKY)} (default {DEFAULT_SPIKY_SPP})")
    parser.add_argument("--illuminants", nargs="+", default=list(ILLUMINANTS),
                        choices=list(ILLUMINANTS), help="default: all")
    parser.add_argument("--cost-spp", type=int, nargs="*", default=list(DEFAULT_COST_SPP),
                        help="spp of the exact-mode cost study, per illuminant (default"
                             f" {' '.join(map(str, DEFAULT_COST_SPP))}; none: skip it)")
    parser.add_argument("--exact-spp", type=int, default=DEFAULT_EXACT_SPP,
                        help="samples per pixel of the separate exact-mode check (default"
                             f" {DEFAULT_EXACT_SPP}; 0: the exact control render at --spp is the check)")
    parser.add_argument("--width", type=int, help="image width (default: the scene's)")
    parser.add_argument("--height", type=int, help="image height (default: the scene's)")
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--seed-check", action="store_true",
                        help="render the exact mode again with another seed and report the"
                             " Delta E between the two")
    parser.add_argument("--out", type=Path, default=REPO_ROOT / "validation" / "results",
                        help="folder for color_accuracy.md and color_accuracy.png")
    args = parser.parse_args(argv)
    if (args.width is None) != (args.height is None):
        parser.error("give both --width and --height, or neither")

    start = time.perf_counter()
    results = []
    for illuminant in args.illuminants:
        spp = args.spiky_spp if illuminant in SPIKY else args.spp
        r = evaluate(args.program, illuminant, spp, args.seed, exact_spp=args.exact_spp or None,
                     seed_check=args.seed_check, width=args.width, height=args.height)
        results.append(r)
        print(text_table(r), flush=True)
    cost = []
    for r in results if args.cost_spp else []:
        cost += exact_cost(args.program, r.illuminant, args.cost_spp, args.seed, args.width,
                           args.height)
        if r.exact.spp not in args.cost_spp:  # the exact-mode check is one more point
            cost.append(CostPoint(r.illuminant, r.exact.spp, r.exact_vs_film, r.exact.noise_mean,
                                  r.exact.seconds))
        print(" ".join(f"{p.illuminant} {p.spp} spp: {p.mean:.4f} ({p.seconds:.1f} s)"
                       for p in cost if p.illuminant == r.illuminant), flush=True)
    total = time.perf_counter() - start
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "color_accuracy.md").write_text(markdown(results, args.program, args.seed, total,
                                                         cost))
    plot(results, args.out / "color_accuracy.png")
    print(f"wrote {args.out / 'color_accuracy.md'} and {args.out / 'color_accuracy.png'} "
          f"({total:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
