// Subpath generation, connection and MIS weights of bidirectional path tracing (see bdpt.h).
#include "render/bdpt.h"

#include <climits>

#include "render/bsdf.h"

namespace spt {

namespace {

enum class VertexType : unsigned char { camera, light, surface };
enum class Transport : unsigned char { radiance, importance };

struct Vertex {
    VertexType type = VertexType::surface;
    Hit hit;  ///< position, error bound, normal (zero: camera or point light), material
    Vec3 wo;  ///< towards the previous vertex of its own subpath (surface vertices)
    SampledSpectrum beta;
    float pdf_fwd = 0.f;  ///< area density of this vertex, sampled from its predecessor
    float pdf_rev = 0.f;  ///< area density of this vertex, sampled from its successor
    bool delta = false;          ///< a specular lobe was sampled here
    bool delta_light = false;    ///< point light origin (delta position)
    bool terminated = false;     ///< a dispersive refraction happened before this vertex
    /// The environment (a light vertex at infinity, measured by direction): `dir` is the unit
    /// direction from the scene towards it, and hit.p is not used.
    bool infinite = false;
    Vec3 dir;

    const Vec3& p() const { return hit.p; }
    bool on_surface() const { return hit.n.x != 0.f || hit.n.y != 0.f || hit.n.z != 0.f; }
};

/// Unit direction from one vertex towards another (a vertex at infinity is a direction).
Vec3 direction(const Vertex& from, const Vertex& to) {
    if (to.infinite) return to.dir;
    if (from.infinite) return -from.dir;
    return normalize(to.p() - from.p());
}

/// Solid-angle density at `from` turned into area density at `to`. The environment is
/// measured by direction: towards it the solid-angle density stays as it is, and from it the
/// density is planar (its disk, light_sampling.h), turned into area by the cosine at `to` only.
float convert_density(float pdf, const Vertex& from, const Vertex& to) {
    if (to.infinite) return pdf;
    if (from.infinite) return to.on_surface() ? pdf * std::fabs(dot(to.hit.n, from.dir)) : pdf;
    const Vec3 w = to.p() - from.p();
    const float d2 = length_squared(w);
    if (!(d2 > 0.f)) return 0.f;
    float result = pdf / d2;
    if (to.on_surface()) result *= std::fabs(dot(to.hit.n, w)) / std::sqrt(d2);
    return result;
}

class Bdpt {
public:
    Bdpt(const BdptContext& ctx, const SampledWavelengths& lambda, Rng& rng, PathStats& stats,
         std::vector<Vertex>& light, std::vector<Vertex>& camera)
        : m_ctx(ctx), m_scene(ctx.scene), m_lambda(lambda), m_rng(rng), m_stats(stats),
          m_hero(lambda.lambda[0]), m_light(light), m_camera(camera) {}

    SampledSpectrum run(const Ray& ray, std::vector<Splat>& splats);

private:
    bool connectible(const Vertex& v) const {
        return v.type != VertexType::surface || m_scene.materials[v.hit.material].has_diffuse();
    }
    void random_walk(Ray ray, SampledSpectrum beta, float pdf_dir, int max_vertices, Transport mode,
                     SampledWavelengths& lambda, std::vector<Vertex>& path);
    float pdf(const Vertex& v, const Vertex* prev, const Vertex& next) const;
    float light_direction_pdf(const Vertex& light, const Vertex& next) const;
    float mis_weight(int s, int t);
    bool visible(const Vertex& a, const Vertex& b);
    SampledSpectrum f(const Vertex& v, const Vec3& wi, const SampledWavelengths& lambda) const;

