// Subpath generation, connection and MIS weights of bidirectional path tracing (see bdpt.h).
#include "render/bdpt.h"

#include <climits>

#include "model/bsdfs/bsdf.h"
#include "render/bdpt_media.h"
#include "render/medium_tracking.h"

namespace spt {

namespace {

using Transport = TransportMode;
using Vertex = BdptVertex;
using VertexType = BdptVertexType;

/// Unit direction from one vertex towards another (a vertex at infinity is a direction).
Vec3 direction(const Vertex& from, const Vertex& to) {
    if (to.infinite) return to.dir;
    if (from.infinite) return -from.dir;
    return normalize(to.p() - from.p());
}

/// Solid-angle density at `from` turned into area density at `to`. An infinite light is
/// measured by direction: towards it the solid-angle density stays as it is, and from it the
/// density is planar (its disk, light_sampling.h), turned into area by the cosine at `to` only.
float convert_density(float pdf, const Vertex& from, const Vertex& to) {
    if (to.infinite) return pdf;
    if (to.type == VertexType::medium) pdf *= to.sigma_t;  // per unit volume: σt where a surface has |cos|
    if (from.infinite) return to.on_surface() ? pdf * std::fabs(dot(to.hit.n, from.dir)) : pdf;
    const Vec3 w = to.p() - from.p();
    const float d2 = length_squared(w);
    if (!(d2 > 0.f)) return 0.f;
    float result = pdf / d2;
    if (to.on_surface()) result *= std::fabs(dot(to.hit.n, w)) / std::sqrt(d2);
    return result;
}

/// One side's part of the MIS sum of a merge: constant + per_density·p, p the solid-angle
/// density with which the merge point's BSDF samples that side's direction from the other
/// side's. The two directions meet only per merge (camera vertex and photon), and for any
/// lobe but a Lambertian one p depends on both (Georgiev et al. 2012; SmallVCM evaluates the
/// camera's BSDF at the photon's direction for both densities).
struct MergeSideSum {
    float constant = 0.f, per_density = 0.f;
};

/// Importance transport with a shading normal that differs from the geometric one: the
/// adjoint BSDF gains |wo·ns||wi·ng| / (|wo·ng||wi·ns|) (Veach 1997, §5.3); 1 when ns = n.
float shading_correction(const Hit& hit, const Vec3& wo, const Vec3& wi) {
    if (hit.ns == hit.n) return 1.f;
    const float den = std::fabs(dot(wo, hit.n)) * std::fabs(dot(wi, hit.ns));
    if (!(den > 0.f)) return 0.f;
    return std::fabs(dot(wo, hit.ns)) * std::fabs(dot(wi, hit.n)) / den;
}

/// Densities of delta events are stored as 0; in ratios they cancel, as 1.
float remap0(float x) { return x != 0.f ? x : 1.f; }

/// Whether v scatters light on (a BSDF or a phase function): a surface or medium vertex.
bool scatters(const Vertex& v) { return v.type == VertexType::surface || v.type == VertexType::medium; }

/// The light of a light origin or emitter vertex, or nullptr.
const Light* light_of(const Scene& scene, const Vertex& light) {
    return light.hit.light >= 0 ? &scene.lights[static_cast<std::size_t>(light.hit.light)] : nullptr;
}
/// |cos| at an area light's origin towards w (unit), or 0 where the light does not emit along
/// w (the back of a one-sided light: its origins leave only by its front).
float emitting_cos(const Scene& scene, const Vertex& origin, const Vec3& w) {
    if (!light_emits_towards(scene.lights[static_cast<std::size_t>(origin.hit.light)], origin.hit.n, w)) return 0.f;
    return std::fabs(dot(origin.hit.n, w));
}
/// The delta-position light (point, spot) a light origin is, or nullptr.
const Light* delta_position_light_of(const Scene& scene, const Vertex& light) {
    const Light* l = light_of(scene, light);
    return l && light_type(*l) == LightType::delta_position ? l : nullptr;
}

class Bdpt {
public:
    /// eta: merging's density relative to a connection (MergeContext::eta); 0 without merging.
    Bdpt(const BdptContext& ctx, const SampledWavelengths& lambda, Rng& rng, PathStats& stats,
         std::vector<Vertex>& light, std::vector<Vertex>& camera, float eta = 0.f, float time = 0.f)
        : m_ctx(ctx), m_scene(ctx.scene), m_lambda(lambda), m_rng(rng), m_stats(stats),
          m_hero(lambda.lambda[0]), m_eta(eta), m_time(time), m_media(ctx.scene.effects.media), m_light(light),
          m_camera(camera), m_hero_only(lambda) {
        m_hero_only.terminate_secondary();
    }

