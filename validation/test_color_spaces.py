"""Output colour spaces (``--color-space srgb|rec2020|acescg|xyz``) against colour-science.

The scene ``colorchecker`` (24 measured reflectances and the D65 background: colours inside and
outside each gamut) is rendered once per space with the same seed, so every space gets the very
same paths; the film keeps XYZ and converts when the file is written. Checks:

* per pixel, RGB = M . XYZ within 1e-4 relative, with M the XYZ -> RGB matrix of colour-science:
  ``colour.RGB_COLOURSPACES['ITU-R BT.2020' | 'ACEScg'].matrix_XYZ_to_RGB``; for sRGB the matrix
  is computed from colour-science's sRGB primaries and whitepoint with
  ``colour.normalised_primary_matrix`` (and inverted), because colour-science's stored sRGB
  matrices are the IEC 61966-2-1 values rounded to 4 decimals (3.2406 for 3.24097: 1e-4 off);
* the default (no ``--color-space``) is linear sRGB, bit for bit;
* the EXR ``chromaticities`` attribute (read with the OpenEXR package) holds colour-science's
  primaries and whitepoint of each space (to float32 precision), and for ``xyz`` OpenEXR's
  convention for XYZ data, red (1, 0), green (0, 1), blue (0, 0), white (1/3, 1/3), for which
  ``colour.normalised_primary_matrix`` gives the identity.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
from pfm import read_pfm
import OpenEXR
import pytest

import colour

WIDTH, HEIGHT, SPP, SEED = 60, 40, 2, 7
RELATIVE_TOLERANCE = 1e-4

COLOUR_SCIENCE_NAMES = {"srgb": "sRGB", "rec2020": "ITU-R BT.2020", "acescg": "ACEScg"}
XYZ_CHROMATICITIES = np.array([1, 0, 0, 1, 0, 0, 1 / 3, 1 / 3])  # OpenEXR: CIE XYZ data


def exr_chromaticities(path: Path) -> np.ndarray:
    with OpenEXR.File(str(path)) as exr:
        return np.array(exr.header()["chromaticities"], dtype=float)


def xyz_to_rgb_matrix(space: str) -> np.ndarray:
    cs = colour.RGB_COLOURSPACES[COLOUR_SCIENCE_NAMES[space]]
    if space == "srgb":
        return np.linalg.inv(colour.normalised_primary_matrix(cs.primaries, cs.whitepoint))
    return np.asarray(cs.matrix_XYZ_to_RGB)


@pytest.fixture(scope="module")
def renders(pathtracer: Path, tmp_path_factory) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """space -> (PFM image, EXR chromaticities); key 'default' for no --color-space."""
    folder = tmp_path_factory.mktemp("color_spaces")
    out = {}
    for space in ["xyz", "srgb", "rec2020", "acescg", "default"]:
        pfm, exr = folder / f"{space}.pfm", folder / f"{space}.exr"
        command = [str(pathtracer), "colorchecker", "--width", str(WIDTH), "--height", str(HEIGHT),
                   "--spp", str(SPP), "--seed", str(SEED), "--quiet", "-o", str(pfm), "-o", str(exr)]
        if space != "default":
            command += ["--color-space", space]
        result = subprocess.run(command, capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, f"{command} failed:\n{result.stderr}"
        out[space] = (read_pfm(pfm), exr_chromaticities(exr))
    return out


def test_srgb_matrix_from_primaries_matches_the_iec_values():
    # The 4-decimal matrix colour-science stores for sRGB is that of IEC 61966-2-1; the one
    # derived from the primaries (what the renderer and this test use) rounds to it.
    derived = xyz_to_rgb_matrix("srgb")
    stored = np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB)
    np.testing.assert_allclose(derived, stored, atol=5e-4)
    assert np.abs(derived - stored).max() > 1e-5  # ... but only to 4 decimals


@pytest.mark.parametrize("space", ["rec2020", "acescg"])
def test_stored_matrices_are_those_of_the_primaries(space):
    cs = colour.RGB_COLOURSPACES[COLOUR_SCIENCE_NAMES[space]]
    npm = colour.normalised_primary_matrix(cs.primaries, cs.whitepoint)
    np.testing.assert_allclose(np.linalg.inv(npm), xyz_to_rgb_matrix(space), rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("space", ["srgb", "rec2020", "acescg"])
def test_rgb_is_the_matrix_times_xyz(renders, space):
    xyz = renders["xyz"][0]
    rgb = renders[space][0]
    m = xyz_to_rgb_matrix(space)
    assert np.all(np.isfinite(xyz)) and xyz[..., 1].max() > 0.1, "the XYZ render is empty"
    expected = xyz @ m.T
    scale = np.abs(xyz) @ np.abs(m).T  # size of the terms summed: relative error of each channel
    error = np.abs(rgb - expected) / np.maximum(scale, 1e-12)
    worst = np.unravel_index(np.argmax(error), error.shape)
    assert error.max() <= RELATIVE_TOLERANCE, (
        f"{space}: pixel {worst[:2]} channel {worst[2]}: {rgb[worst]} vs M.XYZ {expected[worst]} "
        f"(relative {error.max():.2e})")


def test_default_is_linear_srgb(renders):
    np.testing.assert_array_equal(renders["default"][0], renders["srgb"][0])
    np.testing.assert_array_equal(renders["default"][1], renders["srgb"][1])


def test_xyz_output_is_the_film(renders):
    # colour-science: the OpenEXR XYZ chromaticities give the identity matrix
    c = XYZ_CHROMATICITIES
    npm = colour.normalised_primary_matrix(c[:6].reshape(3, 2), c[6:])
    np.testing.assert_allclose(npm, np.eye(3), atol=1e-12)


@pytest.mark.parametrize("space", ["srgb", "rec2020", "acescg", "xyz"])
def test_exr_chromaticities(renders, space):
    stored = renders[space][1]
    if space == "xyz":
        expected = XYZ_CHROMATICITIES
    else:
        cs = colour.RGB_COLOURSPACES[COLOUR_SCIENCE_NAMES[space]]
        expected = np.concatenate([np.ravel(cs.primaries), np.ravel(cs.whitepoint)])
    # The attribute is 8 float32 values.
    np.testing.assert_allclose(stored, expected.astype(np.float32), rtol=0, atol=0)
    np.testing.assert_allclose(stored, expected, rtol=1e-7, atol=0)
