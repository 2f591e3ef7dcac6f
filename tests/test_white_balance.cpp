// White balance (src/spectral/chromatic_adaptation.h): the Bradford matrices by their defining
// properties, the illuminant whites against the CIE spectra compiled into the program, and the
// temperature loci. validation/test_white_balance.py compares the matrices with colour-science.
#include <gtest/gtest.h>

#include <cmath>

#include "spectral/chromatic_adaptation.h"
#include "spectral/cie.h"
#include "spectral/spectral_table.h"

namespace spt {
namespace {

Xyz xyz_of(const Chromaticity& xy) { return {xy[0] / xy[1], 1.0, (1 - xy[0] - xy[1]) / xy[1]}; }

void expect_near(const Matrix3& a, const Matrix3& b, double tolerance) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(a[i][j], b[i][j], tolerance) << i << "," << j;
}

const Matrix3 kIdentity = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

TEST(WhiteBalance, BradfordTakesTheSourceWhiteToTheTargetWhite) {
    const Chromaticity a = *illuminant_xy("A"), d65 = *illuminant_xy("D65");
    const Matrix3 m = bradford_adaptation(a, d65);
    const std::array<double, 3> w = spt::apply(m, xyz_of(a));
    const Xyz t = xyz_of(d65);
    EXPECT_NEAR(w[0], t.x, 1e-14);
    EXPECT_NEAR(w[1], t.y, 1e-14);
    EXPECT_NEAR(w[2], t.z, 1e-14);
    // Undone by the reverse adaptation; nothing to do between equal whites.
    expect_near(bradford_adaptation(d65, a) * m, kIdentity, 1e-14);
    expect_near(bradford_adaptation(d65, d65), kIdentity, 1e-15);
}

TEST(WhiteBalance, BradfordIsDiagonalInItsConeSpace) {
    // M·A·M⁻¹ must be diagonal with the cone-response ratios of the two whites: a matrix that
    // only maps white to white (e.g. a scaling in XYZ) fails this.
    const Chromaticity f11 = *illuminant_xy("F11"), d50 = *illuminant_xy("D50");
    const Matrix3 cone = kBradford * bradford_adaptation(f11, d50) * invert(kBradford);
    const std::array<double, 3> s = spt::apply(kBradford, xyz_of(f11));
    const std::array<double, 3> t = spt::apply(kBradford, xyz_of(d50));
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(cone[i][j], i == j ? t[i] / s[i] : 0.0, 1e-14);
}

TEST(WhiteBalance, BalancedSpaceDevelopsTheSourceWhiteToGrey) {
    for (const char* name : {"acescg", "rec2020", "srgb"}) {
        const ColorSpace space = white_balanced(*color_space_by_name(name), *illuminant_xy("A"));
        const std::array<double, 3> rgb = spt::apply(space.from_xyz, xyz_of(*illuminant_xy("A")));
        for (double v : rgb) EXPECT_NEAR(v, 1.0, 1e-13) << name;
    }
}

/// xy of a spectra/ table under the CIE 1931 2° observer: the table interpolated linearly
/// at each 1 nm CMF entry where it is defined (the tables end at 780 nm).
Chromaticity table_xy(const std::string& file) {
    const SpectralTable& spd = embedded_spectral_table(file);
    const SpectralTable& cmf = embedded_spectral_table("cie_1931_2deg.csv");
    const auto& l = spd.wavelengths_nm;
    const auto& v = spd.column("value");
    double x = 0, y = 0, z = 0;
    for (std::size_t i = 0; i < cmf.wavelengths_nm.size(); ++i) {
        const double lambda = cmf.wavelengths_nm[i];
        if (lambda < l.front() || lambda > l.back()) continue;
        const std::size_t k = std::min<std::size_t>(
            std::upper_bound(l.begin(), l.end(), lambda) - l.begin() - 1, l.size() - 2);
        const double t = (lambda - l[k]) / (l[k + 1] - l[k]);
        const double s = (1 - t) * v[k] + t * v[k + 1];
        x += s * cmf.column("x_bar")[i], y += s * cmf.column("y_bar")[i],
            z += s * cmf.column("z_bar")[i];
    }
    return {x / (x + y + z), y / (x + y + z)};
}

TEST(WhiteBalance, NamedWhitesAreTheCieSpectraCompiledIn) {
    // The published xy (4-5 decimals) against the xy of the tables: A and D65 not swapped or
    // mistyped beyond the published rounding.
    for (const auto& [name, file] :
         {std::pair{"A", "cie_a.csv"}, std::pair{"D65", "cie_d65.csv"}}) {
        const Chromaticity named = *illuminant_xy(name), computed = table_xy(file);
        EXPECT_NEAR(named[0], computed[0], 1e-4) << name;
        EXPECT_NEAR(named[1], computed[1], 1e-4) << name;
    }
    EXPECT_EQ(illuminant_xy("d65"), illuminant_xy("D65"));
    EXPECT_EQ(illuminant_xy("FL11"), illuminant_xy("F11"));
    EXPECT_EQ(illuminant_xy("D66"), std::nullopt);
}

TEST(WhiteBalance, TemperatureLoci) {
    // A is the Planckian radiator at 2856 K (with the CIE's c2 = 1.4388e-2 m·K), D65 and D50
    // are near CIE daylight at 6504 K and 5003 K
    // (their xy come from their tabulated spectra, which lie within 2e-4 of the locus formula).
    // Tolerances: the published 4-5 decimals and the 360-830 nm 1 nm sums; a wrong constant
    // or branch moves xy by 1e-3 or more.
    const Chromaticity planck_a = planckian_xy(2856);
    EXPECT_NEAR(planck_a[0], 0.44758, 5e-5);
    EXPECT_NEAR(planck_a[1], 0.40745, 5e-5);
    const Chromaticity d65 = daylight_xy(6504), d50 = daylight_xy(5003);
    EXPECT_NEAR(d65[0], 0.3127, 2e-4);
    EXPECT_NEAR(d65[1], 0.3290, 2e-4);
    EXPECT_NEAR(d50[0], 0.3457, 2e-4);
    EXPECT_NEAR(d50[1], 0.3585, 2e-4);
    // Both branches of the daylight formula meet at 7000 K; cct_xy switches locus at 4000 K.
    const Chromaticity below = daylight_xy(7000), above = daylight_xy(7000 + 1e-9);
    EXPECT_NEAR(below[0], above[0], 1e-5);
    EXPECT_EQ(cct_xy(3999.9), planckian_xy(3999.9));
    EXPECT_EQ(cct_xy(4000), daylight_xy(4000));
}

TEST(WhiteBalance, ParsesNamesAndTemperatures) {
    EXPECT_EQ(parse_white("A"), illuminant_xy("A"));
    EXPECT_EQ(parse_white("3200K"), planckian_xy(3200));
    EXPECT_EQ(parse_white("6500"), daylight_xy(6500));
    EXPECT_EQ(parse_white("1000k"), planckian_xy(1000));
    EXPECT_EQ(parse_white("25000K"), daylight_xy(25000));
    for (const char* bad : {"", "K", "999K", "25001", "3200KK", "-5000", "nan", "D66", "6500 K"})
        EXPECT_EQ(parse_white(bad), std::nullopt) << bad;
}

}  // namespace
}  // namespace spt
