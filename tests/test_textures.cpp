// Textures: texel addressing, wrap modes and bilinear filtering exact on small synthetic
// images of every format; surface coordinates of quads and the other shapes; a checkerboard's
// cells where the (u, v) mapping puts them; RGB texels → spectra within the scene format's
// promise, emission texels that keep D65's white; and an image of one colour that renders
// as that colour given as a constant.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "ciede2000.h"
#include "program_process.h"
#include "io/image_encoders.h"
#include "io/image_writer.h"
#include "scene/json_scene_reader.h"
#include "scene/texture_parser.h"
#include "spectral/rgb_texels.h"
#include "spectral/rgb_to_spectrum.h"
#include "spectral/spectral_table.h"
#include "test_scenes.h"

namespace spt {
namespace {

/// An image texture over `w` × `h` texels whose entries are the numbers `values` (row-major,
/// top row first), one entry per texel.
Texture number_image(int w, int h, std::vector<float> values, WrapMode wrap = WrapMode::repeat, bool bilinear = true) {
    Texture t;
    ImageTexture img;
    img.width = w, img.height = h, img.wrap = wrap, img.bilinear = bilinear;
    for (std::uint32_t i = 0; i < values.size(); ++i) img.texels.push_back(i);
    t.pattern = img;
    t.bins = 1;
    t.values = std::move(values);
    return t;
}

float eval1(const Texture& t, float u, float v) {
    float out = 0;
    t.eval(u, v, std::span<float>(&out, 1));
    return out;
}

TEST(ImageTexture, TexelCentresBilinearWeightsAndOrientation) {
    // 3 x 2 texels: top row 1 2 4, bottom row 8 16 32. Texel (i, j) has its centre at
    // u = (i + ½)/3, v = 1 − (j + ½)/2 (v = 0 at the bottom edge).
    const Texture t = number_image(3, 2, {1, 2, 4, 8, 16, 32});
    EXPECT_EQ(eval1(t, 0.5f / 3, 0.75f), 1.f);
    EXPECT_EQ(eval1(t, 2.5f / 3, 0.75f), 4.f);
    EXPECT_EQ(eval1(t, 1.5f / 3, 0.25f), 16.f);
    // Halfway between the centres of 1 and 2, and the middle of 1, 2, 8, 16.
    EXPECT_FLOAT_EQ(eval1(t, 1.f / 3, 0.75f), 1.5f);
    EXPECT_FLOAT_EQ(eval1(t, 1.f / 3, 0.5f), (1 + 2 + 8 + 16) / 4.f);
    // A quarter of the way from the centre of 2 to that of 4 and of 16: weights (9, 3, 3, 1)/16.
    EXPECT_FLOAT_EQ(eval1(t, 1.75f / 3, 0.625f), (9 * 2 + 3 * 4 + 3 * 16 + 1 * 32) / 16.f);
    // Nearest: the texel containing the point.
    const Texture n = number_image(3, 2, {1, 2, 4, 8, 16, 32}, WrapMode::repeat, false);
    EXPECT_EQ(eval1(n, 0.34f, 0.51f), 2.f);
    EXPECT_EQ(eval1(n, 0.99f, 0.01f), 32.f);
}

TEST(ImageTexture, TexelsSharingAValueKeepTheirBilinearWeights) {
    // 2 x 2 texels: the top row is one value (entry 0), the bottom row another (entry 1), as
    // when an image's texels share a colour. Between the rows' centres the blend is linear.
    Texture t = number_image(2, 2, {1, 3});
    std::get<ImageTexture>(t.pattern).texels = {0, 0, 1, 1};
    EXPECT_FLOAT_EQ(eval1(t, 0.5f, 0.5f), 2.f);
    EXPECT_FLOAT_EQ(eval1(t, 0.3f, 0.375f), 2.5f);  // a quarter of the way from the bottom centre
    EXPECT_EQ(eval1(t, 0.5f, 0.75f), 1.f);
    EXPECT_EQ(eval1(t, 0.1f, 0.25f), 3.f);
}

TEST(ImageTexture, WrapModesOutsideTheUnitSquare) {
    // One row of 4 texels 0, 1, 2, 3; nearest filtering shows which texel each u reads.
    auto at = [](WrapMode mode, float u) {
        return eval1(number_image(4, 1, {0, 1, 2, 3}, mode, false), u, 0.5f);
    };
    // repeat: the image tiles; clamp: the edge texels extend; mirror: every other tile flipped.
    EXPECT_EQ(at(WrapMode::repeat, 1.1f), 0.f);
    EXPECT_EQ(at(WrapMode::repeat, -0.1f), 3.f);
    EXPECT_EQ(at(WrapMode::repeat, 7.6f), 2.f);
    EXPECT_EQ(at(WrapMode::clamp, 1.6f), 3.f);
    EXPECT_EQ(at(WrapMode::clamp, -3.f), 0.f);
    EXPECT_EQ(at(WrapMode::mirror, 1.1f), 3.f);
    EXPECT_EQ(at(WrapMode::mirror, 1.9f), 0.f);
    EXPECT_EQ(at(WrapMode::mirror, -0.1f), 0.f);
    EXPECT_EQ(at(WrapMode::mirror, -0.3f), 1.f);
    EXPECT_EQ(at(WrapMode::mirror, 2.1f), 0.f);
    // Bilinear across the seam: repeat blends the last and first texels, clamp does not.
    EXPECT_FLOAT_EQ(eval1(number_image(4, 1, {0, 1, 2, 3}, WrapMode::repeat), 1.f, 0.5f), 1.5f);
    EXPECT_FLOAT_EQ(eval1(number_image(4, 1, {0, 1, 2, 3}, WrapMode::clamp), 1.f, 0.5f), 3.f);
    EXPECT_FLOAT_EQ(eval1(number_image(4, 1, {0, 1, 2, 3}, WrapMode::mirror), 0.f, 0.5f), 0.f);
    // Huge or non-finite coordinates read a texel, never outside the array.
    EXPECT_GE(eval1(number_image(4, 1, {0, 1, 2, 3}), 1e30f, 0.5f), 0.f);
    EXPECT_GE(eval1(number_image(4, 1, {0, 1, 2, 3}), NAN, 0.5f), 0.f);
}

TEST(ImageTexture, UniformRegionGivesItsValueBitForBit) {
    // Weights of equal entries merge to exactly 1, whatever the sub-texel position.
    Texture t = number_image(2, 2, {0.1f, 0.1f, 0.1f, 0.1f});
    t.values = {0.1f, 0.1f, 0.1f, 0.1f};
    auto& img = std::get<ImageTexture>(t.pattern);
    img.texels = {0, 0, 0, 0};
    for (float u : {0.13f, 0.5f, 0.77f, 0.9999f}) EXPECT_EQ(eval1(t, u, 0.31f), 0.1f);
}

// ---- Every image format through the loader's texture path (number use: linear values) ----

struct Loaded {
    Scene scene;
    int texture;
};

/// Builds texture "t" of `definition` for `use`, reading every file as `bytes`.
Loaded load_texture(const std::string& definition, const std::string& bytes, TextureUse use,
                    SpectralResolution resolution = {}) {
    Loaded l;
    const RelativeFileReader reader = [&](const std::string& rel, std::string& contents, std::string& display, std::string&) {
        contents = bytes;
        display = rel;
        return true;
    };
    const SpectrumParser spectra(SourceFiles{"t.json"}, resolution);
    TextureParser parser(SourceFiles{"t.json"}, resolution, spectra, reader, l.scene);
    const ParamValue defs = read_json_value("{\"t\": " + definition + "}", "t.json");
    parser.definitions(defs);
    const ParamValue binding = ParamValue::dict({{"texture", ParamValue::string("t")}});
    l.texture = parser.bind(binding, "value", use);
    return l;
}

TEST(TextureFormats, EveryFormatGivesItsTexelsAndTheirBilinearBlend) {
    // 2 x 2 linear values (top row a b, bottom row c d) in each format.
    const float a = 0.25f, b = 0.5f, c = 0.75f, d = 1.f;
    Image img;
    img.width = 2, img.height = 2;
    img.rgb = {a, a, a, b, b, b, c, c, c, d, d, d};
    const ImageWriteOptions options;
    // 8-bit PPM with "encoding": "linear": codes 64, 128, 191, 255 read as code/255.
    const std::string ppm = std::string("P6\n2 2\n255\n") + std::string("\x40\x40\x40\x80\x80\x80\xbf\xbf\xbf\xff\xff\xff", 12);
    struct Case {
        const char* name;
        std::string bytes, encoding;
        std::array<float, 4> expected;
    };
    const Case cases[] = {
        {"pfm", encode_pfm(img, options), "", {a, b, c, d}},
        {"exr", encode_exr(img, options), "", {a, b, c, d}},
        {"ppm linear", ppm, ", \"encoding\": \"linear\"", {64 / 255.f, 128 / 255.f, 191 / 255.f, 1.f}},
    };
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        const Loaded l = load_texture(R"({"type": "image", "file": "x")" + k.encoding + "}", k.bytes, TextureUse::number);
        const Texture& t = l.scene.textures[static_cast<std::size_t>(l.texture)];
        EXPECT_FLOAT_EQ(eval1(t, 0.25f, 0.75f), k.expected[0]);
        EXPECT_FLOAT_EQ(eval1(t, 0.75f, 0.75f), k.expected[1]);
        EXPECT_FLOAT_EQ(eval1(t, 0.25f, 0.25f), k.expected[2]);
        EXPECT_FLOAT_EQ(eval1(t, 0.75f, 0.25f), k.expected[3]);
        const float mid = (k.expected[0] + k.expected[1] + k.expected[2] + k.expected[3]) / 4;
        EXPECT_NEAR(eval1(t, 0.5f, 0.5f), mid, 1e-6f);
    }
    // PNG (16-bit grey, the test file), sRGB-decoded by default: texel (0, 0) of code 11 of
    // 65535; and 8-bit RGB read as linear when told.
    std::ifstream in(std::filesystem::path(SPT_TEST_DIR) / "textures" / "grey16.png", std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const Loaded l = load_texture(R"({"type": "image", "file": "g.png", "filter": "nearest"})", png, TextureUse::number);
    const Texture& t = l.scene.textures[static_cast<std::size_t>(l.texture)];
    auto srgb = [](double x) { return x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4); };
    // Texel (x, y) = (2, 3) of the 5 x 6 image: code (2·37 + 3·71 + 11) mod 65536.
    EXPECT_NEAR(eval1(t, 2.5f / 5, 1 - 3.5f / 6), srgb((2 * 37 + 3 * 71 + 11) / 65535.0), 1e-6);
}

// ---- Surface coordinates ----

TEST(SurfaceUv, QuadTriangleCylinderAndCone) {
    const std::string text = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
      "textures": {"c": {"type": "checkerboard", "even": 0.2, "odd": 0.8}},
      "materials": {"m": {"kd": 0.5}, "t": {"kd": {"texture": "c"}}},
      "shapes": [{"type": "quad", "origin": [-1, -1, 0], "edge1": [4, 0, 0], "edge2": [0, 2, 0], "material": "t"},
        {"type": "triangle", "vertices": [[10, 0, 0], [12, 0, 0], [10, 2, 0]], "material": "m"},
        {"type": "cylinder", "base": [20, -1, 0], "axis": [0, 1, 0], "radius": 1, "height": 4, "material": "m"},
        {"type": "cone", "base": [30, -1, 0], "axis": [0, 1, 0], "radius": 1, "height": 2, "material": "m"}]})";
    const Scene scene = load_scene_text(text, "uv.json", "uv", {}, {});
    auto uv_at = [&](float x, float y, ShapeKind kind) {
        const std::optional<Hit> hit = scene.intersect({{x, y, 5}, {0, 0, -1}, kInfinity});
        EXPECT_TRUE(hit && hit->prim.kind() == kind);
        float u = -1, v = -1;
        if (hit) scene.surface_uv(*hit, u, v);
        return std::pair{u, v};
    };
    // The (textured) quad: u along edge1 (4 long), v along edge2 (2 long), on both triangles.
    for (const auto& [x, y] : {std::pair{0.f, 0.f}, {2.6f, -0.8f}, {-0.6f, 0.9f}, {1.f, 0.5f}}) {
        const auto [u, v] = uv_at(x, y, ShapeKind::triangle);
        EXPECT_NEAR(u, (x + 1) / 4, 1e-6f);
        EXPECT_NEAR(v, (y + 1) / 2, 1e-6f);
    }
    // The triangle: (u, v) = the barycentrics of its second and third vertices.
    const auto [tu, tv] = uv_at(10.5f, 0.5f, ShapeKind::triangle);
    EXPECT_NEAR(tu, 0.25f, 1e-6f);
    EXPECT_NEAR(tv, 0.25f, 1e-6f);
    // Cylinder of height 4 from y = −1: v = (y + 1)/4; the front is a fixed u.
    EXPECT_NEAR(uv_at(20, 1, ShapeKind::cylinder).second, 0.5f, 1e-6f);
    EXPECT_NEAR(uv_at(20, -0.5f, ShapeKind::cylinder).second, 0.125f, 1e-6f);
    EXPECT_NEAR(uv_at(20, 1, ShapeKind::cylinder).first, uv_at(20, -0.5f, ShapeKind::cylinder).first, 1e-6f);
    // Cone of height 2: at y = 0, half way up.
    EXPECT_NEAR(uv_at(30, 0, ShapeKind::cone).second, 0.5f, 1e-5f);
}

