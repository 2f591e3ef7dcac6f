// Glass catalogue (spectra/glasses.csv): published n_d and V_d, the BK7 constants of
// ROBUSTNESS.md §4 and §7 case 21, and a 60° prism at minimum deviation traced through the
// renderer's own dielectric sampling (bsdf_sample) against D(λ) = 2·asin(n·sin(A/2)) − A.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/plane.h"
#include "io/embedded_files.h"
#include "model/bsdfs/bsdf.h"
#include "model/material.h"
#include "spectral/glass_catalog.h"
#include "spectral/sampled.h"
#include "spectral/spectrum.h"

namespace {

constexpr double kPiD = 3.14159265358979323846;

spt::GlassInfo glass(std::string_view name) {
    std::optional<spt::GlassInfo> g = spt::find_glass(name);
    if (!g) throw std::runtime_error("no glass " + std::string(name));
    return *g;
}

/// Clear glass (kt = 1) whose index is evaluated exactly, as with --spectral-bins exact.
spt::Material glass_material(const spt::SpectrumSource& ior) {
    spt::Material m;
    m.name = "glass";
    spt::LobeMixBsdf b;
    b.kt = spt::Spectrum(spt::SpectrumSource::constant(1.0), spt::SpectralResolution{});
    b.eta = spt::Spectrum(ior, spt::SpectralResolution{spt::SpectralResolution::kExact});
    m.bsdf = std::move(b);
    m.flags = spt::bsdf_flags(m.bsdf);
    return m;
}

/// Hero at λ; the companions only have to be live (pdf > 0) so that termination is visible.
spt::SampledWavelengths hero_at(double lambda_nm) {
    spt::SampledWavelengths w;
    w.lambda = {float(lambda_nm), 450.f, 550.f, 650.f};
    w.pdf = {0.25f, 0.25f, 0.25f, 0.25f};
    return w;
}

/// Largest float below 1: sample_dielectric reflects when u < F, so this always refracts
/// unless F = 1 (total internal reflection).
const float kRefract = std::nextafter(1.f, 0.f);

/// Half a unit in the last published digit of a CSV number ("1.51680" → 5e-6).
double half_last_digit(std::string_view s) {
    const std::size_t dot = s.find('.');
    const int decimals = dot == std::string_view::npos ? 0 : int(s.size() - dot - 1);
    return 0.5 * std::pow(10.0, -decimals);
}

/// The nd and vd fields of each row as written, for tolerances that follow the source's digits.
std::map<std::string, std::pair<std::string, std::string>> published_digits() {
    const spt::EmbeddedFile* file = spt::find_embedded("spectra/glasses.csv");
    if (!file) throw std::runtime_error("spectra/glasses.csv not embedded");
    std::map<std::string, std::pair<std::string, std::string>> out;
    std::string_view text = file->text;
    bool header = true;
    while (!text.empty()) {
        const std::size_t eol = text.find('\n');
        const std::string_view line = text.substr(0, eol);
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        if (line.empty() || line.front() == '#') continue;
        if (header) {
            header = false;
            continue;
        }
        std::vector<std::string_view> f;
        for (std::size_t start = 0; f.size() < 12;) {
            const std::size_t comma = line.find(',', start);
            f.push_back(line.substr(start, comma - start));
            start = comma + 1;
        }
        out[std::string(f[0])] = {std::string(f[10]), std::string(f[11])};
    }
    return out;
}

}  // namespace

// ---------------------------------------------------------------- catalogue contents

TEST(GlassCatalog, HoldsTheIssueMaterialsWithSources) {
    for (const char* name : {"N-BK7", "N-SF11", "SF11", "fused_silica", "diamond", "water"})
        EXPECT_TRUE(spt::find_glass(name).has_value()) << name;
    EXPECT_EQ(spt::find_glass("n-bk7")->name, "N-BK7");  // case-insensitive
    EXPECT_EQ(spt::find_glass("WATER")->name, "water");
    EXPECT_FALSE(spt::find_glass("BK8").has_value());
    EXPECT_EQ(spt::glass_names().size(), spt::glass_catalog().size());
    for (const spt::GlassInfo& g : spt::glass_catalog())
        EXPECT_GT(g.source.size(), 20u) << g.name << ": source must cite where the data is from";
}