    /// One bidirectional sample: both subpaths, every strategy.
    SampledSpectrum run(const Ray& ray, std::vector<Splat>& splats);
    /// Replaces the light subpath by a new one.
    void trace_light();
    /// Replaces the camera subpath: the pinhole, then the walk along `ray` (none if null).
    void trace_camera(const Ray* ray);
    /// The light-to-camera strategies (t = 1) of the current subpaths, as splats.
    void splat_light_tracing(std::vector<Splat>& splats);
    /// The strategies with t ≥ 2 of the current subpaths.
    SampledSpectrum connect();
    /// Merges each camera vertex with the photons around it.
    SampledSpectrum merge(const MergeContext& merge);
    /// Fills BdptVertex::mis_sum along a subpath (vertex merging's O(1) weights).
    void prefix_sums(std::vector<Vertex>& path, bool light_side) const;
    /// Everything connect() and merge() found so far, for Film::add_sample.
    SampledSpectrum result() const;

private:
    bool connectible(const Vertex& v) const {
        return v.type != VertexType::surface || m_scene.materials[v.hit.material].has_non_delta();
    }
    /// Whether merging may happen at v: a surface vertex with a non-delta lobe.
    bool mergeable(const Vertex& v) const {
        return v.type == VertexType::surface && !v.infinite && m_scene.materials[v.hit.material].has_non_delta();
    }
    /// `medium`: the one the ray starts in (scenes with media).
    void random_walk(Ray ray, SampledSpectrum beta, float pdf_dir, int max_vertices, Transport mode,
                     SampledWavelengths& lambda, std::vector<Vertex>& path, int medium = -1);
    bool scatter_in_medium(const FreeFlight& flight, const SampledSpectrum& beta, const SampledWavelengths& lambda,
                           int max_vertices, std::vector<Vertex>& path, Ray& ray, float& pdf_fwd);
    float pdf(const Vertex& v, const Vertex* prev, const Vertex& next) const;
    float light_direction_pdf(const Vertex& light, const Vertex& next) const;
    /// t_conn: the hero's transmittance of the connection (media), a factor of its densities.
    float mis_weight(int s, int t, float t_conn = 1.f);
    MergeSideSum camera_merge_sum(int t) const;
    float other_strategies(int s, int t, int camera_stop) const;
    bool visible(const Vertex& a, const Vertex& b);
    /// Scenes with media: the medium a ray leaving scattering vertex v along w travels in:
    /// a medium vertex's own; at a surface, the one the subpath arrived in on wo's side and
    /// the shape's declared one behind it (as the path tracer tracks media: a shape standing
    /// in a medium without naming its exterior reflects back into that medium).
    int medium_towards(const Vertex& v, const Vec3& w) const;
    /// Scenes with media: the transmittance from scattering vertex a to b (0 if blocked).
    Transmittance transmittance(const Vertex& a, const Vertex& b);
    SampledSpectrum f_cos(const Vertex& v, const Vec3& wi, const SampledWavelengths& lambda, Transport mode) const;
    /// The wavelengths a strategy's BSDF evaluations see: hero only once it terminated them
    /// (a dispersive transmission then evaluates to the hero's f, not K times it: bsdf.h).
    const SampledWavelengths& lambda_for(bool terminated) const { return terminated ? m_hero_only : m_lambda; }
    int max_depth() const;
    void accumulate(const SampledSpectrum& c, bool terminated);