TEST(SurfaceTangent, IsTheDirectionOfGrowingUOnEveryShape) {
    // The tangent anisotropic BSDFs are oriented by (Scene::surface_tangent): a small step
    // along it on the surface changes u and (to first order) not v. Quads keep their (u, v)
    // for an anisotropic material, so both of their triangles have edge1's direction.
    const std::string text = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
      "materials": {"m": {"kd": 0.5}, "brushed": {"type": "conductor", "metal": "Al", "roughness_u": 0.05, "roughness_v": 0.3}},
      "shapes": [{"type": "quad", "origin": [-1, -1, 0], "edge1": [4, 0.5, 0], "edge2": [0, 2, 0], "material": "brushed"},
        {"type": "triangle", "vertices": [[10, 0, 0], [12, 0.5, 0], [10, 2, 0]], "material": "m"},
        {"type": "sphere", "center": [40, 0, -1], "radius": 1.5, "material": "m"},
        {"type": "disk", "center": [50, 0, 0], "normal": [0, 0.3, 1], "radius": 1, "material": "m"},
        {"type": "cylinder", "base": [20, -1, 0], "axis": [0, 1, 0], "radius": 1, "height": 4, "material": "m"},
        {"type": "cone", "base": [30, -1, 0], "axis": [0, 1, 0], "radius": 1, "height": 2, "material": "m"}]})";
    const Scene scene = load_scene_text(text, "tangent.json", "tangent", {}, {});
    const std::pair<float, float> points[] = {{0.f, 0.f},    {2.5f, 0.2f},  {-0.6f, 0.9f}, {10.5f, 0.5f}, {40.4f, 0.7f},
                                              {39.3f, -0.5f}, {50.3f, 0.2f},  {20.3f, 1.f},  {29.8f, 0.f}};
    for (const auto& [x, y] : points) {
        const std::optional<Hit> hit = scene.intersect({{x, y, 5}, {0, 0, -1}, kInfinity});
        ASSERT_TRUE(hit) << x;
        const Vec3 t = scene.surface_tangent(*hit);
        ASSERT_GT(length(t), 0.f) << x;
        float u0, v0, u1, v1;
        scene.surface_uv(*hit, u0, v0);
        Hit moved = *hit;
        moved.p = hit->p + normalize(t - hit->n * dot(t, hit->n)) * 1e-3f;
        scene.surface_uv(moved, u1, v1);
        EXPECT_GT(std::fabs(u1 - u0), 1e-4f) << "at x = " << x;
        EXPECT_LT(std::fabs(v1 - v0), 0.02f * std::fabs(u1 - u0)) << "at x = " << x;
    }
    // The quad's two triangles: edge1 on both.
    for (const auto& [x, y] : {std::pair{2.5f, 0.2f}, {-0.6f, 0.9f}}) {
        const Vec3 t = normalize(scene.surface_tangent(*scene.intersect({{x, y, 5}, {0, 0, -1}, kInfinity})));
        EXPECT_NEAR(dot(t, normalize(Vec3(4, 0.5f, 0))), 1.f, 1e-5f);
    }
}

