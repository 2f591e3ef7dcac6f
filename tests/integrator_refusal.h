// What choose_integrator says of an integrator for a scene: its usage error, or "(no error)".
#pragma once
#include <string>

#include "cli/integrator_choice.h"

namespace spt::test {

inline std::string integrator_refusal(IntegratorKind kind, const Scene& scene) {
    Options o;
    o.integrator = kind;
    try {
        choose_integrator(o, scene);
    } catch (const UsageError& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace spt::test
