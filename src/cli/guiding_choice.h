// Whether a render is guided (render/guiding/), and why, for the summary: --guiding on or off
// decides. auto (the default) is off: at equal time guiding has not yet beaten the unguided
// path tracer on any scene measured (docs/GUIDING.md, bench/guiding_benchmark.py), its
// training and tree lookups cost more than its better directions save. auto becomes a rule
// here once a measurement shows where it pays.
#pragma once
#include <string>

#include "cli/options.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace spt {

struct GuidingChoice {
    GuidingMode mode = GuidingMode::off;
    std::string reason;  ///< for the summary: "--guiding on", "auto: it has not yet paid ..."
};

/// Throws UsageError for --guiding on where the path integrator cannot be guided (another
/// integrator ignores the flag, with a warning). With guiding on, the
/// specular chains (caustic_nee) are turned off in `settings`: their MIS weights assume
/// BSDF sampling.
GuidingChoice choose_guiding(const Options& options, const Scene& scene, RenderSettings& settings);

}  // namespace spt
