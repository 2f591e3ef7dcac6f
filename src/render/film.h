// The film: per-pixel sums of CIE XYZ in double precision, in the order samples arrive (each
// pixel belongs to one tile, each tile to one worker at a time, so no locks are needed).
// Samples that are not finite or negative are counted and dropped, never silently fixed.
#pragma once
#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/image.h"
#include "spectral/cie.h"
#include "spectral/color_space.h"

namespace spt {

class Film {
public:
    Film(int width, int height);

    /// Adds one path's radiance at the path's wavelengths to pixel (x, y).
    void add_sample(int x, int y, const SampledSpectrum& L, const SampledWavelengths& lambda) {
        const std::size_t i = index(x, y);
        ++m_count[i];
        for (int k = 0; k < kLambdaCount; ++k) {
            if (!std::isfinite(L[k])) {
                m_rejected_nonfinite.fetch_add(1, std::memory_order_relaxed);
                return;
            }
            if (L[k] < 0.f) {
                m_rejected_negative.fetch_add(1, std::memory_order_relaxed);
                return;
            }
        }
        const Xyz c = Cie1931::get().to_xyz(L, lambda);
        m_xyz[3 * i] += c.x, m_xyz[3 * i + 1] += c.y, m_xyz[3 * i + 2] += c.z;
        m_y_squared[i] += c.y * c.y;
    }

    int width() const { return m_width; }
    int height() const { return m_height; }
    std::uint32_t sample_count(int x, int y) const { return m_count[index(x, y)]; }
    /// Mean XYZ of a pixel (zero when it has no samples).
    Xyz pixel_xyz(int x, int y) const;
    /// Standard error of the pixel's mean Y (from the per-sample second moment).
    double pixel_y_standard_error(int x, int y) const;

    std::uint64_t rejected_nonfinite() const { return m_rejected_nonfinite.load(); }
    std::uint64_t rejected_negative() const { return m_rejected_negative.load(); }
    std::uint64_t rejected_samples() const { return rejected_nonfinite() + rejected_negative(); }

    /// Mean XYZ of every pixel converted to linear RGB of the given colour space.
    Image develop(const ColorSpace& space) const;

    /// Raw state, for bit-exact comparisons.
    const std::vector<double>& xyz_sums() const { return m_xyz; }

    /// The whole accumulation state as bytes (checkpoints) and back. restore_state throws
    /// std::runtime_error when the bytes do not describe a film of this size.
    std::string save_state() const;
    void restore_state(std::string_view bytes);

private:
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(m_width) + static_cast<std::size_t>(x);
    }
    int m_width, m_height;
    std::vector<double> m_xyz;
    std::vector<double> m_y_squared;
    std::vector<std::uint32_t> m_count;
    std::atomic<std::uint64_t> m_rejected_nonfinite{0}, m_rejected_negative{0};
};

}  // namespace spt
