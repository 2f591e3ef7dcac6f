// The names of the integrators and of the path tracer's light-sampling modes: what the command
// line and scene files choose from. No dependencies, so a scene can name its integrator.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/text.h"

namespace spt {

/// Which estimator renders the image: unidirectional path tracing (the default),
/// bidirectional path tracing (bdpt.h), or bidirectional path tracing with vertex merging
/// (vcm: bdpt.h, vertex_merging.h).
enum class IntegratorKind { path, bdpt, vcm };

/// How the path tracer finds lights other than point lights: next-event estimation and BSDF
/// sampling combined by MIS (the default), BSDF sampling alone (emission counted only where
/// paths hit it: the estimator before light sampling), or light sampling alone (emission that
/// BSDF sampling finds after a non-delta bounce is not counted). All three are unbiased; the
/// last two exist to measure what MIS buys and to test it.
enum class LightSampling { mis, bsdf, light };

/// How next-event estimation chooses one light (path, volumetric path, wavefront): by power
/// alone, or by its likely contribution to the shading point (the light BVH,
/// render/light_bvh.h). A scene with one light to choose from samples it either way.
enum class LightSelection { power, bvh };

/// Path guiding (render/guiding/): off, or a learned field of luminance or of radiance per
/// wavelength band.
enum class GuidingMode { off, luminance, spectral };

/// The command-line name of an integrator.
constexpr const char* integrator_name(IntegratorKind kind) {
    switch (kind) {
        case IntegratorKind::bdpt: return "bdpt";
        case IntegratorKind::vcm: return "vcm";
        case IntegratorKind::path: break;
    }
    return "path";
}
/// The name of a light-sampling mode.
constexpr const char* light_sampling_name(LightSampling mode) {
    switch (mode) {
        case LightSampling::bsdf: return "bsdf";
        case LightSampling::light: return "light";
        case LightSampling::mis: break;
    }
    return "mis";
}

/// The name of a light-selection mode.
constexpr const char* light_selection_name(LightSelection mode) {
    return mode == LightSelection::bvh ? "bvh" : "power";
}

/// The name of a guiding mode (as checkpoints record it).
constexpr const char* guiding_mode_name(GuidingMode mode) {
    switch (mode) {
        case GuidingMode::luminance: return "luminance";
        case GuidingMode::spectral: return "spectral";
        case GuidingMode::off: break;
    }
    return "off";
}

inline constexpr IntegratorKind kIntegratorKinds[] = {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm};
inline constexpr LightSampling kLightSamplingModes[] = {LightSampling::mis, LightSampling::bsdf, LightSampling::light};
inline constexpr LightSelection kLightSelectionModes[] = {LightSelection::power, LightSelection::bvh};
inline constexpr GuidingMode kGuidingModes[] = {GuidingMode::off, GuidingMode::luminance, GuidingMode::spectral};

/// The value whose name is `name` (ignoring case), or nullopt. Use: name_lookup(kIntegratorKinds,
/// integrator_name, text).
template <typename T, std::size_t N>
std::optional<T> name_lookup(const T (&values)[N], const char* (*name_of)(T), std::string_view name) {
    for (T v : values)
        if (equal_ignoring_case(name, name_of(v))) return v;
    return std::nullopt;
}
/// Every value's name, in order (for messages and "did you mean").
template <typename T, std::size_t N>
std::vector<std::string> names_of(const T (&values)[N], const char* (*name_of)(T)) {
    std::vector<std::string> names;
    for (T v : values) names.emplace_back(name_of(v));
    return names;
}

inline std::optional<IntegratorKind> integrator_from_name(std::string_view name) {
    return name_lookup(kIntegratorKinds, integrator_name, name);
}
inline std::optional<LightSampling> light_sampling_from_name(std::string_view name) {
    return name_lookup(kLightSamplingModes, light_sampling_name, name);
}
inline std::optional<LightSelection> light_selection_from_name(std::string_view name) {
    return name_lookup(kLightSelectionModes, light_selection_name, name);
}
inline std::vector<std::string> light_selection_names() { return names_of(kLightSelectionModes, light_selection_name); }
inline std::vector<std::string> integrator_names() { return names_of(kIntegratorKinds, integrator_name); }
inline std::vector<std::string> light_sampling_names() { return names_of(kLightSamplingModes, light_sampling_name); }

}  // namespace spt
