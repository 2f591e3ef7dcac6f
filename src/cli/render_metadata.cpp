// Render metadata for the EXR header.
#include "cli/render_metadata.h"

#include <cstdio>
#include <ctime>

namespace spt {

namespace {

std::string number_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

/// Now in UTC, as OpenEXR's capDate wants it: "YYYY:MM:DD hh:mm:ss".
std::string utc_cap_date() {
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char text[32];
    std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &utc);
    return text;
}

}  // namespace

std::vector<ExrAttribute> render_metadata(const Options& opt, const RenderSettings& rs,
                                          const RenderStats& stats, const Observer& observer,
                                          std::pair<int, int> samples_per_pixel) {
    const auto [fewest, most] = samples_per_pixel;
    std::vector<ExrAttribute> a = {
        ExrAttribute::text("software", std::string("pathtracer ") + SPT_VERSION),
        ExrAttribute::text("scene", opt.scene),
        ExrAttribute::integer("spp", fewest),
        ExrAttribute::text("sppPerPixel", std::to_string(fewest) + (most == fewest ? "" : "-" + std::to_string(most))),
        ExrAttribute::integer("sppRequested", rs.spp),
        ExrAttribute::text("integrator", integrator_name(rs.integrator.kind)),
        ExrAttribute::text("seed", std::to_string(rs.seed)),
        ExrAttribute::text("sampler", sampler_name(rs.sampler)),
        ExrAttribute::real("renderTimeSeconds", stats.seconds),
        ExrAttribute::text("capDate", utc_cap_date()),
        {"utcOffset", "float", std::string(4, '\0')},  // +0.0f: capDate is UTC
        ExrAttribute::text("spectralBins", opt.spectral.bins == SpectralResolution::kExact
                                               ? "exact" : std::to_string(opt.spectral.bins)),
        ExrAttribute::text("observer", observer.name()),
        ExrAttribute::integer("maxDepth", rs.integrator.max_depth),
        ExrAttribute::integer("wavelengthsPerPath", rs.integrator.wavelengths_per_path),
    };
    if (opt.spectral_bands.count > 0) {
        a.push_back(ExrAttribute::integer("spectralBands", opt.spectral_bands.count));
        const std::string range = number_text(opt.spectral_bands.min_nm) + ":" +
                                  number_text(opt.spectral_bands.max_nm);
        a.push_back(ExrAttribute::text("spectralRangeNm", range));
    }
    return a;
}

}  // namespace spt
