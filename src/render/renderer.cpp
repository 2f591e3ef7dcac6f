// Tile scheduling. Determinism: every sample draws from its own Rng(seed, pixel, sample) (or
// SobolSampler, a function of the same three) and each pixel adds its samples in sample order,
// so the film does not depend on the threads.
#include "render/renderer.h"

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/sample_dimensions.h"
#include "render/bdpt.h"
#include "render/guiding/guided_bounce.h"
#include "render/light_sampling.h"
#include "render/pixel_sample.h"
#include "render/vertex_merging.h"
#include "render/volumetric_path.h"
#include "render/wavefront.h"
#include "render/work_queue.h"

namespace spt {

namespace {

struct TileTask {
    int x0, y0, x1, y1;
    int first_sample, end_sample;
    int index;  ///< position of the tile in its pass (the order splats are merged in)
    /// vcm's light phase: light subpaths [x0, x1) of sample first_sample instead of pixels
    bool light_subpaths = false;
    /// The wavefront schedule: chunk `index` of its current stage (nothing else is set)
    bool wavefront_chunk = false;
    /// Guided renders: samples before the first one asked for, traced again only to rebuild
    /// the field (their film is a scratch one)
    bool replay = false;
};

/// Merges the tiles' splats into the film in tile order, whichever thread finishes which
/// tile first: a tile's splats wait until every tile before it in the pass is merged, so the
/// film's sums (floating-point, order-sensitive) do not depend on the thread count.
class SplatMerger {
public:
    explicit SplatMerger(Film& film) : m_film(film) {}
    void reset(int tiles) {
        const std::lock_guard lock(m_mutex);
        m_pending.assign(static_cast<std::size_t>(tiles), {});
        m_next = 0;
    }
    void submit(int index, std::vector<Splat>&& splats, std::uint64_t light_paths) {
        const std::lock_guard lock(m_mutex);
        m_pending[static_cast<std::size_t>(index)] = {std::move(splats), light_paths, true};
        while (m_next < m_pending.size() && m_pending[m_next].ready) {
            Pending& p = m_pending[m_next++];
            merge(p);
            p = {};
        }
    }

private:
    struct Pending {
        std::vector<Splat> splats;
        std::uint64_t light_paths = 0;
        bool ready = false;
    };
    void merge(const Pending& p) {
        m_film.add_light_paths(p.light_paths);
        const auto width = static_cast<std::uint32_t>(m_film.width());
        for (const Splat& s : p.splats) {
            const bool finite = std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.z);
            if (!finite || s.x < 0.f || s.y < 0.f || s.z < 0.f) {
                m_film.reject_splat(!finite);
                continue;
            }
            m_film.add_splat(static_cast<int>(s.pixel % width), static_cast<int>(s.pixel / width),
                             {s.x, s.y, s.z});
        }
    }
    Film& m_film;
    std::mutex m_mutex;
    std::vector<Pending> m_pending;
    std::size_t m_next = 0;
};

/// render_pixel for bidirectional path tracing: the same samples (Rng, wavelengths, jitter),
/// the camera-side estimate to the pixel and the light-to-camera splats to `splats`. With the
/// Sobol sampler, the camera sample is Sobol's and the subpaths draw from its PCG stream.
template <class Sampler>
void render_pixel_bdpt(const BdptContext& ctx, const RenderSettings& settings, int x, int y,
                       int first_sample, int end_sample, Film& film, PathStats& stats,
                       std::vector<Splat>& splats) {
    const RngStream stream = pixel_stream(settings, x, y);
    int chunk_end = next_chunk_end(settings, first_sample);
    for (int s = first_sample; s < end_sample; ++s) {
        PixelSample ps = start_pixel_sample<Sampler>(stream, x, y, s, settings, ctx.camera);
        const SampledSpectrum L =
            trace_bdpt(ctx, ps.ray(ctx.camera), ps.time, ps.lambda, pcg_stream(ps.rng), stats, splats);
        film.add_sample(x, y, L, ps.lambda);
        if (s + 1 == chunk_end) film.fold_pixel(x, y), chunk_end = next_chunk_end(settings, chunk_end);
    }
}

/// Stream of the light subpaths of vertex merging (the camera samples use Rng(seed, pixel, s)).
constexpr std::uint64_t kLightSubpathStream = 0x6c8e9cf570932bd5ull;
constexpr int kLightSubpathsPerTask = 4096;

/// vcm's passes (one sample per pixel each). A pass has two phases: the light phase traces one
/// light subpath per pixel at the pass's wavelengths (tasks of the shared queue, their splats
/// merged in task order), then the grid of their photons is built; the camera phase renders
/// the tiles, each camera subpath connected and merged with them.
class VcmPasses {
public:
    VcmPasses(const BdptContext& ctx, const RenderSettings& settings)
        : m_ctx(ctx), m_settings(settings),
          m_first_radius(settings.integrator.merge_radius > 0.f ? settings.integrator.merge_radius
                                                                : default_merge_radius(ctx, settings)) {}

