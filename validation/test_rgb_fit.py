"""Check the renderer's RGB -> spectrum fit with colour-science.

The program prints the fitted spectrum of a linear sRGB reflectance with
``pathtracer --rgb-to-spectrum R,G,B`` (``rgb_sigmoid c0 c1 c2`` or
``constant v``). Here the spectrum is evaluated from that formula, lit by CIE
D65 (the 5 nm table linearly interpolated to 1 nm and held constant beyond
780 nm, as the renderer does), integrated with colour-science
(``colour.sd_to_XYZ``, CIE 1931 2 degree observer), and compared in CIELAB
with the XYZ of the RGB colour: ``colour.XYZ_to_Lab`` and
``colour.delta_E(method="CIE 2000")`` must be within 0.01.

The RGB colour space is sRGB's primaries with the white of that same D65 (as
in the renderer), so that RGB (1, 1, 1) is exactly the perfect reflector.
"""

from __future__ import annotations

import itertools
import subprocess

import numpy as np
import pytest

import colour

LEVELS = [0.0, 0.001, 0.05, 0.3, 0.7, 0.999, 1.0]
EXTRA = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (0, 1, 1), (1, 0, 1),
         (0.001, 0.001, 0.001), (0.999, 0.999, 0.999), (0.8, 0.2, 0.1)]
WAVELENGTHS = np.arange(360, 831, dtype=float)


def spectrum_from_program(pathtracer, rgb) -> np.ndarray:
    arg = ",".join(repr(float(c)) for c in rgb)
    out = subprocess.run([str(pathtracer), "--rgb-to-spectrum", arg], check=True,
                         capture_output=True, text=True).stdout.split()
    if out[0] == "constant":
        return np.full(WAVELENGTHS.shape, float(out[1]))
    assert out[0] == "rgb_sigmoid"
    c0, c1, c2 = map(float, out[1:4])
    t = (WAVELENGTHS - 360.0) / 470.0
    x = (c0 * t + c1) * t + c2
    return 0.5 + x / (2.0 * np.sqrt(1.0 + x * x))


@pytest.fixture(scope="module")
def setup():
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(
        colour.SpectralShape(360, 830, 1))
    d65 = colour.SDS_ILLUMINANTS["D65"]
    d65_values = np.interp(WAVELENGTHS, d65.wavelengths, d65.values)
    illuminant = colour.SpectralDistribution(dict(zip(WAVELENGTHS, d65_values)), name="D65 linear")

    def xyz_of(reflectance: np.ndarray) -> np.ndarray:
        sd = colour.SpectralDistribution(dict(zip(WAVELENGTHS, reflectance)))
        return colour.sd_to_XYZ(sd, cmfs, illuminant, method="Integration") / 100.0

    white_xyz = xyz_of(np.ones_like(WAVELENGTHS))
    white_xy = colour.XYZ_to_xy(white_xyz)
    srgb = colour.RGB_COLOURSPACES["sRGB"]
    space = colour.RGB_Colourspace("sRGB, tabulated D65 white", srgb.primaries, white_xy,
                                   use_derived_matrix_RGB_to_XYZ=True,
                                   use_derived_matrix_XYZ_to_RGB=True)
    return xyz_of, white_xy, space


def test_white_point_is_d65(setup):
    _, white_xy, _ = setup
    assert np.allclose(white_xy, [0.3127, 0.3290], atol=1e-4)


@pytest.mark.parametrize("rgb", sorted(set(itertools.product(LEVELS, repeat=3)) | set(EXTRA)))
def test_fit_reproduces_rgb_within_delta_e_2000(pathtracer, setup, rgb):
    xyz_of, white_xy, space = setup
    reflectance = spectrum_from_program(pathtracer, rgb)
    assert np.all(reflectance >= 0) and np.all(reflectance <= 1)
    target_xyz = colour.RGB_to_XYZ(np.array(rgb, dtype=float), space)
    lab_fit = colour.XYZ_to_Lab(xyz_of(reflectance), white_xy)
    lab_target = colour.XYZ_to_Lab(target_xyz, white_xy)
    de = float(colour.delta_E(lab_fit, lab_target, method="CIE 2000"))
    assert de <= 0.01, f"RGB {rgb}: Delta E 2000 = {de:.5f}"


def test_out_of_range_rgb_is_a_usage_error(pathtracer):
    r = subprocess.run([str(pathtracer), "--rgb-to-spectrum", "1.2,0,0"], capture_output=True, text=True)
    assert r.returncode == 2
    assert "--rgb-to-spectrum" in r.stderr
