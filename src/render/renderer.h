// Renders a scene into a film: the image is cut into tiles, rendered in passes of samples;
// a producer queues each pass's tiles and worker threads take them.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>

#include "render/film.h"
#include "render/integrator.h"
#include "scene/scene.h"

namespace spt {

struct RenderSettings {
    int width = 512, height = 512;
    int spp = 64;               ///< paths per pixel
    std::uint64_t seed = 0;
    int threads = 0;            ///< 0: all hardware threads
    int tile_size = 32;
    int pass_spp = 0;           ///< samples per pass; 0: chosen automatically
    IntegratorSettings integrator;
};

struct RenderStats {
    double seconds = 0;
    std::uint64_t paths = 0;
    std::uint64_t rays = 0;
    int passes_completed = 0;
    int passes_total = 0;
    bool cancelled = false;
};

/// Called by the rendering thread about five times a second: (paths done, paths in total).
using ProgressCallback = std::function<void(std::uint64_t, std::uint64_t)>;

/// Renders into `film` (which must match the settings' size). If `cancel` becomes true the
/// render stops after the tiles in flight; the film then holds whole passes plus part of one,
/// each pixel with its own sample count.
RenderStats render(const Scene& scene, const RenderSettings& settings, Film& film,
                   const ProgressCallback& progress = {}, const std::atomic<bool>* cancel = nullptr);

/// Renders one pixel's samples [first, end) into the film (the unit every path takes).
void render_pixel(const Scene& scene, const RenderSettings& settings, const Camera& camera, int x,
                  int y, int first_sample, int end_sample, Film& film, PathStats& stats);

}  // namespace spt
