"""Beer-Lambert colour through a participating medium: a long straight path through an
absorbing liquid in front of a white emitter must have the colour colour-science predicts
from the same spectra.

The scene: an emitting plane of constant radiance 1 (white E) seen through a slab of depth
D of an absorbing, non-scattering liquid (between two planes without a surface); the
camera looks along the slab's normal with a tiny field of view, so every ray crosses
exactly D. The renderer writes XYZ (``--color-space xyz``) with the spectra evaluated
exactly (``--spectral-bins exact``). Expected: XYZ = sd_to_XYZ(exp(-sigma_a * D), E) / 100
(Y of the white emitter is 1 in both). Free flight ends a path at an absorption, so each
sample is noisy; the tolerance is 5 standard errors of the image mean.
"""
from __future__ import annotations

import json
import subprocess
from pathlib import Path

import colour
import numpy as np

from color_accuracy import cmfs, read_pfm

DEPTH = 2.5
# A wine-like absorption (per scene unit): strong in the blue and green, weak in the red.
SIGMA_A = [(380, 3.0), (450, 4.0), (520, 3.4), (580, 1.4), (610, 0.3), (650, 0.1), (780, 0.05)]


def scene(depth: float) -> dict:
    return {
        "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "vfov_degrees": 0.01},
        "image": {"width": 32, "height": 32, "spp": 256},
        "media": {"liquid": {"type": "homogeneous", "sigma_s": 0,
                             "sigma_a": {"type": "table", "points": [list(p) for p in SIGMA_A]}}},
        "shapes": [
            {"type": "plane", "normal": [0, 0, 1], "point": [0, 0, 0], "interior": "liquid"},
            {"type": "plane", "normal": [0, 0, -1], "point": [0, 0, -depth], "interior": "liquid"},
            {"type": "plane", "normal": [0, 0, 1], "point": [0, 0, -depth - 1], "emission": 1},
        ],
    }


def expected_xyz(depth: float) -> np.ndarray:
    # The table as the renderer reads it: linear between the points, end values held outside.
    wavelengths = np.arange(360.0, 831.0)
    sigma = np.interp(wavelengths, [p[0] for p in SIGMA_A], [p[1] for p in SIGMA_A])
    transmitted = colour.SpectralDistribution(np.exp(-sigma * depth), wavelengths)
    white = colour.sd_ones(transmitted.shape)
    return colour.sd_to_XYZ(transmitted, cmfs(), white, method="Integration") / 100.0


def render_xyz(pathtracer: Path, tmp_path: Path, depth: float, seed: int) -> np.ndarray:
    scene_path = tmp_path / f"slab{depth}.json"
    scene_path.write_text(json.dumps(scene(depth)))
    out = tmp_path / f"slab{depth}.pfm"
    subprocess.run([str(pathtracer), str(scene_path), "--spectral-bins", "exact", "--color-space", "xyz",
                    "--seed", str(seed), "--quiet", "-o", str(out)], check=True)
    return read_pfm(out).reshape(-1, 3)


def test_long_path_through_absorbing_liquid_has_the_predicted_colour(pathtracer, tmp_path):
    pixels = render_xyz(pathtracer, tmp_path, DEPTH, seed=3)
    mean = pixels.mean(axis=0)
    standard_error = pixels.std(axis=0, ddof=1) / np.sqrt(len(pixels))
    expected = expected_xyz(DEPTH)
    assert np.all(np.abs(mean - expected) <= 5 * standard_error + 1e-6), (mean, expected, standard_error)
    # The colour is strongly red (the test would not notice a grey medium otherwise), and it
    # is the predicted chromaticity to within the noise.
    xy, xy_expected = colour.XYZ_to_xy(mean), colour.XYZ_to_xy(expected)
    assert xy_expected[0] > 0.5
    assert np.abs(xy - xy_expected).max() < 0.01, (xy, xy_expected)


def test_colour_deepens_with_depth(pathtracer, tmp_path):
    """Twice the depth: lower luminance and higher purity, both as predicted."""
    shallow, deep = expected_xyz(DEPTH / 2), expected_xyz(DEPTH)
    mean_shallow = render_xyz(pathtracer, tmp_path, DEPTH / 2, seed=4).mean(axis=0)
    assert mean_shallow[1] > deep[1]
    assert np.abs(mean_shallow - shallow).max() < 0.02 * shallow.max() + 3e-3, (mean_shallow, shallow)
    assert colour.XYZ_to_xy(deep)[0] > colour.XYZ_to_xy(shallow)[0]