TEST(GlassCatalog, NdAndAbbeNumberMatchPublishedValues) {
    // Tolerance: half a unit in the last digit the source publishes (SCHOTT: 5 decimals of n_d,
    // 2 of V_d): a mistyped or misplaced coefficient that moves n_d or V_d past that shows.
    const auto digits = published_digits();
    ASSERT_EQ(digits.size(), spt::glass_catalog().size());
    for (const spt::GlassInfo& g : spt::glass_catalog()) {
        const auto& [nd_text, vd_text] = digits.at(g.name);
        EXPECT_NEAR(g.ior.eval(spt::kLineD), g.nd, half_last_digit(nd_text)) << g.name;
        EXPECT_NEAR(spt::abbe_number(g.ior), g.vd, half_last_digit(vd_text)) << g.name;
    }
    // Spot values, so that the table itself cannot drift unnoticed (SCHOTT catalogue).
    EXPECT_EQ(glass("N-BK7").nd, 1.51680);
    EXPECT_EQ(glass("N-BK7").vd, 64.17);
    EXPECT_EQ(glass("N-SF11").nd, 1.78472);
    EXPECT_EQ(glass("N-SF11").vd, 25.68);
}

TEST(GlassCatalog, IndexIsPhysicalAndNormallyDispersive) {
    // Over the film's wavelength range every material has 1 < n < ∞ and dn/dλ < 0 (no pole or
    // absorption band in 360-830 nm), checked at 1 nm steps.
    for (const spt::GlassInfo& g : spt::glass_catalog()) {
        double previous = std::numeric_limits<double>::infinity();
        for (int lambda = 360; lambda <= 830; ++lambda) {
            const double n = g.ior.eval(lambda);
            ASSERT_TRUE(std::isfinite(n) && n > 1.0) << g.name << " at " << lambda << " nm: " << n;
            ASSERT_LT(n, previous) << g.name << " at " << lambda << " nm";
            previous = n;
        }
    }
}

TEST(GlassCatalog, IndependentReferenceValues) {
    // Rows without a manufacturer catalogue, against values measured independently of them.
    // Two fused silicas (Malitson 1965, SCHOTT LITHOSIL Q) agree to a few 1e-5.
    const spt::GlassInfo malitson = glass("fused_silica"), lithosil = glass("LITHOSIL-Q");
    EXPECT_NEAR(malitson.ior.eval(spt::kLineD), lithosil.nd, 5e-5);
    EXPECT_NEAR(spt::abbe_number(malitson.ior), lithosil.vd, 0.05);
    // Diamond: the gemmological n = 2.417 at the sodium D line (589.3 nm).
    EXPECT_NEAR(glass("diamond").ior.eval(589.29), 2.417, 5e-4);
    // Water at 20 °C: n_D = 1.33299 relative to air (589.26 nm). Daimon's index is absolute,
    // so divide by air's 1.000272 (Edlén 1966 standard air at 589 nm, scaled to 20 °C);
    // the tolerance adds the air index's uncertainty to the published rounding.
    EXPECT_NEAR(glass("water").ior.eval(589.26) / 1.000272, 1.33299, 1e-5);
}

TEST(GlassCatalog, WaterTableFollowsTheFourTermFormula) {
    // Daimon & Masumura (2007), 20.0 °C, evaluated here independently of the CSV; the catalogue
    // tabulates it every 0.5 nm because SpectrumSource has three Sellmeier terms.
    const double b[4] = {5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1};
    const double c[4] = {5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1};
    const spt::SpectrumSource water = glass("water").ior;
    for (double lambda = 360.0; lambda <= 830.0; lambda += 0.37) {
        const double l2 = lambda * lambda * 1e-6;
        double n2 = 1.0;
        for (int i = 0; i < 4; ++i) n2 += b[i] * l2 / (l2 - c[i]);
        EXPECT_NEAR(water.eval(lambda), std::sqrt(n2), 1e-7) << lambda << " nm";
    }
}

// ---------------------------------------------------------------- ROBUSTNESS constants

