// A renderable scene: camera, shapes in one flat array per type of the set (geometry/shape.h),
// materials by index, lights.
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/axis_planes.h"
#include "geometry/bvh.h"
#include "geometry/moving_shape.h"
#include "geometry/instanced_mesh.h"
#include "geometry/shape.h"
#include "geometry/sphere_lanes.h"
#include "model/camera.h"
#include "model/lights/light.h"
#include "model/lights/light_distribution.h"
#include "model/media/medium.h"
#include "model/material.h"
#include "model/textures/texture.h"
#include "render/integrator_kind.h"
#include "render/light_bvh.h"
#include "render/sphere_chains.h"
#include "scene/effects.h"

namespace spt {

/// A scene that cannot be rendered as described (bad values, inconsistent materials).
struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Checks one material's BSDF parameters (reflectances in [0, 1], kd + ks + kt ≤ 1 at every
/// wavelength, an index of refraction in [1, 100] where it is used). Throws SceneError
/// naming the defect.
void validate_material(const Material& m);

/// How a scene file asks to be rendered ("integrator" key); each field the command line
/// gives overrides it.
struct IntegratorPreset {
    std::optional<IntegratorKind> kind;
    std::optional<int> max_depth;
    std::optional<LightSampling> light_sampling;  ///< path only
    std::optional<double> merge_radius;           ///< vcm only
};

/// Shapes a shadow ray towards a light sample need not test, because they cannot block it
/// (Scene::occluded; honoured in scenes without a BVH).
struct ShadowSkip {
    /// The light's own sphere when the sample is on the side facing the ray's origin, or −1.
    int sphere = -1;
    /// A planar light (a quad) whose triangles are skipped, or −1: a segment that ends on a
    /// plane and does not lie in it meets the plane only at its end.
    int planar_light = -1;
};

/// The shapes are the arrays of ShapeArrays (spheres, planes, triangles, disks, cylinders,
/// cones: one per type of the set).
struct Scene : ShapeArrays {
    std::string name;
    /// One line for --list-scenes: the file's "summary", else the first sentence of its
    /// "description" (empty when it has neither).
    std::string summary;
    /// The spectra's resolution the scene was built with, and why it is not the one asked
    /// for ("" when it is): build_scene.
    SpectralResolution spectral_resolution;
    std::string spectral_resolution_reason;
    CameraSpec camera;
    int width = 512, height = 512, spp = 128;  ///< defaults the command line may override
    std::string output;  ///< the image file written when the command line names none (empty: NAME.png)
    IntegratorPreset integrator;               ///< the scene's choice; the command line overrides
    /// Things that render but probably not as the author meant (an open or inward-facing
    /// refracting mesh), one line each, for the program to print.
    std::vector<std::string> warnings;
    double bvh_build_seconds = 0;  ///< time finalize() spent building the BVH (0: none)

    std::vector<Material> materials;
    /// Vertex normals and (u, v) of mesh triangles (Triangle::attributes indexes it).
    std::vector<TriangleAttributes> triangle_attributes;
    /// Meshes placed by `instances` (a two-level BVH): each mesh's triangles are stored once,
    /// in its own space, however many times it is placed. Instances do not emit light.
    std::vector<InstancedMesh> instanced_meshes;
    std::vector<MeshInstance> instances;
    /// Bytes held by the shapes and the acceleration structures (not materials or lights).
    std::size_t geometry_bytes() const;
    /// Every light: point lights, the emitters attached to shapes (a shape's `light` is its
    /// index here) and the environment. finalize() copies each emitting shape's geometry
    /// into its light, so shapes may change until then.
    std::vector<Light> lights;
    /// Shapes that move while the shutter is open (motion blur), tested after the static
    /// ones, each behind the box it sweeps.
    std::vector<MovingShape> moving_shapes;

