"""spectra/metal_*.csv (made by generate_metal_tables.py): format the C++ reader expects, a
source named in the first comment, measured points covering 360-830 nm, physical values, and
gold's, silver's, copper's and aluminium's normal-incidence reflectance where textbooks put it."""
from pathlib import Path

import numpy as np
import pytest

SPECTRA = Path(__file__).resolve().parent.parent / "spectra"
METALS = ["au", "ag", "cu", "al"]


def read(symbol):
    lines = (SPECTRA / f"metal_{symbol}.csv").read_text().splitlines()
    comments = [l for l in lines if l.startswith("#")]
    header = lines[len(comments)]
    rows = np.array([[float(x) for x in l.split(",")] for l in lines[len(comments) + 1:]])
    return comments, header, rows


@pytest.mark.parametrize("symbol", METALS)
def test_table_format_source_and_range(symbol):
    comments, header, rows = read(symbol)
    assert comments[0].startswith("# Source: ") and "refractiveindex.info" in comments[0]
    assert header == "wavelength_nm,eta,k"
    assert np.all(np.diff(rows[:, 0]) > 0)
    assert rows[0, 0] <= 360 and rows[-1, 0] >= 830
    assert np.all(rows[:, 1] > 0) and np.all(rows[:, 2] >= 0)


@pytest.mark.parametrize("symbol, nm, lo, hi", [
    ("au", 450, 0.35, 0.45), ("au", 650, 0.9, 1.0),   # yellow: blue absorbed
    ("cu", 450, 0.5, 0.65), ("cu", 650, 0.9, 1.0),    # reddish
    ("ag", 550, 0.95, 1.0), ("al", 550, 0.9, 0.94),
])
def test_normal_incidence_reflectance(symbol, nm, lo, hi):
    _, _, rows = read(symbol)
    n = np.interp(nm, rows[:, 0], rows[:, 1]) + 1j * np.interp(nm, rows[:, 0], rows[:, 2])
    r = abs((n - 1) / (n + 1)) ** 2
    assert lo <= r <= hi, r
