// Flags that were given but change nothing with the chosen settings (a --merge-radius for
// the path tracer, an --exposure without a PNG): the user probably expected an effect.
#pragma once
#include <string>
#include <vector>

#include "cli/options.h"
#include "render/integrator.h"
#include "scene/scene.h"

namespace spt {

/// One line per ineffective flag, naming it and why ("--merge-radius has no effect with the
/// path integrator (vcm only)"). `outputs` are the files that will be written.
std::vector<std::string> ineffective_flag_warnings(const Options& options, const IntegratorSettings& integrator,
                                                   const std::vector<std::string>& outputs, const Scene& scene);

}  // namespace spt