TEST(GlassCatalog, Bk7SellmeierConstants) {
    // ROBUSTNESS §4 / case 21: n(360 / 587.6 / 830 nm) = 1.53719 / 1.51680 / 1.51020 (5 decimals).
    const spt::SpectrumSource bk7 = glass("N-BK7").ior;
    EXPECT_NEAR(bk7.eval(360.0), 1.53719, 5e-6);
    EXPECT_NEAR(bk7.eval(587.6), 1.51680, 5e-6);
    EXPECT_NEAR(bk7.eval(830.0), 1.51020, 5e-6);
    // Unit-error signatures: λ in nm fed to the µm formula gives 1.81168, λ in metres 1.00000.
    // eval() takes nm, so those slips are reproduced by scaling the argument by 1e3 or 1e-6.
    EXPECT_NEAR(bk7.eval(587.6e3), 1.81168, 5e-6);
    EXPECT_NEAR(bk7.eval(587.6e-6), 1.00000, 5e-6);
    EXPECT_GT(std::fabs(bk7.eval(587.6) - 1.81168), 0.2);
    EXPECT_GT(bk7.eval(587.6) - 1.0, 0.5);
}

TEST(GlassCatalog, Bk7RefractionAt60Degrees) {
    // ROBUSTNESS case 21: θt = 34.452° at 400 nm and 34.915° at 700 nm (3 decimals: ±5e-4°;
    // float directions add ~1e-5°), through the renderer's refraction branch.
    const spt::Material m = glass_material(glass("N-BK7").ior);
    const spt::Vec3 n(0.f, 0.f, 1.f);
    const double t = 60.0 * kPiD / 180.0;
    const spt::Vec3 wo(float(std::sin(t)), 0.f, float(std::cos(t)));
    for (auto [lambda, expected] : {std::pair{400.0, 34.452}, std::pair{700.0, 34.915}}) {
        spt::SampledWavelengths w = hero_at(lambda);
        const std::optional<spt::BsdfSample> bs =
            spt::bsdf_sample(m.bsdf, wo, n, w, 0.5f, kRefract, 0.5f, spt::TransportMode::radiance);
        ASSERT_TRUE(bs.has_value());
        ASSERT_LT(bs->wi.z, 0.f) << "refracted into the glass";
        EXPECT_NEAR(std::acos(double(-bs->wi.z)) * 180.0 / kPiD, expected, 5e-4)
            << lambda << " nm";
    }
}

TEST(GlassCatalog, CauchyRowsAndMalformedRows) {
    // ROBUSTNESS §4: Cauchy A = 1.5046, B = 0.00420 µm² gives n(587.6) = 1.51676, n(830) = 1.51070.
    const std::string header = "# test\nname,model,k1,k2,k3,k4,k5,k6,k7,k8,nd,vd,source\n";
    const auto parsed = spt::parse_glass_catalog(
        header + "bk7c,cauchy,1.5046,0.00420,0,0,0,0,0,0,1.51676,63.8,Walther, clovers, table\r\n",
        "inline");
    ASSERT_EQ(parsed.size(), 1u);
    EXPECT_NEAR(parsed[0].ior.eval(587.6), 1.51676, 5e-6);
    EXPECT_NEAR(parsed[0].ior.eval(830.0), 1.51070, 5e-6);
    EXPECT_EQ(parsed[0].source, "Walther, clovers, table");  // commas and CR kept out

    const char* bad_rows[] = {
        "x,cauchy,1.5,0.004,0,0,0,0,0,0,1.5,60\n",                    // no source
        "x,cauchy,1.5,0.004,0,0.1,0,0,0,0,1.5,60,src\n",              // cauchy with k4
        "x,schott,1.5,0.004,0,0,0,0,0,0,1.5,60,src\n",                // unknown model
        "x,cauchy,1.5,0.00a4,0,0,0,0,0,0,1.5,60,src\n",               // not a number
        "x,sellmeier,0,0,0,0,0,0,0,0,1.0,0,src\n",                    // n = 1: no glass
        "x,cauchy,1.5,0.004,0,0,0,0,0,0,1.5,60,a\nX,cauchy,1.5,0,0,0,0,0,0,0,1.5,60,b\n",  // dup
    };
    for (const char* row : bad_rows)
        EXPECT_THROW(spt::parse_glass_catalog(header + row, "inline"), std::runtime_error) << row;
    EXPECT_THROW(spt::parse_glass_catalog("wavelength_nm,n\n400,1.5\n", "inline"),
                 std::runtime_error);
}

// ---------------------------------------------------------------- prism at minimum deviation

