// Colour-space matrices derived from chromaticities (SMPTE RP 177 procedure).
#include "spectral/color_space.h"

namespace spt {

Matrix3 invert(const Matrix3& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    Matrix3 r;
    r[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
    r[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
    r[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
    r[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
    r[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
    r[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
    r[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
    r[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
    r[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
    return r;
}

Matrix3 operator*(const Matrix3& a, const Matrix3& b) {
    Matrix3 r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
    return r;
}

namespace {

std::array<double, 3> xy_to_xyz(std::array<double, 2> xy) {
    return {xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]};
}

}  // namespace

ColorSpace make_color_space(std::string name, std::array<double, 2> red, std::array<double, 2> green,
                            std::array<double, 2> blue, std::array<double, 2> white) {
    const auto r = xy_to_xyz(red), g = xy_to_xyz(green), b = xy_to_xyz(blue), w = xy_to_xyz(white);
    const Matrix3 primaries = {{{r[0], g[0], b[0]}, {r[1], g[1], b[1]}, {r[2], g[2], b[2]}}};
    const Matrix3 inv = invert(primaries);
    // Scale each primary so that RGB (1,1,1) lands on the white point.
    std::array<double, 3> s{};
    for (int i = 0; i < 3; ++i) s[i] = inv[i][0] * w[0] + inv[i][1] * w[1] + inv[i][2] * w[2];
    Matrix3 to_xyz;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) to_xyz[row][col] = primaries[row][col] * s[col];
    return {std::move(name), red, green, blue, white, invert(to_xyz), to_xyz};
}

const ColorSpace& srgb_color_space() {
    static const ColorSpace cs =
        make_color_space("srgb", {0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}, {0.3127, 0.3290});
    return cs;
}

std::optional<ColorSpace> color_space_by_name(const std::string& name) {
    if (name == "srgb") return srgb_color_space();
    if (name == "rec2020")
        return make_color_space("rec2020", {0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046},
                                {0.3127, 0.3290});
    if (name == "acescg")  // ACES AP1 primaries, ACES white (≈ D60)
        return make_color_space("acescg", {0.713, 0.293}, {0.165, 0.830}, {0.128, 0.044},
                                {0.32168, 0.33767});
    if (name == "xyz") {
        ColorSpace cs{"xyz", {1, 0}, {0, 1}, {0, 0}, {1.0 / 3, 1.0 / 3}, {}, {}};
        cs.from_xyz = cs.to_xyz = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
        return cs;
    }
    return std::nullopt;
}

}  // namespace spt