    /// Starts the pass at sample `first`: its wavelengths and radius. Returns how many tasks
    /// its light phase has.
    int begin_pass(int first) {
        m_lambda = pass_wavelengths(m_settings.seed, first);
        if (m_settings.integrator.wavelengths_per_path == 1) m_lambda.terminate_secondary();
        m_radius = merge_radius(m_first_radius, first);
        const int n = m_settings.width * m_settings.height;
        m_eta = kPi * m_radius * m_radius * static_cast<float>(n);
        const int tasks = (n + kLightSubpathsPerTask - 1) / kLightSubpathsPerTask;
        m_batches.assign(static_cast<std::size_t>(tasks), {});
        return tasks;
    }

    /// Pushes the light-phase tasks of the pass begun at sample `first`.
    void queue_light_tasks(int first, WorkQueue<TileTask>& queue) const {
        const int n = m_settings.width * m_settings.height;
        std::vector<TileTask> tasks;
        for (int k = 0; k < static_cast<int>(m_batches.size()); ++k)
            tasks.push_back({k * kLightSubpathsPerTask, 0, std::min(n, (k + 1) * kLightSubpathsPerTask), 1, first,
                             first + 1, k, true});
        queue.push(tasks);
    }

    /// Worker side of the light phase: light subpaths [x0, x1) of the task's sample (none if
    /// cancelled); their splats go to the merger in task order.
    void run_light_task(const TileTask& task, bool cancelled, PathStats& stats, SplatMerger& merger) {
        LightSubpathBatch& batch = m_batches[static_cast<std::size_t>(task.index)];
        if (!cancelled) {
            for (int i = task.x0; i < task.x1; ++i) {
                Rng rng(m_settings.seed ^ kLightSubpathStream, static_cast<std::uint64_t>(i),
                        static_cast<std::uint64_t>(task.first_sample));
                batch.trace(m_ctx, m_lambda, m_eta, rng, stats);
            }
        }
        merger.submit(task.index, std::move(batch.splats), static_cast<std::uint64_t>(task.x1 - task.x0));
    }

    /// After the light phase: the photon grid of the pass.
    void build_grid() { m_pass.build(m_batches, m_ctx.scene, m_radius, m_eta); }

    /// Camera phase of a tile: each pixel's sample (Rng and jitter as the other integrators,
    /// the pass's wavelengths instead of its own), connected to light subpath y·width + x.
    void render_tile(const TileTask& task, Film& film, PathStats& stats) const {
        if (m_settings.sampler == SamplerKind::sobol) render_tile<SobolSampler>(task, film, stats);
        else render_tile<Rng>(task, film, stats);
    }

private:
    template <class Sampler>
    void render_tile(const TileTask& task, Film& film, PathStats& stats) const {
        const MergeContext mc = m_pass.context();
        const bool chunk_ends = next_chunk_end(m_settings, task.first_sample) == task.first_sample + 1;
        for (int y = task.y0; y < task.y1; ++y)
            for (int x = task.x0; x < task.x1; ++x) {
                const int s = task.first_sample;
                PixelSample ps =
                    start_pixel_sample<Sampler>(pixel_stream(m_settings, x, y), x, y, s, m_settings, m_ctx.camera);
                const auto light_path = static_cast<std::uint32_t>(y * m_settings.width + x);
                const SampledSpectrum L = trace_camera_subpath(m_ctx, mc, light_path, ps.ray(m_ctx.camera), m_lambda,
                                                               pcg_stream(ps.rng), stats);
                film.add_sample(x, y, L, m_lambda);
                if (chunk_ends) film.fold_pixel(x, y);
            }
    }