namespace {

constexpr double kApex = 60.0 * kPiD / 180.0;

double angle_in_xz(const spt::Vec3& d) { return std::atan2(double(d.z), double(d.x)); }

/// A prism with apex angle A: two faces through the apex line (the y axis), outward normals
/// n1 (left face) and n2 (right face) tilted A/2 from ±x, base below. A ray enters the left
/// face at the minimum-deviation angle θ1 = asin(n·sin(A/2)) and leaves through the right face;
/// both refractions are bsdf_sample's. Returns the total deviation (positive = towards the base)
/// and the inside ray's tilt from the base direction.
void trace_prism(const spt::SpectrumSource& ior, double lambda_nm, double& deviation,
                 double& inside_tilt) {
    const double half = kApex / 2, n = ior.eval(lambda_nm);
    const spt::Vec3 n1(float(-std::cos(half)), 0.f, float(std::sin(half)));
    const spt::Vec3 n2(float(std::cos(half)), 0.f, float(std::sin(half)));
    const spt::Vec3 face1(float(-std::sin(half)), 0.f, float(-std::cos(half)));  // down the face
    // Symmetric path: inside the glass the ray runs along +x, which is A/2 from the inward
    // normal −n1, so outside it must arrive θ1 from −n1, i.e. tilted θ1 − A/2 above +x.
    const double rise = std::asin(n * std::sin(half)) - half;
    const spt::Vec3 d_in(float(std::cos(rise)), 0.f, float(std::sin(rise)));

    const spt::Material m = glass_material(ior);
    ASSERT_TRUE(m.flags.has(spt::BsdfFlags::dispersive));
    spt::SampledWavelengths w = hero_at(lambda_nm);

    const std::optional<spt::BsdfSample> in =
        spt::bsdf_sample(m.bsdf, -d_in, n1, w, 0.5f, kRefract, 0.5f, spt::TransportMode::radiance);
    ASSERT_TRUE(in.has_value());
    EXPECT_TRUE(in->is_delta());
    ASSERT_LT(spt::dot(in->wi, n1), 0.f) << "refracted into the prism";
    // Dispersive refraction: the companions would bend elsewhere, so only the hero survives.
    EXPECT_TRUE(w.secondary_terminated());
    for (int i = 1; i < spt::kLambdaCount; ++i) {
        EXPECT_EQ(w.pdf[i], 0.f);
        EXPECT_EQ(in->weight[i], 0.f);
    }
    EXPECT_GT(in->weight[0], 0.f);

    const spt::Ray inside{face1 * 2.f, in->wi};  // enters 2 units down the left face
    const spt::Plane right_face{n2, 0.f};
    const double t = right_face.intersect_t(inside);
    ASSERT_TRUE(std::isfinite(t));
    const spt::Hit hit = right_face.make_hit(inside, t);
    EXPECT_NEAR(hit.p.z, inside.o.z, 1e-4) << "exits at the height it entered";

    const std::optional<spt::BsdfSample> out =
        spt::bsdf_sample(m.bsdf, -in->wi, hit.n, w, 0.5f, kRefract, 0.5f, spt::TransportMode::radiance);
    ASSERT_TRUE(out.has_value());
    EXPECT_TRUE(out->is_delta());
    ASSERT_GT(spt::dot(out->wi, n2), 0.f) << "left the prism";
    deviation = angle_in_xz(d_in) - angle_in_xz(out->wi);
    inside_tilt = angle_in_xz(in->wi);
}

}  // namespace

TEST(Prism, MinimumDeviationMatchesClosedForm) {
    // Lines Hg 404.7, H F 486.1, He d 587.6, H C 656.3, He 706.5 nm.
    const double lines[] = {404.7, 486.1, 587.6, 656.3, 706.5};
    for (const char* name : {"N-BK7", "SF11", "N-SF11"}) {
        const spt::SpectrumSource ior = glass(name).ior;
        double previous = std::numeric_limits<double>::infinity();
        for (double lambda : lines) {
            double deviation = 0, tilt = 0;
            ASSERT_NO_FATAL_FAILURE(trace_prism(ior, lambda, deviation, tilt))
                << name << " " << lambda;
            const double expected = 2.0 * std::asin(ior.eval(lambda) * std::sin(kApex / 2)) - kApex;
            EXPECT_NEAR(deviation, expected, 1e-4) << name << " at " << lambda << " nm";
            EXPECT_NEAR(tilt, 0.0, 1e-4) << name << " at " << lambda << " nm: not along the base";
            EXPECT_LT(deviation, previous) << name << ": redder light must deviate less";
            previous = deviation;
        }
    }
}
