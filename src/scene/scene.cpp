// Scene validation (every value checked, with a message naming what is wrong) and the
// analysis of which effects the scene calls for.
#include "scene/scene.h"

#include <cmath>
#include <sstream>

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

void Scene::disable_dispersion() {
    for (Material& m : materials) {
        if (m.eta.is_constant()) continue;
        double sum = 0;
        int n = 0;
        for (double l = Spectrum::kBinMin; l <= Spectrum::kBinMax; l += 1.0, ++n) sum += m.eta.source().eval(l);
        m.eta = Spectrum(SpectrumSource::constant(sum / n), SpectralResolution{});
    }
    finalize();
}

int Scene::add_material(Material m) {
    materials.push_back(std::move(m));
    return static_cast<int>(materials.size()) - 1;
}

void validate_material(const Material& m) {
    const float big = 1e30f;
    const std::string who = "material '" + m.name + "'";
    check_spectrum(m.kd, who + " kd", 0.f, 1.f);
    check_spectrum(m.ks, who + " ks", 0.f, 1.f);
    check_spectrum(m.kt, who + " kt", 0.f, 1.f);
    check_spectrum(m.emission, who + " emission", 0.f, big);
    if (m.has_transmission()) check_spectrum(m.eta, who + " index of refraction", 1.f, 100.f);
    // Energy conservation at every wavelength, for both what the renderer samples (bins)
    // and the exact source (so a scene is valid whatever --spectral-bins says).
    for (float l = kLambdaMin; l <= kLambdaMax; l += 1.f) {
        const double binned = double(m.kd.eval(l)) + m.ks.eval(l) + m.kt.eval(l);
        const double exact = m.kd.source().eval(l) + m.ks.source().eval(l) + m.kt.source().eval(l);
        if (binned <= 1.0 + 1e-6 && exact <= 1.0 + 1e-6) continue;
        std::ostringstream msg;
        msg << who << ": kd + ks + kt = " << std::max(binned, exact) << " at " << l
            << " nm; expected at most 1 (a surface cannot reflect more than it receives)";
        throw SceneError(msg.str());
    }
}

std::optional<Hit> Scene::intersect_bvh(const Ray& ray, double t_best, int best_plane) const {
    BvhHit h;
    if (m_bvh.intersect(ray, {spheres, triangles}, t_best, h)) {
        const auto i = h.prim.index();
        if (h.prim.kind() == ShapeKind::triangle) return with_prim(triangles[i].make_hit(h.tri), ShapeKind::triangle, i);
        return with_prim(spheres[i].make_hit(ray, t_best), ShapeKind::sphere, i);
    }
    if (best_plane >= 0) return with_prim(planes[best_plane].make_hit(ray, t_best), ShapeKind::plane, best_plane);
    return std::nullopt;
}

bool Scene::occluded_bvh(const Ray& ray) const { return m_bvh.occluded(ray, {spheres, triangles}); }

void Scene::finalize() {
    const float big = 1e30f;
    for (const Material& m : materials) validate_material(m);
    auto check_material_index = [&](int index, const std::string& who) {
        require(index >= 0 && index < static_cast<int>(materials.size()),
                who + " refers to a material that does not exist");
    };
    for (const Sphere& s : spheres) {
        require(finite(s.center), "sphere centre must be finite");
        require(std::isfinite(s.radius) && s.radius > 0.f, "sphere radius must be > 0 and finite");
        check_material_index(s.material, "a sphere");
    }
    for (Plane& p : planes) p.set_frame();
    for (const Plane& p : planes) {
        require(finite(p.normal) && std::isfinite(p.offset), "plane must be finite");
        require(std::fabs(length(p.normal) - 1.f) < 1e-4f, "plane normal must be unit length");
        check_material_index(p.material, "a plane");
    }
    for (const Triangle& t : triangles) {
        require(finite(t.p0) && finite(t.p1) && finite(t.p2), "triangle vertices must be finite");
        require(!t.is_degenerate(), "triangle has zero area (collinear or repeated vertices)");
        check_material_index(t.material, "a triangle");
    }
    for (const PointLight& l : point_lights) {
        require(finite(l.position), "point light position must be finite");
        check_spectrum(l.intensity, "point light intensity", 0.f, big);
    }
    check_spectrum(background, "background radiance", 0.f, big);
    require(width > 0 && height > 0 && spp > 0, "image size and spp must be positive");
    require(finite(camera.position) && finite(camera.look_at) && finite(camera.up),
            "camera vectors must be finite");
    require(length(cross(camera.look_at - camera.position, camera.up)) > 0.f,
            "camera up vector must not be parallel to the viewing direction");
    require(camera.vfov_degrees > 0.f && camera.vfov_degrees < 180.f,
            "camera field of view must be in (0, 180) degrees");

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

    // Bounded shapes: a BVH once there are more than a handful (see kBvhThreshold).
    m_bvh = Bvh{};
    if (spheres.size() + triangles.size() > kBvhThreshold) m_bvh.build({spheres, triangles});
    m_use_bvh = !m_bvh.empty();
    m_sphere_lanes.build(m_use_bvh ? std::vector<Sphere>{} : spheres);
    std::vector<Sphere> bounds;
    if (!m_use_bvh)
        for (const Triangle& t : triangles) bounds.push_back(bounding_sphere(t));
    m_triangle_lanes.build(bounds);

    // Which effects are called for: only materials that some shape uses count.
    effects = Effects{};
    effects.point_lights = !point_lights.empty();
    effects.background = !background.is_zero();
    auto analyse = [&](int index) {
        const Material& m = materials[index];
        effects.emissive_surfaces |= m.is_emissive();
        effects.mirror |= m.has_mirror() || m.has_transmission();
        effects.transmission |= m.has_transmission();
        effects.dispersion |= m.is_dispersive();
    };
    for (const Sphere& s : spheres) analyse(s.material);
    for (const Plane& p : planes) analyse(p.material);
    for (const Triangle& t : triangles) analyse(t.material);
}

}  // namespace spt
