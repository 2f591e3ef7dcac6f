// The rare part of a sample's start: thin lens and motion blur.
#include "render/pixel_sample.h"

namespace spt {

[[gnu::noinline]] PixelSample start_lens_and_time(Rng rng, const SampledWavelengths& lambda, float px, float py,
                                                  const Camera& camera) {
    PixelSample ps{rng, lambda, px, py};
    ps.time = camera.shutter_open();
    if (camera.thin_lens()) {
        ps.lens_u = ps.rng.uniform();
        ps.lens_v = ps.rng.uniform();
    }
    if (camera.motion_blur()) ps.time = camera.shutter_time(ps.rng.uniform());
    return ps;
}
}  // namespace spt