    const BdptContext& m_ctx;
    const Scene& m_scene;
    const SampledWavelengths& m_lambda;
    Rng& m_rng;
    PathStats& m_stats;
    float m_hero;
    std::vector<Vertex>& m_light;   ///< light subpath: the origin, then surface vertices
    std::vector<Vertex>& m_camera;  ///< camera subpath: the pinhole, surface vertices, and the
                                    ///< environment when the last ray escaped
};

/// Extends `path` from its last vertex along `ray`. pdf_dir is the density of the ray's
/// direction in solid angle, or planar (the disk) when the path starts at the environment.
void Bdpt::random_walk(Ray ray, SampledSpectrum beta, float pdf_dir, int max_vertices, Transport mode,
                       SampledWavelengths& lambda, std::vector<Vertex>& path) {
    const IntegratorSettings& settings = m_ctx.settings;
    float pdf_fwd = pdf_dir, eta_scale = 1.f;
    const float roulette_norm = 1.f / std::max(beta.max_value(), 1e-30f);
    int bounces = 0;
    while (static_cast<int>(path.size()) < max_vertices) {
        ++m_stats.rays;
        const std::optional<Hit> hit = m_scene.intersect(ray);
        if (!hit) {
            // A camera path that escapes ends on the environment, a light vertex at infinity.
            if (mode == Transport::radiance && m_scene.effects.background) {
                Vertex env;
                env.type = VertexType::light;
                env.infinite = true;
                env.dir = ray.d;
                env.beta = beta;
                env.terminated = lambda.secondary_terminated();
                env.pdf_fwd = pdf_fwd;  // solid angle (convert_density keeps it)
                path.push_back(env);
            }
            break;
        }
        Vertex v;
        v.hit = *hit;
        v.wo = -ray.d;
        v.beta = beta;
        v.terminated = lambda.secondary_terminated();
        v.pdf_fwd = convert_density(pdf_fwd, path.back(), v);
        path.push_back(v);
        const Material& mat = m_scene.materials[hit->material];
        if (!mat.reflects() || static_cast<int>(path.size()) == max_vertices) break;

        const float u_lobe = m_rng.uniform(), u1 = m_rng.uniform(), u2 = m_rng.uniform();
        const std::optional<BsdfSample> bs = sample_bsdf(mat, v.wo, hit->n, lambda, u_lobe, u1, u2);
        if (!bs) break;
        Vertex& cur = path.back();
        Vertex& prev = path[path.size() - 2];
        float pdf_rev;
        if (bs->is_specular) {
            cur.delta = true;
            pdf_fwd = pdf_rev = 0.f;
        } else {
            pdf_fwd = mis_pdf(mat, cur.wo, bs->wi, hit->n, m_hero);
            pdf_rev = mis_pdf(mat, bs->wi, cur.wo, hit->n, m_hero);
        }
        // Importance transport has no (η_i/η_t)² compression of radiance.
        if (mode == Transport::importance) beta *= bs->weight * bs->eta_scale;
        else beta *= bs->weight, eta_scale *= bs->eta_scale;
        prev.pdf_rev = convert_density(pdf_rev, cur, prev);
        ray = spawn_ray(cur.hit, bs->wi);

        // Roulette on throughput relative to the subpath's start (light paths start at power).
        if (settings.roulette && ++bounces >= settings.roulette_depth) {
            const float survive = std::min(0.95f, beta.max_value() * eta_scale * roulette_norm);
            if (!(m_rng.uniform() < survive)) break;
            beta /= survive;
        }
    }
}

SampledSpectrum Bdpt::f(const Vertex& v, const Vec3& wi, const SampledWavelengths& lambda) const {
    return eval_diffuse_f(m_scene.materials[v.hit.material], v.wo, wi, v.hit.n, lambda);
}

float Bdpt::light_direction_pdf(const Vertex& light, const Vertex& next) const {
    if (light.infinite)  // the disk point on the ray that reaches `next`
        return convert_density(m_ctx.lights.environment_position_pdf(next.p(), -light.dir), light, next);
    const Vec3 w = normalize(next.p() - light.p());
    const float pdf_dir = light.on_surface() ? LightSampler::direction_pdf(light.hit.n, w) : 1.f / (4.f * kPi);
    return convert_density(pdf_dir, light, next);
}

float Bdpt::pdf(const Vertex& v, const Vertex* prev, const Vertex& next) const {
    if (v.type == VertexType::light) return light_direction_pdf(v, next);
    const Vec3 wn = direction(v, next);
    if (v.type == VertexType::camera) {
        float x, y;
        if (!m_ctx.camera.raster_position(wn, x, y)) return 0.f;
        return convert_density(m_ctx.camera.direction_pdf(dot(wn, m_ctx.camera.forward())), v, next);
    }
    const Vec3 wp = direction(v, *prev);
    return convert_density(mis_pdf(m_scene.materials[v.hit.material], wp, wn, v.hit.n, m_hero), v, next);
}

/// Balance heuristic over all (s', t') with s' + t' = s + t, by walking the path with the
/// ratios of reverse to forward densities (pbrt-v3 MISWeight). Zero densities of delta
/// vertices are mapped to 1 and those strategies skipped. A camera vertex next to the
/// environment that its disk cannot reach (environment_position_pdf 0) is a true zero: no
/// strategy whose light subpath includes it exists, and the walk stops before it.
float Bdpt::mis_weight(int s, int t) {
    if (s + t == 2) return 1.f;
    Vertex* qs = s > 0 ? &m_light[s - 1] : nullptr;
    Vertex* pt = &m_camera[t - 1];
    Vertex* qs_minus = s > 1 ? &m_light[s - 2] : nullptr;
    Vertex* pt_minus = t > 1 ? &m_camera[t - 2] : nullptr;

    // The densities of the connection, computed here and restored on return.
    const float saved[4] = {pt->pdf_rev, pt_minus ? pt_minus->pdf_rev : 0.f, qs ? qs->pdf_rev : 0.f,
                            qs_minus ? qs_minus->pdf_rev : 0.f};
    const bool saved_delta[2] = {pt->delta, qs ? qs->delta : false};
    if (s > 0) {
        pt->pdf_rev = pdf(*qs, qs_minus, *pt);
        if (pt_minus) pt_minus->pdf_rev = pdf(*pt, qs, *pt_minus);
        qs->pdf_rev = pdf(*pt, pt_minus, *qs);
        if (qs_minus) qs_minus->pdf_rev = pdf(*qs, pt, *qs_minus);
        qs->delta = false;
    } else {
        pt->pdf_rev = pt->infinite ? m_ctx.lights.environment_pdf() : m_ctx.lights.origin_pdf(pt->hit);
        if (pt_minus) pt_minus->pdf_rev = light_direction_pdf(*pt, *pt_minus);
    }
    pt->delta = false;
    int camera_stop = 0;  // camera vertices i > camera_stop may belong to the light subpath
    if (s == 0 && pt->infinite && pt_minus && pt_minus->pdf_rev == 0.f) camera_stop = t - 2;
    if (s == 1 && qs->infinite && pt->pdf_rev == 0.f) camera_stop = t - 1;

    auto remap0 = [](float x) { return x != 0.f ? x : 1.f; };
    float sum_ri = 0.f, ri = 1.f;
    for (int i = t - 1; i > camera_stop; --i) {
        ri *= remap0(m_camera[i].pdf_rev) / remap0(m_camera[i].pdf_fwd);
        if (!m_camera[i].delta && !m_camera[i - 1].delta) sum_ri += ri;
    }
    ri = 1.f;
    for (int i = s - 1; i >= 0; --i) {
        ri *= remap0(m_light[i].pdf_rev) / remap0(m_light[i].pdf_fwd);
        const bool delta_before = i > 0 ? m_light[i - 1].delta : m_light[0].delta_light;
        if (!m_light[i].delta && !delta_before) sum_ri += ri;
    }

    pt->pdf_rev = saved[0];
    if (pt_minus) pt_minus->pdf_rev = saved[1];
    if (qs) qs->pdf_rev = saved[2], qs->delta = saved_delta[1];
    if (qs_minus) qs_minus->pdf_rev = saved[3];
    pt->delta = saved_delta[0];
    const float w = 1.f / (1.f + sum_ri);
    return std::isfinite(w) ? w : 0.f;
}

bool Bdpt::visible(const Vertex& a, const Vertex& b) {
    const Vec3 o = offset_ray_origin(a.p(), a.hit.p_err, a.hit.n, b.p() - a.p());
    const Vec3 target = offset_ray_origin(b.p(), b.hit.p_err, b.hit.n, o - b.p());
    const Vec3 d = target - o;
    const float dist = length(d);
    if (!(dist > 0.f)) return false;
    ++m_stats.rays;
    return !m_scene.occluded({o, d / dist, dist * (1.f - 1e-4f)});
}

SampledSpectrum Bdpt::run(const Ray& camera_ray, std::vector<Splat>& splats) {
    const IntegratorSettings& settings = m_ctx.settings;
    const int max_depth = settings.max_depth == IntegratorSettings::kUnbounded ? INT_MAX / 4 : settings.max_depth;
    const bool start_terminated = m_lambda.secondary_terminated();
    SampledWavelengths lambda_light = m_lambda, lambda_camera = m_lambda;
    m_light.clear();
    m_camera.clear();

    // ---- Light subpath (importance transport), traced first ----
    const float ul = m_rng.uniform(), ul1 = m_rng.uniform(), ul2 = m_rng.uniform(),
                ul3 = m_rng.uniform(), ul4 = m_rng.uniform(), ul5 = m_rng.uniform();
    if (const std::optional<LightOrigin> o = m_ctx.lights.sample(lambda_light, ul, ul1, ul2, ul3, ul4, ul5)) {
        Vertex v;
        v.type = VertexType::light;
        if (o->environment) {
            // The origin is the direction (pdf_dir, choice included); the disk point only
            // starts the walk, its planar density pdf_pos going to the first hit (pbrt-v3).
            v.infinite = true;
            v.dir = -o->w;
            v.beta = o->Le / o->pdf_dir;
            v.pdf_fwd = o->pdf_dir;
            m_light.push_back(v);
            if (!o->blocked)
                random_walk({o->p, o->w, kInfinity}, o->Le / (o->pdf_pos * o->pdf_dir), o->pdf_pos, max_depth + 1,
                            Transport::importance, lambda_light, m_light);
        } else {
            v.hit.p = o->p;
            v.hit.p_err = o->p_err;
            v.hit.n = o->n;
            v.beta = o->Le / o->pdf_pos;
            v.pdf_fwd = o->pdf_pos;
            v.delta_light = o->delta_position;
            m_light.push_back(v);
            const float cos_o = o->delta_position ? 1.f : std::fabs(dot(o->n, o->w));
            const SampledSpectrum beta = o->Le * (cos_o / (o->pdf_pos * o->pdf_dir));
            const Ray ray{offset_ray_origin(o->p, o->p_err, o->n, o->w), o->w, kInfinity};
            random_walk(ray, beta, o->pdf_dir, max_depth + 1, Transport::importance, lambda_light, m_light);
        }
    }

    // ---- Camera subpath (radiance transport) ----
    {
        Vertex v;
        v.type = VertexType::camera;
        v.hit.p = m_ctx.camera.origin();
        v.beta = SampledSpectrum(1.f);
        m_camera.push_back(v);
        const float pdf_dir = m_ctx.camera.direction_pdf(dot(camera_ray.d, m_ctx.camera.forward()));
        random_walk(camera_ray, SampledSpectrum(1.f), pdf_dir, max_depth + 2, Transport::radiance,
                    lambda_camera, m_camera);
    }

    // ---- Every connection, sorted by whether it kept the companions ----
    SampledSpectrum L_full(0.f), L_hero(0.f);
    auto accumulate = [&](const SampledSpectrum& c, bool terminated) {
        if (terminated && !start_terminated) L_hero[0] += c[0];
        else L_full += c;
    };
    const int n_light = static_cast<int>(m_light.size()), n_camera = static_cast<int>(m_camera.size());
    for (int t = 1; t <= n_camera; ++t) {
        for (int s = 0; s <= n_light; ++s) {
            const int depth = s + t - 2;
            if ((s == 1 && t == 1) || depth < 0 || depth > max_depth) continue;
            const Vertex& pt = m_camera[t - 1];
            const bool terminated = pt.terminated || (s > 0 && m_light[s - 1].terminated);
            if (pt.infinite) {
                // The camera path escaped: only s = 0 ends on the environment. Weight 1 when
                // the environment is not a light of the sampler (no power in 380–780 nm).
                if (s > 0) continue;
                const SampledSpectrum c = pt.beta * m_scene.background.sample(m_lambda);
                if (c.is_zero()) continue;
                accumulate(c * (m_ctx.lights.has_environment() ? mis_weight(0, t) : 1.f), terminated);
                continue;
            }
            if (s == 0) {
                // The camera path hits an emitter.
                const Material& mat = m_scene.materials[pt.hit.material];
                if (pt.type != VertexType::surface || !mat.is_emissive()) continue;
                const SampledSpectrum c = pt.beta * mat.emission.sample(m_lambda);
                if (c.is_zero()) continue;
                const float w = m_ctx.lights.origin_pdf(pt.hit) > 0.f ? mis_weight(0, t) : 1.f;
                accumulate(c * w, terminated);
                continue;
            }
            const Vertex& qs = m_light[s - 1];
            if (!connectible(qs)) continue;  // a sampled specular lobe does not matter here
            if (qs.infinite) {
                // s = 1 on the environment: towards the light subpath's direction (uniform over
                // the sphere, density environment_pdf), unoccluded to infinity.
                if (!connectible(pt)) continue;
                SampledSpectrum c = qs.beta * pt.beta * f(pt, qs.dir, m_lambda) * std::fabs(dot(pt.hit.n, qs.dir));
                if (c.is_zero()) continue;
                ++m_stats.rays;
                if (m_scene.occluded(spawn_ray(pt.hit, qs.dir))) continue;
                accumulate(c * mis_weight(1, t), terminated);
                continue;
            }
            if (t == 1) {
                // Light vertex seen by the pinhole: a splat on the pixel it projects to.
                const Vec3 to_camera = pt.p() - qs.p();
                const float dist2 = length_squared(to_camera);
                if (!(dist2 > 0.f)) continue;
                const Vec3 w_cam = to_camera / std::sqrt(dist2);  // from qs to the camera
                float px, py;
                if (!m_ctx.camera.raster_position(-w_cam, px, py)) continue;
                const float cos_cam = dot(-w_cam, m_ctx.camera.forward());
                SampledSpectrum c = qs.beta * (m_ctx.camera.importance(cos_cam) * cos_cam / dist2);
                if (qs.type == VertexType::surface) c *= f(qs, w_cam, m_lambda);
                if (qs.on_surface()) c *= std::fabs(dot(qs.hit.n, w_cam));
                if (c.is_zero() || !visible(qs, pt)) continue;
                c *= mis_weight(s, 1);
                SampledWavelengths lw = m_lambda;
                if (terminated) lw.terminate_secondary();
                const Xyz xyz = Cie1931::get().to_xyz(c, lw);
                const auto pixel = static_cast<std::uint32_t>(static_cast<int>(py) * m_ctx.width + static_cast<int>(px));
                splats.push_back({pixel, static_cast<float>(xyz.x), static_cast<float>(xyz.y),
                                  static_cast<float>(xyz.z)});
                continue;
            }
            if (!connectible(pt)) continue;
            const Vec3 d = qs.p() - pt.p();
            const float dist2 = length_squared(d);
            if (!(dist2 > 0.f)) continue;
            const Vec3 w_pt = d / std::sqrt(dist2);  // from pt towards qs
            SampledSpectrum c = qs.beta * pt.beta * f(pt, w_pt, m_lambda) / dist2;
            if (qs.type == VertexType::surface) c *= f(qs, -w_pt, m_lambda);
            if (qs.on_surface()) c *= std::fabs(dot(qs.hit.n, w_pt));
            c *= std::fabs(dot(pt.hit.n, w_pt));
            if (c.is_zero() || !visible(pt, qs)) continue;
            accumulate(c * mis_weight(s, t), terminated);
        }
    }
    // Strategies that kept only the hero count as after terminate_secondary() (pdf₀/K): fold
    // them into the hero channel of the unterminated set, which the film weighs by 1/(K·pdf₀).
    L_full[0] += static_cast<float>(kLambdaCount) * L_hero[0];
    return L_full;
}

}  // namespace

SampledSpectrum trace_bdpt(const BdptContext& ctx, const Ray& ray, const SampledWavelengths& lambda,
                           Rng& rng, PathStats& stats, std::vector<Splat>& splats) {
    // The vertex arrays of this thread are reused: no allocation per sample once warmed up.
    thread_local std::vector<Vertex> light_storage, camera_storage;
    Bdpt bdpt(ctx, lambda, rng, stats, light_storage, camera_storage);
    return bdpt.run(ray, splats);
}

}  // namespace spt
