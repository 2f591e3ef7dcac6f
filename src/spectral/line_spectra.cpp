#include "spectral/line_spectra.h"

#include <cmath>
#include <map>
#include <mutex>
#include <vector>

#include "spectral/catalog_lookup.h"
#include "spectral/cie.h"

namespace spt {

namespace {

struct Lab {
    double l, a, b;
};

Lab to_lab(const Xyz& c, const Xyz& white) {
    auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
    const double fx = f(c.x / white.x), fy = f(c.y / white.y), fz = f(c.z / white.z);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

constexpr int kFirst = 360, kCount = 471;  // 1 nm over 360–830 nm

/// Values of `f` at 360, 361, ..., 830 nm.
template <typename F>
std::vector<double> tabulate(F f) {
    std::vector<double> v(kCount);
    for (int i = 0; i < kCount; ++i) v[i] = f(static_cast<float>(kFirst + i));
    return v;
}

/// Σ s(λ)·t(λ)·cmf(λ) over the 1 nm rows.
Xyz tristimulus(const std::vector<double>& s, const std::vector<double>& t) {
    static const std::vector<Xyz> cmf = [] {
        std::vector<Xyz> c(kCount);
        for (int i = 0; i < kCount; ++i) c[i] = Cie1931::get().cmf(static_cast<float>(kFirst + i));
        return c;
    }();
    Xyz sum;
    for (int i = 0; i < kCount; ++i) {
        const double v = s[i] * t[i];
        sum.x += v * cmf[i].x, sum.y += v * cmf[i].y, sum.z += v * cmf[i].z;
    }
    return sum;
}

/// The ColorChecker's patches at 1 nm, exact or binned at `bins` (0: exact); tables of the
/// bin counts asked for so far, kept.
const std::vector<std::vector<double>>& patches(int bins) {
    static std::mutex mutex;
    static std::map<int, std::vector<std::vector<double>>> tables;
    const std::lock_guard lock(mutex);
    auto [it, added] = tables.try_emplace(bins);
    if (added) {
        const SpectralTable& t = embedded_spectral_table("colorchecker.csv");
        for (std::size_t c = 1; c < t.column_names.size(); ++c) {
            const Spectrum patch(column_spectrum(t, t.column_names[c]), SpectralResolution{bins});
            it->second.push_back(tabulate([&](float l) { return patch.eval(l); }));
        }
    }
    return it->second;
}

}  // namespace

double binned_colour_error(const SpectrumSource& light, int bins) {
    const Spectrum binned_light(light, SpectralResolution{bins});
    const std::vector<double> exact = tabulate([&](float l) { return light.eval(l); });
    const std::vector<double> binned = tabulate([&](float l) { return binned_light.eval(l); });
    const Xyz white = tristimulus(exact, std::vector<double>(kCount, 1.0));
    if (!(white.x > 0 && white.y > 0 && white.z > 0)) return 0;
    const std::vector<std::vector<double>>& exact_patches = patches(SpectralResolution::kExact);
    const std::vector<std::vector<double>>& binned_patches = patches(bins);
    double sum = 0;
    for (std::size_t k = 0; k < exact_patches.size(); ++k) {
        const Lab a = to_lab(tristimulus(exact, exact_patches[k]), white);
        const Lab b = to_lab(tristimulus(binned, binned_patches[k]), white);
        sum += std::hypot(a.l - b.l, a.a - b.a, a.b - b.b);
    }
    return sum / static_cast<double>(exact_patches.size());
}

int bins_for_light(const SpectrumSource& light) {
    static const double daylight = [] {
        const SpectralTable& t = embedded_spectral_table("cie_d65.csv");
        return binned_colour_error(column_spectrum(t, "value"), SpectralResolution::kDefaultBins);
    }();
    int bins = SpectralResolution::kDefaultBins;
    while (bins < 256 && binned_colour_error(light, bins) > 1.5 * daylight) bins *= 2;
    return bins;
}

}  // namespace spt