    const BdptContext& m_ctx;
    const Scene& m_scene;
    const SampledWavelengths& m_lambda;
    Rng& m_rng;
    PathStats& m_stats;
    float m_hero;
    float m_eta;
    float m_time;  ///< of the sample: both subpaths and every connection see the scene then
    bool m_media;  ///< the scene has participating media (bdpt_media.h)
    std::vector<Vertex>& m_light;   ///< light subpath: the origin, then surface vertices
    std::vector<Vertex>& m_camera;  ///< camera subpath: the pinhole, surface vertices, and the
                                    ///< infinite lights' vertex when the last ray escaped
    SampledSpectrum m_L_full{0.f}, m_L_hero{0.f};  ///< contributions, by whether they kept the companions
    SampledWavelengths m_hero_only;                ///< m_lambda after terminate_secondary()
};

/// Extends `path` from its last vertex along `ray`. pdf_dir is the density of the ray's
/// direction in solid angle, or planar (the disk) when the path starts at an infinite light.
void Bdpt::random_walk(Ray ray, SampledSpectrum beta, float pdf_dir, int max_vertices, Transport mode,
                       SampledWavelengths& lambda, std::vector<Vertex>& path, int medium) {
    const IntegratorSettings& settings = m_ctx.settings;
    float pdf_fwd = pdf_dir, eta_scale = 1.f;
    const float roulette_norm = 1.f / std::max(beta.max_value(), 1e-30f);
    int bounces = 0;
    // Roulette on throughput relative to the subpath's start (light paths start at power).
    auto survives_roulette = [&]() {
        if (!settings.roulette || ++bounces < settings.roulette_depth) return true;
        const float survive = std::min(0.95f, beta.max_value() * eta_scale * roulette_norm);
        if (!(m_rng.uniform() < survive)) return false;
        beta /= survive;
        return true;
    };
    while (static_cast<int>(path.size()) < max_vertices) {
        std::optional<Hit> hit;
        float edge_T = 1.f;      // the hero's transmittance up to hit
        int medium_at_hit = -1;  // the medium the ray met the hit in
        if (m_media) {
            const FreeFlight flight = free_flight(m_scene, ray, medium, lambda, m_rng, m_stats);
            if (flight.chromatic) lambda.terminate_secondary();
            beta *= flight.weight;
            if (beta.is_zero()) break;
            if (flight.scattered) {
                medium = flight.medium;  // the walk goes on from there
                if (!scatter_in_medium(flight, beta, lambda, max_vertices, path, ray, pdf_fwd) || !survives_roulette())
                    break;
                continue;
            }
            hit = flight.hit;
            edge_T = flight.T_hero;
            medium_at_hit = flight.medium;
        } else {
            ++m_stats.rays;
            hit = m_scene.intersect(ray, m_time);
        }
        if (!hit) {
            // A camera path that escapes ends on the infinite lights, a light vertex at
            // infinity (connect() takes each light in turn: Vertex::hit.light).
            if (mode == Transport::radiance && m_scene.effects.background) {
                Vertex far;
                far.type = VertexType::light;
                far.infinite = true;
                far.dir = ray.d;
                far.beta = beta;
                far.terminated = lambda.secondary_terminated();
                far.pdf_fwd = pdf_fwd * edge_T;  // solid angle (convert_density keeps it)
                far.edge_T = edge_T;
                path.push_back(far);
            }
            break;
        }
        Vertex v;
        v.hit = *hit;
        v.wo = -ray.d;
        v.beta = beta;
        v.terminated = lambda.secondary_terminated();
        v.edge_T = edge_T;
        if (m_media) v.medium = medium_at_hit;
        v.pdf_fwd = convert_density(pdf_fwd, path.back(), v) * edge_T;
        path.push_back(v);
        const Material& mat = m_scene.materials[hit->material];
        if (!mat.reflects() || static_cast<int>(path.size()) == max_vertices) break;

        const float u_lobe = m_rng.uniform(), u1 = m_rng.uniform(), u2 = m_rng.uniform();
        const Bsdf& bsdf = m_scene.bsdf_at(*hit);
        const std::optional<BsdfSample> bs = bsdf_sample(bsdf, v.wo, hit->ns, lambda, u_lobe, u1, u2, mode);
        if (!bs) break;
        Vertex& cur = path.back();
        Vertex& prev = path[path.size() - 2];
        float pdf_rev;
        if (bs->is_delta()) {
            cur.delta = true;
            pdf_fwd = pdf_rev = 0.f;
        } else {
            pdf_fwd = bs->pdf;
            pdf_rev = bsdf_pdf(bsdf, bs->wi, cur.wo, hit->ns, m_hero);
        }
        // The BSDF weighs importance with the adjoint BSDF (no (η_i/η_t)² on refraction).
        beta *= bs->weight;
        if (mode == Transport::radiance) eta_scale *= bs->eta_scale;
        // Importance with shading normals: the adjoint's cosine factors (Veach 1997, §5.3).
        if (mode == Transport::importance) beta *= shading_correction(cur.hit, cur.wo, bs->wi);
        prev.pdf_rev = convert_density(pdf_rev, cur, prev) * cur.edge_T;
        ray = spawn_ray(cur.hit, bs->wi);
        if (m_media) medium = medium_towards(cur, bs->wi);
        if (!survives_roulette()) break;
    }
}

/// Appends the medium vertex where free flight scattered and samples the phase function
/// there (exactly: the throughput is unchanged), giving the next ray and its density.
/// False when the subpath ends at the vertex.
bool Bdpt::scatter_in_medium(const FreeFlight& flight, const SampledSpectrum& beta, const SampledWavelengths& lambda,
                             int max_vertices, std::vector<Vertex>& path, Ray& ray, float& pdf_fwd) {
    Vertex v;
    v.type = VertexType::medium;
    v.hit.p = flight.p;  // no normal: rays leave it without offset
    v.medium = flight.medium;
    v.sigma_t = flight.sigma_t_hero;
    v.edge_T = flight.T_hero;
    v.wo = -ray.d;
    v.beta = beta;
    v.terminated = lambda.secondary_terminated();
    v.pdf_fwd = convert_density(pdf_fwd, path.back(), v) * v.edge_T;
    path.push_back(v);
    if (static_cast<int>(path.size()) == max_vertices) return false;
    const HenyeyGreenstein& phase = m_scene.media[static_cast<std::size_t>(v.medium)].phase;
    const float u1 = m_rng.uniform(), u2 = m_rng.uniform();
    const Vec3 wi = phase.sample(v.wo, u1, u2);
    pdf_fwd = phase.eval(v.wo, wi);
    Vertex& prev = path[path.size() - 2];
    prev.pdf_rev = convert_density(phase.eval(wi, v.wo), path.back(), prev) * v.edge_T;
    ray = {v.p(), wi, kInfinity};
    return true;
}

/// f·|cos| at surface vertex v between v.wo and wi: radiance mode at camera vertices (light
/// arrives from wi), importance mode at light vertices (light arrives from v.wo and leaves
/// along wi: the adjoint BSDF, which differs from f where refraction scales radiance).
SampledSpectrum Bdpt::f_cos(const Vertex& v, const Vec3& wi, const SampledWavelengths& lambda, Transport mode) const {
    if (v.type == VertexType::medium)  // the phase function (σs is in the throughput)
        return SampledSpectrum(m_scene.media[static_cast<std::size_t>(v.medium)].phase.eval(v.wo, wi));
    return bsdf_eval(m_scene.bsdf_at(v.hit), v.wo, wi, v.hit.ns, lambda, mode);
}

float Bdpt::light_direction_pdf(const Vertex& light, const Vertex& next) const {
    if (light.infinite)  // the disk point on the ray that reaches `next`
        return convert_density(m_ctx.lights.infinite_position_pdf(light.hit.light, next.p(), -light.dir), light,
                               next);
    const Vec3 w = normalize(next.p() - light.p());
    const Light* l = light_of(m_scene, light);
    // An emitter that starts no subpath (the infinite plane) still answers as a two-sided
    // area emitter: the MIS weights ask for the density of its reverse direction.
    const float pdf_dir = l && light_can_start_subpath(*l) ? light_pdf_le_dir(*l, light.hit.n, w)
                                                           : two_sided_direction_pdf(light.hit.n, w);
    return convert_density(pdf_dir, light, next);
}

float Bdpt::pdf(const Vertex& v, const Vertex* prev, const Vertex& next) const {
    if (v.type == VertexType::light) return light_direction_pdf(v, next);
    const Vec3 wn = direction(v, next);
    if (v.type == VertexType::camera) {
        float x, y;
        if (!m_ctx.camera.raster_position(v.p(), wn, x, y)) return 0.f;
        return convert_density(m_ctx.camera.direction_pdf(dot(wn, m_ctx.camera.forward())), v, next);
    }
    const Vec3 wp = direction(v, *prev);
    if (v.type == VertexType::medium)
        return convert_density(m_scene.media[static_cast<std::size_t>(v.medium)].phase.eval(wp, wn), v, next);
    return convert_density(bsdf_pdf(m_scene.bsdf_at(v.hit), wp, wn, v.hit.ns, m_hero), v, next);
}

/// Balance heuristic over all (s', t') with s' + t' = s + t, by walking the path with the
/// ratios of reverse to forward densities (pbrt-v3 MISWeight). Zero densities of delta
/// vertices are mapped to 1 and those strategies skipped. A camera vertex next to an
/// infinite light that its disk cannot reach (infinite_position_pdf 0) is a true zero: no
/// strategy whose light subpath includes it exists, and the walk stops before it.
float Bdpt::mis_weight(int s, int t, float t_conn) {
    const IntegratorSettings& only = m_ctx.settings;
    if (only.bdpt_only_s >= 0 || only.bdpt_only_t >= 0)  // one strategy class alone (tests)
        return s == only.bdpt_only_s || t == only.bdpt_only_t || (s == 0 && t == 2) ? 1.f : 0.f;
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
        pt->pdf_rev = pdf(*qs, qs_minus, *pt) * t_conn;
        if (pt_minus) pt_minus->pdf_rev = pdf(*pt, qs, *pt_minus) * pt->edge_T;
        qs->pdf_rev = pdf(*pt, pt_minus, *qs) * t_conn;
        if (qs_minus) qs_minus->pdf_rev = pdf(*qs, pt, *qs_minus) * qs->edge_T;
        qs->delta = false;
    } else {
        pt->pdf_rev = pt->infinite ? m_ctx.lights.infinite_pdf(pt->hit.light, -pt->dir) : m_ctx.lights.origin_pdf(pt->hit);
        if (pt_minus) pt_minus->pdf_rev = light_direction_pdf(*pt, *pt_minus) * pt->edge_T;
    }
    pt->delta = false;
    int camera_stop = 0;  // camera vertices i > camera_stop may belong to the light subpath
    if (s == 0 && pt->infinite && pt_minus && pt_minus->pdf_rev == 0.f) camera_stop = t - 2;
    if (s == 1 && qs->infinite && pt->pdf_rev == 0.f) camera_stop = t - 1;
    const float others = other_strategies(s, t, camera_stop);

