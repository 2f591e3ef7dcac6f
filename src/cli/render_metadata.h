// What every EXR header records about the render that made it (OpenEXR attributes).
#pragma once
#include <vector>

#include "cli/options.h"
#include "io/image_writer.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace spt {

/// The render's metadata as EXR attributes:
///   software (string)  "pathtracer <version>"      scene (string)     SCENE as given
///   spp (int)          samples per pixel in the image (whole passes; less than asked when
///                      interrupted or time-limited)   sppRequested (int)
///   integrator (string)  path, bdpt or vcm          seed (string)      decimal, 64-bit
///   renderTimeSeconds (double)  this run's render time
///   capDate (string)   "YYYY:MM:DD hh:mm:ss" UTC when written, utcOffset (float) 0
///   spectralBins (string)  "16" or "exact"          observer (string)  "CIE 1931 2 degree" or
///                      the --sensor file            maxDepth (int, -1 unbounded)
///   wavelengthsPerPath (int); with --spectral-bands: spectralBands (int), spectralRangeNm
///   (string "MIN:MAX")
std::vector<ExrAttribute> render_metadata(const Options& options, const RenderSettings& settings,
                                          const RenderStats& stats, const Observer& observer);

}  // namespace spt
