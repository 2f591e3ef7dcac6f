"""The spectral EXR (``--spectral-bands``) read with the reference OpenEXR reader (PyPI
``OpenEXR``): the layout of Fichet, Pacanowski & Wilkie, "An OpenEXR Layout for Spectral Images"
(JCGT 10(3), 2021), the render metadata of every EXR header, and the bands integrated against
the CIE 1931 functions of colour-science giving the XYZ image of the same render.

Binning error, stated and bounded per pixel without noise: both images come from the same
samples. For one lane, the XYZ film adds L/p * xbar(lambda) and the bands L/p * [lambda in b] / D
(D the band width); integrating the bands with the band integrals of xbar replaces xbar(lambda)
by its band mean m_b. So, per pixel and exactly for every sample (L >= 0),
    |X_bands - X_film| <= sum_b S_b * D * max_{lambda in b} |xbar(lambda) - m_b| / int(ybar),
S_b the band values: about half the change of xbar across a band, a worst case (9.7 % of Y at
10-nm bands on cornell, 1.0 % at 1-nm bands; the largest pixel error measured is 0.7 of it). The image means must also agree
within 5 standard errors of their difference plus the first-order binning error estimated from
the mean spectrum (measured 2e-4 relative at 10 nm, the noise's size).
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import colour
import numpy as np
import OpenEXR
import pytest
from colour.io.fichet2021 import PATTERN_FICHET2021, match_groups_to_nm

CMFS = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
WIDTH, HEIGHT, SPP, SEED = 24, 24, 32, 5


def render(pathtracer: Path, out: Path, *extra: str) -> None:
    command = [str(pathtracer), "cornell", "--width", str(WIDTH), "--height", str(HEIGHT), "--spp",
               str(SPP), "--seed", str(SEED), "--quiet", "-o", str(out), *extra]
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, f"{command} failed:\n{result.stderr}"


def read_exr(path: Path) -> tuple[dict, dict[str, np.ndarray]]:
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        header = dict(exr.header())  # the live header is emptied when the file closes
        channels = {name: c.pixels.astype(np.float64) for name, c in exr.channels().items()}
    return header, channels


def spectral_channels(channels: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(wavelengths in nm, increasing; bands array (h, w, n)) parsed with colour-science's own
    reading of the Fichet et al. names."""
    pattern = re.compile(rf"^S0\.{PATTERN_FICHET2021}$")
    found = []
    for name, pixels in channels.items():
        if name in ("R", "G", "B"):
            continue
        match = pattern.match(name)
        assert match, f"channel {name!r} is not an emissive spectral channel"
        found.append((match_groups_to_nm(match.group(1), match.group(3), match.group(4)), pixels))
    found.sort(key=lambda item: item[0])
    return np.array([w for w, _ in found]), np.stack([p for _, p in found], axis=-1)


def cmf_table() -> tuple[np.ndarray, np.ndarray]:
    """The 1-nm CIE table over 360-830 nm (the renderer's, spectra/cie_1931_2deg.csv)."""
    w = CMFS.wavelengths
    keep = (w >= 360) & (w <= 830)
    return w[keep], CMFS.values[keep]


def band_integrals(lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """(integral of xbar, ybar, zbar over [lo, hi]; max |cmf - band mean| there), for the linear
    interpolation of the 1-nm table (band edges on whole nanometres)."""
    w, v = cmf_table()
    inside = (w >= lo) & (w <= hi)
    integral = np.trapezoid(v[inside], w[inside], axis=0)
    # the interpolated table is linear between entries: its extremes are at the entries
    deviation = np.abs(v[inside] - integral / (hi - lo)).max(axis=0)
    return integral, deviation


# 10-nm and 1-nm bands over 360-830 nm, the film's whole CMF range (edges on whole nanometres)
@pytest.mark.parametrize("BANDS", [47, 470])
def test_spectral_exr_layout_metadata_and_xyz(pathtracer: Path, tmp_path: Path, BANDS: int) -> None:
    out = tmp_path / "spectral.exr"
    render(pathtracer, out, "--color-space", "xyz", "--spectral-bands", str(BANDS))
    header, channels = read_exr(out)

    # ---- Layout (Fichet et al. 2021) and metadata ----
    assert header["spectralLayoutVersion"] == "1.0"
    assert header["emissiveUnits"] == "W.m^-2.sr^-1"
    width = 470 / BANDS
    wavelengths, bands = spectral_channels(channels)
    np.testing.assert_allclose(wavelengths, 360 + width * (np.arange(BANDS) + 0.5), rtol=0, atol=1e-6)
    # the exact spelling: %f, decimal comma
    assert ("S0.365,000000nm" if BANDS == 47 else "S0.360,500000nm") in channels
    assert bands.shape == (HEIGHT, WIDTH, BANDS)
    assert header["software"].startswith("pathtracer ")
    assert header["scene"] == "cornell"
    assert header["integrator"] == "path"
    assert header["spp"] == SPP and header["sppRequested"] == SPP
    assert header["seed"] == str(SEED)
    assert header["spectralBins"] == "16"
    assert header["observer"] == "CIE 1931 2 degree"
    assert header["spectralBands"] == BANDS and header["spectralRangeNm"] == "360:830"
    assert float(np.ravel(header["renderTimeSeconds"])[0]) > 0
    assert re.fullmatch(r"\d{4}:\d\d:\d\d \d\d:\d\d:\d\d", header["capDate"])

    # ---- Bands x CIE functions = the XYZ image ----
    xyz = np.stack([channels[c] for c in "RGB"], axis=-1)  # --color-space xyz
    assert np.all(xyz[..., 1] > 0), "a black pixel would make the comparison vacuous"
    _, table = cmf_table()
    y_integral = np.trapezoid(table[:, 1], dx=1.0)
    integrals, deviations = zip(*(band_integrals(360 + b * width, 360 + (b + 1) * width) for b in range(BANDS)))
    integrals, deviations = np.array(integrals), np.array(deviations)  # (bands, 3)
    xyz_from_bands = bands @ integrals / y_integral

    # per pixel: the noise-free bound of the docstring (+ float32 storage)
    bound = (bands * width) @ deviations / y_integral
    error = np.abs(xyz_from_bands - xyz)
    assert np.all(error <= bound + 1e-5 * np.abs(xyz)), f"worst excess {np.max(error - bound)}"
    relative_bound = bound[..., 1].mean() / xyz[..., 1].mean()
    print(f"\nper-pixel bound on Y: {relative_bound:.2%} of the mean Y; "
          f"largest error/bound {np.max(error / np.maximum(bound, 1e-30)):.2f}")
    # the bound shrinks with the band width (measured 9.7 % of Y at 10 nm, 1.0 % at 1 nm)
    assert relative_bound < 0.012 * width

    # image means: noise (pixels independent) plus the first-order binning error of the mean
    # spectrum: half its change across each band times the band's deviation share
    difference = (xyz_from_bands - xyz).reshape(-1, 3)
    mean, standard_error = difference.mean(axis=0), difference.std(axis=0, ddof=1) / np.sqrt(len(difference))
    spectrum = bands.reshape(-1, BANDS).mean(axis=0)
    slope = np.abs(np.gradient(spectrum))  # change per band
    first_order = (0.5 * slope * width) @ deviations / y_integral
    print(f"image-mean difference {mean / xyz.reshape(-1, 3).mean(axis=0)} (relative), "
          f"standard error {standard_error}, first-order binning {first_order}")
    assert np.all(np.abs(mean) <= 5 * standard_error + first_order)
