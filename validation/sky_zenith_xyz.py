#!/usr/bin/env python3
"""The zenith chromaticity of the Hosek-Wilkie sky from the model's own CIE XYZ dataset
(ArHosekSkyModelData_CIEXYZ.h of the authors' BSD-licensed sample implementation, fitted to
the same reference simulations as the spectral dataset, but in XYZ), for the values
tests/test_sky.cpp compares the renderer's spectral sky against.

Usage: python3 validation/sky_zenith_xyz.py PATH/TO/ArHosekSkyModelData_CIEXYZ.h [PATH/TO/ArHosekSkyModelData_Spectral.h]

An implementation of its own (numpy, nothing of src/): the same formula as the renderer's
(Hosek & Wilkie 2012, eq. 9 and 10) at the zenith, with the XYZ dataset's coefficients.
Prints x, y of the zenith for each (sun elevation, turbidity, ground albedo); with the
spectral dataset too, also the chromaticity of its spectrum (linear between the 11 channels,
held beyond 720 nm, as the renderer) under the CIE 1931 observer of spectra/cie_1931_2deg.csv,
and the distance between the two.
"""
import importlib.util
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
_spec = importlib.util.spec_from_file_location(
    "hosek_wilkie_tables", os.path.join(HERE, "..", "tools", "hosek_wilkie_tables.py"))
hwt = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(hwt)

CASES = [(el, t, a) for el in (5, 15, 30, 45, 60, 85) for t in (2, 3, 6) for a in (0.1,)]


def bezier5(p, x):
    b = [1, 5, 10, 10, 5, 1]
    return sum(b[k] * (1 - x) ** (5 - k) * x ** k * p[k] for k in range(6))


def cooked(coeffs, rad, elevation_deg, turbidity, albedo):
    """The 9 parameters and L_M at one elevation (turbidity integer-blended, albedo blended)."""
    x = (elevation_deg / 90.0) ** (1 / 3)
    t0 = min(int(turbidity), 9) - 1
    wt = turbidity - (t0 + 1)
    params = np.zeros(9)
    lm = 0.0
    for a, wa in ((0, 1 - albedo), (1, albedo)):
        for t, w in ((t0, 1 - wt), (min(t0 + 1, 9), wt)):
            if wa * w == 0:
                continue
            for q in range(9):
                p = [coeffs[((a * 10 + t) * 6 + k) * 9 + q] for k in range(6)]
                params[q] += wa * w * bezier5(p, x)
            lm += wa * w * bezier5([rad[(a * 10 + t) * 6 + k] for k in range(6)], x)
    return params, lm


def zenith(params, lm, elevation_deg):
    A, B, C, D, E, F, G, I, H = params  # data order
    gamma = np.radians(90.0 - elevation_deg)
    cg = np.cos(gamma)
    chi = (1 + cg * cg) / (1 + H * H - 2 * H * cg) ** 1.5
    return (1 + A * np.exp(B / (1 + 0.01))) * (C + D * np.exp(E * gamma) + F * cg * cg + G * chi + I) * lm


def spectral_xy(spectral, el, t, a):
    with open(os.path.join(HERE, "..", "spectra", "cie_1931_2deg.csv")) as f:
        rows = [l for l in f if not l.startswith("#")][1:]  # after the header
    cmf = np.array([[float(v) for v in l.split(",")] for l in rows])
    values = []
    for c in hwt.CHANNELS:
        params, lm = cooked([float(v) for v in hwt.need(spectral, f"dataset{c}", 1080)],
                            [float(v) for v in hwt.need(spectral, f"datasetRad{c}", 120)], el, t, a)
        values.append(max(zenith(params, lm, el), 0.0))
    lam = cmf[:, 0]
    L = np.interp(lam, hwt.CHANNELS, values)  # holds beyond the ends
    X, Y, Z = (np.sum(L * cmf[:, i]) for i in (1, 2, 3))
    return X / (X + Y + Z), Y / (X + Y + Z)


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    with open(sys.argv[1], encoding="latin-1") as f:
        data = hwt.arrays(f.read())
    spectral = None
    if len(sys.argv) == 3:
        with open(sys.argv[2], encoding="latin-1") as f:
            spectral = hwt.arrays(f.read())
    print("# elevation_deg turbidity albedo x y  (zenith, Hosek-Wilkie CIE XYZ dataset)"
          + ("  x y (spectral dataset, CIE 1931)  distance" if spectral else ""))
    for el, t, a in CASES:
        xyz = []
        for ch in (1, 2, 3):
            params, lm = cooked([float(v) for v in hwt.need(data, f"datasetXYZ{ch}", 1080)],
                                [float(v) for v in hwt.need(data, f"datasetXYZRad{ch}", 120)], el, t, a)
            xyz.append(zenith(params, lm, el))
        s = sum(xyz)
        line = f"{el} {t} {a} {xyz[0] / s:.4f} {xyz[1] / s:.4f}"
        if spectral:
            sx, sy = spectral_xy(spectral, el, t, a)
            line += f"  {sx:.4f} {sy:.4f}  {np.hypot(sx - xyz[0] / s, sy - xyz[1] / s):.4f}"
        print(line)


if __name__ == "__main__":
    main()
