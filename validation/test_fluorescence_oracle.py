"""Quick checks of validation/fluorescence_oracle.py: its closed form, and two renders against it."""
from __future__ import annotations

import numpy as np
import pytest

import fluorescence_oracle as fo


def test_donaldson_matrix_creates_no_energy():
    for name in fo.DYES:
        d = fo.dye(name)
        li = fo.CENTRES
        # Energy re-emitted from light absorbed in each 1 nm bin: a(li) Phi sum_lo e(lo) li/lo [li < lo].
        out = np.array([d.phi * np.sum(d.e * (l / fo.CENTRES) * (fo.CENTRES > l)) for l in li]) * d.a
        assert np.all(out <= d.a + 1e-12), name
        assert np.all(fo.BASE * (1 - d.a) + out <= 1 + 1e-12), name


def test_quantum_yield_zero_leaves_the_reflectance():
    d = fo.dye("fluorescein")
    l = np.array([450.0, 515.0, 600.0])
    E = fo.illuminant("D65")
    glow = fo.radiance(d, E, l)
    dark = fo.radiance(fo.Dye(d.a, d.e, 0.0), E, l)
    np.testing.assert_allclose(dark, fo.BASE * (1 - np.interp(l, fo.CENTRES, d.a)) * E(l))
    assert glow[1] > dark[1] * 1.2  # fluorescein glows at 515 nm under D65


@pytest.mark.parametrize("name,illum", [("fluorescein", "D65"), ("stilbene", "led365")])
def test_render_matches_oracle(pathtracer, name, illum):
    want, got, se, z = fo.compare(pathtracer, name, illum, spp=32, size=16)
    assert np.all(z <= fo.Z), f"{name} under {illum}: oracle {want}, render {got} +- {se}"
