// What every EXR header records about the render that made it (OpenEXR attributes).
#pragma once
#include <utility>
#include <vector>

#include "cli/options.h"
#include "io/image_writer.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace spt {

/// The render's metadata as EXR attributes:
///   software (string)  "pathtracer <version>"      scene (string)     SCENE as given
///   spp (int)          samples every pixel of the image has (the fewest; less than asked
///                      when interrupted or time-limited)   sppRequested (int)
///   sppPerPixel (string)  "A-B": the fewest and the most samples a pixel has (an image
///                      interrupted in a pass has pixels with more), "A" when all have A
///   integrator (string)  path, bdpt or vcm          seed (string)      decimal, 64-bit
///   renderTimeSeconds (double)  this run's render time
///   capDate (string)   "YYYY:MM:DD hh:mm:ss" UTC when written, utcOffset (float) 0
///   spectralBins (string)  "16" or "exact"          observer (string)  "CIE 1931 2 degree" or
///                      the --sensor file            maxDepth (int, -1 unbounded)
///   wavelengthsPerPath (int); with --spectral-bands: spectralBands (int), spectralRangeNm
///   (string "MIN:MAX")
/// `samples_per_pixel`: the fewest and the most samples a pixel of the image has.
std::vector<ExrAttribute> render_metadata(const Options& options, const RenderSettings& settings,
                                          const RenderStats& stats, const Observer& observer,
                                          std::pair<int, int> samples_per_pixel);

}  // namespace spt
