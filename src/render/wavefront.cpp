// The wavefront stages: the path kernel's phases (integrator.cpp's path_loop) run for many
// paths at a time, with each path's state kept in PathState between stages. The phases call
// the same per-vertex steps (render/path_vertex.h); next-event estimation is split in two
// (render/direct_light.h) so that the shadow rays are traced in a stage of their own.
#include "render/wavefront.h"

#include <algorithm>

#include "model/bsdfs/bsdf.h"
#include "render/direct_light.h"
#include "render/light_context.h"
#include "render/path_vertex.h"
#include "render/pixel_sample.h"

namespace spt {

namespace {
/// Paths per chunk: a chunk is one task of a stage (its queue pop and its completion cost
/// about a microsecond, the chunk's work some tens).
constexpr int kChunkPaths = 512;
}  // namespace

/// One path between stages: path_loop's local variables.
struct Wavefront::PathState {
    Ray ray;
    Rng rng{0, 0, 0};
    SampledWavelengths lambda;
    float time = 0.f;
    SampledSpectrum L{0.f}, beta{1.f};
    SampledSpectrum beta_nee{0.f};  ///< beta at the vertex whose light samples await the shadow stage
    float eta_scale = 1.f;
    int depth = 0;
    EmissionMis mis;
    Hit hit;
};

/// A light sample waiting for its shadow ray, with what it adds if the ray is clear.
struct Wavefront::ShadowRay {
    Ray ray;
    ShadowSkip skip;
    SampledSpectrum contribution;
    bool past_planes = false;  ///< as spt::ShadowRay::past_planes
};

/// The light samples of one path's vertex: its point and spot lights' rays, then (area) the
/// one light chosen by NeeLightChoice (its ray last, if it has one).
struct Wavefront::NeeRecord {
    std::uint32_t path;
    std::uint32_t first_ray, point_rays;
    bool point, area, area_ray;
};

/// What one chunk of a stage produced: the paths for the next stage and the light samples.
struct Wavefront::ChunkQueues {
    std::vector<std::uint32_t> paths;
    std::vector<NeeRecord> nee;
    std::vector<ShadowRay> rays;
};

const char* wavefront_unsupported(const Scene& scene, const IntegratorSettings& settings, SamplerKind sampler) {
    if (settings.kind != IntegratorKind::path) return "the bdpt and vcm integrators";
    if (scene.effects.media) return "participating media";
    if (scene.effects.textures) return "textures";
    if (scene.effects.fluorescence) return "fluorescence";
    if (sampler != SamplerKind::independent) return "the sobol sampler";
    if (scene.effects.caustic_spheres && settings.caustic_nee && settings.light_sampling == LightSampling::mis)
        return "specular next-event estimation through or off spheres (add --caustic-nee off)";
    return nullptr;
}

Wavefront::Wavefront(const Scene& scene, const RenderSettings& settings, const Camera& camera, Film& film)
    : m_scene(scene), m_settings(settings), m_camera(camera), m_film(film) {}

Wavefront::~Wavefront() = default;

void Wavefront::begin_pass(int first_sample, int end_sample) {
    m_first_sample = first_sample;
    m_end_sample = end_sample;
    m_next_pixel = 0;
    m_stage = Stage::idle;
}

int Wavefront::chunks_of(std::size_t items) const {
    return static_cast<int>((items + kChunkPaths - 1) / kChunkPaths);
}

void Wavefront::gather(std::vector<std::uint32_t>& queue) {
    queue.clear();
    for (int k = 0; k < m_stage_chunks; ++k) {
        const std::vector<std::uint32_t>& part = m_chunk_queues[static_cast<std::size_t>(k)].paths;
        queue.insert(queue.end(), part.begin(), part.end());
    }
}

int Wavefront::next_stage() {
    const int spp = m_end_sample - m_first_sample;
    const int pixels = m_settings.width * m_settings.height;
    switch (m_stage) {
    case Stage::idle:
    case Stage::accumulate: {
        if (m_next_pixel >= pixels) {
            m_stage = Stage::idle;
            return 0;
        }
        // A batch of whole pixels, so that each pixel's samples reach the film in order.
        m_batch_pixel = m_next_pixel;
        m_batch_pixels = std::min(pixels - m_next_pixel, std::max(1, m_settings.wavefront_batch / spp));
        m_next_pixel += m_batch_pixels;
        const std::size_t n = std::size_t(m_batch_pixels) * spp;
        m_paths.resize(n);
        m_queue.resize(n);
        for (std::size_t i = 0; i < n; ++i) m_queue[i] = static_cast<std::uint32_t>(i);
        if (m_chunk_queues.size() < static_cast<std::size_t>(chunks_of(n))) m_chunk_queues.resize(chunks_of(n));
        m_stage = Stage::generate;
        return m_stage_chunks = chunks_of(n);
    }
    case Stage::generate:
        m_stage = Stage::intersect;  // every path of the batch (m_queue as generate left it)
        return m_stage_chunks = chunks_of(m_queue.size());
    case Stage::intersect:
        gather(m_queue);
        if (m_queue.empty()) break;
        m_stage = Stage::shade;
        return m_stage_chunks = chunks_of(m_queue.size());
    case Stage::shade:
        // The shadow stage takes each shade chunk's light samples (m_stage_chunks unchanged);
        // the paths that go on wait in m_queue for the next intersection.
        gather(m_queue);
        m_stage = Stage::shadow;
        return m_stage_chunks;
    case Stage::shadow:
        if (m_queue.empty()) break;
        m_stage = Stage::intersect;
        return m_stage_chunks = chunks_of(m_queue.size());
    }
    // Every path of the batch has ended: to the film, a chunk of pixels per task.
    const int pixels_per_chunk = std::max(1, kChunkPaths / spp);
    m_stage = Stage::accumulate;
    return m_stage_chunks = (m_batch_pixels + pixels_per_chunk - 1) / pixels_per_chunk;
}

std::uint64_t Wavefront::run_chunk(int chunk, PathStats& stats) {
    const int begin = chunk * kChunkPaths;
    const int end = std::min<int>(begin + kChunkPaths, static_cast<int>(m_queue.size()));
    ChunkQueues& out = m_chunk_queues[static_cast<std::size_t>(chunk)];
    switch (m_stage) {
    case Stage::generate: generate(begin, end); return 0;
    case Stage::intersect: intersect(begin, end, out, stats); return 0;
    case Stage::shade: shade(begin, end, out, stats); return 0;
    case Stage::shadow: trace_shadow_rays(out); return 0;
    case Stage::accumulate: {
        const int pixels_per_chunk = std::max(1, kChunkPaths / (m_end_sample - m_first_sample));
        const int first = chunk * pixels_per_chunk;
        return accumulate(first, std::min(first + pixels_per_chunk, m_batch_pixels));
    }
    case Stage::idle: break;
    }
    return 0;
}

// ---- generate: the camera ray of each path, as render_samples starts it ----
void Wavefront::generate(int begin, int end) {
    const int spp = m_end_sample - m_first_sample;
    for (int i = begin; i < end; ++i) {
        const int pixel = m_batch_pixel + i / spp;
        const int x = pixel % m_settings.width, y = pixel / m_settings.width;
        const PixelSample ps = start_pixel_sample<Rng>(pixel_stream(m_settings, x, y), x, y, m_first_sample + i % spp,
                                                  m_settings, m_camera);
        PathState& path = m_paths[static_cast<std::size_t>(i)];
        path = PathState{};
        path.ray = ps.ray(m_camera);
        path.rng = ps.rng;
        path.lambda = ps.lambda;
        path.time = ps.time;
    }
}

// ---- intersect: "find the next vertex; escaping rays see the infinite lights" ----
void Wavefront::intersect(int begin, int end, ChunkQueues& out, PathStats& stats) {
    out.paths.clear();
    const NeeLightChoice choices(m_scene, m_settings.integrator);
    for (int q = begin; q < end; ++q) {
        const std::uint32_t i = m_queue[static_cast<std::size_t>(q)];
        PathState& path = m_paths[i];
        ++stats.rays;
        if (const std::optional<Hit> hit = m_scene.intersect(path.ray, path.time)) {
            path.hit = *hit;
            out.paths.push_back(i);
        } else {
            for (int l : m_scene.infinite_light_indices) {
                const float w = path.mis.weight(m_scene, choices, l, path.ray.d, nullptr);
                path.L += path.beta * light_arriving(m_scene.lights[l], path.ray.d, path.lambda) * w;
            }
        }
    }
}

// ---- shade: emission, next-event estimation (rays queued), BSDF sample, roulette ----
void Wavefront::shade(int begin, int end, ChunkQueues& out, PathStats& stats) {
    out.paths.clear();
    out.nee.clear();
    out.rays.clear();
    const Scene& scene = m_scene;
    const IntegratorSettings& settings = m_settings.integrator;
    const bool point_nee = scene.effects.point_lights;
    const NeeLightChoice choices(scene, settings);
    const bool area_nee = settings.light_sampling != LightSampling::bsdf && !choices.empty();
    for (int q = begin; q < end; ++q) {
        const std::uint32_t i = m_queue[static_cast<std::size_t>(q)];
        PathState& path = m_paths[i];
        const Hit& hit = path.hit;
        const SampledWavelengths& lambda = path.lambda;
        const Material& mat = scene.materials[hit.material];
        const Vec3 wo = -path.ray.d;

        // Emission found by the path
        if (hit.light >= 0) {
            const float w = path.mis.weight(scene, choices, hit.light, path.ray.d, &hit);
            path.L += path.beta * scene.emitted(hit, wo, lambda) * w;
        }
        if (!mat.reflects() || path.depth == settings.max_depth) continue;
        const Bsdf& bsdf = mat.bsdf;

        // Next-event estimation: the rays go to the shadow stage with what they would add
        const bool non_delta = mat.has_non_delta();
        NeeRecord record{i, static_cast<std::uint32_t>(out.rays.size()), 0, point_nee && non_delta,
                         area_nee && non_delta, false};
        if (record.point) {
            auto add = [&](int l) {
                if (const std::optional<DeltaLightRay> r =
                        delta_light_ray(scene.lights[l], bsdf, hit, wo, lambda, path.time)) {
                    out.rays.push_back({r->shadow, {}, r->contribution});
                    ++record.point_rays;
                }
            };
            for (int l : scene.point_light_indices) add(l);
            for (int l : scene.spot_light_indices) add(l);
        }
        LightSampleContext ctx;
        if (record.area) {
            ctx = light_context(hit, mat, wo);
            const float ul = path.rng.uniform(), ul1 = path.rng.uniform(), ul2 = path.rng.uniform();
            if (const std::optional<AreaLightRay> r =
                    area_light_ray<false>(scene, choices, bsdf, hit, ctx, wo, lambda, ul, ul1, ul2)) {
                const bool mis = settings.light_sampling == LightSampling::mis;
                out.rays.push_back({r->shadow, r->skip, area_light_contribution(*r, bsdf, hit, wo, lambda, mis),
                                    r->past_planes});
                record.area_ray = true;
            }
        }
        if (record.point || record.area) {
            stats.rays += record.point_rays + (record.area_ray ? 1 : 0);
            path.beta_nee = path.beta;
            out.nee.push_back(record);
        }

        // Continue the path
        const std::optional<BsdfSample> bs = sample_bounce(bsdf, hit, wo, path.lambda, path.depth, path.rng);
        if (!bs) continue;
        path.beta *= bs->weight;
        path.eta_scale *= bs->eta_scale;
        path.ray = spawn_ray(hit, bs->wi);
        if (area_nee) path.mis.leave(*bs, settings.light_sampling, ctx);

        // Russian roulette
        if (!survives_roulette(settings, path.depth, [&] { return path.beta.max_value() * path.eta_scale; },
                               path.beta, path.rng))
            continue;
        ++path.depth;
        out.paths.push_back(i);
    }
}

// ---- shadow: the light samples that see their light join the radiance, as sample_point_lights
// and sample_area_light return them (a zero for the blocked ones: the same additions) ----
void Wavefront::trace_shadow_rays(const ChunkQueues& in) {
    for (const NeeRecord& record : in.nee) {
        PathState& path = m_paths[record.path];
        const ShadowRay* ray = in.rays.data() + record.first_ray;
        if (record.point) {
            SampledSpectrum Ld(0.f);
            for (std::uint32_t k = 0; k < record.point_rays; ++k, ++ray)
                if (!m_scene.occluded(ray->ray, ray->skip, path.time)) Ld += ray->contribution;
            path.L += path.beta_nee * Ld;
        }
        if (record.area) {
            const bool clear = record.area_ray && !shadow_blocked(m_scene, {ray->ray, ray->skip, ray->past_planes},
                                                                 path.time);
            path.L += path.beta_nee * (clear ? ray->contribution : SampledSpectrum(0.f));
        }
    }
}

// ---- accumulate: each pixel's samples in sample order, folded at chunk ends (render_samples) ----
std::uint64_t Wavefront::accumulate(int first_pixel, int end_pixel) {
    const int spp = m_end_sample - m_first_sample;
    for (int p = first_pixel; p < end_pixel; ++p) {
        const int pixel = m_batch_pixel + p;
        const int x = pixel % m_settings.width, y = pixel / m_settings.width;
        int chunk_end = next_chunk_end(m_settings, m_first_sample);
        for (int s = m_first_sample; s < m_end_sample; ++s) {
            const PathState& path = m_paths[std::size_t(p) * spp + (s - m_first_sample)];
            m_film.add_sample(x, y, path.L, path.lambda);
            if (s + 1 == chunk_end) m_film.fold_pixel(x, y), chunk_end = next_chunk_end(m_settings, chunk_end);
        }
    }
    return std::uint64_t(end_pixel - first_pixel) * spp;
}

}  // namespace spt
