// Scene validation (every value checked, with a message naming what is wrong) and the
// analysis of which effects the scene calls for.
#include "scene/scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "geometry/aabb.h"
#include "scene/material_types.h"

namespace spt {

namespace {

void require(bool ok, const std::string& message) {
    if (!ok) throw SceneError(message);
}

bool finite(const Vec3& v) { return is_finite(v); }

/// A sphere around the triangle: the centroid and the farthest vertex, padded by 0.1 % (far
/// above the float rounding of both), so the float rejection of SphereLanes never drops a hit.
Sphere bounding_sphere(const Triangle& t) {
    Sphere s;
    s.center = (t.p0 + t.p1 + t.p2) / 3.f;
    const float r2 = std::max({length_squared(t.p0 - s.center), length_squared(t.p1 - s.center),
                               length_squared(t.p2 - s.center)});
    s.radius = std::sqrt(r2) * 1.001f;
    s.material = t.material;
    return s;
}

/// Checks a spectrum over the sampled range: finite, within [lo, hi].
void check_spectrum(const Spectrum& s, const std::string& what, float lo, float hi) {
    for (float l = kLambdaMin; l <= kLambdaMax; l += 1.f) {
        const float v = s.eval(l);
        if (std::isfinite(v) && v >= lo && v <= hi) continue;
        std::ostringstream msg;
        msg << what << " is " << v << " at " << l << " nm; expected a finite value in [" << lo
            << ", " << hi << "]";
        throw SceneError(msg.str());
    }
}

}  // namespace

bool Scene::needs_bvh() const {
    bool others = !instances.empty();
    for_each_array([&]<typename T>(const std::vector<T>& shapes) {
        if constexpr (BoundedShape<T> && !std::is_same_v<T, Sphere> && !std::is_same_v<T, Triangle>)
            others |= !shapes.empty();
    });
    return others;
}

bool Scene::disable_bvh() {
    if (needs_bvh()) return false;
    m_bvh_allowed = false;
    finalize();
    return true;
}

void Scene::disable_dispersion() {
    for (Material& m : materials) {
        Spectrum* eta = nullptr;
        if (LobeMixBsdf* mix = std::get_if<LobeMixBsdf>(&m.bsdf)) eta = &mix->eta;
        if (DielectricBsdf* d = std::get_if<DielectricBsdf>(&m.bsdf)) eta = &d->eta;
        if (!eta || eta->is_constant()) continue;
        double sum = 0;
        int n = 0;
        for (double l = Spectrum::kBinMin; l <= Spectrum::kBinMax; l += 1.0, ++n) sum += eta->source().eval(l);
        *eta = Spectrum(SpectrumSource::constant(sum / n), SpectralResolution{});
    }
    finalize();
}

/// The material's flags: its BSDF's, and a re-emitting diffuse lobe when it fluoresces (a
/// fluorescent surface whose reflectance part is black still scatters).
static BsdfFlags material_flags(const Material& m) {
    BsdfFlags f = bsdf_flags(m.bsdf);
    if (m.fluorescence) f.bits |= BsdfFlags::reflection | BsdfFlags::non_delta;
    return f;
}

int Scene::add_material(Material m) {
    m.flags = material_flags(m);
    m.textured = !m.textures.empty() || needs_tangent(m.bsdf);
    materials.push_back(std::move(m));
    return static_cast<int>(materials.size()) - 1;
}

void Scene::add_point_light(const Vec3& position, Spectrum intensity) {
    lights.emplace_back(PointLight{position, std::move(intensity), {}});
}

void Scene::set_background(Spectrum radiance) {
    remove_background();
    if (!radiance.is_zero()) lights.emplace_back(EnvironmentLight{std::move(radiance), {}, 1.f});
}

void Scene::set_background(EnvironmentMapLight map) {
    remove_background();
    lights.emplace_back(std::move(map));
}

void Scene::set_background(PortalLight portal) {
    remove_background();
    lights.emplace_back(std::move(portal));
}

void Scene::set_background(SkyLight sky, std::optional<SunLight> sun) {
    remove_background();
    lights.emplace_back(std::move(sky));
    if (sun) lights.emplace_back(std::move(*sun));
}

void Scene::remove_background() {
    // Backwards: a sky's sun follows it.
    for (std::size_t i = lights.size(); i-- > 0;) {
        if (!std::holds_alternative<EnvironmentLight>(lights[i]) && !std::holds_alternative<EnvironmentMapLight>(lights[i]) &&
            !std::holds_alternative<PortalLight>(lights[i]) && !std::holds_alternative<SkyLight>(lights[i]) &&
            !std::holds_alternative<SunLight>(lights[i]))
            continue;
        lights.erase(lights.begin() + static_cast<std::ptrdiff_t>(i));
        if (i < light_textures.size()) light_textures.erase(light_textures.begin() + static_cast<std::ptrdiff_t>(i));
        // Later lights moved down by one: so must the shapes' indices of them.
        for_each_shape_array([&](auto& shapes) {
            for (auto& shape : shapes)
                if (shape.light > static_cast<int>(i)) --shape.light;
        });
    }
}

int Scene::add_emitter(ShapeKind kind, Spectrum radiance) {
    switch (kind) {
        case ShapeKind::sphere: lights.emplace_back(SphereLight{{}, std::move(radiance)}); break;
        case ShapeKind::plane: lights.emplace_back(PlaneLight{{}, std::move(radiance)}); break;
        case ShapeKind::triangle: lights.emplace_back(TriangleMeshLight{{}, {}, 0.f, std::move(radiance)}); break;
        case ShapeKind::disk: lights.emplace_back(QuadricLight{Disk{}, std::move(radiance)}); break;
        case ShapeKind::cylinder: lights.emplace_back(QuadricLight{Cylinder{}, std::move(radiance)}); break;
        case ShapeKind::cone: lights.emplace_back(QuadricLight{Cone{}, std::move(radiance)}); break;
        case ShapeKind::moving: throw SceneError("a moving shape cannot emit light");
        case ShapeKind::instance: throw SceneError("an instanced mesh cannot emit light");
    }
    return static_cast<int>(lights.size()) - 1;
}

int Scene::add_quad_emitter(const Vec3& o, const Vec3& e1, const Vec3& e2, Spectrum radiance) {
    QuadLight q;
    q.o = o, q.e1 = e1, q.e2 = e2;
    q.Le = std::move(radiance);
    q.finish();
    lights.emplace_back(std::move(q));
    return static_cast<int>(lights.size()) - 1;
}

void Scene::surface_uv(const Hit& hit, float& u, float& v) const {
    // Neither is kept: a moving shape's rest frame at the hit's time is gone, and instances
    // keep no surface coordinates (see scenes/README.md).
    if (hit.prim.kind() == ShapeKind::moving || hit.prim.kind() == ShapeKind::instance) {
        u = v = 0.f;
        return;
    }
    const std::uint32_t i = hit.prim.index();
    visit_shape_kind(hit.prim.kind(), [&]<typename T>(std::type_identity<T>) {
        if constexpr (std::is_same_v<T, Triangle>) triangle_uv(triangles[i], hit.p, u, v);
        else shapes_of<T>()[i].uv(hit.p, u, v);
    });
}

Vec3 Scene::surface_tangent(const Hit& hit) const {
    // None kept for moving shapes and instances: the BSDF takes a fixed perpendicular.
    if (hit.prim.kind() == ShapeKind::moving || hit.prim.kind() == ShapeKind::instance) return {};
    const std::uint32_t i = hit.prim.index();
    if (hit.prim.kind() != ShapeKind::triangle)
        return visit_shape_kind(hit.prim.kind(), [&]<typename T>(std::type_identity<T>) -> Vec3 {
            if constexpr (std::is_same_v<T, Triangle>) return {};
            else return shapes_of<T>()[i].dpdu(hit.p);
        });
    const Triangle& t = triangles[i];
    const Vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0;
    if (t.attributes >= 0 && triangle_attributes[static_cast<std::size_t>(t.attributes)].has_uv) {
        // dp/du from the vertices' (u, v): e1 = du1·dp/du + dv1·dp/dv, e2 likewise.
        const TriangleAttributes& a = triangle_attributes[static_cast<std::size_t>(t.attributes)];
        const float du1 = a.uv[1][0] - a.uv[0][0], dv1 = a.uv[1][1] - a.uv[0][1];
        const float du2 = a.uv[2][0] - a.uv[0][0], dv2 = a.uv[2][1] - a.uv[0][1];
        const float det = du1 * dv2 - dv1 * du2;
        if (det != 0.f && std::isfinite(det)) return (e1 * dv2 - e2 * dv1) / det;
    }
    return e1;  // u = b1: p moves along p1 − p0
}

void Scene::triangle_uv(const Triangle& t, const Vec3& p, float& u, float& v) const {
    if (t.attributes >= 0 && triangle_attributes[static_cast<std::size_t>(t.attributes)].has_uv) {
        // The vertices' (u, v) interpolated with the barycentrics of p.
        float b1, b2;
        t.uv(p, b1, b2);
        const TriangleAttributes& a = triangle_attributes[static_cast<std::size_t>(t.attributes)];
        const float b0 = 1.f - b1 - b2;
        u = b0 * a.uv[0][0] + b1 * a.uv[1][0] + b2 * a.uv[2][0];
        v = b0 * a.uv[0][1] + b1 * a.uv[1][1] + b2 * a.uv[2][1];
        return;
    }
    t.uv(p, u, v);
}

void validate_material(const Material& m) {
    const std::string who = "material '" + m.name + "'";
    if (const DiffuseBsdf* d = std::get_if<DiffuseBsdf>(&m.bsdf)) {
        check_spectrum(d->kd, who + " kd", 0.f, 1.f);
        return;
    }
    const LobeMixBsdf* mix = std::get_if<LobeMixBsdf>(&m.bsdf);
    if (!mix) return validate_surface_model(m.bsdf, who);  // the microfacet-era types
    const LobeMixBsdf& b = *mix;
    check_spectrum(b.kd, who + " kd", 0.f, 1.f);
    check_spectrum(b.ks, who + " ks", 0.f, 1.f);
    check_spectrum(b.kt, who + " kt", 0.f, 1.f);
    if (b.has_transmission()) check_spectrum(b.eta, who + " index of refraction", 1.f, 100.f);
    // Energy conservation at every wavelength, for both what the renderer samples (bins)
    // and the exact source (so a scene is valid whatever --spectral-bins says).
    for (float l = kLambdaMin; l <= kLambdaMax; l += 1.f) {
        const double binned = double(b.kd.eval(l)) + b.ks.eval(l) + b.kt.eval(l);
        const double exact = b.kd.source().eval(l) + b.ks.source().eval(l) + b.kt.source().eval(l);
        if (binned <= 1.0 + 1e-6 && exact <= 1.0 + 1e-6) continue;
        std::ostringstream msg;
        msg << who << ": kd + ks + kt = " << std::max(binned, exact) << " at " << l
            << " nm; expected at most 1 (a surface cannot reflect more than it receives)";
        throw SceneError(msg.str());
    }
}

std::optional<Hit> Scene::intersect_bvh(const Ray& ray, double t_best, int best_plane) const {
    BvhHit h;
    if (m_bvh.intersect(ray, bvh_shapes(), t_best, h)) {
        if (h.instance != BvhHit::kNoInstance) [[unlikely]] return instance_hit(h);
        const auto i = h.prim.index();
        return visit_shape_kind(h.prim.kind(), [&]<typename T>(std::type_identity<T>) -> Hit {
            if constexpr (std::is_same_v<T, Triangle>) return triangle_hit(triangles[i], h.tri);
            else return with_prim(shapes_of<T>()[i].make_hit(ray, t_best), shape_kind<T>, i);
        });
    }
    if (best_plane >= 0) return with_prim(planes[best_plane].make_hit(ray, t_best), ShapeKind::plane, best_plane);
    return std::nullopt;
}

bool Scene::occluded_bvh(const Ray& ray) const { return m_bvh.occluded(ray, bvh_shapes()); }

Hit Scene::instance_hit(const BvhHit& h) const {
    const MeshInstance& inst = instances[h.instance];
    const Triangle& tri = instanced_meshes[static_cast<std::size_t>(inst.mesh)].triangles[h.prim.index()];
    const Hit local = tri.make_hit(h.tri);
    Hit hit = local;
    // The point mapped in double: its object-space error carried by |A| (rounded up by one
    // part in 2^20), the double arithmetic's error and the rounding to float.
    const DVec3 p(local.p);
    hit.p = inst.to_world.point(p).to_float();
    const DVec3 reach = inst.to_world.abs_vector(DVec3(abs(local.p)));
    const double magnitude = std::max({reach.x + std::fabs(inst.to_world.a[0][3]),
                                       reach.y + std::fabs(inst.to_world.a[1][3]),
                                       reach.z + std::fabs(inst.to_world.a[2][3])});
    hit.p_err = inst.to_world.abs_vector(DVec3(local.p_err)).to_float() * (1.f + 0x1p-20f) +
                double_point_error(hit.p, magnitude);
    hit.n = normalize(inst.to_world.cofactor_vector(DVec3(local.n))).to_float();
    hit.ns = hit.n;
    if (tri.attributes >= 0) [[unlikely]] {
        const TriangleAttributes& a = triangle_attributes[static_cast<std::size_t>(tri.attributes)];
        if (a.has_normals) {
            const Vec3 ns = a.shading_normal(h.tri.b0, h.tri.b1, h.tri.b2, local.n);
            hit.ns = face_forward(normalize(inst.to_world.cofactor_vector(DVec3(ns))).to_float(), hit.n);
        }
    }
    hit.light = -1;
    hit.prim = PrimId(ShapeKind::instance, h.instance);
    return hit;
}

std::size_t Scene::geometry_bytes() const {
    std::size_t bytes = 0;
    for_each_shape_array([&bytes](const auto& shapes) { bytes += shapes.capacity() * sizeof(shapes[0]); });
    bytes += triangle_attributes.capacity() * sizeof(TriangleAttributes) + m_bvh.memory_bytes() +
             instances.capacity() * sizeof(MeshInstance) + instanced_meshes.capacity() * sizeof(InstancedMesh);
    for (const InstancedMesh& m : instanced_meshes) bytes += m.bvh.memory_bytes();
    return bytes;
}

void Scene::finalize() {
    prepare_materials();
    validate_shapes();
    validate_camera();
    build_acceleration();
    finalize_lights();
    prepare_fluorescence();
    analyse_effects();
    prepare_strategies();
}

void Scene::prepare_materials() {
    for (Material& m : materials) {
        validate_material(m);
        m.flags = material_flags(m);
        m.textured = !m.textures.empty() || needs_tangent(m.bsdf);
        for (const TextureBinding& b : m.textures) {
            require(b.parameter && b.texture >= 0 && b.texture < static_cast<int>(textures.size()),
                    "material '" + m.name + "' refers to a texture that does not exist");
            // A textured number (a roughness) holds its largest value; its smallest may add
            // lobes (α = 0: a delta lobe), which the flags must include.
            const std::vector<float>& values = textures[static_cast<std::size_t>(b.texture)].values;
            if (!b.parameter->number || values.empty()) continue;
            Bsdf lowest = m.bsdf;
            *b.parameter->number(lowest) = *std::min_element(values.begin(), values.end());
            m.flags.bits |= bsdf_flags(lowest).bits;
        }
    }
}

void Scene::validate_shapes() {
    auto check_material_index = [&](int index, const std::string& who) {
        require(index >= 0 && index < static_cast<int>(materials.size()),
                who + " refers to a material that does not exist");
    };
    // Each shape's own defects (its contract's defect()), then its references into the scene.
    auto check_shapes = [&]<typename T>(const std::vector<T>& shapes) {
        for (const T& shape : shapes) {
            if (const char* defect = shape.defect()) throw SceneError(defect);
            if constexpr (std::is_same_v<T, Triangle>)
                require(shape.attributes < static_cast<int>(triangle_attributes.size()),
                        "a triangle refers to vertex attributes that do not exist");
            check_material_index(shape.material, std::string("a ") + T::kName);
        }
    };
    for (Plane& p : planes) p.set_frame();
    for_each_array(check_shapes);
    for (MovingShape& m : moving_shapes) {
        m.for_each_array([&]<typename T>(const std::vector<T>& shapes) {
            require(kCanMove<T> || shapes.empty(), std::string("a ") + T::kName + " cannot move");
            check_shapes(shapes);
            for (const T& shape : shapes) require(shape.light < 0, "a moving shape cannot emit light");
        });
        for (std::size_t k = 1; k < m.motion.keys.size(); ++k)
            require(m.motion.keys[k].time > m.motion.keys[k - 1].time, "motion keyframe times must increase");
        m.finish();
    }
    for (InstancedMesh& mesh : instanced_meshes) {
        require(!mesh.triangles.empty(), "an instanced mesh has no triangles");
        mesh.bounds = Aabb{};
        check_shapes(mesh.triangles);
        for (const Triangle& t : mesh.triangles) {
            require(t.light < 0, "an instanced mesh cannot emit light");
            mesh.bounds.expand(bounds(t));
        }
        mesh.bvh.build(mesh.shapes());
    }
    for (MeshInstance& inst : instances) {
        require(inst.mesh >= 0 && inst.mesh < static_cast<int>(instanced_meshes.size()),
                "an instance refers to a mesh that does not exist");
        const double det = inst.to_world.determinant();
        require(std::isfinite(det) && det != 0.0, "an instance's transform must be finite and invertible");
        inst.world_bounds = instance_bounds(inst.to_world, instanced_meshes[static_cast<std::size_t>(inst.mesh)].bounds);
        require(finite(inst.world_bounds.lo) && finite(inst.world_bounds.hi), "an instance must be finite after its transform");
    }
}

void Scene::validate_camera() {
    require(width > 0 && height > 0 && spp > 0, "image size and spp must be positive");
    require(finite(camera.position) && finite(camera.look_at) && finite(camera.up),
            "camera vectors must be finite");
    require(length(cross(camera.look_at - camera.position, camera.up)) > 0.f,
            "camera up vector must not be parallel to the viewing direction");
    require(camera.fov_degrees > 0.f && camera.fov_degrees < 180.f,
            "camera field of view must be in (0, 180) degrees");
    const Aperture& aperture = camera.aperture;
    require(std::isfinite(aperture.radius) && aperture.radius >= 0.f, "camera aperture radius must be finite and >= 0");
    require(aperture.radius == 0.f || (std::isfinite(camera.focus_distance) && camera.focus_distance > 0.f),
            "camera focus distance must be finite and > 0");
    require(aperture.blades == 0 || (aperture.blades >= 3 && aperture.blades <= 64),
            "camera aperture blades must be 0 (a disc) or 3 to 64");
    require(std::isfinite(camera.shutter_open) && std::isfinite(camera.shutter_close) &&
                camera.shutter_open <= camera.shutter_close,
            "camera shutter must be finite with open <= close");
}

void Scene::build_acceleration() {
    // Split planes for intersection: axis-aligned ones take the fast path.
    m_axis_planes.clear();
    m_general_planes.clear();
    m_plane_axis.assign(planes.size(), -1);
    for (int i = 0; i < static_cast<int>(planes.size()); ++i) {
        const Plane& p = planes[i];
        int axis = -1;
        // Only exactly axis-aligned normals: a tiny tilt can round a component to 1.
        for (int a = 0; a < 3; ++a)
            if (p.normal[(a + 1) % 3] == 0.f && p.normal[(a + 2) % 3] == 0.f) axis = a;
        m_plane_axis[i] = static_cast<signed char>(axis);
        if (axis >= 0) m_axis_planes.add(axis, double(p.normal[axis]) * p.offset, i);
        else m_general_planes.push_back(i);
    }

    // Bounded shapes: a BVH once there are more than a handful (see kBvhThreshold), or any
    // other bounded type (the loop below the threshold knows spheres and triangles only).
    m_bvh = Bvh{};
    const auto bvh_start = std::chrono::steady_clock::now();
    const bool many = spheres.size() + triangles.size() > kBvhThreshold;
    if ((many && m_bvh_allowed) || needs_bvh()) m_bvh.build(bvh_shapes());
    bvh_build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - bvh_start).count();
    m_use_bvh = !m_bvh.empty();
    m_out_of_line = m_use_bvh || !moving_shapes.empty();
    m_sphere_lanes.build(m_use_bvh ? std::vector<Sphere>{} : spheres);
    std::vector<Sphere> bounds;
    if (!m_use_bvh)
        for (const Triangle& t : triangles) bounds.push_back(bounding_sphere(t));
    m_triangle_lanes.build(bounds);
}