TEST(Checkerboard, CellsLandWhereTheUvMappingPutsThem) {
    // A 4 x 2 quad with 4 x 4 cells over its (u, v): the cell of (x, y) is
    // (⌊(x + 1)⌋, ⌊2(y + 1)⌋), "even" (0.2) when their sum is even, "odd" (0.8) otherwise.
    const std::string text = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
      "textures": {"c": {"type": "checkerboard", "even": 0.2, "odd": 0.8, "uv_scale": [4, 4]}},
      "materials": {"m": {"kd": {"texture": "c"}}},
      "shapes": [{"type": "quad", "origin": [-1, -1, 0], "edge1": [4, 0, 0], "edge2": [0, 2, 0], "material": "m"}]})";
    const Scene scene = load_scene_text(text, "c.json", "c", {}, {});
    EXPECT_TRUE(scene.effects.textures);
    Bsdf scratch;
    int cells_seen = 0;
    for (float x = -0.95f; x < 3.f; x += 0.1f)
        for (float y = -0.95f; y < 1.f; y += 0.1f) {
            const std::optional<Hit> hit = scene.intersect({{x, y, 5}, {0, 0, -1}, kInfinity});
            ASSERT_TRUE(hit);
            const Bsdf& bsdf = scene.textured_bsdf(*hit, scratch);
            const float kd = std::get<DiffuseBsdf>(bsdf).kd.eval(550.f);
            const int parity = (static_cast<int>(std::floor(x + 1)) + static_cast<int>(std::floor(2 * (y + 1)))) % 2;
            EXPECT_FLOAT_EQ(kd, parity == 0 ? 0.2f : 0.8f) << x << ", " << y;
            ++cells_seen;
        }
    EXPECT_GT(cells_seen, 600);
    // The material's own BSDF holds the envelope (the larger value): flags and checks.
    EXPECT_FLOAT_EQ(std::get<DiffuseBsdf>(scene.materials[0].bsdf).kd.eval(550.f), 0.8f);
}