    /// Participating media and where they are (all empty in scenes without media): the
    /// medium around the camera, each shape's two sides ([ShapeKind][index in its array])
    /// and the material of shapes that only bound a medium (no surface: rays pass straight
    /// through them), −1 for none.
    std::vector<Medium> media;
    int camera_medium = -1;
    std::array<std::vector<MediumInterface>, kShapeTypeCount> shape_media;
    int interface_material = -1;
    MediumInterface medium_interface(PrimId prim) const {
        return shape_media[static_cast<std::size_t>(prim.kind())][prim.index()];
    }
    /// Gives `sides` to every shape that has no medium interface yet (the ones just added).
    void extend_shape_media(const MediumInterface& sides) {
        const auto counts = shape_counts();
        for (std::size_t k = 0; k < kShapeTypeCount; ++k) shape_media[k].resize(counts[k], sides);
    }

    /// Textures that material parameters (Material::textures) and emitters (light_textures)
    /// are bound to.
    std::vector<Texture> textures;
    /// Per light: the texture its emission is bound to, or −1 (empty: none is). Only area
    /// lights may have one (their points have surface coordinates). The light's own Le is
    /// then the texture's mean (its power for light selection).
    std::vector<int> light_textures;

    Effects effects;  ///< filled by finalize()

    /// Derived by finalize(): the point lights (each sampled at every vertex: no random
    /// numbers, no MIS), the other lights chosen by power for next-event estimation (without
    /// and with the emitting infinite planes, see IntegratorSettings::sample_planes), the
    /// infinite lights (what a ray that escapes sees: none, one or several) and the bounding
    /// sphere of the finite shapes, the camera and the point lights.
    std::vector<int> point_light_indices;
    std::vector<int> spot_light_indices;  ///< sampled like the point lights
    LightDistribution area_light_choice;
    LightDistribution area_light_choice_with_planes;
    /// The same lights in a light BVH (render/light_bvh.h), built when there are at least two
    /// of them (one light is chosen with probability 1 by either).
    LightBvh light_bvh;
    std::vector<int> infinite_light_indices;
    /// Next-event strategies beyond the light sampler, prepared by finalize() (each holds its
    /// own tables): specular chains through and off spheres (effects.caustic_spheres).
    SphereChains sphere_chains;
    Vec3 bounds_center;
    float bounds_radius = 1.f;

    /// Adds a material and returns its index.
    int add_material(Material m);
    /// Adds a point light.
    void add_point_light(const Vec3& position, Spectrum intensity);
    /// Sets the environment's radiance (rays that escape); zero removes it.
    void set_background(Spectrum radiance);
    /// Makes an environment map the background (in place of any other).
    void set_background(EnvironmentMapLight map);
    /// Makes an environment map sampled through a portal the background.
    void set_background(PortalLight portal);
    /// Makes a sky, and its sun if any, the background (in place of any other).
    void set_background(SkyLight sky, std::optional<SunLight> sun);
    /// Removes the background (constant, map, or sky and sun), if any.
    void remove_background();
    /// Adds the emitter for a shape of the given kind (a quad's or a mesh's triangles share
    /// one) and returns the index to store in the shapes' `light`.
    int add_emitter(ShapeKind kind, Spectrum radiance);
    /// Adds the emitter of a parallelogram o, o + e1, o + e1 + e2, o + e2 (a quad's two
    /// triangles store its index): sampled by solid angle when it is a rectangle.
    int add_quad_emitter(const Vec3& o, const Vec3& e1, const Vec3& e2, Spectrum radiance);
    /// Radiance leaving the emitter of `hit`'s shape towards wo (zero if it has none, or
    /// shows wo its back): the light's L. kTextured (scenes with textures): an emitter with
    /// an emission texture gives the texture's value at the hit's (u, v) instead.
    template <bool kTextured = false>
    [[gnu::always_inline]] SampledSpectrum emitted(const Hit& hit, const Vec3& wo,
                                                   const SampledWavelengths& lambda) const {
        if (hit.light < 0) return SampledSpectrum(0.f);
        if constexpr (kTextured)
            if (light_textured(hit.light)) return texture_emission(hit, wo, lambda);
        return light_emitted(lights[hit.light], hit.p, hit.n, wo, lambda);
    }
    /// Surface coordinates of a hit (see each shape's uv()).
    void surface_uv(const Hit& hit, float& u, float& v) const;
    /// The direction of growing u at a hit (dp/du, not normalised; zero where a shape keeps
    /// none): the tangent of anisotropic BSDFs.
    Vec3 surface_tangent(const Hit& hit) const;
    /// Surface coordinates of the point p on triangle t: its vertices' (u, v) interpolated
    /// (meshes with u, v or s, t; quads with a texture), else the barycentrics (b1, b2).
    void triangle_uv(const Triangle& t, const Vec3& p, float& u, float& v) const;