void Scene::analyse_effects() {
    // Which effects are called for: only materials that some shape uses count.
    effects = Effects{};
    effects.point_lights = !point_light_indices.empty() || !spot_light_indices.empty();
    effects.background = !infinite_light_indices.empty();
    effects.depth_of_field = camera.aperture.radius > 0.f;
    // Motion only blurs when the shutter stays open while something moves.
    bool moves = !moving_shapes.empty();
    for (const Light& l : lights)
        if (const PointLight* p = std::get_if<PointLight>(&l)) moves |= !p->motion.is_static();
    effects.motion_blur = moves && camera.shutter_close > camera.shutter_open;
    for (const Light& l : lights)
        effects.emissive_surfaces |= light_type(l) == LightType::area;
    auto material_effects = [&](const auto& shapes) {
        for (const auto& shape : shapes) {
            const Material& m = materials[shape.material];
            effects.mirror |= m.flags.has(BsdfFlags::delta);
            effects.transmission |= m.flags.has(BsdfFlags::transmission);
            effects.dispersion |= m.flags.has(BsdfFlags::dispersive);
            effects.textures |= m.textured;
            effects.fluorescence |= m.fluorescence != nullptr;
        }
    };
    for_each_shape_array(material_effects);
    require(media.empty() || !effects.motion_blur,
            "participating media and motion blur cannot be rendered together yet; expected one of them");
    finalize_media();
    effects.media = !media.empty();
    // Triangles of meshes, instanced meshes and moving shapes alike.
    for_each_shape_array([&](const auto& shapes) {
        if constexpr (std::is_same_v<std::decay_t<decltype(shapes[0])>, Triangle>)
            for (const Triangle& t : shapes)
                effects.shading_normals |=
                    t.attributes >= 0 && triangle_attributes[static_cast<std::size_t>(t.attributes)].has_normals;
    });
    if (!light_textures.empty()) {
        light_textures.resize(lights.size(), -1);
        for (std::size_t i = 0; i < lights.size(); ++i) {
            const int t = light_textures[i];
            if (t < 0) continue;
            require(t < static_cast<int>(textures.size()), "an emitter refers to a texture that does not exist");
            require(!std::holds_alternative<PointLight>(lights[i]) && !std::holds_alternative<SpotLight>(lights[i]) &&
                        light_type(lights[i]) != LightType::infinite,
                    "an emission texture is on a light without surface coordinates (a point or spot light, or "
                    "the background)");
            effects.textures = true;
        }
    }
}