    pt->pdf_rev = saved[0];
    if (pt_minus) pt_minus->pdf_rev = saved[1];
    if (qs) qs->pdf_rev = saved[2], qs->delta = saved_delta[1];
    if (qs_minus) qs_minus->pdf_rev = saved[3];
    pt->delta = saved_delta[0];
    const float w = 1.f / (1.f + others);
    return std::isfinite(w) ? w : 0.f;
}

/// The sum of the densities of every other strategy for the path of light prefix s and camera
/// prefix t, relative to the density of (s, t): connections at each split whose two vertices
/// are not delta and, with merging, merges at each mergeable vertex that is not delta (a
/// merge at x has the density of the connection whose light prefix ends at x, times the
/// camera side's density of x, times eta). Merging starts at the second bounce of light
/// (light_index ≥ 2): direct light is next-event estimation's job, and leaving those photons
/// out halves the grid.
float Bdpt::other_strategies(int s, int t, int camera_stop) const {
    const bool merging = m_eta > 0.f;
    float sum = 0.f, ri = 1.f;
    for (int i = t - 1; i > camera_stop; --i) {
        const Vertex& v = m_camera[i];
        // Merges need a light subpath of three vertices or more (light_index ≥ 2).
        if (merging && i <= s + t - 3 && !v.delta && mergeable(v)) sum += ri * remap0(v.pdf_rev) * m_eta;
        ri *= remap0(v.pdf_rev) / remap0(v.pdf_fwd);
        if (!v.delta && !m_camera[i - 1].delta) sum += ri;
    }
    ri = 1.f;
    for (int i = s - 1; i >= 0; --i) {
        const Vertex& v = m_light[i];
        if (merging && i >= 2 && !v.delta && mergeable(v)) sum += ri * remap0(v.pdf_rev) * m_eta;
        ri *= remap0(v.pdf_rev) / remap0(v.pdf_fwd);
        const bool delta_before = i > 0 ? m_light[i - 1].delta : m_light[0].delta_light;
        if (!v.delta && !delta_before) sum += ri;
    }
    return sum;
}

/// S_k = r_k·S_(k−1) + term_k along a subpath, with r_k = rev_k/fwd_k (delta zeros mapped
/// to 1) and term_k the strategies that split at vertex k: a connection between k − 1 and k
/// (neither delta: r_k) and a merge at k (rev_k·eta). S_k is other_strategies' sum for the
/// subpath ending at k, computed once per vertex; it is exact as long as the stored reverse
/// densities are, i.e. up to two vertices before the end a merge connects (those two are
/// redone per merge in merge_weight). Light side: merges from light index 2; camera side:
/// any index ≥ 1 (a merge's light side has at least three vertices).
void Bdpt::prefix_sums(std::vector<Vertex>& path, bool light_side) const {
    float sum = 0.f;
    for (std::size_t k = 0; k < path.size(); ++k) {
        Vertex& v = path[k];
        if (!light_side && k == 0) {
            v.mis_sum = 0.f;
            continue;
        }
        const float r = remap0(v.pdf_rev) / remap0(v.pdf_fwd);
        const bool delta_before = k > 0 ? path[k - 1].delta : v.delta_light;
        const bool merge_here = (!light_side || k >= 2) && !v.delta && mergeable(v);
        sum = r * sum + (merge_here ? remap0(v.pdf_rev) * m_eta : 0.f) + (!v.delta && !delta_before ? r : 0.f);
        v.mis_sum = sum;
    }
}

/// The camera side of the MIS sum of a merge at c = m_camera[t − 1], including the
/// reference strategy (the constant: 1 if it exists). The merged path is the photon's light
/// prefix followed by the camera prefix before c (c and the photon coincide within the
/// radius); its densities are taken relative to the connection of the photon with
/// pt = m_camera[t − 2], itself a strategy only if pt is not delta. Densities that depend on
/// both sides use c's geometry and material for the photon's (as SmallVCM does): pt's density
/// of pt_minus with the light arriving from c, and (per merge, the per_density part) c's
/// density of the direction towards pt with the light arriving along the photon's.
MergeSideSum Bdpt::camera_merge_sum(int t) const {
    if (t < 3) return {1.f, 0.f};  // pt is the camera: light tracing is the reference
    const Vertex& c = m_camera[t - 1];
    const Vertex& pt = m_camera[t - 2];
    const Vertex& pt_minus = m_camera[t - 3];
    float before_pt = 0.f;  // the sum up to pt_minus
    if (t >= 4) {
        const Vertex& pt_minus2 = m_camera[t - 4];
        const float rev = remap0(pt.delta ? pt_minus.pdf_rev : pdf(pt, &c, pt_minus));
        const float r = rev / remap0(pt_minus.pdf_fwd);
        before_pt = r * pt_minus2.mis_sum + (!pt_minus.delta && mergeable(pt_minus) ? rev * m_eta : 0.f) +
                    (!pt_minus.delta && !pt_minus2.delta ? r : 0.f);
    }
    // pt's reverse density is g·p (area per solid angle at pt); every term below is ∝ it.
    const float g = convert_density(1.f, c, pt), fwd = remap0(pt.pdf_fwd);
    const float per_density = g * (before_pt / fwd + (!pt.delta && mergeable(pt) ? m_eta : 0.f) +
                                   (!pt.delta && !pt_minus.delta ? 1.f / fwd : 0.f));
    return {pt.delta ? 0.f : 1.f, per_density};
}

bool Bdpt::visible(const Vertex& a, const Vertex& b) {
    const Ray ray = spawn_ray_between(a.p(), a.hit.p_err, a.hit.n, b.p(), b.hit.p_err, b.hit.n);
    if (!(ray.t_max > 0.f)) return false;
    ++m_stats.rays;
    return !m_scene.occluded(ray, {}, m_time);
}

int Bdpt::medium_towards(const Vertex& v, const Vec3& w) const {
    if (v.type == VertexType::medium) return v.medium;
    const Vec3& n = v.hit.n;
    return dot(w, n) * dot(v.wo, n) < 0.f ? m_scene.medium_interface(v.hit.prim).after(n, w) : v.medium;
}

Transmittance Bdpt::transmittance(const Vertex& a, const Vertex& b) {
    const Ray ray = b.infinite ? spawn_ray(a.hit, b.dir)
                               : spawn_ray_between(a.p(), a.hit.p_err, a.hit.n, b.p(), b.hit.p_err, b.hit.n);
    if (!(ray.t_max > 0.f)) return {SampledSpectrum(0.f), false};
    return connection_transmittance(m_scene, ray, medium_towards(a, ray.d), m_lambda, m_stats);
}

int Bdpt::max_depth() const {
    const int d = m_ctx.settings.max_depth;
    return d == IntegratorSettings::kUnbounded ? INT_MAX / 4 : d;
}

void Bdpt::trace_light() {
    SampledWavelengths lambda_light = m_lambda;  // its own termination state
    m_light.clear();
    const float ul = m_rng.uniform(), ul1 = m_rng.uniform(), ul2 = m_rng.uniform(),
                ul3 = m_rng.uniform(), ul4 = m_rng.uniform(), ul5 = m_rng.uniform();
    const std::optional<LightOrigin> o = m_ctx.lights.sample(lambda_light, ul, ul1, ul2, ul3, ul4, ul5, m_time);
    if (!o) return;
    Vertex v;
    v.type = VertexType::light;
    if (o->infinite) {
        // The origin is the direction (pdf_dir, choice included); the disk point only
        // starts the walk, its planar density pdf_pos going to the first hit (pbrt-v3).
        v.infinite = true;
        v.hit.light = o->light;
        v.dir = -o->w;
        v.beta = o->Le / o->pdf_dir;
        v.pdf_fwd = o->pdf_dir;
        m_light.push_back(v);
        const int medium = m_media ? medium_at(m_scene, m_ctx.camera.origin(), o->p, m_stats) : -1;
        SampledSpectrum beta = o->Le / (o->pdf_pos * o->pdf_dir);
        // A medium at the disk fills all space beyond it: the light crosses an infinite
        // stretch of it before the disk, and the path tracer's rays never escape it either.
        if (medium >= 0) {
            SampledSpectrum sigma_a, sigma_s;
            m_scene.media[static_cast<std::size_t>(medium)].coefficients(lambda_light, sigma_a, sigma_s);
            beta *= majorant_transmittance(sigma_a + sigma_s, kInfinity);
        }
        if (!o->blocked && !beta.is_zero())
            random_walk({o->p, o->w, kInfinity}, beta, o->pdf_pos, max_depth() + 1, Transport::importance,
                        lambda_light, m_light, medium);
        return;
    }
    v.hit.p = o->p;
    v.hit.p_err = o->p_err;
    v.hit.n = o->n;
    v.hit.light = o->light;
    v.beta = o->Le / o->pdf_pos;
    // A delta-position light's falloff belongs to each direction (Le has the sampled one's):
    // s = 1 applies it.
    if (const Light* l = delta_position_light_of(m_scene, v)) v.beta = light_I_max(*l, lambda_light) / o->pdf_pos;
    v.pdf_fwd = o->pdf_pos;
    v.delta_light = o->delta_position;
    m_light.push_back(v);
    const float cos_o = o->delta_position ? 1.f : std::fabs(dot(o->n, o->w));
    const SampledSpectrum beta = o->Le * (cos_o / (o->pdf_pos * o->pdf_dir));
    const Ray ray{offset_ray_origin(o->p, o->p_err, o->n, o->w), o->w, kInfinity};
    const int medium = m_media ? medium_at(m_scene, m_ctx.camera.origin(), ray.o, m_stats) : -1;
    random_walk(ray, beta, o->pdf_dir, max_depth() + 1, Transport::importance, lambda_light, m_light, medium);
}

void Bdpt::trace_camera(const Ray* camera_ray) {
    SampledWavelengths lambda_camera = m_lambda;
    m_camera.clear();
    Vertex v;
    v.type = VertexType::camera;
    v.hit.p = camera_ray ? camera_ray->o : m_ctx.camera.origin();  // the lens point of a thin lens
    v.beta = SampledSpectrum(1.f);
    m_camera.push_back(v);
    if (!camera_ray) return;
    const float pdf_dir = m_ctx.camera.direction_pdf(dot(camera_ray->d, m_ctx.camera.forward()));
    random_walk(*camera_ray, SampledSpectrum(1.f), pdf_dir, max_depth() + 2, Transport::radiance,
                lambda_camera, m_camera, m_scene.camera_medium);
}

void Bdpt::splat_light_tracing(std::vector<Splat>& splats) {
    Vertex& pt = m_camera[0];
    const Vec3 camera_p = pt.p();  // restored at the end: a thin lens moves pt per splat
    const bool lens = m_ctx.camera.thin_lens();
    const int n_light = static_cast<int>(m_light.size());
    for (int s = 2; s <= n_light && s - 1 <= max_depth(); ++s) {
        const Vertex& qs = m_light[s - 1];
        if (!connectible(qs)) continue;  // a sampled specular lobe does not matter here
        // A thin lens: a lens point of its own per splat, uniform as the camera rays' (so
        // that its density cancels in the MIS ratios, as in pbrt-v3's Sample_Wi).
        if (lens) {
            const float u1 = m_rng.uniform();
            pt.hit.p = m_ctx.camera.lens_point(u1, m_rng.uniform());
        }
        // Light vertex seen by the pinhole (the lens point): a splat on the pixel it projects to.
        const Vec3 to_camera = pt.p() - qs.p();
        const float dist2 = length_squared(to_camera);
        if (!(dist2 > 0.f)) continue;
        const Vec3 w_cam = to_camera / std::sqrt(dist2);  // from qs to the camera
        float px, py;
        if (!m_ctx.camera.raster_position(pt.p(), -w_cam, px, py)) continue;
        const float cos_cam = dot(-w_cam, m_ctx.camera.forward());
        bool terminated = qs.terminated;
        Transmittance tr;  // without media: 1, and visibility is tested below
        if (m_media) {
            tr = transmittance(qs, pt);
            if (tr.T.is_zero()) continue;
            terminated |= tr.chromatic;
        }
        SampledSpectrum c = qs.beta * tr.T * (m_ctx.camera.importance(cos_cam) * cos_cam / dist2);
        if (scatters(qs))
            c *= f_cos(qs, w_cam, lambda_for(terminated), Transport::importance) *
                 shading_correction(qs.hit, qs.wo, w_cam);
        else if (qs.on_surface()) c *= emitting_cos(m_scene, qs, w_cam);  // an area light's origin
        if (c.is_zero() || (!m_media && !visible(qs, pt))) continue;
        c *= mis_weight(s, 1, tr.T[0]);
        SampledWavelengths lw = m_lambda;
        if (terminated) lw.terminate_secondary();
        const Xyz xyz = m_ctx.observer->to_xyz(c, lw);
        const auto pixel = static_cast<std::uint32_t>(static_cast<int>(py) * m_ctx.width + static_cast<int>(px));
        splats.push_back({pixel, static_cast<float>(xyz.x), static_cast<float>(xyz.y), static_cast<float>(xyz.z)});
    }
    pt.hit.p = camera_p;
}

void Bdpt::accumulate(const SampledSpectrum& c, bool terminated) {
    if (terminated && !m_lambda.secondary_terminated()) m_L_hero[0] += c[0];
    else m_L_full += c;
}

SampledSpectrum Bdpt::connect() {
    const int n_light = static_cast<int>(m_light.size()), n_camera = static_cast<int>(m_camera.size());
    for (int t = 2; t <= n_camera; ++t) {
        for (int s = 0; s <= n_light; ++s) {
            const int depth = s + t - 2;
            if (depth > max_depth()) continue;
            const Vertex& pt = m_camera[t - 1];
            bool terminated = pt.terminated || (s > 0 && m_light[s - 1].terminated);
            if (pt.infinite) {
                // The camera path escaped: only s = 0 ends on the infinite lights, each with its
                // own densities (the vertex names the light in turn). Weight 1 for a light the
                // sampler never chooses (no power in 380–780 nm).
                if (s > 0) continue;
                for (int light : m_scene.infinite_light_indices) {
                    const SampledSpectrum c =
                        pt.beta * light_arriving(m_scene.lights[static_cast<std::size_t>(light)], pt.dir, m_lambda);
                    if (c.is_zero()) continue;
                    m_camera[t - 1].hit.light = light;
                    accumulate(c * (m_ctx.lights.infinite_pdf(light, -pt.dir) > 0.f ? mis_weight(0, t) : 1.f),
                               terminated);
                }
                continue;
            }
            if (s == 0) {
                // The camera path hits an emitter.
                if (pt.type != VertexType::surface || pt.hit.light < 0) continue;
                const SampledSpectrum c = pt.beta * m_scene.emitted<true>(pt.hit, pt.wo, m_lambda);
                if (c.is_zero()) continue;
                const float w = m_ctx.lights.origin_pdf(pt.hit) > 0.f ? mis_weight(0, t) : 1.f;
                accumulate(c * w, terminated);
                continue;
            }
            const Vertex& qs = m_light[s - 1];
            if (!connectible(qs) || !connectible(pt)) continue;
            Transmittance tr;  // without media: 1, and visibility is tested below
            if (m_media) {
                tr = transmittance(pt, qs);
                if (tr.T.is_zero()) continue;
                terminated |= tr.chromatic;
            }
            if (qs.infinite) {
                // s = 1 on an infinite light: towards the light subpath's direction (density
                // infinite_pdf), unoccluded to infinity.
                SampledSpectrum c =
                    qs.beta * pt.beta * tr.T * f_cos(pt, qs.dir, lambda_for(terminated), Transport::radiance);
                if (c.is_zero()) continue;
                if (!m_media) {
                    ++m_stats.rays;
                    if (m_scene.occluded(spawn_ray(pt.hit, qs.dir), {}, m_time)) continue;
                }
                accumulate(c * mis_weight(1, t, tr.T[0]), terminated);
                continue;
            }
            const Vec3 d = qs.p() - pt.p();
            const float dist2 = length_squared(d);
            if (!(dist2 > 0.f)) continue;
            const Vec3 w_pt = d / std::sqrt(dist2);  // from pt towards qs
            const SampledWavelengths& lw = lambda_for(terminated);
            SampledSpectrum c = qs.beta * pt.beta * tr.T * f_cos(pt, w_pt, lw, Transport::radiance) / dist2;
            if (scatters(qs))
                c *= f_cos(qs, -w_pt, lw, Transport::importance) * shading_correction(qs.hit, qs.wo, -w_pt);
            else if (qs.on_surface()) c *= emitting_cos(m_scene, qs, -w_pt);  // an area light's origin
            else if (const Light* l = delta_position_light_of(m_scene, qs)) c *= light_falloff(*l, -w_pt);
            if (c.is_zero() || (!m_media && !visible(pt, qs))) continue;
            accumulate(c * mis_weight(s, t, tr.T[0]), terminated);
        }
    }
    return result();
}

/// Merging at camera vertex c with photon q: contribution f(c)·β_c·β_q/(π r² N) times the
/// balance weight merge/(camera side + light side + merge), all densities relative to the
/// connection of q with the camera vertex before c. The merge's own density is the camera's
/// density of c times eta; the light side is the photon's sum (make_photon) times the same
/// camera density. Both sides' sums depend on c's BSDF density between c.wo and the photon's
/// wo, in either order: evaluated per merge. Photons arriving on the other side of the
/// surface merge where the material transmits (the MIS sums count a merge at every mergeable
/// vertex, transmitting or not).
SampledSpectrum Bdpt::merge(const MergeContext& mc) {
    const float inv_eta = 1.f / mc.eta;
    const int n_camera = static_cast<int>(m_camera.size());
    for (int t = 2; t <= n_camera; ++t) {
        const Vertex& c = m_camera[t - 1];
        if (!mergeable(c) || c.beta.is_zero()) continue;
        const MergeSideSum camera_sum = camera_merge_sum(t);  // before bsdf_at(c): it may use the scratch
        const Bsdf& bsdf = m_scene.bsdf_at(c.hit);
        const bool transmits = m_scene.materials[c.hit.material].flags.has(BsdfFlags::transmission);
        const float cos_o = dot(c.wo, c.hit.n);
        const float camera_density = remap0(c.pdf_fwd);
        const float merge_density = camera_density * mc.eta;
        mc.grid.query(c.p(), [&](std::uint32_t j, float) {
            const MergeContext::Photon& q = mc.photons[j];
            // Only photons on surfaces facing the same way (not a corner's other face),
            // arriving on c's side unless c transmits, within the depth limit (a merge at
            // (s, t) has the depth of the connection (s, t − 1)).
            if (q.s + t - 3 > max_depth() || dot(q.n, c.hit.n) < 0.5f) return;
            if (!transmits && cos_o * dot(q.wo, c.hit.n) <= 0.f) return;
            const float to_light = bsdf_pdf(bsdf, c.wo, q.wo, c.hit.ns, m_hero);
            const float to_camera = bsdf_pdf(bsdf, q.wo, c.wo, c.hit.ns, m_hero);
            const float camera_side = camera_sum.constant + camera_sum.per_density * to_camera + merge_density;
            const float light_side = camera_density * (q.light_connection + q.light_per_density * to_light);
            const float w = merge_density / (camera_side + light_side);
            if (!(w > 0.f) || !std::isfinite(w)) return;
            // f without the cosine: the photon's throughput is flux arriving at its point.
            const float cos_q = std::fabs(dot(q.wo, c.hit.ns));
            if (!(cos_q > 0.f)) return;
            const SampledSpectrum f =
                bsdf_eval(bsdf, c.wo, q.wo, c.hit.ns, lambda_for(c.terminated || q.terminated), TransportMode::radiance) /
                cos_q;
            accumulate(c.beta * f * q.beta * (w * inv_eta), c.terminated || q.terminated);
        });
    }
    return result();
}

// Strategies that kept only the hero count as after terminate_secondary() (pdf₀/K): fold
// them into the hero channel of the unterminated set, which the film weighs by 1/(K·pdf₀).
SampledSpectrum Bdpt::result() const {
    SampledSpectrum L = m_L_full;
    L[0] += static_cast<float>(kLambdaCount) * m_L_hero[0];
    return L;
}

SampledSpectrum Bdpt::run(const Ray& camera_ray, std::vector<Splat>& splats) {
    trace_light();
    trace_camera(&camera_ray);
    splat_light_tracing(splats);
    return connect();
}

}  // namespace

