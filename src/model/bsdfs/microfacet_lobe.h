// What the rough BSDF types share besides the distribution: the optional thin film on their
// interface, the local frame on wo's side, and the mean of a spectral value over the
// wavelengths still alive (for lobe choices).
#pragma once
#include "core/frame.h"
#include "model/bsdfs/thin_film.h"
#include "spectral/spectrum.h"

namespace spt {

/// A thin film on an interface: thickness (nm) and real index (any spectrum, ≥ 1). Absent
/// when thickness_nm is 0 (the bare interface; its Fresnel formula is used, not the Airy sum).
struct ThinFilm {
    Spectrum eta;
    float thickness_nm = 0.f;
    bool present() const { return thickness_nm > 0.f; }
};

/// Mean of s over the wavelengths that still carry the path.
inline float mean_over_live(const SampledSpectrum& s, const SampledWavelengths& lambda) {
    return lambda.secondary_terminated() ? s[0] : s.average();
}

/// Frame whose z is the normal on wo's side (types that reflect alike on both sides).
inline Frame frame_on_side_of(const Vec3& wo, const Vec3& n) { return Frame(dot(wo, n) > 0.f ? n : -n); }

}  // namespace spt