void Scene::prepare_strategies() {
    sphere_chains = SphereChains::prepare(*this);
    effects.caustic_spheres = sphere_chains.active();
}

void Scene::finalize_media() {
    for (const Medium& m : media) {
        const std::string who = "medium '" + m.name + "'";
        check_spectrum(m.sigma_a, who + " sigma_a", 0.f, 1e30f);
        check_spectrum(m.sigma_s, who + " sigma_s", 0.f, 1e30f);
        require(std::isfinite(m.phase.g) && std::fabs(m.phase.g) < 1.f, who + " g must be in (-1, 1)");
        if (const GridDensity* g = std::get_if<GridDensity>(&m.density)) {
            require(g->grid && g->grid->nx > 0 && g->grid->values.size() ==
                    static_cast<std::size_t>(g->grid->nx) * g->grid->ny * g->grid->nz, who + " has no grid");
            require(finite(g->lo) && finite(g->hi) && g->lo.x < g->hi.x && g->lo.y < g->hi.y && g->lo.z < g->hi.z,
                    who + " box must be finite with min < max on every axis");
        }
        if (const HeightFogDensity* h = std::get_if<HeightFogDensity>(&m.density))
            require(std::isfinite(h->scale_height) && h->scale_height > 0.f && std::isfinite(h->base),
                    who + " scale_height must be > 0 and base finite");
    }
    const int n = static_cast<int>(media.size());
    require(camera_medium >= -1 && camera_medium < n, "the camera's medium does not exist");
    if (media.empty()) {
        for (auto& sides : shape_media) sides.clear();
        require(interface_material < 0, "a shape without a surface bounds no medium");
        return;
    }
    const auto counts = shape_counts();
    for (std::size_t kind = 0; kind < kShapeTypeCount; ++kind) {
        require(shape_media[kind].size() == counts[kind], "every shape needs its medium interface");
        for (const MediumInterface& mi : shape_media[kind])
            require(mi.interior >= -1 && mi.interior < n && mi.exterior >= -1 && mi.exterior < n,
                    "a shape refers to a medium that does not exist");
    }
}

