#!/usr/bin/env python3
"""Regenerate the spectral data tables in ``spectra/`` from colour-science.

Usage (from the repository root)::

    .venv/bin/python validation/generate_spectral_tables.py [--out DIR]

File format (the C++ reader relies on it exactly):

* zero or more ``#`` comment lines at the top, the first naming the source;
* one header line of comma-separated column names, first ``wavelength_nm``;
* numeric rows, comma-separated, no spaces, no trailing comma, ``\\n`` line
  endings. Wavelengths are written as integers (all tabulated wavelengths are
  whole nanometres), every other value as ``repr(float(x))``, the shortest
  string that round-trips to the exact float64 held by colour-science.
"""

from __future__ import annotations

import argparse
import re
import sys
import warnings
from pathlib import Path

# colour-science warns at import time when SciPy is absent; nothing used here
# needs SciPy.
warnings.filterwarnings("ignore", message='"SciPy" related API')

import colour  # noqa: E402
import numpy as np  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parent.parent

CMFS_NAME = "CIE 1931 2 Degree Standard Observer"
COLORCHECKER_NAME = "ColorChecker N Ohta"
CAMERA_NAME = "Nikon 5100 (NPL)"

# (colour-science key, file, what the CIE calls it): fluorescent lamps of CIE 15:2004 and a
# phosphor-converted white LED of CIE 015:2018 (LED-B3, 4103 K: about the colour
# temperature of F2 and F11, so the three kinds of light can be compared at one white).
SPIKY_ILLUMINANTS = (
    ("FL2", "cie_f2.csv", "CIE 15:2004 tables, CIE illuminant F2 (standard cool "
     "white fluorescent lamp, halophosphate, 4230 K)"),
    ("FL7", "cie_f7.csv", "CIE 15:2004 tables, CIE illuminant F7 (broadband "
     "fluorescent lamp, D65 simulator, 6500 K)"),
    ("FL11", "cie_f11.csv", "CIE 15:2004 tables, CIE illuminant F11 (narrow "
     "tri-band fluorescent lamp, 4000 K)"),
    ("LED-B3", "cie_led_b3.csv", "CIE 015:2018, CIE illuminant LED-B3 "
     "(phosphor-converted blue white LED, 4103 K)"),
)


def snake_case(name: str) -> str:
    """Lower-case; every run of characters outside [a-z0-9] becomes one '_'."""
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")


def format_wavelength(w: float) -> str:
    w = float(w)
    if not w.is_integer():
        raise ValueError(f"non-integral wavelength {w!r}")
    return str(int(w))


def format_value(v: float) -> str:
    s = repr(float(v))
    if not np.isfinite(float(v)) or float(s) != float(v):
        raise ValueError(f"cannot format {v!r}")
    return s


def step_of(wavelengths: np.ndarray) -> float:
    steps = np.unique(np.diff(wavelengths))
    if steps.size != 1:
        raise ValueError(f"irregular wavelength steps {steps}")
    return float(steps[0])


def range_text(wavelengths: np.ndarray) -> str:
    return (
        f"{format_wavelength(wavelengths[0])}-{format_wavelength(wavelengths[-1])} nm"
        f" at {format_wavelength(step_of(wavelengths))} nm"
        f" ({len(wavelengths)} rows)"
    )


def write_table(
    path: Path,
    comments: list[str],
    columns: list[str],
    wavelengths: np.ndarray,
    values: np.ndarray,
) -> None:
    wavelengths = np.asarray(wavelengths, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64)
    if values.ndim == 1:
        values = values[:, None]
    assert values.shape == (len(wavelengths), len(columns) - 1)
    assert columns[0] == "wavelength_nm"
    assert np.all(np.diff(wavelengths) > 0), "wavelengths must increase strictly"
    lines = []
    for c in comments:
        assert "\n" not in c and "\r" not in c
        lines.append("# " + c if c else "#")
    lines.append(",".join(columns))
    for w, row in zip(wavelengths, values):
        lines.append(",".join([format_wavelength(w)] + [format_value(v) for v in row]))
    text = "\n".join(lines) + "\n"
    text.encode("ascii")  # keep the files plain ASCII
    path.write_bytes(text.encode("ascii"))


def provenance(dataset: str) -> str:
    return (
        f"Produced from colour-science {colour.__version__} dataset {dataset} by "
        "validation/generate_spectral_tables.py; values are the dataset's float64 "
        "values written as shortest round-trip decimals (Python repr)."
    )


