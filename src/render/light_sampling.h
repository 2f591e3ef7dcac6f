// Light sources as the origins of light subpaths (bidirectional path tracing).
//
// What can start a light subpath:
//   - point lights: a delta position, directions uniform over the sphere;
//   - emitting spheres and triangles (quads, meshes): a point uniform over the area, then a
//     side (both sides emit) with probability 1/2 and a cosine-weighted direction on it.
// A light is chosen with probability proportional to its power (mean over 380–780 nm of
// 4π·I for points, 2π·A·Le for two-sided area emitters). For area emitters the choice
// probability over the area is then 2π·Le/P_total: a property of the material alone, so the
// density of a point that a camera path happens to hit needs no shape identifier.
//
// What cannot: emitting infinite planes (the Cornell ceiling) have no finite area to sample,
// and the constant environment is not sampled either in this version. Like pbrt's lights
// that cannot be sampled, they are reached only by camera subpaths that hit them (the s = 0
// strategies); their light-origin density is 0, and the MIS weight of such a path is 1 since
// no other strategy can produce it.
#pragma once
#include <optional>
#include <vector>

#include "scene/scene.h"
#include "spectral/sampled.h"

namespace spt {

/// A sampled light-path origin: the point, the first direction, the emitted quantity and
/// the densities that produced them.
struct LightOrigin {
    Vec3 p, p_err;
    Vec3 n;              ///< surface normal (zero for point lights: no cosine there)
    Vec3 w;              ///< emission direction (unit)
    SampledSpectrum Le;  ///< radiance (area) or intensity (point) along w
    float pdf_pos = 0;   ///< area density of the point, light choice included (1·choice if delta)
    float pdf_dir = 0;   ///< solid-angle density of w
    bool delta_position = false;
};

class LightSampler {
public:
    explicit LightSampler(const Scene& scene);

    bool empty() const { return m_lights.empty(); }

    /// Samples a light ∝ power, a point on it and a direction; nullopt when there is none.
    std::optional<LightOrigin> sample(const SampledWavelengths& lambda, float u_light, float u1,
                                      float u2, float u_side, float u3, float u4) const;

    /// Area density (choice included) with which sample() would produce this emitting hit
    /// point; 0 for emitters that cannot be sampled (infinite planes) and non-emitters.
    float origin_pdf(const Hit& hit) const;

    /// Solid-angle density of emitting towards w from an area emitter of normal n.
    static float direction_pdf(const Vec3& n, const Vec3& w) { return 0.5f * std::fabs(dot(n, w)) * kInvPi; }

private:
    enum class Kind { point, sphere, triangle };
    struct Entry {
        Kind kind;
        int index;  ///< into the scene's point_lights, spheres or triangles
    };
    const Scene& m_scene;
    std::vector<Entry> m_lights;
    std::vector<float> m_cdf;               ///< cumulative choice probabilities
    std::vector<float> m_choice;            ///< choice probability of each light
    std::vector<float> m_material_area_pdf;  ///< 2π·Le/P_total per material (0: not sampled)
    std::vector<int> m_emissive_planes;     ///< indices of emitting planes (never sampled)
};

}  // namespace spt
