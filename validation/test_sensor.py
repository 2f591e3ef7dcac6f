"""``--sensor``: the film integrates against a camera's spectral sensitivities instead of the CIE
observer. The measured curve shipped in spectra/ (Nikon D5100, NPL; Darrodi et al. 2015) is
checked value by value against colour-science in test_spectral_tables.py; here a render with it
is checked against the integral computed with colour-science.

Scene: no shapes, a 3000 K blackbody sky (exact spectra), so every pixel's radiance is
L(lambda) = B(lambda, 3000 K) / B(560 nm, 3000 K) and the raw camera RGB is
    c = int L(lambda) s_c(lambda) dlambda / int s_g(lambda) dlambda,
with s_c the dataset's curves linear between its 5-nm rows and 0 outside 380-780 nm (the file
format's rule), evaluated here on the renderer's 1-nm grid with colour-science's alignment.
Only the wavelength sampling is random: the image mean must match within 5 standard errors
(pixels independent) plus 1e-4 for the 1-nm trapezoid rule.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import colour
import numpy as np
import OpenEXR

from colour.algebra import LinearInterpolator

CAMERA = "Nikon 5100 (NPL)"
SKY = ('{"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1]}, "shapes": [], '
       '"background": {"type": "blackbody", "temperature_k": 3000}}')
WIDTH, HEIGHT, SPP = 8, 8, 256


def render(pathtracer: Path, tmp_path: Path, name: str, *extra: str) -> tuple[dict, np.ndarray]:
    scene = tmp_path / "sky.json"
    scene.write_text(SKY)
    out = tmp_path / f"{name}.exr"
    command = [str(pathtracer), str(scene), "--width", str(WIDTH), "--height", str(HEIGHT), "--spp",
               str(SPP), "--spectral-bins", "exact", "--quiet", "-o", str(out), *extra]
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, f"{command} failed:\n{result.stderr}"
    with OpenEXR.File(str(out), separate_channels=True) as exr:
        header = dict(exr.header())
        rgb = np.stack([exr.channels()[c].pixels.astype(np.float64) for c in "RGB"], axis=-1)
    return header, rgb.reshape(-1, 3)


def expected_camera_rgb() -> np.ndarray:
    shape = colour.SpectralShape(360, 830, 1)
    camera = colour.characterisation.MSDS_CAMERA_SENSITIVITIES[CAMERA].copy().align(
        shape, interpolator=LinearInterpolator,
        extrapolator_kwargs={"method": "Constant", "left": 0, "right": 0})
    w = camera.wavelengths
    planck = colour.colorimetry.planck_law
    radiance = planck(w * 1e-9, 3000) / planck(560e-9, 3000)
    radiance = np.ravel(radiance)
    s = camera.values
    return np.trapezoid(radiance[:, None] * s, w, axis=0) / np.trapezoid(s[:, 1], w)


def test_sensor_render_matches_colour_science(pathtracer: Path, repo_root: Path, tmp_path: Path) -> None:
    sensor = repo_root / "spectra" / "camera_nikon_d5100_npl.csv"
    header, rgb = render(pathtracer, tmp_path, "sensor", "--sensor", str(sensor))
    assert "chromaticities" not in header, "raw camera RGB has no colour space"
    assert header["observer"] == str(sensor)

    expected = expected_camera_rgb()
    mean = rgb.mean(axis=0)
    standard_error = rgb.std(axis=0, ddof=1) / np.sqrt(len(rgb))
    print(f"\ncamera RGB {mean} +- {standard_error}, colour-science {expected}")
    assert np.all(standard_error > 0)
    assert np.all(np.abs(mean - expected) <= 5 * standard_error + 1e-4 * expected)

    # The flag changes the observer: the XYZ of the same sky is far from the camera's RGB.
    _, xyz = render(pathtracer, tmp_path, "xyz", "--color-space", "xyz")
    assert np.abs(xyz.mean(axis=0) - mean).max() > 100 * standard_error.max()