// ---- RGB texels → spectra ----

/// XYZ (Y = 1 for a perfect white) of reflectance bins lit by D65, and of emission bins
/// seen directly (the film's normalisation: Σ L·cmf / Σ ȳ).
Xyz bins_xyz(std::span<const float> bins, bool emission) {
    Spectrum s;
    s.assign_bins(bins);
    const SpectralTable& cmf = embedded_spectral_table("cie_1931_2deg.csv");
    Xyz xyz;
    double norm = 0;
    for (std::size_t i = 0; i < cmf.wavelengths_nm.size(); ++i) {
        const double l = cmf.wavelengths_nm[i];
        const double light = emission ? 1.0 : d65_unit_luminance(l);
        const double v = s.eval(static_cast<float>(l)) * light;
        xyz.x += v * cmf.column("x_bar")[i], xyz.y += v * cmf.column("y_bar")[i], xyz.z += v * cmf.column("z_bar")[i];
        norm += (emission ? 1.0 : light) * cmf.column("y_bar")[i];
    }
    xyz.x /= norm, xyz.y /= norm, xyz.z /= norm;
    return xyz;
}

TEST(RgbTexels, ReflectanceAndEmissionRoundTripsKeepTheFormatsPromise) {
    // At 1 nm bins (exact mode) the texel spectrum is the fit itself to far below a bin:
    // the scene format's promise for RGB (CIEDE2000 ≤ 0.01) holds for textures too.
    const std::array<float, 3> colours[] = {{0.8f, 0.3f, 0.1f}, {0.1f, 0.5f, 0.9f}, {0.5f, 0.5f, 0.5f},
                                            {0.05f, 0.9f, 0.2f}, {0.9f, 0.85f, 0.1f}};
    for (const auto& rgb : colours) {
        const std::array<double, 3> want = {rgb[0], rgb[1], rgb[2]};
        const auto lab = xyz_d65_to_lab(linear_srgb_to_xyz_d65(want));
        const std::vector<float> r = rgb_texel_bins(rgb, TexelUse::reflectance, kExactTextureBins);
        EXPECT_LE(delta_e_2000(xyz_d65_to_lab(bins_xyz(r, false)), lab), 0.01) << rgb[0] << " " << rgb[1];
        // Emission: seen directly, the texel has its colour's XYZ (luminance included).
        const std::vector<float> e = rgb_texel_bins(rgb, TexelUse::emission, kExactTextureBins);
        EXPECT_LE(delta_e_2000(xyz_d65_to_lab(bins_xyz(e, true)), lab), 0.01) << rgb[0] << " " << rgb[1];
        // At the default 16 bins a texel is exactly what a constant "kd": [r, g, b] holds.
        // (A grey is a constant spectrum: no bins, its value everywhere.)
        const std::vector<float> r16 = rgb_texel_bins(rgb, TexelUse::reflectance, 16);
        const Spectrum constant(rgb_to_spectrum(want), SpectralResolution{16});
        for (std::size_t i = 0; i < r16.size(); ++i)
            EXPECT_EQ(r16[i], constant.is_constant() ? constant.eval(550.f) : constant.bins()[i]);
    }
    // White emission is D65 of luminance 1 (the illuminant's white kept), not illuminant E.
    const std::vector<float> white = rgb_texel_bins({1, 1, 1}, TexelUse::emission, kExactTextureBins);
    EXPECT_NEAR(bins_xyz(white, true).y, 1.0, 1e-3);
    for (int i = 0; i < kExactTextureBins; i += 37) {
        const double l = 380.0 + i + 0.5;
        EXPECT_NEAR(white[static_cast<std::size_t>(i)], d65_unit_luminance(l), 0.02 * d65_unit_luminance(l)) << l;
    }
    EXPECT_THROW(rgb_texel_bins({1.5f, 0, 0}, TexelUse::reflectance, 16), std::invalid_argument);
    EXPECT_THROW(rgb_texel_bins({-1, 0, 0}, TexelUse::emission, 16), std::invalid_argument);
}

