#include "cli/guiding_choice.h"

namespace spt {

GuidingChoice choose_guiding(const Options& options, const Scene& scene, RenderSettings& settings) {
    GuidingChoice c;
    if (!options.guiding) {
        c.reason = "auto: it has not yet paid at equal time in a measured scene; docs/GUIDING.md";
        return c;
    }
    if (!*options.guiding) {
        c.reason = "--guiding off";
        return c;
    }
    // Other integrators: the flag is warned about as having no effect (cli/flag_warnings.h).
    if (settings.integrator.kind != IntegratorKind::path) return c;
    if (const char* needs = guiding_unsupported(scene, settings))
        throw UsageError(std::string("--guiding on: scene '") + scene.name +
                         "' with these settings; expected " + needs);
    const bool chains = scene.effects.caustic_spheres && settings.integrator.caustic_nee &&
                        settings.integrator.light_sampling == LightSampling::mis;
    c.mode = options.guiding_field;
    c.reason = chains ? "--guiding on; the specular chains are off with it" : "--guiding on";
    if (chains) settings.integrator.caustic_nee = false;
    return c;
}

}  // namespace spt
