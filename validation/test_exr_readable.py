"""The renderer's OpenEXR output opens in the reference OpenEXR reader (PyPI `OpenEXR`) and holds
the same image as its PFM output from the same render (our own writers, src/io/)."""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import OpenEXR
from pfm import read_pfm

WIDTH, HEIGHT = 16, 8


def read_exr(path: Path) -> tuple[dict, np.ndarray]:
    """(header, float32 array (height, width, 3) in R, G, B order)."""
    with OpenEXR.File(str(path), separate_channels=True) as exr:
        header = dict(exr.header())  # the live header is emptied when the file closes
        channels = exr.channels()
        assert sorted(channels) == ["B", "G", "R"], f"channels: {sorted(channels)}"
        for name in "RGB":
            assert channels[name].pixels.dtype == np.float32, f"{name} is not FLOAT"
        return header, np.stack([channels[name].pixels for name in "RGB"], axis=-1)


def test_exr_and_pfm_hold_the_same_image(pathtracer: Path, tmp_path: Path) -> None:
    exr_path, pfm_path = tmp_path / "a.exr", tmp_path / "a.pfm"
    command = [str(pathtracer), "--width", str(WIDTH), "--height", str(HEIGHT), "--spp", "1",
               "-o", str(exr_path), "-o", str(pfm_path)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"{command} failed:\n{result.stdout}\n{result.stderr}"

    header, exr = read_exr(exr_path)
    (x_min, y_min), (x_max, y_max) = header["dataWindow"]
    assert (x_max - x_min + 1, y_max - y_min + 1) == (WIDTH, HEIGHT)
    assert "chromaticities" in header
    assert exr.shape == (HEIGHT, WIDTH, 3)

    pfm = read_pfm(pfm_path)
    assert pfm.shape == (HEIGHT, WIDTH, 3)
    np.testing.assert_array_equal(exr, pfm)  # the same floats, bit for bit (NaNs in place)
    assert np.any(exr > 0), "the render is black: the comparison above would prove nothing"
