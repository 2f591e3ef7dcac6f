"""Check the CSV tables in spectra/ against colour-science, value by value.

Each table is read with the small parser below (independent of the generator,
validation/generate_spectral_tables.py) and every value is compared for exact
float64 equality with the colour-science dataset it claims to come from.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import colour

SPECTRA_DIR = Path(__file__).resolve().parent.parent / "spectra"

CMFS_NAME = "CIE 1931 2 Degree Standard Observer"
CHECKER_NAME = "ColorChecker N Ohta"
CAMERA_NAME = "Nikon 5100 (NPL)"

# Sum of y_bar at 1 nm over 360-830 nm, as tabulated by colour-science (CVRL
# transcription of the CIE 1931 table). pbrt and others use 106.856895, which
# differs by 2.2e-5 absolute (2.1e-7 relative): see test_cmf_y_integral.
Y_SUM_DATASET = 106.856917101172
Y_SUM_PUBLISHED = 106.856895

# Fluorescent lamps and a white LED (lines a few nm wide): file -> colour-science key.
SPIKY = {"cie_f2.csv": "FL2", "cie_f7.csv": "FL7", "cie_f11.csv": "FL11",
         "cie_led_b3.csv": "LED-B3"}


# --------------------------------------------------------------------------
# Parser
# --------------------------------------------------------------------------


@dataclass
class Table:
    path: Path
    comments: list[str]  # without the leading '#'
    columns: list[str]
    raw_rows: list[list[str]]

    @property
    def wavelengths(self) -> np.ndarray:
        return np.array([float(r[0]) for r in self.raw_rows])

    def column(self, name: str) -> np.ndarray:
        i = self.columns.index(name)
        return np.array([float(r[i]) for r in self.raw_rows])


class FormatError(ValueError):
    pass


def parse_table(text: str, path: Path = Path("<text>")) -> Table:
    """Parse the spectra/ CSV format, rejecting anything the C++ reader may not."""
    if "\r" in text:
        raise FormatError("CR characters (line endings must be \\n)")
    if not text.endswith("\n"):
        raise FormatError("file does not end with \\n")
    lines = text[:-1].split("\n")
    comments = []
    i = 0
    while i < len(lines) and lines[i].startswith("#"):
        comments.append(lines[i][1:])
        i += 1
    if i >= len(lines):
        raise FormatError("no header line")
    header = lines[i]
    if " " in header or header.endswith(","):
        raise FormatError(f"bad header {header!r}")
    columns = header.split(",")
    if columns[0] != "wavelength_nm" or not all(columns):
        raise FormatError(f"bad header {header!r}")
    if len(set(columns)) != len(columns):
        raise FormatError("duplicate column names")
    rows = []
    for n, line in enumerate(lines[i + 1 :], start=i + 2):
        if line.startswith("#"):
            raise FormatError(f"line {n}: comment after the header")
        if " " in line or "\t" in line or line.endswith(","):
            raise FormatError(f"line {n}: whitespace or trailing comma: {line!r}")
        fields = line.split(",")
        if len(fields) != len(columns):
            raise FormatError(f"line {n}: {len(fields)} fields, expected {len(columns)}")
        for f in fields:
            try:
                v = float(f)
            except ValueError:
                raise FormatError(f"line {n}: not a number: {f!r}") from None
            if not math.isfinite(v):
                raise FormatError(f"line {n}: non-finite value {f!r}")
        rows.append(fields)
    if not rows:
        raise FormatError("no data rows")
    table = Table(path, comments, columns, rows)
    if not np.all(np.diff(table.wavelengths) > 0):
        raise FormatError("wavelengths not strictly increasing")
    return table


def read_table(name: str) -> Table:
    path = SPECTRA_DIR / name
    data = path.read_bytes()
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError as e:
        raise FormatError(f"{name}: not ASCII") from e
    return parse_table(text, path)


def mismatches(table: Table, column: str, wavelengths, values) -> list[str]:
    """Every (wavelength, value) of the reference that the table does not
    reproduce exactly (float64 equality), plus wavelength-set differences."""
    ref = {float(w): float(v) for w, v in zip(wavelengths, values)}
    got = dict(zip(table.wavelengths.tolist(), table.column(column).tolist()))
    out = []
    if set(ref) != set(got):
        out.append(
            f"{column}: wavelengths differ: missing {sorted(set(ref) - set(got))[:5]}"
            f" extra {sorted(set(got) - set(ref))[:5]}"
        )
    for w in sorted(set(ref) & set(got)):
        if got[w] != ref[w]:
            out.append(f"{column} @ {w:g} nm: table {got[w]!r} != colour {ref[w]!r}")
    return out


def snake_case(name: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")


# --------------------------------------------------------------------------
# Expectations for each table
# --------------------------------------------------------------------------


def reference_columns(filename: str):
    """{column name: (wavelengths, values)} from colour-science for a table."""
    if filename == "cie_1931_2deg.csv":
        cmfs = colour.MSDS_CMFS[CMFS_NAME]
        return {
            label: (cmfs.wavelengths, cmfs.values[:, i])
            for i, label in enumerate(cmfs.labels)
        }
    if filename in ("cie_d65.csv", "cie_a.csv"):
        sd = colour.SDS_ILLUMINANTS["D65" if filename == "cie_d65.csv" else "A"]
        return {"value": (sd.wavelengths, sd.values)}
    if filename in SPIKY:
        sd = colour.SDS_ILLUMINANTS[SPIKY[filename]]
        return {"value": (sd.wavelengths, sd.values)}
    if filename == "colorchecker.csv":
        checker = colour.SDS_COLOURCHECKERS[CHECKER_NAME]
        return {
            snake_case(name): (sd.wavelengths, sd.values)
            for name, sd in ((n, checker[n]) for n in checker.keys())
        }
    if filename == "camera_nikon_d5100_npl.csv":
        camera = colour.characterisation.MSDS_CAMERA_SENSITIVITIES[CAMERA_NAME]
        return {
            column: (camera.wavelengths, camera.values[:, i])
            for i, column in enumerate("rgb")
        }
    raise KeyError(filename)


# filename: (columns after wavelength_nm or None, rows, first, last, step,
#            substrings the first comment line must contain)
EXPECTED = {
    "cie_1931_2deg.csv": (
        ["x_bar", "y_bar", "z_bar"],
        471, 360, 830, 1,
        ["CIE 015:2018", "11664-1", "CIE 1931 2 degree standard",
         "1 nm", f"colour.MSDS_CMFS['{CMFS_NAME}']"],
    ),
    "cie_d65.csv": (
        ["value"],
        97, 300, 780, 5,
        ["CIE 015:2018", "illuminant D65", "5 nm",
         "colour.SDS_ILLUMINANTS['D65']"],
    ),
    "cie_a.csv": (
        ["value"],
        97, 300, 780, 5,
        ["CIE 015:2018", "illuminant A", "5 nm", "colour.SDS_ILLUMINANTS['A']"],
    ),
    "cie_f2.csv": (["value"], 81, 380, 780, 5,
                   ["CIE 15:2004", "illuminant F2", "5 nm", "colour.SDS_ILLUMINANTS['FL2']"]),
    "cie_f7.csv": (["value"], 81, 380, 780, 5,
                   ["CIE 15:2004", "illuminant F7", "5 nm", "colour.SDS_ILLUMINANTS['FL7']"]),
    "cie_f11.csv": (["value"], 81, 380, 780, 5,
                    ["CIE 15:2004", "illuminant F11", "5 nm", "colour.SDS_ILLUMINANTS['FL11']"]),
    "cie_led_b3.csv": (["value"], 81, 380, 780, 5,
                       ["CIE 015:2018", "illuminant LED-B3", "5 nm",
                        "colour.SDS_ILLUMINANTS['LED-B3']"]),
    "colorchecker.csv": (
        None,
        81, 380, 780, 5,
        ["Ohta", "1997", "ColorChecker", "5 nm",
         f"colour.SDS_COLOURCHECKERS['{CHECKER_NAME}']"],
    ),
    "camera_nikon_d5100_npl.csv": (
        ["r", "g", "b"],
        81, 380, 780, 5,
        ["Darrodi", "2015", "JOSA A 32(3)", "Nikon D5100", "National Physical Laboratory",
         "5 nm", f"MSDS_CAMERA_SENSITIVITIES['{CAMERA_NAME}']"],
    ),
}

TABLES = sorted(EXPECTED)


@pytest.fixture(scope="module", params=TABLES)
def table(request) -> Table:
    return read_table(request.param)


# --------------------------------------------------------------------------
# Tests
# --------------------------------------------------------------------------


def test_spectra_dir_holds_the_tables():
    present = {p.name for p in SPECTRA_DIR.glob("*.csv")}
    assert set(TABLES) <= present


def test_format_is_canonical(table: Table):
    """Wavelengths are integers; values are shortest round-trip decimals."""
    for row in table.raw_rows:
        assert re.fullmatch(r"[1-9][0-9]*", row[0]), row[0]
        for f in row[1:]:
            assert repr(float(f)) == f, f"{table.path.name}: {f!r} not repr-formatted"


def test_first_comment_names_source(table: Table):
    assert table.comments, f"{table.path.name}: no comment lines"
    first = table.comments[0]
    for needle in EXPECTED[table.path.name][5]:
        assert needle in first, f"{table.path.name}: {needle!r} not in {first!r}"
    assert re.search(r"colour-science \d+\.\d+\.\d+", first), first


def test_shape_range_and_step(table: Table):
    columns, rows, first, last, step, _ = EXPECTED[table.path.name]
    ref = reference_columns(table.path.name)
    if columns is None:
        columns = list(ref)
    assert table.columns == ["wavelength_nm"] + columns
    w = table.wavelengths
    assert len(table.raw_rows) == rows
    assert (w[0], w[-1]) == (first, last)
    assert np.all(np.diff(w) == step)


def test_every_value_matches_colour_science(table: Table):
    ref = reference_columns(table.path.name)
    assert table.columns[1:] == list(ref)
    problems = []
    for column, (wavelengths, values) in ref.items():
        problems += mismatches(table, column, wavelengths, values)
    assert not problems, f"{table.path.name}: {len(problems)} mismatches:\n" + "\n".join(
        problems[:20]
    )


def test_colorchecker_comment_lists_original_names():
    table = read_table("colorchecker.csv")
    names = list(colour.SDS_COLOURCHECKERS[CHECKER_NAME].keys())
    assert len(names) == 24
    text = "\n".join(table.comments)
    for name in names:
        assert f"{snake_case(name)} = {name}" in text, name


def test_cmf_y_integral():
    table = read_table("cie_1931_2deg.csv")
    y_sum = math.fsum(table.column("y_bar"))  # 1 nm steps: sum == Riemann integral
    # Exact for this dataset ...
    assert abs(y_sum - Y_SUM_DATASET) <= 1e-9
    # ... and within 1e-6 *relative* of the commonly quoted constant (pbrt's
    # CIE_Y_integral); the absolute difference is 2.2e-5.
    assert abs(y_sum - Y_SUM_PUBLISHED) <= 1e-6 * Y_SUM_PUBLISHED


def _cmfs_from_csv() -> colour.colorimetry.XYZ_ColourMatchingFunctions:
    t = read_table("cie_1931_2deg.csv")
    data = np.stack([t.column(c) for c in ("x_bar", "y_bar", "z_bar")], axis=1)
    return colour.colorimetry.XYZ_ColourMatchingFunctions(
        data, t.wavelengths, name="CMFs from spectra/cie_1931_2deg.csv"
    )


def _sd_from_csv(name: str) -> colour.SpectralDistribution:
    t = read_table(name)
    return colour.SpectralDistribution(t.column("value"), t.wavelengths, name=name)


@pytest.mark.parametrize(
    "filename, xy_expected",
    [("cie_d65.csv", (0.3127, 0.3290)), ("cie_a.csv", (0.44757, 0.40745))],
)
def test_illuminant_chromaticity(filename, xy_expected):
    # colour's default ASTM E308 method: the 5 nm illuminant table is weighted
    # with the CMFs over their common 360-780 nm range at 5 nm. colour warns
    # that it aligns the shapes; that is expected here.
    with colour.utilities.suppress_warnings(colour_runtime_warnings=True):
        XYZ = colour.sd_to_XYZ(_sd_from_csv(filename), _cmfs_from_csv())
    XYZ = XYZ / XYZ[1]  # normalise to Y = 1
    assert XYZ[1] == 1.0
    xy = colour.XYZ_to_xy(XYZ)
    assert np.all(np.abs(xy - np.array(xy_expected)) <= 1e-4), xy


def test_a_changed_digit_is_caught():
    """The comparison really fails when one value in a table is altered."""
    path = SPECTRA_DIR / "cie_1931_2deg.csv"
    text = path.read_text("ascii")
    # y_bar at 555 nm is exactly 1.0; make it 1.0000001.
    altered = text.replace("\n555,0.5120501,1.0,", "\n555,0.5120501,1.0000001,")
    assert altered != text
    cmfs = colour.MSDS_CMFS[CMFS_NAME]
    good = parse_table(text)
    bad = parse_table(altered)
    assert not mismatches(good, "y_bar", cmfs.wavelengths, cmfs.values[:, 1])
    found = mismatches(bad, "y_bar", cmfs.wavelengths, cmfs.values[:, 1])
    assert len(found) == 1 and "555" in found[0]


@pytest.mark.parametrize(
    "text",
    [
        "wavelength_nm,value\r\n400,1.0\r\n",  # CRLF
        "wavelength_nm,value\n400,1.0",  # no final newline
        "wavelength_nm,value\n400, 1.0\n",  # space
        "wavelength_nm,value\n400,1.0,\n",  # trailing comma
        "wavelength_nm,value\n410,1.0\n400,1.0\n",  # decreasing
        "wavelength_nm,value\n400,1.0\n400,1.0\n",  # repeated wavelength
        "nm,value\n400,1.0\n",  # wrong first column
        "wavelength_nm,value\n400,abc\n",  # not a number
    ],
)
def test_parser_rejects_malformed(text):
    with pytest.raises(FormatError):
        parse_table(text)
