#!/usr/bin/env python3
"""Writes spectra/hosek_wilkie_sky.csv and spectra/hosek_wilkie_sun.csv from the spectral
datasets of the Hosek-Wilkie sky model (ArHosekSkyModelData_Spectral.h, version 1.4a, the
data header of the authors' BSD-licensed sample implementation).

Usage: python3 tools/hosek_wilkie_tables.py PATH/TO/ArHosekSkyModelData_Spectral.h [OUT_DIR]

Only the numbers are taken; the arrays are read by name and checked for their sizes:
  datasetNNN[1080]       per channel NNN nm: albedo (0, 1) x turbidity (1..10) x 6 quintic
                         Bezier control points over elevation x 9 parameters (the order of
                         the data: A B C D E F G I H, I the sqrt(cos theta) weight and H the
                         anisotropy of the Mie lobe)
  datasetRadNNN[120]     albedo x turbidity x 6 control points: the radiance scale L_M
  solarDatasetNNN[1800]  turbidity x 45 elevation pieces x 4 polynomial coefficients,
                         highest power first (the 2013 solar radiance function)
  limbDarkeningDatasetNNN[6]  limb darkening polynomial in the cosine on the solar disc
Values are copied as the header spells them (decimal text), so the tables hold exactly the
published numbers.
"""
import os
import re
import sys

CHANNELS = [320 + 40 * i for i in range(11)]
PARAMS = "ABCDEFGIH"

LICENSE = """Copyright (c) 2012 - 2013, Lukas Hosek and Alexander Wilkie
All rights reserved.

Redistribution and use in source and binary forms, with or without
modification, are permitted provided that the following conditions are met:

    * Redistributions of source code must retain the above copyright
      notice, this list of conditions and the following disclaimer.
    * Redistributions in binary form must reproduce the above copyright
      notice, this list of conditions and the following disclaimer in the
      documentation and/or other materials provided with the distribution.
    * None of the names of the contributors may be used to endorse or promote
      products derived from this software without specific prior written
      permission.

THIS SOFTWARE IS PROVIDED BY THE COPYRIGHT HOLDERS AND CONTRIBUTORS "AS IS" AND
ANY EXPRESS OR IMPLIED WARRANTIES, INCLUDING, BUT NOT LIMITED TO, THE IMPLIED
WARRANTIES OF MERCHANTABILITY AND FITNESS FOR A PARTICULAR PURPOSE ARE
DISCLAIMED. IN NO EVENT SHALL THE COPYRIGHT HOLDERS BE LIABLE FOR ANY
DIRECT, INDIRECT, INCIDENTAL, SPECIAL, EXEMPLARY, OR CONSEQUENTIAL DAMAGES
(INCLUDING, BUT NOT LIMITED TO, PROCUREMENT OF SUBSTITUTE GOODS OR SERVICES;
LOSS OF USE, DATA, OR PROFITS; OR BUSINESS INTERRUPTION) HOWEVER CAUSED AND
ON ANY THEORY OF LIABILITY, WHETHER IN CONTRACT, STRICT LIABILITY, OR TORT
(INCLUDING NEGLIGENCE OR OTHERWISE) ARISING IN ANY WAY OUT OF THE USE OF THIS
SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF SUCH DAMAGE."""

CITATION = [
    "L. Hosek and A. Wilkie, An Analytic Model for Full Spectral Sky-Dome Radiance, ACM Trans. Graph. 31(4), 95 (SIGGRAPH 2012), doi:10.1145/2185520.2185591.",
    "L. Hosek and A. Wilkie, Adding a Solar-Radiance Function to the Hosek-Wilkie Skylight Model, IEEE Computer Graphics and Applications 33(3), 44-52 (2013), doi:10.1109/MCG.2013.18.",
]


def arrays(text):
    """name -> list of number strings, for every `double name[] = { ... };` in the text."""
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    out = {}
    for m in re.finditer(r"double\s+(\w+)\s*\[\]\s*=\s*\{([^}]*)\}", text):
        values = [v.strip() for v in m.group(2).split(",") if v.strip()]
        for v in values:
            float(v)  # a number, or the file is not what we expect
        out[m.group(1)] = values
    return out


def need(data, name, size):
    values = data.get(name)
    if values is None or len(values) != size:
        sys.exit(f"{name}: expected {size} numbers, found {0 if values is None else len(values)}")
    return values


def header(source_name, what):
    lines = [
        f"Source: Hosek-Wilkie sky model spectral datasets, {source_name} (version 1.4a, 2013-02-22), {what}.",
        "Written by tools/hosek_wilkie_tables.py (values copied as published); read by src/model/lights/hosek_wilkie.cpp.",
    ]
    lines += CITATION
    lines += ["The datasets are published under the following 3-clause BSD licence:"]
    lines += LICENSE.splitlines()
    return "".join(f"# {l}\n" if l else "#\n" for l in lines)


def write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="\n") as f:
        f.write(text)
    os.replace(tmp, path)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    src = sys.argv[1]
    out_dir = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "..", "spectra")
    with open(src, encoding="latin-1") as f:
        data = arrays(f.read())
    name = os.path.basename(src)

    # Sky: one row per channel; columns a{albedo}_t{turbidity}_k{control point}_{parameter},
    # then the radiance scale a{albedo}_t{turbidity}_k{control point}_L.
    cols = [f"a{a}_t{t}_k{k}_{p}" for a in range(2) for t in range(1, 11) for k in range(6) for p in PARAMS]
    cols += [f"a{a}_t{t}_k{k}_L" for a in range(2) for t in range(1, 11) for k in range(6)]
    text = header(name, "sky dome: 9 parameters (data order A B C D E F G I H) and the radiance scale, each as 6 quintic Bezier control points over (elevation / 90 deg)^(1/3), per ground albedo 0 and 1 and turbidity 1-10, 11 channels 320-720 nm; radiance in W m^-2 sr^-1 nm^-1")
    text += "wavelength_nm," + ",".join(cols) + "\n"
    for c in CHANNELS:
        row = need(data, f"dataset{c}", 1080) + need(data, f"datasetRad{c}", 120)
        text += f"{c}," + ",".join(row) + "\n"
    write(os.path.join(out_dir, "hosek_wilkie_sky.csv"), text)

    # Sun: t{turbidity}_s{piece}_c{power} (the piece's polynomial in elevation minus the
    # piece's start, coefficient of that power), then the limb darkening ld{power}.
    cols = [f"t{t}_s{s}_c{p}" for t in range(1, 11) for s in range(45) for p in (3, 2, 1, 0)]
    cols += [f"ld{p}" for p in range(6)]
    text = header(name, "solar radiance function: per turbidity 1-10, 45 pieces over elevation (piece i starts at (i/45)^3 x 90 deg), cubic in (elevation - start) in radians; limb darkening polynomial of degree 5 in the cosine across the disc; 11 channels 320-720 nm; radiance in W m^-2 sr^-1 nm^-1")
    text += "wavelength_nm," + ",".join(cols) + "\n"
    for c in CHANNELS:
        row = need(data, f"solarDataset{c}", 1800) + need(data, f"limbDarkeningDataset{c}", 6)
        text += f"{c}," + ",".join(row) + "\n"
    write(os.path.join(out_dir, "hosek_wilkie_sun.csv"), text)


if __name__ == "__main__":
    main()