// ---- Rendering ----

TEST(TextureRender, EveryIntegratorRendersTheTexturedScene) {
    // bdpt and vcm read textures as the path tracer does (their agreement with it is in
    // test_bidirectional_materials.cpp): the program renders the built-in scene with each.
    const std::filesystem::path dir = ::test::fresh_test_dir("textures");
    for (const char* integrator : {"path", "bdpt", "vcm"}) {
        std::filesystem::remove(dir / "t.png");
        EXPECT_EQ(::test::run({"textured", "--integrator", integrator, "--spp", "1", "--width", "8", "--quiet", "-o",
                               (dir / "t.png").string()}, dir / "log"), 0)
            << integrator << ": " << ::test::read_file(dir / "log");
        EXPECT_TRUE(std::filesystem::exists(dir / "t.png")) << integrator;
    }
    std::filesystem::remove_all(dir);
}

/// A floor quad of material "m" lit by an emitting sphere, seen from above; `material` has
/// KD where its kd goes.
std::string lit_floor_scene(const std::string& textures, const std::string& kd,
                            std::string material = R"({"kd": KD, "ks": 0.05})") {
    material.replace(material.find("KD"), 2, kd);
    return R"({"camera": {"position": [0, 2, 3], "look_at": [0, 0, 0]},
      "textures": {)" + textures + R"(},
      "materials": {"m": )" + material + R"(},
      "shapes": [{"type": "quad", "origin": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "m"},
        {"type": "sphere", "center": [0.3, 1.2, 0], "radius": 0.3, "emission": 5},
        {"type": "sphere", "center": [-0.5, 0.3, 0.2], "radius": 0.3, "material": "m"}]})";
}

