// Output colour spaces: XYZ to linear RGB matrices, applied only when an image is written.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "spectral/cie.h"

namespace spt {

using Matrix3 = std::array<std::array<double, 3>, 3>;

Matrix3 invert(const Matrix3& m);
Matrix3 operator*(const Matrix3& a, const Matrix3& b);

struct ColorSpace {
    std::string name;
    std::array<double, 2> red, green, blue, white;  ///< CIE 1931 xy chromaticities
    Matrix3 from_xyz;                               ///< XYZ → linear RGB
    Matrix3 to_xyz;                                 ///< linear RGB → XYZ
};

/// Builds the matrices from primaries and white point (RGB (1,1,1) maps to the white, Y = 1).
ColorSpace make_color_space(std::string name, std::array<double, 2> red, std::array<double, 2> green,
                            std::array<double, 2> blue, std::array<double, 2> white);

/// Linear sRGB / Rec.709 primaries with the D65 white (IEC 61966-2-1).
const ColorSpace& srgb_color_space();
/// Named colour space: "srgb", "rec2020", "acescg", "xyz"; nullopt if unknown.
std::optional<ColorSpace> color_space_by_name(const std::string& name);

inline std::array<double, 3> apply(const Matrix3& m, const Xyz& c) {
    return {m[0][0] * c.x + m[0][1] * c.y + m[0][2] * c.z,
            m[1][0] * c.x + m[1][1] * c.y + m[1][2] * c.z,
            m[2][0] * c.x + m[2][1] * c.y + m[2][2] * c.z};
}

}  // namespace spt
