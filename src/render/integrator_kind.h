// The names of the integrators and of the path tracer's light-sampling modes: what the command
// line and scene files choose from. No dependencies, so a scene can name its integrator.
#pragma once
#include <optional>
#include <string_view>

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

/// The command-line name of an integrator, and back (case-insensitive; nullopt for an unknown
/// name).
constexpr const char* integrator_name(IntegratorKind kind) {
    switch (kind) {
        case IntegratorKind::bdpt: return "bdpt";
        case IntegratorKind::vcm: return "vcm";
        case IntegratorKind::path: break;
    }
    return "path";
}
inline std::optional<IntegratorKind> integrator_from_name(std::string_view name) {
    for (IntegratorKind k : {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm})
        if (equal_ignoring_case(name, integrator_name(k))) return k;
    return std::nullopt;
}

/// The name of a light-sampling mode, and back (case-insensitive; nullopt for an unknown name).
constexpr const char* light_sampling_name(LightSampling mode) {
    switch (mode) {
        case LightSampling::bsdf: return "bsdf";
        case LightSampling::light: return "light";
        case LightSampling::mis: break;
    }
    return "mis";
}
inline std::optional<LightSampling> light_sampling_from_name(std::string_view name) {
    for (LightSampling m : {LightSampling::mis, LightSampling::bsdf, LightSampling::light})
        if (equal_ignoring_case(name, light_sampling_name(m))) return m;
    return std::nullopt;
}

}  // namespace spt