SampledSpectrum trace_bdpt(const BdptContext& ctx, const Ray& ray, float time, const SampledWavelengths& lambda,
                           Rng& rng, PathStats& stats, std::vector<Splat>& splats) {
    // The vertex arrays of this thread are reused: no allocation per sample once warmed up.
    thread_local std::vector<Vertex> light_storage, camera_storage;
    Bdpt bdpt(ctx, lambda, rng, stats, light_storage, camera_storage, 0.f, time);
    return bdpt.run(ray, splats);
}

void trace_light_subpath(const BdptContext& ctx, const SampledWavelengths& lambda, float eta, Rng& rng,
                         PathStats& stats, std::vector<BdptVertex>& out, std::vector<Splat>& splats) {
    thread_local std::vector<Vertex> light_storage, camera_storage;
    Bdpt bdpt(ctx, lambda, rng, stats, light_storage, camera_storage, eta);
    bdpt.trace_light();
    bdpt.trace_camera(nullptr);
    bdpt.splat_light_tracing(splats);
    bdpt.prefix_sums(light_storage, true);
    out.insert(out.end(), light_storage.begin(), light_storage.end());
}

SampledSpectrum trace_camera_subpath(const BdptContext& ctx, const MergeContext& merge,
                                     std::uint32_t light_path, const Ray& ray,
                                     const SampledWavelengths& lambda, Rng& rng, PathStats& stats) {
    thread_local std::vector<Vertex> light_storage, camera_storage;
    Bdpt bdpt(ctx, lambda, rng, stats, light_storage, camera_storage, merge.eta);
    bdpt.trace_camera(&ray);
    light_storage.assign(merge.vertices.begin() + merge.path_begin[light_path],
                         merge.vertices.begin() + merge.path_begin[light_path + 1]);
    bdpt.connect();
    bdpt.prefix_sums(camera_storage, false);
    return bdpt.merge(merge);
}