TEST(TextureRender, AnImageOfOneColourRendersAsThatConstant) {
    // Components exact in float, so the texel and the constant are the same RGB, fitted the
    // same: identical bins, hence the same BSDF values, random numbers and image.
    Image img;
    img.width = 3, img.height = 2;
    for (int i = 0; i < 6; ++i) img.rgb.insert(img.rgb.end(), {0.5f, 0.375f, 0.25f});
    const std::string pfm = encode_pfm(img, ImageWriteOptions{});
    const RelativeFileReader reader = [&](const std::string&, std::string& contents, std::string& display, std::string&) {
        contents = pfm;
        display = "c.pfm";
        return true;
    };
    // The kd of the lobe mix and of the plastic (whose lobe choice reads the texture's envelope).
    for (const char* material : {R"({"kd": KD, "ks": 0.05})", R"({"type": "plastic", "kd": KD, "roughness": 0.2})"})
    for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm}) {
        const Scene textured = load_scene_text(
            lit_floor_scene(R"("c": {"type": "image", "file": "c.pfm"})", R"({"texture": "c"})", material), "a.json", "a",
            {}, reader);
        const Scene constant =
            load_scene_text(lit_floor_scene("", "[0.5, 0.375, 0.25]", material), "b.json", "b", {}, reader);
        ASSERT_TRUE(textured.effects.textures);
        ASSERT_FALSE(constant.effects.textures);
        RenderSettings settings = test::small_settings(24, 16, 8);
        settings.integrator.kind = kind;
        // Specular next-event estimation reflects off the constant ball's ks lobe but leaves
        // textured materials to BSDF sampling (render/reflection_nee.h): a different estimator
        // of the same image, so it is off for this bit-for-bit comparison.
        settings.integrator.caustic_nee = false;
        const auto a = test::render_film(textured, settings), b = test::render_film(constant, settings);
        int identical = 0;
        double worst = 0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 24; ++x) {
                const Xyz p = a->pixel_xyz(x, y), q = b->pixel_xyz(x, y);
                identical += p.x == q.x && p.y == q.y && p.z == q.z;
                for (double diff : {p.x - q.x, p.y - q.y, p.z - q.z}) worst = std::max(worst, std::fabs(diff));
            }
        // Bit-identical: the textured code reads the same bins (the one entry's weight is
        // exactly 1), draws the same random numbers and does the same arithmetic (no FMA
        // contraction: -ffp-contract=off), so every pixel is the same double.
        EXPECT_EQ(identical, 24 * 16) << material << ", " << integrator_name(kind) << ": largest difference " << worst;
        EXPECT_GT(test::image_mean_y(*b).mean, 0.01);  // the comparison is not between two black images
    }
}

