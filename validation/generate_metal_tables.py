#!/usr/bin/env python3
"""Regenerate spectra/metal_*.csv (complex index eta + i k of gold, silver, copper and
aluminium) from a checkout of the refractiveindex.info database (CC0).

Usage (from the repository root)::

    python validation/generate_metal_tables.py --database PATH/refractiveindex.info-database

The renderer reads these files at build time (embedded, like every table in spectra/); this
script is how they were made and is not part of the build. Each file keeps the source's own
rows unchanged (no interpolation), converted from micrometres to nanometres, from the last row
at or below 350 nm to the first at or above 850 nm, so the range the renderer samples
(360-830 nm) is covered by measured points.
"""

from __future__ import annotations

import argparse
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent

JOHNSON = ("P. B. Johnson and R. W. Christy, Optical constants of the noble metals, "
           "Phys. Rev. B 6, 4370-4379 (1972), room temperature")
RAKIC = ("A. D. Rakic, Algorithm for the determination of intrinsic optical constants of metal "
         "films: application to aluminum, Appl. Opt. 34, 4755-4767 (1995)")

METALS = {
    # symbol: (file in the database, source text)
    "au": ("database/data/main/Au/nk/Johnson.yml", JOHNSON),
    "ag": ("database/data/main/Ag/nk/Johnson.yml", JOHNSON),
    "cu": ("database/data/main/Cu/nk/Johnson.yml", JOHNSON),
    "al": ("database/data/main/Al/nk/Rakic.yml", RAKIC),
}

LOW_NM, HIGH_NM = 350.0, 850.0


def read_nk(path: Path) -> list[tuple[str, str, str]]:
    """Rows (wavelength_um, n, k) of the first 'tabulated nk' block, as written in the file."""
    rows, inside = [], False
    for line in path.read_text().splitlines():
        if "type: tabulated nk" in line:
            inside = True
            continue
        if not inside or "data:" in line:
            continue
        parts = line.split()
        if len(parts) != 3:
            if rows:
                break
            continue
        rows.append((parts[0], parts[1], parts[2]))
    if not rows:
        raise ValueError(f"{path}: no 'tabulated nk' rows")
    return rows


def micrometres_to_nm(text: str) -> str:
    """Exact decimal shift by three places (no float rounding)."""
    from decimal import Decimal
    return format((Decimal(text) * 1000).normalize(), "f")


def select(rows):
    nm = [float(micrometres_to_nm(r[0])) for r in rows]
    first = max(i for i, x in enumerate(nm) if x <= LOW_NM)
    last = min(i for i, x in enumerate(nm) if x >= HIGH_NM)
    return rows[first:last + 1]


def write_table(symbol: str, database: Path, out_dir: Path) -> Path:
    rel, source = METALS[symbol]
    rows = select(read_nk(database / rel))
    lo, hi = micrometres_to_nm(rows[0][0]), micrometres_to_nm(rows[-1][0])
    lines = [
        f"# Source: {source}; transcribed from the refractiveindex.info database "
        f"(github.com/polyanskiy/refractiveindex.info-database, CC0), file {rel}; {lo}-{hi} nm ({len(rows)} rows).",
        "# Produced by validation/generate_metal_tables.py: the source's rows unchanged, wavelengths converted "
        "from um to nm; eta + i k is the complex index of refraction relative to vacuum.",
        "wavelength_nm,eta,k",
    ]
    lines += [f"{micrometres_to_nm(w)},{n},{k}" for w, n, k in rows]
    path = out_dir / f"metal_{symbol}.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--database", type=Path, required=True, help="refractiveindex.info-database checkout")
    ap.add_argument("--out", type=Path, default=REPO_ROOT / "spectra")
    args = ap.parse_args()
    for symbol in METALS:
        print(write_table(symbol, args.database, args.out))


if __name__ == "__main__":
    main()