    const BdptContext& m_ctx;
    const RenderSettings& m_settings;
    float m_first_radius;
    SampledWavelengths m_lambda{};  ///< the current pass's wavelengths
    float m_radius = 0.f, m_eta = 0.f;
    std::vector<LightSubpathBatch> m_batches;
    MergePass m_pass;
};

/// Counts finished tiles so the producer can wait for the end of a pass.
class PassLatch {
public:
    void finished_one(std::uint64_t paths) {
        {
            const std::lock_guard lock(m_mutex);
            ++m_done;
            m_paths += paths;
        }
        m_cv.notify_all();
    }
    /// Waits up to `timeout` for `count` tiles; returns true when they are all done.
    bool wait_for(int count, std::chrono::milliseconds timeout) {
        std::unique_lock lock(m_mutex);
        return m_cv.wait_for(lock, timeout, [&] { return m_done >= count; });
    }
    std::uint64_t paths() {
        const std::lock_guard lock(m_mutex);
        return m_paths;
    }
    void reset() {
        const std::lock_guard lock(m_mutex);
        m_done = 0;
    }

private:
    std::mutex m_mutex;
    std::condition_variable m_cv;
    int m_done = 0;
    std::uint64_t m_paths = 0;
};

/// Samples per pass for an explicit --pass-spp (0: automatic).
int pass_size(const RenderSettings& s, int pass_spp) {
    // Vertex merging traces the light subpaths of one sample for all pixels, then the camera
    // subpaths: one sample per pass.
    if (s.integrator.kind == IntegratorKind::vcm) return 1;
    if (pass_spp > 0) return std::min(pass_spp, s.spp);
    // About four million paths per pass: frequent enough for progress and interruption,
    // long enough that waiting for the last tile of a pass costs little.
    const double pixels = double(s.width) * s.height;
    const int pass = static_cast<int>(std::max(1.0, s.paths_per_pass / pixels));
    return std::min(pass, s.spp);
}

}  // namespace

int effective_pass_spp(const RenderSettings& s) { return pass_size(s, s.pass_spp); }

int chunk_spp(const RenderSettings& s) { return pass_size(s, 0); }

int next_chunk_end(const RenderSettings& s, int samples) {
    const int chunk = chunk_spp(s);
    return std::min(s.spp, (samples / chunk + 1) * chunk);
}

/// The samples [first_sample, end_sample) of pixel (x, y), each traced by `trace`.
template <class Sampler, typename Trace>
[[gnu::always_inline]] inline void render_samples(const Trace& trace, const RenderSettings& settings,
                                                  const Camera& camera, int x, int y, int first_sample,
                                                  int end_sample, Film& film) {
    const RngStream stream = pixel_stream(settings, x, y);
    int chunk_end = next_chunk_end(settings, first_sample);
    for (int s = first_sample; s < end_sample; ++s) {
        PixelSample ps = start_pixel_sample<Sampler>(stream, x, y, s, settings, camera);
        const SampledSpectrum L = trace(ps.ray(camera), ps.time, ps.lambda, ps.rng);
        film.add_sample(x, y, L, ps.lambda);
        if (s + 1 == chunk_end) film.fold_pixel(x, y), chunk_end = next_chunk_end(settings, chunk_end);
    }
}

