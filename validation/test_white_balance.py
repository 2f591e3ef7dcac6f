"""White balance (``--white-balance WHITE``) against colour-science.

* The matrix the program applies, printed by ``pathtracer --print-adaptation WHITE`` (XYZ -> XYZ,
  to the white of ``--color-space``), equals
  ``colour.adaptation.matrix_chromatic_adaptation_VonKries(XYZ_w, XYZ_wr, transform='Bradford')``
  to 1e-12, for every named illuminant, for temperatures on both loci, and for each output space.
* The whites: named illuminants are colour-science's ``CCS_ILLUMINANTS`` (CIE 1931 2 degree) xy;
  a temperature below 4000 K is the Planckian radiator (``colour.sd_blackbody``, whose
  c2 = 1.4388e-2 m K is the CIE's, integrated with
  ``colour.sd_to_XYZ`` over the renderer's 1 nm 360-830 nm CMF table) and from 4000 K the CIE
  daylight locus (``colour.temperature.CCT_to_xy_CIE_D``).
* ``colorchecker-a`` (the chart under illuminant A) rendered with ``--white-balance A`` shows its
  six neutral patches neutral: CIELAB chroma (D65 white) at most 1.5 (colour-science predicts
  0.1-1.0 for these not quite flat reflectances; 21-65 without white balance), and every patch
  matches the Bradford-adapted colour-science reference within CIEDE2000 0.3 on average.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import colour
import numpy as np
import pytest

import color_accuracy as ca

NAMED = ["A", "D50", "D55", "D65", "D75", "E", "F2", "F11"]
COLOUR_NAMES = {"F2": "FL2", "F11": "FL11"}  # colour-science's keys for the CIE F series
TARGETS = {"srgb": (0.3127, 0.3290), "rec2020": (0.3127, 0.3290),
           "acescg": (0.32168, 0.33767), "xyz": (1 / 3, 1 / 3)}

NEUTRALS = ["white_9_5_05_d", "neutral_8_23_d", "neutral_6_5_44_d", "neutral_5_70_d",
            "neutral_3_5_1_05_d", "black_2_1_5_d"]
NEUTRAL_CHROMA = 1.5
MEAN_DELTA_E = 0.3


def print_adaptation(pathtracer: Path, white: str, space: str = "srgb"):
    out = subprocess.run([str(pathtracer), "--print-adaptation", white, "--color-space", space],
                         check=True, capture_output=True, text=True).stdout.split("\n")
    assert out[0].startswith("source_xy ") and out[1].startswith("target_xy "), out
    source = np.array(out[0].split()[1:], float)
    target = np.array(out[1].split()[1:], float)
    matrix = np.array([row.split() for row in out[2:5]], float)
    return source, target, matrix


def colour_matrix(source_xy, target_xy) -> np.ndarray:
    return colour.adaptation.matrix_chromatic_adaptation_VonKries(
        colour.xy_to_XYZ(source_xy), colour.xy_to_XYZ(target_xy), transform="Bradford")


def planckian_xy(kelvin: float) -> np.ndarray:
    sd = colour.sd_blackbody(kelvin, ca.SHAPE)
    return colour.XYZ_to_xy(colour.sd_to_XYZ(sd, ca.cmfs(), method="Integration"))


@pytest.mark.parametrize("name", NAMED)
def test_named_white_and_matrix(pathtracer, name):
    source, target, matrix = print_adaptation(pathtracer, name)
    expected_xy = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"][
        COLOUR_NAMES.get(name, name)]
    np.testing.assert_allclose(source, expected_xy, atol=1e-15)
    np.testing.assert_allclose(target, TARGETS["srgb"], atol=1e-15)
    np.testing.assert_allclose(matrix, colour_matrix(source, target), atol=1e-12)


@pytest.mark.parametrize("space", list(TARGETS))
def test_matrix_adapts_to_the_output_space_white(pathtracer, space):
    source, target, matrix = print_adaptation(pathtracer, "A", space)
    np.testing.assert_allclose(target, TARGETS[space], atol=1e-15)
    np.testing.assert_allclose(matrix, colour_matrix(source, target), atol=1e-12)


@pytest.mark.parametrize("kelvin", [1000, 2000, 2856, 3200, 3999])
def test_low_temperatures_are_planckian(pathtracer, kelvin):
    source, target, matrix = print_adaptation(pathtracer, f"{kelvin}K")
    np.testing.assert_allclose(source, planckian_xy(kelvin), atol=1e-9)
    np.testing.assert_allclose(matrix, colour_matrix(source, target), atol=1e-12)


@pytest.mark.parametrize("kelvin", [4000, 5003, 6504, 7000, 7001, 10000, 25000])
def test_high_temperatures_are_cie_daylight(pathtracer, kelvin):
    source, target, matrix = print_adaptation(pathtracer, str(kelvin))
    np.testing.assert_allclose(source, colour.temperature.CCT_to_xy_CIE_D(kelvin), atol=1e-12)
    np.testing.assert_allclose(matrix, colour_matrix(source, target), atol=1e-12)


def test_d65_balance_is_the_identity_for_srgb(pathtracer):
    _, _, matrix = print_adaptation(pathtracer, "D65")
    np.testing.assert_allclose(matrix, np.eye(3), atol=1e-15)


def chroma(xyz: np.ndarray) -> np.ndarray:
    lab = colour.XYZ_to_Lab(xyz, TARGETS["srgb"])
    return np.hypot(lab[..., 1], lab[..., 2])


def test_colorchecker_a_neutrals_come_out_neutral(pathtracer, tmp_path):
    out = tmp_path / "balanced.pfm"
    # --scale 0.5: 120 x 80 (patches of 18 pixels), exact spectra, so only noise remains.
    subprocess.run([str(pathtracer), str(ca.scene_file("A")), "--scale", "0.5", "--spp", "512",
                    "--spectral-bins", "exact", "--white-balance", "A", "--seed", "3", "--quiet",
                    "-o", str(out)], check=True, capture_output=True)
    rgb = ca.read_pfm(out)
    srgb = colour.RGB_COLOURSPACES["sRGB"]
    to_xyz = colour.normalised_primary_matrix(srgb.primaries, srgb.whitepoint)
    xyz = rgb @ to_xyz.T * ca.renderer_white_scale("A")  # Y_white = 1 (Bradford keeps it)
    height, width, _ = xyz.shape
    assert (width, height) == (120, 80)
    regions = ca.patch_regions("A", width, height)
    means = np.array([xyz[regions[name]].reshape(-1, 3).mean(axis=0) for name in ca.PATCHES])

    reference, _ = ca.reference_xyz("A")
    source = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["A"]
    expected = reference @ colour_matrix(source, TARGETS["srgb"]).T
    names = list(ca.PATCHES)
    neutral = [names.index(n) for n in NEUTRALS]

    assert np.all(chroma(reference[neutral]) > 20), "the unbalanced neutrals must be coloured"
    assert np.all(chroma(expected[neutral]) <= NEUTRAL_CHROMA), chroma(expected[neutral])
    assert np.all(chroma(means[neutral]) <= NEUTRAL_CHROMA), chroma(means[neutral])
    delta_e = colour.delta_E(colour.XYZ_to_Lab(means, TARGETS["srgb"]),
                             colour.XYZ_to_Lab(expected, TARGETS["srgb"]), method="CIE 2000")
    assert np.mean(delta_e) <= MEAN_DELTA_E, delta_e