MergeContext::Photon make_photon(const Scene& scene, const BdptVertex* path, int s, float eta) {
    const BdptVertex& q = path[s - 1];
    const BdptVertex& q_minus = path[s - 2];
    MergeContext::Photon photon;
    photon.p = q.p();
    photon.n = q.hit.n;
    photon.wo = q.wo;
    photon.beta = q.beta;
    photon.s = s;
    photon.terminated = q.terminated;
    // Light side of other_strategies' walk for the merged path, from q_minus down: q_minus's
    // reverse density is g·p, p the merge point's BSDF density of wo from the camera's
    // direction (per merge: Bdpt::merge), and every term of q_minus's sum is ∝ it; the
    // connection of q_minus with the merge point is the constant. q's density is the
    // camera's density of c, a factor the caller applies.
    const float g = convert_density(1.f, q, q_minus), fwd = remap0(q_minus.pdf_fwd);
    const bool delta_before = s - 2 > 0 ? path[s - 3].delta : q_minus.delta_light;
    const bool merge_q_minus = s - 2 >= 2 && !q_minus.delta && q_minus.type == BdptVertexType::surface &&
                               !q_minus.infinite && scene.materials[q_minus.hit.material].has_non_delta();
    const float per_density = g * (path[s - 3].mis_sum / fwd + (merge_q_minus ? eta : 0.f) +
                                   (!q_minus.delta && !delta_before ? 1.f / fwd : 0.f));
    photon.light_connection = (!q_minus.delta ? 1.f : 0.f) / remap0(q.pdf_fwd);
    photon.light_per_density = per_density / remap0(q.pdf_fwd);
    return photon;
}

}  // namespace spt