    // Textures (scene_textures.cpp): only integrators of scenes with effects.textures call these.
    /// The BSDF of a textured material at `hit`: `scratch` becomes the material's BSDF with
    /// each bound parameter set to its texture's value at the hit's (u, v), and an
    /// anisotropic conductor's tangent to the surface's; returns it. Allocates nothing once
    /// `scratch` has held this material's BSDF.
    const Bsdf& textured_bsdf(const Hit& hit, Bsdf& scratch) const;
    /// The BSDF at a surface hit: its material's, or for a textured material textured_bsdf
    /// made in this thread's scratch BSDF (valid until the thread's next call). bdpt and the
    /// volumetric path take it; the path loop keeps its own scratch on its stack.
    const Bsdf& bsdf_at(const Hit& hit) const {
        const Material& m = materials[hit.material];
        if (!m.textured) [[likely]] return m.bsdf;
        thread_local Bsdf scratch;
        return textured_bsdf(hit, scratch);
    }
    /// True when light `index` has an emission texture.
    bool light_textured(int index) const {
        return static_cast<std::size_t>(index) < light_textures.size() && light_textures[static_cast<std::size_t>(index)] >= 0;
    }
    /// Radiance of textured light `index` at the point p on it (a light sample's point; on a
    /// mesh light, on its triangle `triangle`: LightSample::triangle).
    SampledSpectrum light_point_emission(int index, const Vec3& p, std::uint32_t triangle,
                                         const SampledWavelengths& lambda) const;
    /// Makes the scene renderable, in named steps (the private functions below, in order):
    /// validation of materials, shapes and camera (throws SceneError naming the culprit),
    /// the acceleration build (the BVH when there are enough bounded shapes), the lights and
    /// their sampler, the effect analysis, and the next-event strategies' tables.
    void finalize();
    /// Replaces every wavelength-dependent index by its mean over 380–780 nm (dispersion off,
    /// for measuring its cost), then finalizes again.
    void disable_dispersion();

    /// Scenes with at most this many spheres and triangles test them in a loop: for a few
    /// spheres and a quad the loop is cheaper than any tree.
    static constexpr std::size_t kBvhThreshold = 8;
    /// True when finalize() built a BVH (intersect and occluded use it).
    bool uses_bvh() const { return m_use_bvh; }
    /// Tests every sphere and triangle in a loop instead of a BVH (to measure what the BVH
    /// buys), then finalizes again. Returns false and leaves the scene as it was when a shape
    /// only the BVH intersects (a quadric, a disk, an instance) is present.
    bool disable_bvh();
    const Bvh& bvh() const { return m_bvh; }

    /// Nearest surface along the ray, t in (0, ray.t_max), with the moving shapes where they
    /// are at `time` (static scenes ignore it). Candidates are compared by distance only; the
    /// hit record (the costly part) is built once, for the winner.
    [[gnu::always_inline]] std::optional<Hit> intersect(const Ray& ray, float time = 0.f) const {
        double t_best = ray.t_max;
        int best_plane = -1;
        m_axis_planes.nearest(ray, t_best, best_plane);
        for (int i : m_general_planes)
            if (const double t = planes[i].intersect_t(ray); t < t_best) t_best = t, best_plane = i;
        // Scenes with a BVH or moving shapes leave here; the hint keeps the small-scene path
        // inlined whole.
        if (m_out_of_line) [[unlikely]] return intersect_out_of_line(ray, t_best, best_plane, time);
        return intersect_few(ray, t_best, best_plane);
    }

    /// True if anything blocks the ray before ray.t_max (shadow rays; glass is opaque to them),
    /// the moving shapes where they are at `time`. In scenes without a BVH the shapes `skip`
    /// names are not tested (a light's own shape that cannot occlude the point sampled on it:
    /// the exact test of an emitting sphere or of a quad light's two triangles is a large part
    /// of next-event estimation in small scenes); with a BVH every shape is tested.
    bool occluded(const Ray& ray, ShadowSkip skip = {}, float time = 0.f) const {
        if (m_axis_planes.any_hit(ray)) return true;
        for (int i : m_general_planes)
            if (planes[i].intersect_t(ray) < ray.t_max) return true;
        if (m_out_of_line) [[unlikely]] return occluded_out_of_line(ray, skip, time);
        return occluded_few(ray, skip);
    }

