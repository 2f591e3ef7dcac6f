// Float material parameters bound to textures (model/textures/texture_binding.h): the GGX
// roughness of conductors and dielectrics and the thickness of thin films, each read at the
// hit as the texture gives it. A constant texture must render bit for bit as the constant;
// a checkerboard must give, on each square, the image of the material with that square's
// value; the loader checks every value of the texture against the parameter's range.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "model/camera.h"
#include "test_scenes.h"

namespace spt {
namespace {

/// A floor quad of material "m" (u along x, v along −z over [−1, 1]²) seen from straight
/// above, lit by an emitting sphere; `textures` are the scene's texture definitions.
std::string floor_scene(const std::string& textures, const std::string& material) {
    return R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "vfov_degrees": 45},
      "textures": {)" + textures + R"(},
      "materials": {"m": )" + material + R"(},
      "shapes": [{"type": "quad", "origin": [-1, 0, 1], "edge1": [2, 0, 0], "edge2": [0, 0, -2], "material": "m"},
        {"type": "sphere", "center": [0.7, 1.4, -0.3], "radius": 0.3, "emission": 8}]})";
}

Scene load(const std::string& text) { return test::load_exact_scene(text, "parameters"); }

/// Number of pixels whose XYZ differ between the films.
int differing_pixels(const Film& a, const Film& b) {
    int n = 0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const Xyz p = a.pixel_xyz(x, y), q = b.pixel_xyz(x, y);
            n += !(p.x == q.x && p.y == q.y && p.z == q.z);
        }
    return n;
}

struct ParameterCase {
    const char* name;
    std::string constant, textured;  ///< the material with the number, and bound to texture "c"
    std::string value;               ///< the texture's value on both colours of its cells
};

/// Each texturable number as a checkerboard of one value renders as that number, with every
/// integrator: the textured code reads the same float (weight exactly 1) and does the same
/// arithmetic. Planted bug: a binding that sets another member (the film's thickness for the
/// roughness) changes the image.
TEST(TextureParameters, AConstantTextureRendersAsTheConstant) {
    const ParameterCase cases[] = {
        {"conductor roughness", R"({"type": "conductor", "metal": "Au", "roughness": 0.25})",
         R"({"type": "conductor", "metal": "Au", "roughness": {"texture": "c"}})", "0.25"},
        {"dielectric roughness", R"({"type": "dielectric", "ior": 1.5, "roughness": 0.3})",
         R"({"type": "dielectric", "ior": 1.5, "roughness": {"texture": "c"}})", "0.3"},
        {"conductor film", R"({"type": "conductor", "metal": "Al", "roughness": 0.2, "film": {"thickness_nm": 350, "ior": 1.46}})",
         R"({"type": "conductor", "metal": "Al", "roughness": 0.2, "film": {"thickness_nm": {"texture": "c"}, "ior": 1.46}})",
         "350"},
        {"dielectric film", R"({"type": "dielectric", "ior": 1.33, "roughness": 0.1, "film": {"thickness_nm": 420, "ior": 1.47}})",
         R"({"type": "dielectric", "ior": 1.33, "roughness": 0.1, "film": {"thickness_nm": {"texture": "c"}, "ior": 1.47}})",
         "420"},
        {"thin sheet", R"({"type": "thin_sheet", "thickness_nm": 380, "ior": 1.33})",
         R"({"type": "thin_sheet", "thickness_nm": {"texture": "c"}, "ior": 1.33})", "380"},
        // A row of the coat's table over α (0.25 = 8/32): bit for bit (coat_albedo.h).
        {"plastic roughness", R"({"type": "plastic", "kd": [0.7, 0.4, 0.2], "roughness": 0.25})",
         R"({"type": "plastic", "kd": [0.7, 0.4, 0.2], "roughness": {"texture": "c"}})", "0.25"},
    };
    for (const ParameterCase& c : cases) {
        const std::string texture = R"("c": {"type": "checkerboard", "even": )" + c.value + ", \"odd\": " + c.value +
                                    R"(, "uv_scale": [3, 3]})";
        const Scene textured = load(floor_scene(texture, c.textured)), constant = load(floor_scene("", c.constant));
        ASSERT_TRUE(textured.effects.textures) << c.name;
        ASSERT_EQ(textured.materials[0].flags.bits, constant.materials[0].flags.bits) << c.name;
        for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm}) {
            RenderSettings rs = test::small_settings(16, 16, 4);
            rs.integrator.kind = kind;
            const auto a = test::render_film(textured, rs), b = test::render_film(constant, rs);
            EXPECT_EQ(differing_pixels(*a, *b), 0) << c.name << ", " << integrator_name(kind);
            EXPECT_GT(test::image_mean_y(*b).mean, 1e-3) << c.name;  // not two black images
        }
    }
}

