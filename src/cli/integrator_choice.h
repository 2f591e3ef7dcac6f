// Which integrator renders, with which settings, and why: the command line overrides the
// scene file's "integrator" field by field, and the defaults fill the rest.
#pragma once
#include <string>

#include "cli/options.h"
#include "render/integrator.h"
#include "scene/scene.h"

namespace spt {

struct IntegratorChoice {
    IntegratorSettings settings;
    /// Why settings.kind is what it is, for the summary: "chosen by --integrator",
    /// "the scene's choice" or "the default".
    std::string reason;
};

/// Throws UsageError when the chosen integrator cannot render the scene: bdpt and vcm
/// refuse participating media, spot lights and textures (only the path integrator has them),
/// vcm refuses motion blur, rather than render a silently wrong image.
IntegratorChoice choose_integrator(const Options& options, const Scene& scene);

/// One line for the summary when the chosen integrator cannot sample light paths the scene's
/// effects call for, naming the integrator that can ("" when none is missed): the path
/// tracer's next-event estimation cannot connect to a point or spot light through a specular
/// or refracting surface, and a path never hits such a light, so their caustics are black.
std::string missed_light_paths(const IntegratorSettings& settings, const Scene& scene);

}  // namespace spt