/// render_pixel with the Sobol sampler: the path integrator takes every dimension from it, the
/// volumetric one the camera sample (and the rest from its PCG stream). Out of line, so the
/// independent sampler's loop below is the one of before.
[[gnu::noinline]] void render_pixel_sobol(const Scene& scene, const RenderSettings& settings, const Camera& camera,
                                          int x, int y, int first_sample, int end_sample, Film& film,
                                          PathStats& stats) {
    if (scene.effects.media) {
        render_samples<SobolSampler>([&](const Ray& ray, float, SampledWavelengths& lambda, SobolSampler& sampler) {
            return trace_volumetric_path(scene, settings.integrator, ray, lambda, pcg_stream(sampler), stats);
        }, settings, camera, x, y, first_sample, end_sample, film);
        return;
    }
    render_samples<SobolSampler>([&](const Ray& ray, float time, SampledWavelengths& lambda, SobolSampler& sampler) {
        return trace_path(scene, settings.integrator, ray, time, lambda, sampler, stats);
    }, settings, camera, x, y, first_sample, end_sample, film);
}

void render_pixel(const Scene& scene, const RenderSettings& settings, const Camera& camera, int x,
                  int y, int first_sample, int end_sample, Film& film, PathStats& stats) {
    if (settings.sampler == SamplerKind::sobol) [[unlikely]] {
        render_pixel_sobol(scene, settings, camera, x, y, first_sample, end_sample, film, stats);
        return;
    }
    // Scenes with media take the volumetric path tracer, chosen once per pixel: the surface
    // loop below is the one of before, for scenes without media.
    if (scene.effects.media) [[unlikely]] {
        // (Scene::finalize refuses media with motion blur: the time is the shutter's opening.)
        render_samples<Rng>([&](const Ray& ray, float, SampledWavelengths& lambda, Rng& rng) {
            return trace_volumetric_path(scene, settings.integrator, ray, lambda, rng, stats);
        }, settings, camera, x, y, first_sample, end_sample, film);
        return;
    }
    render_samples<Rng>([&](const Ray& ray, float time, SampledWavelengths& lambda, Rng& rng) {
        return trace_path(scene, settings.integrator, ray, time, lambda, rng, stats);
    }, settings, camera, x, y, first_sample, end_sample, film);
}

namespace {

/// render_pixel with path guiding: each sample samples and records as `guide` says.
void render_pixel_guided(const Scene& scene, const RenderSettings& settings, const Camera& camera, int x, int y,
                         int first_sample, int end_sample, Film& film, PathStats& stats, const PathGuide& guide) {
    if (settings.sampler == SamplerKind::sobol) {
        render_samples<SobolSampler>([&](const Ray& ray, float time, SampledWavelengths& lambda, SobolSampler& sampler) {
            return trace_guided_path(scene, settings.integrator, ray, time, lambda, sampler, stats, guide);
        }, settings, camera, x, y, first_sample, end_sample, film);
        return;
    }
    render_samples<Rng>([&](const Ray& ray, float time, SampledWavelengths& lambda, Rng& rng) {
        return trace_guided_path(scene, settings.integrator, ray, time, lambda, rng, stats, guide);
    }, settings, camera, x, y, first_sample, end_sample, film);
}

/// Stream of the guiding pilot's paths.
constexpr std::uint64_t kGuidingPilotStream = 0x2f4a7b1c93d5e861ull;

}  // namespace

const char* guiding_unsupported(const Scene& scene, const RenderSettings& settings) {
    if (settings.integrator.kind != IntegratorKind::path) return "the path integrator";
    if (scene.effects.media) return "a scene without participating media";
    if (scene.effects.fluorescence) return "a scene without fluorescence";
    if (settings.schedule != Schedule::tiles) return "the tiles schedule";
    return nullptr;
}

