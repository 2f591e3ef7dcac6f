// Each rule: the flag, the condition under which it does nothing, and the reason shown.
#include "cli/flag_warnings.h"

#include <algorithm>

#include "io/image_writer.h"

namespace spt {

std::vector<std::string> ineffective_flag_warnings(const Options& options, const IntegratorSettings& integrator,
                                                   const std::vector<std::string>& outputs, const Scene& scene) {
    auto writes = [&](ImageFormat f) {
        return std::any_of(outputs.begin(), outputs.end(),
                           [&](const std::string& path) { return image_format_from_path(path) == f; });
    };
    const bool linear_output = writes(ImageFormat::Exr) || writes(ImageFormat::Pfm) || writes(ImageFormat::Ppm);
    const std::string kind = integrator_name(integrator.kind);
    const struct {
        const char* flag;
        bool ineffective;
        std::string why;
    } rules[] = {
        {"--merge-radius", integrator.kind != IntegratorKind::vcm, "with the " + kind + " integrator (vcm only)"},
        {"--light-sampling", integrator.kind != IntegratorKind::path, "with the " + kind + " integrator (path only)"},
        {"--light-selection", integrator.kind != IntegratorKind::path, "with the " + kind + " integrator (path only)"},
        {"--guiding", integrator.kind != IntegratorKind::path, "with the " + kind + " integrator (path only)"},
        {"--guiding-field", integrator.kind != IntegratorKind::path || options.guiding != std::optional<bool>(true),
         "without --guiding on and the path integrator"},
        {"--caustic-nee", integrator.kind != IntegratorKind::path || !scene.effects.caustic_spheres,
         "without the path integrator and a smooth glass sphere under an emitting sphere or quad"},
        {"--plane-nee", integrator.kind != IntegratorKind::path ||
                            std::none_of(scene.lights.begin(), scene.lights.end(),
                                         [](const Light& l) { return std::holds_alternative<PlaneLight>(l); }),
         "without the path integrator and an emitting infinite plane"},
        {"--exposure", !writes(ImageFormat::Png), "without a .png output (EXR, PFM and PPM stay linear)"},
        {"--auto-exposure", !writes(ImageFormat::Png), "without a .png output (EXR, PFM and PPM stay linear)"},
        {"--tonemap", !writes(ImageFormat::Png), "without a .png output (EXR, PFM and PPM stay linear)"},
        {"--color-resolution", !writes(ImageFormat::Ppm), "without a .ppm output"},
        {"--color-space", !linear_output, "with only .png outputs (a PNG is always sRGB)"},
        {"--checkpoint-interval", options.checkpoint.empty(), "without --checkpoint"},
        {"--no-dispersion", !scene.effects.dispersion, "in a scene without dispersive glass"},
        {"--no-bvh", !scene.uses_bvh(), "in a scene this small (it tests its few shapes in a loop already)"},
    };
    std::vector<std::string> warnings;
    for (const auto& r : rules)
        if (r.ineffective && options.given.count(r.flag)) warnings.push_back(std::string(r.flag) + " has no effect " + r.why);
    return warnings;
}

}  // namespace spt
