// Command line first, then the scene file, then the defaults of IntegratorSettings.
#include "cli/integrator_choice.h"

#include <algorithm>

namespace spt {

IntegratorChoice choose_integrator(const Options& options, const Scene& scene) {
    const IntegratorPreset& preset = scene.integrator;
    IntegratorChoice c;
    IntegratorSettings& s = c.settings;
    s.kind = options.integrator.value_or(preset.kind.value_or(s.kind));
    c.reason = options.integrator ? "chosen by --integrator"
               : preset.kind      ? "the scene's choice; --integrator overrides it"
                                  : "the default";
    s.max_depth = options.max_depth.value_or(preset.max_depth.value_or(s.max_depth));
    // The scene's mode and radius belong to the integrator it names: a different integrator
    // from the command line starts from the defaults.
    const bool scene_integrator = preset.kind && *preset.kind == s.kind;
    s.light_sampling = options.light_sampling.value_or(
        scene_integrator ? preset.light_sampling.value_or(s.light_sampling) : s.light_sampling);
    s.merge_radius = static_cast<float>(options.merge_radius.value_or(
        scene_integrator ? preset.merge_radius.value_or(s.merge_radius) : s.merge_radius));
    s.wavelengths_per_path = options.wavelengths_per_path;
    s.caustic_nee = options.caustic_nee;
    s.sample_planes = options.plane_nee;
    s.light_selection = options.light_selection;
    // Effects an integrator cannot render: a usage error, never a wrong image.
    const char* feature = nullptr;
    const char* instead = "--integrator path";
    // bdpt renders homogeneous media (bdpt_media.h); grid and height fog would need delta
    // tracking's distance densities for its MIS weights, which have no closed form. vcm has
    // no volume merging.
    const bool heterogeneous = std::any_of(scene.media.begin(), scene.media.end(),
                                           [](const Medium& m) { return !m.is_uniform(); });
    if (s.kind == IntegratorKind::bdpt && heterogeneous) {
        feature = "heterogeneous media (grid, height fog)";
    } else if (s.kind == IntegratorKind::vcm && scene.effects.media) {
        feature = "participating media";
        instead = heterogeneous ? "--integrator path" : "--integrator bdpt or path";
    }
    // Re-emission at another wavelength is sampled backwards from the camera only
    // (model/fluorescence.h); light subpaths would need the forward densities, and the
    // volumetric path tracer has no fluorescent vertex.
    if (!feature && scene.effects.fluorescence && (s.kind != IntegratorKind::path || scene.effects.media)) {
        feature = s.kind == IntegratorKind::path ? "fluorescence together with participating media"
                                                 : "fluorescence (it cannot render re-emission at another wavelength)";
        instead = s.kind == IntegratorKind::path ? "a scene without one of them" : "--integrator path";
    }
    if (!feature && s.kind == IntegratorKind::vcm && scene.effects.motion_blur) {
        // Its merges join light subpaths of a whole pass, each at its own shutter time.
        feature = "motion blur";
        instead = "--integrator bdpt or path";
    }
    if (feature)
        throw UsageError(std::string("the ") + integrator_name(s.kind) + " integrator (" + c.reason +
                         ") does not support " + feature + ", which scene '" + scene.name + "' has; expected " +
                         instead);
    return c;
}

std::string missed_light_paths(const IntegratorSettings& settings, const Scene& scene) {
    const Effects& e = scene.effects;
    if (settings.kind != IntegratorKind::path || !e.point_lights || !(e.mirror || e.transmission)) return "";
    // The bidirectional integrators trace paths from the lights; vcm merges the caustic ones
    // best, but has no media or motion blur, and bdpt no heterogeneous media.
    const bool heterogeneous = std::any_of(scene.media.begin(), scene.media.end(),
                                           [](const Medium& m) { return !m.is_uniform(); });
    if (heterogeneous) return "";
    const char* instead = e.media || e.motion_blur ? "--integrator bdpt" : "--integrator vcm (or bdpt)";
    return std::string("the path integrator renders no light from point or spot lights through "
                       "mirrors or glass (caustics); ") + instead + " renders it";
}

}  // namespace spt
