// The scene's out-of-line intersection (scenes with a BVH or moving shapes) and the moving
// shapes of motion blur.
#include <algorithm>
#include <cmath>

#include "scene/scene.h"

namespace spt {

namespace {

float max_abs(const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

/// Takes the rest-frame hit of a moving shape to the world at the transform xf. The error
/// box: the rest box turned by a rotation fits in the ball of its half-diagonal, and the
/// transform's own rounding (a rotation through the quaternion, a few sums: well under 32
/// roundings) is bounded relative to the magnitudes involved. The same bound covers the
/// inverse transform of the next ray's origin, which is offset by this error.
Hit hit_to_world(const Hit& rest, const RigidTransform& xf) {
    Hit hit = rest;
    hit.p = xf.point(rest.p);
    const float turned = length(rest.p_err);
    const float scale = max_abs(rest.p - xf.pivot) * 1.7320508f + max_abs(xf.pivot) + max_abs(xf.translation) +
                        max_abs(hit.p);
    const float e = turned + gamma_bound(32) * scale;
    hit.p_err = Vec3(e, e, e);
    hit.n = normalize(xf.vector(rest.n));
    hit.ns = rest.ns == rest.n ? hit.n : normalize(xf.vector(rest.ns));
    return hit;
}

}  // namespace

void Scene::make_moving(const ShapeCounts& first, RigidMotion motion) {
    MovingShape shape;
    shape.motion = std::move(motion);
    for_each_array([&]<typename T>(std::vector<T>& all) {
        const auto begin = all.begin() + static_cast<std::ptrdiff_t>(first[std::size_t(shape_kind<T>)]);
        shape.shapes_of<T>().assign(begin, all.end());
        all.erase(begin, all.end());
    });
    moving_shapes.push_back(std::move(shape));
}

bool Scene::can_move_since(const ShapeCounts& first) const {
    bool can = true;
    for_each_array([&]<typename T>(const std::vector<T>& all) {
        if constexpr (!kCanMove<T>) can &= all.size() == first[std::size_t(shape_kind<T>)];
    });
    return can;
}

bool Scene::emits_since(const ShapeCounts& first) const {
    bool emits = false;
    for_each_array([&]<typename T>(const std::vector<T>& all) {
        for (std::size_t i = first[std::size_t(shape_kind<T>)]; i < all.size(); ++i) emits |= all[i].light >= 0;
    });
    return emits;
}

Aabb Scene::pivot_box_since(const ShapeCounts& first) const {
    Aabb box;
    for_each_array([&]<typename T>(const std::vector<T>& all) {
        if constexpr (kCanMove<T>)
            for (std::size_t i = first[std::size_t(shape_kind<T>)]; i < all.size(); ++i) box.expand(extent_box(all[i]));
    });
    return box;
}

std::optional<Hit> Scene::intersect_moving(std::size_t i, const Ray& ray, float time, double t_max) const {
    const MovingShape& m = moving_shapes[i];
    const Aabb& box = m.swept;
    const float* const bounds[2] = {&box.lo.x, &box.hi.x};
    if (!slab_hit(bounds, RaySlabs(ray), static_cast<float>(std::min(t_max, double(kInfinity))))) return std::nullopt;
    const RigidTransform xf = m.motion.at(time);
    // The rotation keeps lengths: t is the same along the rest-frame ray.
    const Ray rest{xf.inverse_point(ray.o), xf.inverse_vector(ray.d), ray.t_max};
    double t_best = t_max;
    PrimId best;
    TriangleIntersection best_ti{};
    if (!m.bvh.empty()) {
        BvhHit h;
        if (!m.bvh.intersect(rest, m.shapes(), t_best, h)) return std::nullopt;
        best = h.prim, best_ti = h.tri;
    } else {
        // Candidates by distance only, in the order of the shape types.
        m.for_each_array([&]<typename T>(const std::vector<T>& shapes) {
            for (std::size_t k = 0; k < shapes.size(); ++k) {
                if constexpr (std::is_same_v<T, Triangle>) {
                    if (auto ti = shapes[k].intersect(rest, t_best))
                        t_best = ti->t, best = PrimId(shape_kind<T>, std::uint32_t(k)), best_ti = *ti;
                } else if (const double t = shapes[k].intersect_t(rest); t < t_best) {
                    t_best = t, best = PrimId(shape_kind<T>, std::uint32_t(k));
                }
            }
        });
        if (!best.valid()) return std::nullopt;
    }
    const std::uint32_t k = best.index();
    const Hit hit = visit_shape_kind(best.kind(), [&]<typename T>(std::type_identity<T>) -> Hit {
        if constexpr (std::is_same_v<T, Triangle>) return triangle_hit(m.triangles[k], best_ti);
        else return m.shapes_of<T>()[k].make_hit(rest, t_best);
    });
    Hit world = hit_to_world(hit, xf);
    world.prim = PrimId(ShapeKind::moving, static_cast<std::uint32_t>(i));
    return world;
}

std::optional<Hit> Scene::intersect_out_of_line(const Ray& ray, double t_best, int best_plane, float time) const {
    std::optional<Hit> hit = m_use_bvh ? intersect_bvh(ray, t_best, best_plane) : intersect_few(ray, t_best, best_plane);
    double t_limit = hit ? double(hit->t) : double(ray.t_max);
    for (std::size_t i = 0; i < moving_shapes.size(); ++i)
        if (std::optional<Hit> h = intersect_moving(i, ray, time, t_limit)) hit = h, t_limit = h->t;
    return hit;
}

bool Scene::occluded_out_of_line(const Ray& ray, ShadowSkip skip, float time) const {
    if (m_use_bvh ? occluded_bvh(ray) : occluded_few(ray, skip)) return true;
    for (std::size_t i = 0; i < moving_shapes.size(); ++i)
        if (intersect_moving(i, ray, time, ray.t_max)) return true;
    return false;
}

}  // namespace spt
