// Conductor Fresnel and the named metals:
//   - at normal incidence the exact conductor Fresnel equals |(η + ik − 1)/(η + ik + 1)|² for
//     the gold table (Johnson & Christy) at several wavelengths, through the BSDF too;
//   - k = 0 gives the dielectric Fresnel; grazing incidence reflects everything;
//   - the metal tables cover the sampled range and give gold its colour (red reflects more
//     than blue); silver and aluminium reflect > 85 % across the visible;
//   - scene files: "metal": "Au", explicit eta/k, anisotropic roughness (roughness_u,
//     roughness_v), and the clear errors for unknown metals, anisotropic roughness given
//     wrongly or on another type, both metal and eta (a plastic's dispersive coat:
//     test_plastic_dispersion.cpp).
#include <gtest/gtest.h>

#include <complex>

#include "io/located_error.h"
#include "model/bsdfs/bsdf.h"
#include "scene/scene_loader.h"
#include "spectral/metal_catalog.h"

namespace {

using namespace spt;

double normal_incidence(double eta, double k) {
    const std::complex<double> n(eta, k);
    return std::norm((n - 1.0) / (n + 1.0));
}

TEST(Conductor, NormalIncidenceMatchesTheClosedFormForGold) {
    const std::optional<MetalInfo> au = find_metal("Au");
    ASSERT_TRUE(au);
    const ConductorBsdf gold{Spectrum(au->eta, {SpectralResolution::kExact}), Spectrum(au->k, {SpectralResolution::kExact}),
                             {}, {}};
    const Vec3 n{0, 0, 1};
    for (double l : {400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0}) {
        const double eta = au->eta.eval(l), k = au->k.eval(l);
        EXPECT_NEAR(fresnel_conductor(1.f, float(eta), float(k)), normal_incidence(eta, k), 1e-6) << l;
        SampledWavelengths lambda{};
        lambda.lambda = {float(l), float(l), float(l), float(l)};
        lambda.pdf = {1, 1, 1, 1};
        SampledWavelengths lw = lambda;
        const auto bs = gold.sample(n, n, lw, 0.5f, 0.5f, 0.5f, TransportMode::radiance);
        ASSERT_TRUE(bs);
        EXPECT_NEAR(bs->weight[0], normal_incidence(eta, k), 1e-6) << l;
    }
    // Gold's colour: red reflects far more than blue (J&C: about 0.41 at 450 nm, 0.95 at 650 nm).
    EXPECT_LT(normal_incidence(au->eta.eval(450), au->k.eval(450)), 0.45);
    EXPECT_GT(normal_incidence(au->eta.eval(650), au->k.eval(650)), 0.9);
}

TEST(Conductor, LimitsAndTheDielectricCase) {
    for (double cos_i : {1.0, 0.7, 0.3, 0.05}) {
        EXPECT_NEAR(fresnel_conductor(float(cos_i), 1.5f, 0.f), fresnel_dielectric(float(cos_i), 1.5f), 1e-6);
    }
    EXPECT_NEAR(fresnel_conductor(0.f, 0.2f, 3.f), 1.f, 1e-6);
    // Between normal and grazing incidence a metal's reflectance dips (p polarisation) but stays
    // below 1 and above 0.
    for (double cos_i = 0.02; cos_i <= 1; cos_i += 0.02) {
        const float r = fresnel_conductor(float(cos_i), 0.2f, 3.f);
        EXPECT_GT(r, 0.f);
        EXPECT_LT(r, 1.f);
    }
}

TEST(Conductor, MetalTablesCoverTheRangeAndReflect) {
    for (const std::string& name : metal_names()) {
        const std::optional<MetalInfo> m = find_metal(name);
        ASSERT_TRUE(m) << name;
        ASSERT_FALSE(m->eta.table.empty());
        EXPECT_LE(m->eta.table.front().first, 360.0) << name;
        EXPECT_GE(m->eta.table.back().first, 830.0) << name;
        EXPECT_NE(m->source.find("Source:"), std::string::npos) << name;
    }
    EXPECT_TRUE(find_metal("au"));  // case is ignored
    EXPECT_FALSE(find_metal("Pt"));
    for (const char* bright : {"Ag", "Al"}) {
        const MetalInfo m = *find_metal(bright);
        for (double l = 450; l <= 700; l += 50) EXPECT_GT(normal_incidence(m.eta.eval(l), m.k.eval(l)), 0.85) << bright << l;
    }
}

std::string scene_with(const std::string& material) {
    return R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
  "materials": {"m": )" + material + R"(},
  "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})";
}

Scene load(const std::string& material) {
    return load_scene_text(scene_with(material), "test.json", "test", {}, {});
}

std::string error_of(const std::string& material) {
    try {
        load(material);
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "";
}

TEST(Conductor, SceneFileMaterials) {
    const Scene s = load(R"({"type": "conductor", "metal": "Cu", "roughness": 0.2})");
    const ConductorBsdf* c = std::get_if<ConductorBsdf>(&s.materials[0].bsdf);
    ASSERT_TRUE(c);
    EXPECT_FLOAT_EQ(c->ggx.alpha, 0.2f);
    EXPECT_TRUE(s.materials[0].has_non_delta());
    const Scene e = load(R"({"type": "conductor", "eta": {"type": "table", "points": [[400, 0.2], [700, 0.3]]}, "k": 3})");
    EXPECT_TRUE(std::get_if<ConductorBsdf>(&e.materials[0].bsdf)->ggx.is_smooth());
    EXPECT_TRUE(std::get_if<DielectricBsdf>(&load(R"({"type": "dielectric", "ior": {"type": "glass", "name": "SF11"},
        "roughness": 0.1, "film": {"thickness_nm": 300, "ior": 1.38}})").materials[0].bsdf));
    EXPECT_TRUE(std::get_if<ThinSheetBsdf>(&load(R"({"type": "thin_sheet", "thickness_nm": 400, "ior": 1.33})").materials[0].bsdf));
    EXPECT_TRUE(std::get_if<PlasticBsdf>(&load(R"({"type": "plastic", "kd": [0.2, 0.3, 0.7], "roughness": 0.3})").materials[0].bsdf));

    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Gold"})").find("unknown metal"), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Au", "roughness": [0.1, 0.3]})").find("roughness_u"), std::string::npos);
    // Anisotropic roughness: both keys, numbers in [0.001, 1], conductors only.
    const Scene a = load(R"({"type": "conductor", "metal": "Al", "roughness_u": 0.05, "roughness_v": 0.4})");
    const ConductorBsdf* brushed = std::get_if<ConductorBsdf>(&a.materials[0].bsdf);
    ASSERT_TRUE(brushed);
    EXPECT_TRUE(brushed->anisotropic());
    EXPECT_FLOAT_EQ(brushed->aniso.alpha_x, 0.05f);
    EXPECT_FLOAT_EQ(brushed->aniso.alpha_y, 0.4f);
    EXPECT_TRUE(a.materials[0].has_non_delta());
    EXPECT_TRUE(a.materials[0].textured);  // read per hit: its tangent
    EXPECT_TRUE(a.effects.textures);
    EXPECT_FALSE(s.materials[0].textured);
    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Au", "roughness_u": 0.1})").find("only one of"), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Au", "roughness_u": 0.1, "roughness_v": 0, "roughness": 0.1})")
                  .find("has both \"roughness\""), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Au", "roughness_u": 0.1, "roughness_v": 0})").find("[0.001, 1]"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"type": "dielectric", "ior": 1.5, "roughness_u": 0.1, "roughness_v": 0.2})")
                  .find("conductors only"), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Au", "anisotropy": 0.5})").find("roughness_u"), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Au", "k": 2})").find("both"), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "conductor", "eta": 0.2})").find("not both"), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "conductor", "metal": "Au", "roughness": 1.5})").find("[0, 1]"), std::string::npos);
    EXPECT_NE(error_of(R"({"type": "dielectric", "ior": 0.5})").find("index of refraction"), std::string::npos);
    // The error names the file, line and column of the offending value.
    EXPECT_EQ(error_of(R"({"type": "conductor", "metal": "Gold"})").rfind("test.json:2:", 0), 0u);
}

}  // namespace
