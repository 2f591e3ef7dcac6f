// Clip and Khronos PBR Neutral tone curves (see tone_map.h for the definitions).
#include "io/tone_map.h"

#include <algorithm>
#include <cfloat>

namespace spt {

std::optional<ToneMap> tone_map_from_name(const std::string& name) {
    if (name == "clip") return ToneMap::clip;
    if (name == "neutral") return ToneMap::neutral;
    if (name == "pbr-neutral") return ToneMap::pbr_neutral;
    return std::nullopt;
}

const char* tone_map_name(ToneMap map) {
    switch (map) {
        case ToneMap::clip: return "clip";
        case ToneMap::neutral: return "neutral";
        case ToneMap::pbr_neutral: return "pbr-neutral";
    }
    return "";
}

namespace {

/// Khronos PBR Neutral. F90 is the normal-incidence reflectance the offset takes away: 0.04
/// (index 1.5) in the specification, so that a glossy glTF dielectric's base colour comes out
/// as authored; 0 for radiance that has no such layer to undo.
std::array<double, 3> pbr_neutral(std::array<double, 3> c, double f90) {
    constexpr double kDesaturation = 0.15;  // K_d
    const double compression_start = 0.8 - f90;  // K_s
    // +inf would give inf/inf below; FLT_MAX already maps to white.
    for (double& v : c) v = v > 0.0 ? std::min(v, double(FLT_MAX)) : 0.0;  // NaN → 0
    const double x = std::min({c[0], c[1], c[2]});
    const double offset = f90 > 0 && x <= 2 * f90 ? x - x * x / (4 * f90) : f90;
    for (double& v : c) v -= offset;
    const double peak = std::max({c[0], c[1], c[2]});
    if (peak <= compression_start) return c;
    const double d = 1.0 - compression_start;
    const double new_peak = 1.0 - d * d / (peak + d - compression_start);
    const double g = 1.0 / (kDesaturation * (peak - new_peak) + 1.0);
    // new_peak < 1, but the blend may round one ulp above it.
    for (double& v : c) v = std::min(v * (new_peak / peak) * g + new_peak * (1.0 - g), 1.0);
    return c;
}

}  // namespace

std::array<double, 3> tone_map(ToneMap map, std::array<double, 3> rgb) {
    switch (map) {
        case ToneMap::neutral: return pbr_neutral(rgb, 0.0);
        case ToneMap::pbr_neutral: return pbr_neutral(rgb, 0.04);
        case ToneMap::clip: break;
    }
    for (double& v : rgb) v = v > 0.0 ? std::min(v, 1.0) : 0.0;  // also maps NaN to 0
    return rgb;
}

}  // namespace spt