namespace {

/// The mean of a light's spectral power over [lo, hi] at 10 nm steps.
float mean_spectral_power(const Light& light, float lo, float hi) {
    double sum = 0;
    int n = 0;
    for (float l = lo; l <= hi; l += 10.f, ++n) sum += light_spectral_power(light, l);
    return static_cast<float>(sum / n);
}

}  // namespace

void Scene::prepare_fluorescence() {
    std::vector<double> illumination;
    for (Material& m : materials) {
        if (!m.fluorescence) continue;
        if (illumination.empty()) {
            illumination.assign(kTransportBins, 0.0);
            for (const Light& light : lights)
                for (int k = 0; k < kTransportBins; ++k)
                    illumination[k] += light_spectral_power(light, kTransportMin + static_cast<float>(k) + 0.5f);
        }
        auto f = std::make_shared<Fluorescence>(*m.fluorescence);
        f->sample_excitation_by(illumination);
        m.fluorescence = std::move(f);
    }
}

void Scene::finalize_lights() {
    // The bounding sphere of what light subpaths from the environment should reach, and of
    // the disk an infinite plane's selection power is measured over.
    Aabb box;
    for_each_array([&]<typename T>(const std::vector<T>& shapes) {
        if constexpr (BoundedShape<T>)
            for (const T& shape : shapes) box.expand(extent_box(shape));
    });
    for (const MovingShape& m : moving_shapes) box.expand(m.swept);
    for (const MeshInstance& i : instances) box.expand(i.world_bounds);
    for (const Light& l : lights)
        if (const PointLight* p = std::get_if<PointLight>(&l)) {
            box.expand(p->position);
            for (const Keyframe& k : p->motion.keys) box.expand(p->motion.at(k.time).point(p->position));
        } else if (const SpotLight* s = std::get_if<SpotLight>(&l)) {
            box.expand(s->position);
        }
    const Vec3 lens(camera.aperture.radius, camera.aperture.radius, camera.aperture.radius);
    box.expand(camera.position - lens);  // the whole lens (the pinhole's point when 0)
    box.expand(camera.position + lens);
    bounds_center = box.centroid();
    bounds_radius = 0.5f * length(box.hi - box.lo);
    if (!(bounds_radius > 0.f)) bounds_radius = 1.f;  // a lone camera: any radius is correct

    // Each emitter gets its shape's geometry; a light that no shape refers to is an error.
    std::vector<char> attached(lights.size(), 0);
    auto light_of = [&](int index, const char* shape) -> Light& {
        require(index >= 0 && index < static_cast<int>(lights.size()), std::string("a ") + shape +
                                                                            " refers to a light that does not exist");
        attached[static_cast<std::size_t>(index)] = 1;
        return lights[static_cast<std::size_t>(index)];
    };
    for (Light& l : lights)
        if (TriangleMeshLight* m = std::get_if<TriangleMeshLight>(&l)) m->triangles.clear();
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        const Sphere& s = spheres[i];
        if (s.light < 0) continue;
        SphereLight* l = std::get_if<SphereLight>(&light_of(s.light, "sphere"));
        require(l != nullptr, "an emitting sphere's light is not a sphere light");
        l->sphere = s;
        l->sphere_index = static_cast<int>(i);
    }
    for (const Plane& p : planes) {
        if (p.light < 0) continue;
        PlaneLight* l = std::get_if<PlaneLight>(&light_of(p.light, "plane"));
        require(l != nullptr, "an emitting plane's light is not a plane light");
        l->plane = p;
        l->scene_radius = bounds_radius;
        // The other planes hide what lies beyond them (plane_light.h); planes that rays pass
        // (media interfaces) hide nothing.
        l->blocker_count = 0;
        l->blocks_every_plane = true;
        for (const Plane& other : planes) {
            if (&other == &p) continue;
            if (other.material == interface_material || l->blocker_count == VisibleLune::kMaxBlockers) {
                l->blocks_every_plane = false;
                continue;
            }
            l->blockers[static_cast<std::size_t>(l->blocker_count++)] = {other.normal, other.offset};
        }
        l->prepare_regions();
    }
    auto attach_quadric = [&](const auto& shape, const char* what) {
        if (shape.light < 0) return;
        QuadricLight* l = std::get_if<QuadricLight>(&light_of(shape.light, what));
        require(l != nullptr, std::string("an emitting ") + what + "'s light is not a quadric light");
        l->shape = shape;
    };
    for (const Disk& d : disks) attach_quadric(d, "disk");
    for (const Cylinder& c : cylinders) attach_quadric(c, "cylinder");
    for (const Cone& c : cones) attach_quadric(c, "cone");
    for (const Triangle& t : triangles) {
        if (t.light < 0) continue;
        Light& light = light_of(t.light, "triangle");
        if (std::holds_alternative<QuadLight>(light)) continue;  // a quad's: it keeps its own corners
        TriangleMeshLight* l = std::get_if<TriangleMeshLight>(&light);
        require(l != nullptr, "an emitting triangle's light is not a triangle or quad light");
        l->add(t);
    }

    point_light_indices.clear();
    spot_light_indices.clear();
    infinite_light_indices.clear();
    // Lights are chosen by their power over the observer's range, or in a scene with
    // fluorescent materials over the transport range: a UV lamp, dark to the observer, is
    // then chosen by what it emits (model/fluorescence.h).
    const bool fluorescent =
        std::any_of(materials.begin(), materials.end(), [](const Material& m) { return m.fluorescence != nullptr; });
    std::vector<float> area_power(lights.size(), 0.f);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        Light& light = lights[i];
        if (PointLight* p = std::get_if<PointLight>(&light)) {
            require(finite(p->position), "point light position must be finite");
            check_spectrum(p->intensity, "point light intensity", 0.f, 1e30f);
            point_light_indices.push_back(static_cast<int>(i));
            continue;
        }
        if (SpotLight* s = std::get_if<SpotLight>(&light)) {
            require(finite(s->position), "spot light position must be finite");
            require(finite(s->direction) && std::fabs(length(s->direction) - 1.f) < 1e-4f,
                    "spot light direction must be a unit vector");
            require(s->cos_cone >= -1.f && s->cos_cone < s->cos_falloff + 1e-7f && s->cos_falloff <= 1.f &&
                        s->cos_cone < 1.f,
                    "spot light angles must satisfy 0 <= falloff <= cone <= 180 degrees, cone > 0");
            check_spectrum(s->intensity, "spot light intensity", 0.f, 1e30f);
            spot_light_indices.push_back(static_cast<int>(i));
            continue;
        }
        if (light_type(light) == LightType::infinite) {
            if (const EnvironmentLight* e = std::get_if<EnvironmentLight>(&light))
                check_spectrum(e->Le, "background radiance", 0.f, 1e30f);
            // Light subpaths from infinity start on a disk facing the scene's bounding sphere.
            visit_light_of<kInfiniteLights>(light, [&](auto& l) {
                l.center = bounds_center;
                l.radius = bounds_radius;
            });
            infinite_light_indices.push_back(static_cast<int>(i));
        } else {
            require(attached[i] != 0, "an emitter is attached to no shape");
            std::visit([&](auto& l) {
                if constexpr (requires { l.Le; }) check_spectrum(l.Le, "emission", 0.f, 1e30f);
            }, light);
            if (TriangleMeshLight* m = std::get_if<TriangleMeshLight>(&light)) m->finish();
            if (QuadLight* q = std::get_if<QuadLight>(&light)) {
                require(q->area() > 0.f && is_finite(q->o) && is_finite(q->e1) && is_finite(q->e2),
                        "a quad light must be a finite parallelogram of non-zero area");
            }
        }
        area_power[i] = fluorescent ? mean_spectral_power(light, kTransportMin, kTransportMax) : light_power(light);
    }
    area_light_choice_with_planes.build(area_power);
    light_bvh = LightBvh{};
    if (area_light_choice_with_planes.size() > 1) {
        // A mesh light's triangles are found from a hit when they are consecutive in `triangles`.
        std::vector<int> first(lights.size(), -1), count(lights.size(), 0);
        std::vector<char> split(lights.size(), 0);
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            const int l = triangles[t].light;
            if (l < 0 || !std::holds_alternative<TriangleMeshLight>(lights[static_cast<std::size_t>(l)])) continue;
            const std::size_t li = static_cast<std::size_t>(l);
            if (count[li] == 0) first[li] = static_cast<int>(t);
            else if (first[li] + count[li] != static_cast<int>(t)) split[li] = 1;
            ++count[li];
        }
        for (std::size_t i = 0; i < lights.size(); ++i)
            if (split[i]) first[i] = -1;
        light_bvh.build(lights, area_power, first);
    }
    for (std::size_t i = 0; i < lights.size(); ++i)
        if (std::holds_alternative<PlaneLight>(lights[i])) area_power[i] = 0.f;
    area_light_choice.build(area_power);
}

}  // namespace spt
