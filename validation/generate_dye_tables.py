"""Writes spectra/fluorescent_dyes.csv and spectra/uv_lamps.csv: analytic band fits of the
named fluorescent dyes and UV-A lamps, tabulated at 1 nm over the transport range 300-830 nm.

These are NOT measured spectra (this project cannot download PhotochemCAD or OMLC files): each
band is a split Gaussian (its own width on each side of the peak) placed at the peak wavelength
and with the full width at half maximum quoted by the sources named in SOURCES below. Excitation
columns are relative absorption (peak 1); emission columns are relative photon spectra per nm
(peak 1); lamp columns are relative spectral radiance (peak 1). Run from the repository root:
    python validation/generate_dye_tables.py
"""
import math
import pathlib

LO, HI = 300, 830

# name: (excitation bands, emission bands, quantum yield); a band is (peak nm, FWHM left of the
# peak nm, FWHM right of the peak nm, relative height).
DYES = {
    "fluorescein": ([(490, 34, 22, 1.0), (470, 30, 30, 0.25), (322, 50, 60, 0.08)],
                    [(514, 22, 52, 1.0)], 0.925),
    "rhodamine6g": ([(530, 30, 20, 1.0), (500, 30, 30, 0.25), (348, 40, 40, 0.10)],
                    [(552, 22, 48, 1.0)], 0.95),
    "quinine": ([(347, 36, 32, 1.0)], [(451, 70, 110, 1.0)], 0.546),
    "stilbene": ([(350, 46, 40, 1.0)], [(435, 40, 70, 1.0)], 0.80),
}
LAMPS = {
    "led365": [(365, 10, 12, 1.0)],
    # Eu2+-doped strontium borate phosphor behind Wood's glass, plus the 404.7 nm mercury line
    # that leaks through the filter (the violet glow of a black-light tube).
    "blacklight": [(368, 18, 18, 1.0), (404.7, 2, 2, 0.05)],
}

SOURCES = {
    "fluorescein": "fluorescein dianion in 0.1 M NaOH: absorption maximum 490 nm with a shoulder near 470 nm "
                   "and a weak near-UV band (Sjoeback, Nygren, Kubista, Spectrochim. Acta A 51, L7-L21, 1995); "
                   "emission maximum 514 nm; quantum yield 0.925 (Magde, Wong, Seybold, Photochem. Photobiol. "
                   "75, 327-334, 2002)",
    "rhodamine6g": "rhodamine 6G in ethanol: absorption maximum 530 nm with a vibronic shoulder near 500 nm, "
                   "emission maximum 552 nm, quantum yield 0.95 (Kubin and Fletcher, J. Luminescence 27, 455-462, "
                   "1982; Magde et al. 2002; the PhotochemCAD entry, Du et al., Photochem. Photobiol. 68, "
                   "141-142, 1998)",
    "quinine": "quinine sulfate in 0.5 M H2SO4: long-wavelength absorption band at 347 nm (the 250 nm band "
               "lies below the transport range and is left out), emission maximum near 451 nm, broad; "
               "quantum yield 0.546 (Melhuish, J. Phys. Chem. 65, 229-235, 1961; Velapoldi and Mielenz, "
               "NBS SRM 936, 1980)",
    "stilbene": "a 4,4'-diaminostilbene-2,2'-disulfonic acid (DAS) optical brightener: absorption maximum "
                "near 350 nm, blue emission maximum near 435 nm (Zollinger, Color Chemistry, 3rd ed., "
                "Wiley-VCH 2003, ch. 15 fluorescent brighteners); quantum yield 0.80 is an assumed "
                "typical value, not a cited one",
    "led365": "365 nm UV-A LED: peak 365 nm, FWHM about 10 nm (typical datasheet values of 365 nm LEDs)",
    "blacklight": "black-light-blue (BLB) fluorescent tube: SrB4O7:Eu2+ phosphor band peaking at 368 nm, "
                  "FWHM about 18 nm (Blasse and Grabmaier, Luminescent Materials, Springer 1994), and the "
                  "404.7 nm mercury line leaking through the Wood's glass at 5 % of the peak (assumed)",
}


def band(lam, peak, fwhm_left, fwhm_right, height):
    fwhm = fwhm_left if lam < peak else fwhm_right
    sigma = fwhm / (2 * math.sqrt(2 * math.log(2)))
    return height * math.exp(-0.5 * ((lam - peak) / sigma) ** 2)


def curve(bands, lam):
    return sum(band(lam, *b) for b in bands)


def column(bands):
    values = [curve(bands, lam) for lam in range(LO, HI + 1)]
    peak = max(values)
    # Values below 1e-6 of the peak are written as 0 (the Gaussians' far tails).
    return [v / peak if v / peak >= 1e-6 else 0.0 for v in values]


def write(path, header, columns):
    names = list(columns)
    lines = [f"# {h}" for h in header]
    lines.append(",".join(["wavelength_nm"] + names))
    for i, lam in enumerate(range(LO, HI + 1)):
        lines.append(",".join([str(lam)] + [f"{columns[n][i]:.6g}" for n in names]))
    pathlib.Path(path).write_text("\n".join(lines) + "\n")


def main():
    root = pathlib.Path(__file__).resolve().parent.parent
    dyes = {}
    header = ["Source: analytic fits, NOT measured spectra: each band is a split Gaussian (a width on each side "
              "of its peak) at the peak wavelength and roughly the full width at half maximum quoted by the "
              "sources below; the bands' shapes are approximations of the published curves, good to a few nm "
              "in peak and some 10 % in width. Produced by validation/generate_dye_tables.py (1 nm, "
              f"{LO}-{HI} nm, the renderer's transport range)."]
    header.append("Columns: NAME_excitation = relative absorption (peak 1); NAME_emission = relative photon "
                  "spectrum per nm (peak 1). Quantum yields (photons out per photon absorbed): " +
                  ", ".join(f"{n} {q}" for n, (_, _, q) in DYES.items()) + ".")
    for name, (exc, emi, _) in DYES.items():
        header.append(f"{name}: {SOURCES[name]}.")
        dyes[f"{name}_excitation"] = column(exc)
        dyes[f"{name}_emission"] = column(emi)
    write(root / "spectra" / "fluorescent_dyes.csv", header, dyes)
    lamps = {name: column(b) for name, b in LAMPS.items()}
    header = ["Source: analytic fits, NOT measured spectra: split Gaussians at the peak wavelengths and widths "
              "below (relative spectral radiance, peak 1). Produced by validation/generate_dye_tables.py (1 nm, "
              f"{LO}-{HI} nm)."]
    header += [f"{name}: {SOURCES[name]}." for name in LAMPS]
    write(root / "spectra" / "uv_lamps.csv", header, lamps)


if __name__ == "__main__":
    main()