TEST(TextureRender, AnEmissionTextureSeenDirectlyHasItsColour) {
    // A quad filling the view emits a texture of one colour: the film's XYZ is that linear
    // sRGB colour's (the emission texel keeps D65's white), up to the wavelength noise.
    Image img;
    img.width = 2, img.height = 2;
    for (int i = 0; i < 4; ++i) img.rgb.insert(img.rgb.end(), {0.5f, 0.25f, 0.125f});
    const std::string pfm = encode_pfm(img, ImageWriteOptions{});
    const RelativeFileReader reader = [&](const std::string&, std::string& contents, std::string& display, std::string&) {
        contents = pfm;
        display = "e.pfm";
        return true;
    };
    const std::string text = R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "vfov_degrees": 30},
      "textures": {"e": {"type": "image", "file": "e.pfm"}},
      "shapes": [{"type": "quad", "origin": [-5, -5, 0], "edge1": [10, 0, 0], "edge2": [0, 10, 0],
                  "emission": {"texture": "e", "scale": 2}}]})";
    const Scene scene = load_scene_text(text, "e.json", "e", {}, reader);
    const auto film = test::render_film(scene, test::small_settings(16, 16, 64));
    Xyz mean;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const Xyz p = film->pixel_xyz(x, y);
            mean.x += p.x / 256, mean.y += p.y / 256, mean.z += p.z / 256;
        }
    const std::array<double, 3> rgb = xyz_d65_to_linear_srgb(mean);
    EXPECT_NEAR(rgb[0], 1.0, 0.02);
    EXPECT_NEAR(rgb[1], 0.5, 0.01);
    EXPECT_NEAR(rgb[2], 0.25, 0.01);
}

