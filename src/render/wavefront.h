// The wavefront schedule (Laine, Karras and Aila 2013, "Megakernels considered harmful", on
// the CPU): a pass's paths go through the renderer in batches, and each batch through stages
// that each consume their own queue of paths, every worker thread taking chunks of it:
//   generate (camera rays) → intersect (closest hit; escaped paths take the infinite lights)
//   → shade (emission, light samples and their shadow rays, BSDF sample, roulette)
//   → shadow (shadow rays; unoccluded light samples join the path's radiance)
//   → intersect again with the surviving paths … → accumulate (film, in sample order).
// It computes what trace_path computes, operation for operation (the light sampling of
// direct_light.h, the same Rng per (pixel, sample), the same order of additions to each
// path's radiance and to the film): the image is bit-identical to the tiles schedule's.
#pragma once
#include <cstdint>
#include <vector>

#include "model/camera.h"
#include "render/film.h"
#include "render/integrator.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace spt {

/// Why the wavefront cannot render this (a phrase naming the feature), or nullptr when it can:
/// it runs the path integrator with the independent sampler (its paths carry a PCG stream) on
/// scenes without participating media or textures.
const char* wavefront_unsupported(const Scene& scene, const IntegratorSettings& settings, SamplerKind sampler);

/// Driven by one producer thread, which calls begin_pass, then next_stage until it returns
/// 0, handing each stage's chunk numbers [0, count) to the workers (run_chunk) and waiting for
/// all of them before calling next_stage again.
class Wavefront {
public:
    Wavefront(const Scene& scene, const RenderSettings& settings, const Camera& camera, Film& film);
    ~Wavefront();

    /// Starts the pass of samples [first_sample, end_sample) of every pixel.
    void begin_pass(int first_sample, int end_sample);
    /// Moves to the next stage (gathering the queues the last one filled); returns its number
    /// of chunks, 0 when the pass is done.
    int next_stage();
    /// Worker side: chunk `chunk` of the current stage. Returns the paths it added to the film.
    std::uint64_t run_chunk(int chunk, PathStats& stats);

private:
    struct PathState;
    struct ShadowRay;
    struct NeeRecord;
    struct ChunkQueues;
    enum class Stage { idle, generate, intersect, shade, shadow, accumulate };

    void generate(int begin, int end);
    void intersect(int begin, int end, ChunkQueues& out, PathStats& stats);
    void shade(int begin, int end, ChunkQueues& out, PathStats& stats);
    void trace_shadow_rays(const ChunkQueues& in);
    std::uint64_t accumulate(int first_pixel, int end_pixel);
    /// Concatenates the chunks' path lists (in chunk order) into `queue`.
    void gather(std::vector<std::uint32_t>& queue);
    int chunks_of(std::size_t items) const;

    const Scene& m_scene;
    const RenderSettings& m_settings;
    const Camera& m_camera;
    Film& m_film;
    int m_first_sample = 0, m_end_sample = 0;
    int m_next_pixel = 0;              ///< first pixel of the next batch
    int m_batch_pixel = 0, m_batch_pixels = 0;
    Stage m_stage = Stage::idle;
    int m_stage_chunks = 0;
    std::vector<PathState> m_paths;           ///< the batch, pixel by pixel, samples in order
    std::vector<std::uint32_t> m_queue;       ///< the paths the current stage consumes
    std::vector<ChunkQueues> m_chunk_queues;  ///< what each chunk of a stage produced
};

}  // namespace spt