    /// occluded() for a ray known to cross no infinite plane before t_max (a plane light's
    /// sample, LightSample::past_planes): the finite shapes only.
    bool occluded_past_planes(const Ray& ray, ShadowSkip skip = {}, float time = 0.f) const {
        if (m_out_of_line) [[unlikely]] return occluded_out_of_line(ray, skip, time);
        return occluded_few(ray, skip);
    }

    /// Makes the shapes from `first` on (shape_counts() before the loader added them) one
    /// moving shape with `motion`: they leave the static arrays. Call before finalize().
    void make_moving(const ShapeCounts& first, RigidMotion motion);
    /// Whether every shape from `first` on can move (kCanMove: not a plane).
    bool can_move_since(const ShapeCounts& first) const;
    /// Whether a shape from `first` on emits light (moving emitters are not supported).
    bool emits_since(const ShapeCounts& first) const;
    /// The box of the shapes from `first` on whose centre is their motion's default pivot.
    Aabb pivot_box_since(const ShapeCounts& first) const;

private:
    /// emitted() of a light with an emission texture: its value at the hit's (u, v) on the
    /// light's emitting sides.
    SampledSpectrum texture_emission(const Hit& hit, const Vec3& wo, const SampledWavelengths& lambda) const;
    /// The rest of intersect() without a BVH and moving shapes: spheres and triangles in
    /// lanes (a small scene's few), given the nearest plane so far.
    [[gnu::always_inline]] std::optional<Hit> intersect_few(const Ray& ray, double t_best, int best_plane) const {
        const Sphere* best_sphere = nullptr;
        m_sphere_lanes.candidates(ray, [&](int i) {
            if (const double t = spheres[i].intersect_t_exact(ray); t < t_best) t_best = t, best_sphere = &spheres[i];
        });
        const Triangle* best_triangle = nullptr;
        std::optional<TriangleIntersection> best_ti;
        m_triangle_lanes.candidates(ray, [&](int i) {
            if (auto ti = triangles[i].intersect(ray, t_best)) t_best = ti->t, best_triangle = &triangles[i], best_ti = ti;
        });
        if (best_triangle) return triangle_hit(*best_triangle, *best_ti);
        if (best_sphere)
            return with_prim(best_sphere->make_hit(ray, t_best), ShapeKind::sphere, best_sphere - spheres.data());
        if (best_plane >= 0) {
            const int axis = m_plane_axis[best_plane];
            return with_prim(axis >= 0 ? planes[best_plane].make_axis_hit(ray, t_best, axis)
                                       : planes[best_plane].make_hit(ray, t_best),
                             ShapeKind::plane, best_plane);
        }
        return std::nullopt;
    }
    [[gnu::always_inline]] bool occluded_few(const Ray& ray, ShadowSkip skip) const {
        bool blocked = false;
        m_sphere_lanes.candidates(ray, [&](int i) {
            if (i != skip.sphere) blocked |= spheres[i].intersect_t_exact(ray) < ray.t_max;
        });
        if (blocked) return true;
        m_triangle_lanes.candidates(ray, [&](int i) {
            if (skip.planar_light < 0 || triangles[i].light != skip.planar_light)
                blocked |= triangles[i].intersect(ray, ray.t_max).has_value();
        });
        return blocked;
    }
    /// intersect() and occluded() for scenes with a BVH or moving shapes (scene_motion.cpp).
    [[gnu::noinline]] std::optional<Hit> intersect_out_of_line(const Ray& ray, double t_best, int best_plane,
                                                               float time) const;
    [[gnu::noinline]] bool occluded_out_of_line(const Ray& ray, ShadowSkip skip, float time) const;
    /// Whether a bounded shape other than spheres and triangles (or an instance) is present:
    /// the loop of a small scene knows those two only.
    bool needs_bvh() const;
    /// Moving shape i at `time`: its nearest hit before t_max, in world space.
    std::optional<Hit> intersect_moving(std::size_t i, const Ray& ray, float time, double t_max) const;
    BvhShapes bvh_shapes() const {
        BvhShapes shapes = BvhShapes::of_all(*this);
        shapes.instances = instances, shapes.meshes = instanced_meshes.data();
        return shapes;
    }
    /// Calls f with each array of shapes (every shape has a material and a light).
    template <typename F>
    void for_each_shape_array(F&& f) {
        for_each_array(f);
        for (InstancedMesh& m : instanced_meshes) f(m.triangles);
        for (MovingShape& m : moving_shapes) m.for_each_array(f);
    }
    template <typename F>
    void for_each_shape_array(F&& f) const {
        for_each_array(f);
        for (const InstancedMesh& m : instanced_meshes) f(m.triangles);
        for (const MovingShape& m : moving_shapes) m.for_each_array(f);
    }
    /// The hit record of a triangle: its primitive, and its shading normal on meshes with
    /// vertex normals.
    Hit triangle_hit(const Triangle& tri, const TriangleIntersection& ti) const {
        Hit hit = with_prim(tri.make_hit(ti), ShapeKind::triangle, &tri - triangles.data());
        if (tri.attributes >= 0) [[unlikely]] {
            const TriangleAttributes& a = triangle_attributes[static_cast<std::size_t>(tri.attributes)];
            if (a.has_normals) hit.ns = a.shading_normal(ti.b0, ti.b1, ti.b2, hit.n);
        }
        return hit;
    }
    // The steps of finalize(), in order (each may throw SceneError naming the defect).
    /// Checks each material and derives its flags (the lobes its textures can add included).
    void prepare_materials();
    /// Checks every shape, finishes the moving ones and the instanced meshes (their own BVHs).
    void validate_shapes();
    /// Checks the image size, spp and the camera.
    void validate_camera();
    /// Sorts the planes for intersection and builds the BVH (or the small scene's lanes).
    void build_acceleration();
    /// Copies the emitting shapes' geometry into their lights, checks the lights, finds the
    /// bounding sphere and builds the light choices (the light sampler).
    void finalize_lights();
    /// Fluorescent materials draw excitation wavelengths by the lights' summed spectral power
    /// too (model/fluorescence.h).
    void prepare_fluorescence();
    /// Sets effects from what the scene holds; checks the media and the emission textures.
    void analyse_effects();
    /// Checks the media (coefficients, g, boxes) and that every shape has its interface.
    void finalize_media();
    /// Prepares the next-event strategies' tables (sphere_chains) and sets
    /// effects.caustic_spheres.
    void prepare_strategies();
    static Hit with_prim(Hit hit, ShapeKind kind, std::ptrdiff_t index) {
        hit.prim = PrimId(kind, static_cast<std::uint32_t>(index));
        return hit;
    }
    /// The rest of intersect() for scenes with a BVH, given the nearest plane so far. Kept
    /// out of line so that the small-scene path stays small enough to inline.
    [[gnu::noinline]] std::optional<Hit> intersect_bvh(const Ray& ray, double t_best, int best_plane) const;
    [[gnu::noinline]] bool occluded_bvh(const Ray& ray) const;
    /// The world-space hit record of a triangle of an instance (BvhHit::instance).
    Hit instance_hit(const BvhHit& h) const;

    AxisPlanes m_axis_planes;              ///< built by finalize()
    SphereLanes m_sphere_lanes;            ///< built by finalize() when there is no BVH
    /// The triangles' bounding spheres, so that most rays skip the exact (double) test.
    SphereLanes m_triangle_lanes;
    std::vector<int> m_general_planes;     ///< planes that are not axis-aligned
    std::vector<signed char> m_plane_axis;  ///< per plane: its normal's axis, −1 if tilted
    Bvh m_bvh;                             ///< over spheres and triangles; empty below the threshold
    bool m_use_bvh = false;                ///< !m_bvh.empty(), in one byte for the hot path
    bool m_bvh_allowed = true;             ///< false after disable_bvh()
    bool m_out_of_line = false;            ///< m_use_bvh or moving shapes
};

}  // namespace spt