TEST(TextureRender, TheVolumetricPathReadsTexturesAsThePathTracerDoes) {
    // The same textured scene (a checkerboard kd floor lit by a checkerboard-emitting sphere
    // and triangle) in a medium that neither absorbs nor scatters: the volumetric path tracer
    // must find the path tracer's image. Planted bug (the state before): the volumetric loop
    // read Material::bsdf (the kd envelope, 0.8 everywhere) and the lights' Le (their mean
    // radiance), which brightens the floor far beyond 5σ.
    const std::string shapes = R"("textures": {"f": {"type": "checkerboard", "even": 0.8, "odd": 0.05, "uv_scale": [4, 4]},
                   "e": {"type": "checkerboard", "even": 12, "odd": 0.5, "uv_scale": [6, 3]}},
      "materials": {"m": {"kd": {"texture": "f"}}},
      "shapes": [{"type": "quad", "origin": [-2, 0, 2], "edge1": [4, 0, 0], "edge2": [0, 0, -4], "material": "m"},
        {"type": "sphere", "center": [0.3, 1.2, 0], "radius": 0.3, "emission": {"texture": "e"}},
        {"type": "triangle", "vertices": [[-1, 0.8, -0.5], [-0.4, 0.8, -0.5], [-1, 1.2, 0]], "emission": {"texture": "e"}}]})";
    const std::string camera = R"({"camera": {"position": [0, 2, 3], "look_at": [0, 0, 0]}, )";
    const Scene plain = test::load_exact_scene(camera + shapes, "plain");
    const Scene vacuum = test::load_exact_scene(
        camera + R"("media": {"clear": {"type": "homogeneous", "sigma_a": 0, "sigma_s": 0}}, "medium": "clear", )" + shapes,
        "vacuum");
    ASSERT_TRUE(vacuum.effects.media);
    ASSERT_TRUE(vacuum.effects.textures);
    const RenderSettings rs = test::small_settings(24, 16, 64, 3);
    const test::ImageMean a = test::image_mean_y(*test::render_film(plain, rs));
    const test::ImageMean b = test::image_mean_y(*test::render_film(vacuum, rs));
    std::printf("[textures in a medium] path %.5f ± %.5f, volumetric %.5f ± %.5f\n", a.mean, a.standard_error, b.mean,
                b.standard_error);
    EXPECT_NEAR(a.mean, b.mean, 5 * std::hypot(a.standard_error, b.standard_error));
    EXPECT_GT(a.mean, 0.01);
}

}  // namespace
}  // namespace spt