double guiding_pilot_radiance(const Scene& scene, const RenderSettings& settings) {
    constexpr int kSide = 64;
    const Camera camera(scene.camera, settings.width, settings.height, scene.effects.motion_blur);
    RenderSettings pilot = settings;
    pilot.seed ^= kGuidingPilotStream;
    PathStats stats;
    double sum = 0;
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i) {
            const int x = (2 * i + 1) * settings.width / (2 * kSide), y = (2 * j + 1) * settings.height / (2 * kSide);
            PixelSample ps = start_pixel_sample<Rng>(pixel_stream(pilot, x, y), x, y, 0, pilot, camera);
            const SampledSpectrum L =
                trace_path(scene, settings.integrator, ps.ray(camera), ps.time, ps.lambda, ps.rng, stats);
            const double mean = L.average();
            if (std::isfinite(mean) && mean > 0) sum += mean;
        }
    return sum / (kSide * kSide);
}

RenderStats render(const Scene& scene, const RenderSettings& settings, Film& film,
                   const RenderHooks& hooks) {
    const ProgressCallback& progress = hooks.progress;
    const std::atomic<bool>* cancel = hooks.cancel;
    const auto start = std::chrono::steady_clock::now();
    const Camera camera(scene.camera, settings.width, settings.height, scene.effects.motion_blur);
    const int threads = settings.threads > 0
                            ? settings.threads
                            : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const bool vcm = settings.integrator.kind == IntegratorKind::vcm;
    // Merges join light and camera subpaths of different samples, so of different times.
    if (vcm && scene.effects.motion_blur) throw std::invalid_argument("vcm cannot render motion blur");
    // Re-emission is sampled from the camera side only, by the surface path loop
    // (model/fluorescence.h).
    if (scene.effects.fluorescence && (settings.integrator.kind != IntegratorKind::path || scene.effects.media))
        throw std::invalid_argument(std::string(integrator_name(settings.integrator.kind)) +
                                    " cannot render fluorescence" + (scene.effects.media ? " with participating media" : ""));
    const int max_pass_spp = effective_pass_spp(settings);
    // Timed passes start with one sample, then follow the measured pace (a pixel's samples
    // are added in sample order whatever the passes, so the image does not change).
    const bool timed_passes = settings.pass_seconds > 0 && settings.pass_spp == 0 && !vcm;
    int pass_spp = timed_passes ? 1 : max_pass_spp;
    RenderStats stats;
    const int end_sample = settings.end_sample > 0 ? std::min(settings.end_sample, settings.spp) : settings.spp;
    const int first_sample = std::clamp(settings.first_sample, 0, end_sample);
    auto passes_left = [&](int first) { return (end_sample - first + pass_spp - 1) / pass_spp; };
    stats.passes_total = passes_left(first_sample);
    stats.samples_completed = first_sample;
    const std::uint64_t total_paths =
        std::uint64_t(settings.width) * settings.height * (end_sample - first_sample);

    const bool bdpt = settings.integrator.kind == IntegratorKind::bdpt;
    std::optional<LightSampler> lights;
    std::optional<BdptContext> bidir;  // what both bidirectional integrators share
    if (bdpt || vcm) {
        lights.emplace(scene);
        // Braces, not emplace's parentheses: clang 14 has no parenthesized aggregate init.
        bidir.emplace(BdptContext{scene, camera, *lights, settings.integrator, settings.width, &film.observer()});
    }
    SplatMerger merger(film);
    std::optional<VcmPasses> vcm_passes;
    if (vcm) vcm_passes.emplace(*bidir, settings);

    const TileGrid grid(settings.width, settings.height, settings.tile);
    // The ring holds a whole pass's tiles (or vcm light tasks, or wavefront chunks), up to 64 k.
    const int most_tasks = std::max(grid.count(), (settings.width * settings.height + kLightSubpathsPerTask - 1) /
                                                       kLightSubpathsPerTask);
    WorkQueue<TileTask> queue(settings.queue, static_cast<std::size_t>(std::clamp(most_tasks, 1024, 1 << 16)));
    std::optional<Wavefront> wavefront;
    if (settings.schedule == Schedule::wavefront) {
        if (const char* feature = wavefront_unsupported(scene, settings.integrator, settings.sampler))
            throw std::invalid_argument(std::string("the wavefront schedule does not support ") + feature);
        wavefront.emplace(scene, settings, camera, film);
    }
    // Path guiding: the field, the ends of its iterations, and what the pass in flight does
    // with it (set by the producer before it queues a pass's tiles).
    std::optional<GuidingField> field;
    std::vector<int> iteration_ends;
    PathGuide pass_guide;
    std::optional<Film> scratch;  // the film of replayed samples
    if (settings.guiding != GuidingMode::off) {
        if (const char* needs = guiding_unsupported(scene, settings))
            throw std::invalid_argument(std::string("path guiding needs ") + needs);
        const int channels = settings.guiding == GuidingMode::spectral ? kGuideBands : 1;
        field.emplace(scene.bounds_center, scene.bounds_radius, channels);
        // The unit resolves 2^-24 of the scene's mean radiance (or of 1 if the pilot found none).
        const double mean = guiding_pilot_radiance(scene, settings);
        field->set_unit((mean > 0 ? mean : 1.0) * 0x1p-24);
        iteration_ends = guiding_iteration_ends(settings.spp);
        if (first_sample > 0) scratch.emplace(settings.width, settings.height, film.observer());
    }
    // The end of the iteration that sample s belongs to, and whether it is a training one.
    auto iteration_end = [&](int s) {
        for (int end : iteration_ends)
            if (s < end) return end;
        return settings.spp;
    };
    auto training = [&](int s) { return iteration_ends.size() > 1 && s < iteration_ends[iteration_ends.size() - 2]; };
    // Samples before first_sample are replayed (guided renders only).
    const int replay_from = field ? 0 : first_sample;
    // The end of the pass that starts at sample `first`: passes stop at the end of an
    // iteration and at first_sample.
    auto pass_end = [&](int first) {
        int end = std::min(end_sample, first + pass_spp);
        if (field) end = std::min(end, iteration_end(first));
        if (first < first_sample) end = std::min(end, first_sample);
        return end;
    };
    if (field) {
        stats.passes_total = 0;
        for (int s = first_sample; s < end_sample; s = pass_end(s)) ++stats.passes_total;
    }

    PassLatch latch;
    std::atomic<std::uint64_t> rays{0};
    auto cancelled = [&] { return cancel && cancel->load(std::memory_order_relaxed); };

    std::vector<std::thread> workers;
    for (int t = 0; t < threads; ++t) {
        workers.emplace_back([&] {
            PathStats local;
            while (std::optional<TileTask> task = queue.pop()) {
                std::uint64_t paths = 0;
                std::vector<Splat> splats;
                if (task->wavefront_chunk) {
                    latch.finished_one(wavefront->run_chunk(task->index, local));
                    continue;
                }
                if (task->light_subpaths) {
                    vcm_passes->run_light_task(*task, cancelled(), local, merger);
                    latch.finished_one(0);
                    continue;
                }
                if (!cancelled()) {
                    if (vcm) {
                        vcm_passes->render_tile(*task, film, local);
                    } else if (bdpt) {
                        const auto render = settings.sampler == SamplerKind::sobol ? render_pixel_bdpt<SobolSampler>
                                                                                   : render_pixel_bdpt<Rng>;
                        for (int y = task->y0; y < task->y1; ++y)
                            for (int x = task->x0; x < task->x1; ++x)
                                render(*bidir, settings, x, y, task->first_sample, task->end_sample, film, local,
                                       splats);
                    } else if (field) {
                        Film& target = task->replay ? *scratch : film;
                        for (int y = task->y0; y < task->y1; ++y)
                            for (int x = task->x0; x < task->x1; ++x)
                                render_pixel_guided(scene, settings, camera, x, y, task->first_sample,
                                                    task->end_sample, target, local, pass_guide);
                    } else {
                        for (int y = task->y0; y < task->y1; ++y)
                            for (int x = task->x0; x < task->x1; ++x)
                                render_pixel(scene, settings, camera, x, y, task->first_sample,
                                             task->end_sample, film, local);
                    }
                    paths = std::uint64_t(task->x1 - task->x0) * (task->y1 - task->y0) *
                            (task->end_sample - task->first_sample);
                }
                if (bdpt) merger.submit(task->index, std::move(splats), paths);
                latch.finished_one(paths);
            }
            rays.fetch_add(local.rays);
        });
    }

    // Producer: one pass at a time, so a pixel never gets samples out of order.
    double seconds_per_spp = 0;  // pace of the last pass
    std::uint64_t replayed_paths = 0;  // paths of replayed samples (not this run's work)
    for (int first = replay_from; first < end_sample && !cancelled();) {
        const auto pass_start = std::chrono::steady_clock::now();
        const int end = pass_end(first);
        const bool replay = first < first_sample;
        if (field) pass_guide = {&*field, field->iterations() > 0, training(first)};
        if (settings.time_limit > 0 && first > first_sample) {
            const double elapsed = std::chrono::duration<double>(pass_start - start).count();
            if (elapsed + seconds_per_spp * (end - first) > settings.time_limit) {
                stats.time_limited = true;
                break;
            }
        }
        if (vcm) {
            // Light phase: every light subpath of the pass, then the grid of their photons.
            const int tasks = vcm_passes->begin_pass(first);
            latch.reset();
            merger.reset(tasks);
            vcm_passes->queue_light_tasks(first, queue);
            while (!latch.wait_for(tasks, std::chrono::milliseconds(200)))
                if (progress) progress(latch.paths() - replayed_paths, total_paths);
            if (cancelled()) break;
            vcm_passes->build_grid();
        }
        if (wavefront) {
            // Stage after stage, each one's chunks through the queue, all done before the next.
            wavefront->begin_pass(first, end);
            while (!cancelled()) {
                const int chunks = wavefront->next_stage();
                if (chunks == 0) break;
                std::vector<TileTask> tasks(static_cast<std::size_t>(chunks));
                for (int k = 0; k < chunks; ++k) tasks[static_cast<std::size_t>(k)] = {0, 0, 0, 0, 0, 0, k, false, true};
                latch.reset();
                queue.push(tasks);
                while (!latch.wait_for(chunks, std::chrono::milliseconds(200)))
                    if (progress) progress(latch.paths() - replayed_paths, total_paths);
            }
        } else {
            latch.reset();
            if (!vcm) merger.reset(grid.count());
            std::vector<TileTask> tiles(static_cast<std::size_t>(grid.count()));
            for (int k = 0; k < grid.count(); ++k) {
                const TileRect r = grid.tile(k);
                tiles[static_cast<std::size_t>(k)] = {r.x0, r.y0, r.x1, r.y1, first, end, k};
                tiles[static_cast<std::size_t>(k)].replay = replay;
            }
            queue.push(tiles);
            while (!latch.wait_for(grid.count(), std::chrono::milliseconds(200)))
                if (progress && !replay) progress(latch.paths() - replayed_paths, total_paths);
        }
        if (cancelled()) break;
        if (field && training(first) && end == iteration_end(first)) {
            const int iteration = field->iterations();
            field->end_iteration(end - (iteration == 0 ? 0 : iteration_ends[static_cast<std::size_t>(iteration) - 1]));
        }
        if (replay) {
            replayed_paths = latch.paths();
            first = end;
            continue;
        }
        if (film.has_splats() && next_chunk_end(settings, end - 1) == end) film.fold_splats();
        ++stats.passes_completed;
        stats.samples_completed = end;
        if (hooks.pass_completed) hooks.pass_completed(end);
        const double pass_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
        seconds_per_spp = pass_seconds / (end - first);
        first = end;
        if (timed_passes) {
            const double fit = settings.pass_seconds / std::max(seconds_per_spp, 1e-9);
            pass_spp = static_cast<int>(std::clamp(fit, 1.0, double(max_pass_spp)));
            stats.passes_total = stats.passes_completed + passes_left(first);
        }
    }
    queue.close();
    for (std::thread& w : workers) w.join();

    stats.paths = latch.paths() - replayed_paths;
    stats.rays = rays.load();
    stats.cancelled = cancelled() && stats.samples_completed < end_sample;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (progress) progress(stats.paths, total_paths);
    return stats;
}

}  // namespace spt
