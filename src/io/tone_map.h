// Tone curves for 8-bit display output: linear RGB after exposure in, display-linear RGB in
// [0, 1] out (the sRGB OETF comes after). Only the PNG writer uses them; EXR, PFM and PPM
// stay scene-linear.
#pragma once
#include <array>
#include <optional>
#include <string>

namespace spt {

/// Both shoulders are the Khronos PBR Neutral tone mapper (KhronosGroup/ToneMapping,
/// PBR_Neutral/README.md, 2024). With F90 its one constant, x = min(R, G, B):
///   f = x − x²/(4 F90) for x ≤ 2 F90, else F90 (an offset taken from every channel);
///   p = max(R, G, B) − f; K_s = 0.8 − F90; below p = K_s the result is c − f;
///   above it the peak is compressed to p_n = 1 − (1 − K_s)²/(p + 1 − 2 K_s) and the colour,
///   scaled by p_n/p, is blended toward grey p_n with weight 1 − g, g = 1/(0.15 (p − p_n) + 1).
/// Hue is kept (all changes lie in the plane of the colour and the grey axis), p_n < 1 for
/// every finite input, and each channel is non-decreasing as the exposure rises.
enum class ToneMap {
    clip,         ///< min(v, 1) per channel: exact below 1, every brighter value is white
    neutral,      ///< PBR Neutral with F90 = 0: the identity below 0.8, a grey reaches
                  ///< 8-bit white at 9.57 (3.26 stops above 1)
    pbr_neutral,  ///< PBR Neutral as specified, F90 = 0.04: a glTF material's base colour
                  ///< comes out exactly (0.04 darker, its specular); a grey reaches white
                  ///< at 13.5; values below 0.08 are pressed toward black (v²/0.16)
};

/// The curve of a PNG unless --tonemap says otherwise; chosen by measuring every built-in
/// scene (README, "Images for people").
inline constexpr ToneMap kDefaultToneMap = ToneMap::neutral;

/// "clip", "neutral" or "pbr-neutral"; nullopt for anything else.
std::optional<ToneMap> tone_map_from_name(const std::string& name);
const char* tone_map_name(ToneMap map);

/// Applies the curve to one pixel. Every curve first replaces NaN and negative components
/// (colours outside the output gamut) by 0, per channel, and never returns a value outside
/// [0, 1].
std::array<double, 3> tone_map(ToneMap map, std::array<double, 3> rgb);

}  // namespace spt
