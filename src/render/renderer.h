// Renders a scene into a film: the image is cut into tiles, rendered in passes of samples;
// a producer queues each pass's tiles and worker threads take them.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>

#include "render/film.h"
#include "render/guiding/guiding_schedule.h"
#include "render/integrator.h"
#include "render/sampler_kind.h"
#include "render/tile_grid.h"
#include "render/work_queue.h"
#include "scene/scene.h"
#include "spectral/wavelength_range.h"

namespace spt {

/// How the workers share a pass: tiles (each path traced whole by one worker) or wavefront
/// (batches of paths moved through stages, every worker on each stage: render/wavefront.h).
enum class Schedule { tiles, wavefront };

struct RenderSettings {
    int width = 512, height = 512;
    int spp = 64;               ///< paths per pixel
    std::uint64_t seed = 0;
    int threads = 0;            ///< 0: all hardware threads
    TileShape tile;             ///< the tiles of the tiles schedule (the wavefront has none)
    QueueKind queue = QueueKind::mutex;  ///< how workers take tasks (tiles, wavefront stage chunks)
    Schedule schedule = Schedule::tiles;
    int wavefront_batch = 1 << 14;  ///< wavefront: paths per batch (rounded to whole pixels)
    int pass_spp = 0;           ///< samples per pass; 0: chosen automatically
    /// With automatic passes (pass_spp 0), > 0: each pass is sized, at the pace of the one
    /// before, to take about this long (the first has 1 spp; at most effective_pass_spp), so
    /// that live previews, which are written between passes, come on time. No effect on vcm
    /// (one sample per pass) or on the image.
    double pass_seconds = 0;
    /// Paths per automatic pass (the program's 4 million; tests lower it to cut small
    /// renders into many passes). Sets the chunks, so it changes the image's last bits.
    double paths_per_pass = 4.0e6;
    int first_sample = 0;       ///< samples per pixel already in the film (resuming)
    /// > 0: stop after this many samples per pixel instead of spp (a partial film rendering
    /// samples [first_sample, end_sample) of the spp-sample render; a chunk end, see below).
    int end_sample = 0;
    /// Seconds (0: no limit): a pass is not started if, at the pace of the previous one, it
    /// would end after this. The first pass always runs, so the image has samples.
    double time_limit = 0;
    IntegratorSettings integrator;
    /// The random numbers of each path sample (the command line chooses default_sampler).
    SamplerKind sampler = SamplerKind::independent;
    /// Path guiding (render/guiding/): path integrator, tiles schedule, no media or
    /// fluorescence. The image depends on it, not on the threads or the passes.
    GuidingMode guiding = GuidingMode::off;
    /// Set only for spectral output beyond 360-830 nm (path integrator): wavelengths are then
    /// drawn from this wider density instead of the visible one.
    std::optional<WideWavelengthSampling> wide_wavelengths;
};

/// Samples per pass actually used for these settings (the most, with pass_seconds).
int effective_pass_spp(const RenderSettings& settings);

/// Samples per chunk: each pixel's sums are folded into the film's exact totals after every
/// chunk_spp samples and after the last (spp), and the splats after each pass that ends there.
/// It is the automatic pass size, whatever --pass-spp and timed passes do, so they do not
/// change the image, and a partial film of whole passes holds whole chunks.
int chunk_spp(const RenderSettings& settings);

/// The first chunk end after `samples` samples (at most spp).
int next_chunk_end(const RenderSettings& settings, int samples);

struct RenderStats {
    double seconds = 0;
    std::uint64_t paths = 0;
    std::uint64_t rays = 0;
    int passes_completed = 0;   ///< passes finished in this run
    int passes_total = 0;       ///< passes this run set out to render (pass_seconds: the
                                ///< passes done plus the rest at the last pass size)
    int samples_completed = 0;  ///< samples per pixel in the film after the last whole pass
    bool cancelled = false;
    bool time_limited = false;  ///< stopped before spp by RenderSettings::time_limit
};

/// Called by the rendering thread about five times a second: (paths done, paths in total).
using ProgressCallback = std::function<void(std::uint64_t, std::uint64_t)>;
/// Called by the rendering thread after each whole pass, with the samples per pixel in the film.
using PassCallback = std::function<void(int)>;

struct RenderHooks {
    ProgressCallback progress;
    PassCallback pass_completed;
    const std::atomic<bool>* cancel = nullptr;  ///< set (e.g. by a signal) to stop early
};

/// Renders samples [first_sample, end_sample or spp) of every pixel into `film` (which must match the
/// settings' size), in passes of effective_pass_spp samples. If
/// hooks.cancel becomes true the render stops after the tiles in flight; the film then holds
/// whole passes plus part of one, each pixel with its own sample count.
RenderStats render(const Scene& scene, const RenderSettings& settings, Film& film,
                   const RenderHooks& hooks = {});

/// Why a render cannot be guided (what it needs instead, e.g. "the path integrator"), or null.
const char* guiding_unsupported(const Scene& scene, const RenderSettings& settings);

/// The mean radiance of 4096 unguided paths of the path integrator through pixels spread
/// evenly over the image (traced in order on the calling thread: the result does not depend
/// on the threads), the guiding field's scale (render/guiding/guiding_field.h).
double guiding_pilot_radiance(const Scene& scene, const RenderSettings& settings);

/// Renders one pixel's samples [first, end) into the film (the unit every path takes).
void render_pixel(const Scene& scene, const RenderSettings& settings, const Camera& camera, int x,
                  int y, int first_sample, int end_sample, Film& film, PathStats& stats);

}  // namespace spt