def generate(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    version = colour.__version__

    # --- CIE 1931 2 degree standard observer -------------------------------
    cmfs = colour.MSDS_CMFS[CMFS_NAME]
    write_table(
        out / "cie_1931_2deg.csv",
        [
            "Source: CIE 015:2018 / ISO/CIE 11664-1:2019 (formerly CIE S 014-1), CIE 1931 2 degree "
            "standard colorimetric observer x_bar,y_bar,z_bar, "
            f"{range_text(cmfs.wavelengths)}; colour-science {version} dataset "
            f"colour.MSDS_CMFS['{CMFS_NAME}'].",
            provenance(f"colour.MSDS_CMFS['{CMFS_NAME}']"),
            "colour-science transcribed this table from the CVRL database "
            "('Older CIE Standards', CIE 1931 2-deg XYZ CMFs at 1 nm).",
            "1 nm sum of y_bar over 360-830 nm of these values: "
            f"{repr(float(np.sum(cmfs.values[:, 1], dtype=np.float64)))}.",
        ],
        ["wavelength_nm"] + list(cmfs.labels),
        cmfs.wavelengths,
        cmfs.values,
    )

    # --- Illuminants D65 and A -------------------------------------------
    illuminant_text = {
        "D65": (
            "CIE standard illuminant D65",
            "ISO 11664-2:2007 / CIE S 014-2:2006 defines D65 at 1 nm over 300-830 nm; "
            "colour-science carries the 5 nm CIE 15:2004 tabulation only over "
            "300-780 nm, and this file keeps that native range and step unchanged "
            "(no interpolation or extrapolation).",
        ),
        "A": (
            "CIE standard illuminant A (Planckian radiator, T = 2856 K, "
            "normalised to 100 at 560 nm)",
            "ISO 11664-2:2007 / CIE S 014-2:2006 defines A by Planck's law at 1 nm "
            "over 300-830 nm; colour-science carries the 5 nm CIE 15:2004 "
            "tabulation only over 300-780 nm, and this file keeps that native range "
            "and step unchanged (no interpolation or extrapolation).",
        ),
    }
    for key, filename in (("D65", "cie_d65.csv"), ("A", "cie_a.csv")):
        sd = colour.SDS_ILLUMINANTS[key]
        title, note = illuminant_text[key]
        write_table(
            out / filename,
            [
                f"Source: CIE 015:2018 / CIE 15:2004 tables, {title}, relative "
                f"spectral power distribution, {range_text(sd.wavelengths)}; "
                f"colour-science {version} dataset colour.SDS_ILLUMINANTS['{key}'].",
                provenance(f"colour.SDS_ILLUMINANTS['{key}']"),
                note,
            ],
            ["wavelength_nm", "value"],
            sd.wavelengths,
            sd.values,
        )

    # --- Spiky light: fluorescent lamps and a white LED --------------------
    for key, filename, title in SPIKY_ILLUMINANTS:
        sd = colour.SDS_ILLUMINANTS[key]
        write_table(
            out / filename,
            [
                f"Source: {title}, relative spectral power distribution, "
                f"{range_text(sd.wavelengths)}; colour-science {version} dataset "
                f"colour.SDS_ILLUMINANTS['{key}'].",
                provenance(f"colour.SDS_ILLUMINANTS['{key}']"),
                "The tabulation's own scale (not 100 at 560 nm, where this lamp may have no "
                "line): the renderer's named illuminant rescales it to luminance 1 "
                "(scenes/README.md). Native range and step, no interpolation or extrapolation.",
            ],
            ["wavelength_nm", "value"],
            sd.wavelengths,
            sd.values,
        )

    # --- ColorChecker (Ohta 1997) ------------------------------------------
    checker = colour.SDS_COLOURCHECKERS[COLORCHECKER_NAME]
    names = list(checker.keys())
    assert len(names) == 24, names
    sds = [checker[n] for n in names]
    wavelengths = sds[0].wavelengths
    for sd in sds:
        if not np.array_equal(sd.wavelengths, wavelengths):
            raise ValueError(f"{sd.name}: wavelengths differ from {names[0]}")
    columns = [snake_case(n) for n in names]
    assert len(set(columns)) == 24, columns
    comments = [
        "Source: N. Ohta (1997), The Basis of Color Reproduction Engineering, "
        "measured spectral reflectances of the 24 patches of the X-Rite/Macbeth "
        "ColorChecker Classic (identical to the ISO 17321-1:2012 data, per colour-science), "
        f"{range_text(wavelengths)}; colour-science {version} dataset "
        f"colour.SDS_COLOURCHECKERS['{COLORCHECKER_NAME}'].",
        provenance(f"colour.SDS_COLOURCHECKERS['{COLORCHECKER_NAME}']"),
        "Columns: colour-science patch names lower-cased, each run of other "
        "characters turned into one '_'. Original names, in column order:",
    ]
    comments += [f"  {c} = {n}" for c, n in zip(columns, names)]
    write_table(
        out / "colorchecker.csv",
        comments,
        ["wavelength_nm"] + columns,
        wavelengths,
        np.stack([sd.values for sd in sds], axis=1),
    )

    # --- A measured camera: spectral sensitivities for --sensor ------------
    camera = colour.characterisation.MSDS_CAMERA_SENSITIVITIES[CAMERA_NAME]
    assert list(camera.labels) == ["red", "green", "blue"], camera.labels
    write_table(
        out / "camera_nikon_d5100_npl.csv",
        [
            "Source: M. M. Darrodi, G. Finlayson, T. Goodman, M. Mackiewicz (2015), "
            "Reference data set for camera spectral sensitivity estimation, JOSA A 32(3) "
            "381-391, doi:10.1364/JOSAA.32.000381: Nikon D5100 spectral sensitivities "
            "measured at the UK National Physical Laboratory (NPL), "
            f"{range_text(camera.wavelengths)}; colour-science {version} dataset "
            f"colour.characterisation.MSDS_CAMERA_SENSITIVITIES['{CAMERA_NAME}'].",
            provenance(f"colour.characterisation.MSDS_CAMERA_SENSITIVITIES['{CAMERA_NAME}']"),
            "Columns r, g, b = colour-science's red, green, blue (each normalised to a peak "
            "of 1 by the dataset); the format of --sensor FILE.csv.",
        ],
        ["wavelength_nm", "r", "g", "b"],
        camera.wavelengths,
        camera.values,
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO_ROOT / "spectra")
    args = parser.parse_args(argv)
    generate(args.out)
    print(f"wrote tables to {args.out} (colour-science {colour.__version__})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