/// A checkerboard of two roughnesses (or film thicknesses) gives, on each square, the image of
/// the material with that square's value: the pixels whose whole footprint lies in one
/// square (its four corners' rays land there; squares are convex) are bit-identical to the
/// render of that constant (same random numbers; reflected paths leave upwards and never
/// meet the floor again). Planted bugs: the envelope (largest value) used everywhere, or the
/// value of the other square, both fail; and the test asserts that each square kind has
/// pixels and that the two constant renders differ there.
TEST(TextureParameters, ACheckerboardGivesEachSquareItsMaterial) {
    struct Case {
        const char* name;
        std::string material;  ///< with VALUE where the number goes
        std::string even, odd;
    };
    const Case cases[] = {
        {"conductor roughness", R"({"type": "conductor", "metal": "Cu", "roughness": VALUE})", "0.05", "0.4"},
        {"conductor roughness with a smooth square", R"({"type": "conductor", "metal": "Cu", "roughness": VALUE})", "0",
         "0.3"},
        // Rows of the plastic's coat table (4/32 and 16/32): each square bit for bit.
        {"plastic roughness", R"({"type": "plastic", "kd": [0.7, 0.4, 0.2], "roughness": VALUE})", "0.125", "0.5"},
        {"dielectric film thickness",
         R"({"type": "dielectric", "ior": 1.5, "roughness": 0.15, "film": {"thickness_nm": VALUE, "ior": 1.38}})", "250",
         "600"},
    };
    const int size = 32;
    for (const Case& c : cases) {
        auto with = [&](const std::string& value) {
            std::string m = c.material;
            m.replace(m.find("VALUE"), 5, value);
            return m;
        };
        const std::string texture = R"("c": {"type": "checkerboard", "even": )" + c.even + ", \"odd\": " + c.odd +
                                    R"(, "uv_scale": [4, 4]})";
        const Scene textured = load(floor_scene(texture, with(R"({"texture": "c"})")));
        const Scene even = load(floor_scene("", with(c.even))), odd = load(floor_scene("", with(c.odd)));
        // The flags cover both squares: a smooth square adds the delta lobe.
        EXPECT_EQ(textured.materials[0].flags.bits,
                  std::uint8_t(even.materials[0].flags.bits | odd.materials[0].flags.bits))
            << c.name;
        const RenderSettings rs = test::small_settings(size, size, 8);
        const auto t = test::render_film(textured, rs), e = test::render_film(even, rs), o = test::render_film(odd, rs);

        const Camera camera(textured.camera, size, size);
        // The cell (−1 off the floor) under film position (x, y): the ray meets y = 0 at
        // u = (px + 1)/2, v = (1 − pz)/2, cells ⌊4u⌋, ⌊4v⌋.
        auto cell = [&](float x, float y) {
            const Ray r = camera.generate_ray(x, y);
            const float s = -r.o.y / r.d.y;
            const float u = (r.o.x + s * r.d.x + 1.f) / 2.f, v = (1.f - (r.o.z + s * r.d.z)) / 2.f;
            if (!(u > 0.f && u < 1.f && v > 0.f && v < 1.f)) return -1;
            return static_cast<int>(std::floor(4.f * u)) * 4 + static_cast<int>(std::floor(4.f * v));
        };
        int checked[2] = {0, 0}, mismatched[2] = {0, 0}, distinct = 0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const int k = cell(float(x), float(y));
                if (k < 0 || cell(x + 1.f, float(y)) != k || cell(float(x), y + 1.f) != k || cell(x + 1.f, y + 1.f) != k)
                    continue;
                const int parity = (k / 4 + k % 4) % 2;  // 0: even cell
                const Film& expected = parity == 0 ? *e : *o;
                const Xyz p = t->pixel_xyz(x, y), q = expected.pixel_xyz(x, y), other = (parity == 0 ? *o : *e).pixel_xyz(x, y);
                ++checked[parity];
                mismatched[parity] += !(p.x == q.x && p.y == q.y && p.z == q.z);
                distinct += q.y != other.y;
            }
        EXPECT_GT(checked[0], 20) << c.name;
        EXPECT_GT(checked[1], 20) << c.name;
        EXPECT_EQ(mismatched[0], 0) << c.name << ": even squares";
        EXPECT_EQ(mismatched[1], 0) << c.name << ": odd squares";
        EXPECT_GT(distinct, (checked[0] + checked[1]) / 4) << c.name << ": the two materials look alike";
    }
}

/// A plastic roughness between the rows of the coat's table over α (0.3): the coat's albedo
/// is interpolated in α (within 3.2e-3 for cos θ ≥ 0.1, coat_albedo.h), so the image differs
/// from the constant's only by that: the diffuse term's factors (1 − E)·(1 − E)/(1 − E_avg) move
/// by a few 3.2e-3/(1 − E), about 1 %. Same random numbers, so compared pixel by pixel; the lobe
/// choice (its probability moves with E too) may go the other way in a rare sample, which
/// changes its pixel by the noise: at most 5 % of the pixels may differ by more.
TEST(TextureParameters, PlasticRoughnessBetweenTableRowsWithinTheTablesError) {
    const std::string texture = R"("c": {"type": "checkerboard", "even": 0.3, "odd": 0.3})";
    const Scene textured =
        load(floor_scene(texture, R"({"type": "plastic", "kd": [0.7, 0.4, 0.2], "roughness": {"texture": "c"}})"));
    const Scene constant = load(floor_scene("", R"({"type": "plastic", "kd": [0.7, 0.4, 0.2], "roughness": 0.3})"));
    const auto a = test::render_film(textured, test::small_settings(16, 16, 4));
    const auto b = test::render_film(constant, test::small_settings(16, 16, 4));
    int lit = 0, close = 0, identical = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const double p = a->pixel_xyz(x, y).y, q = b->pixel_xyz(x, y).y;
            if (!(q > 1e-4)) continue;
            ++lit;
            close += std::fabs(p - q) <= 1e-2 * q;
            identical += p == q;
        }
    std::printf("[plastic roughness 0.3] %d lit pixels: %d within 1 %%, %d identical\n", lit, close, identical);
    EXPECT_GT(lit, 100);
    EXPECT_GE(close, lit - lit / 20);
    EXPECT_LT(identical, lit / 2);  // the table is read: the images are not the same bits
}

TEST(TextureParameters, LoaderChecksEveryValueAndRefusesWhatCannotBeTextured) {
    auto error = [](const std::string& texture, const std::string& material) {
        return test::scene_error(floor_scene(texture, material), "parameters");
    };
    const std::string checks = R"("c": {"type": "checkerboard", "even": 0.2, "odd": 1.5})";
    EXPECT_NE(error(checks, R"({"type": "conductor", "metal": "Au", "roughness": {"texture": "c"}})")
                  .find("roughness texture has the value 1.5; expected every value in [0, 1]"),
              std::string::npos);
    const std::string zero = R"("c": {"type": "checkerboard", "even": 0, "odd": 300})";
    EXPECT_NE(error(zero, R"({"type": "thin_sheet", "ior": 1.33, "thickness_nm": {"texture": "c"}})")
                  .find("thickness_nm texture has the value 0; expected every value in (0, 100000]"),
              std::string::npos);
    const std::string fine = R"("c": {"type": "checkerboard", "even": 0.2, "odd": 0.3})";
    EXPECT_EQ(error(fine, R"({"type": "plastic", "kd": 0.5, "roughness": {"texture": "c"}})"), "(no error)");
    EXPECT_NE(error(checks, R"({"type": "plastic", "kd": 0.5, "roughness": {"texture": "c"}})")
                  .find("roughness texture has the value 1.5; expected every value in [0, 1]"),
              std::string::npos);
    EXPECT_NE(error(fine, R"({"type": "dielectric", "ior": {"texture": "c"}})").find("ior"), std::string::npos);
    EXPECT_EQ(error(fine, R"({"type": "dielectric", "ior": 1.5, "roughness": {"texture": "c"}})"), "(no error)");
}

}  // namespace
}  // namespace spt
