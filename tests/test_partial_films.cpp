// Distributed renders: parts of a render's passes (partial films) merge, in any order, into
// the very bits of one uninterrupted render, for every integrator; bad parts are refused with
// the file and the reason, and nothing is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/checksums.h"
#include "program_process.h"
#include "render/renderer.h"
#include "scene/builtin_scenes.h"
#include "test_scenes.h"

namespace spt {
namespace {

namespace fs = std::filesystem;

const Scene& cornell() {
    static const Scene scene = *make_builtin_scene("cornell", SpectralResolution{});
    return scene;
}

/// 24x20 pixels, 23 spp in passes of 3 (the last of 2; vcm: 23 passes of 1).
RenderSettings small_render(IntegratorKind kind) {
    RenderSettings rs;
    rs.width = 24;
    rs.height = 20;
    rs.spp = 23;
    rs.seed = 11;
    rs.threads = 2;
    rs.integrator.kind = kind;
    rs.paths_per_pass = 3.0 * rs.width * rs.height;
    return rs;
}

/// The films of the parts that split `rs`'s passes at `cuts` (pass indices, first 0, last the
/// pass count), each rendered on its own as another machine would.
std::vector<std::unique_ptr<Film>> render_parts(const RenderSettings& rs, const std::vector<int>& cuts) {
    std::vector<std::unique_ptr<Film>> parts;
    const int chunk = chunk_spp(rs);
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
        RenderSettings part = rs;
        part.first_sample = cuts[k] * chunk;
        part.end_sample = std::min(rs.spp, cuts[k + 1] * chunk);
        parts.push_back(test::render_film(cornell(), part));
        EXPECT_TRUE(parts.back()->is_folded());
    }
    return parts;
}

TEST(PartialFilms, AnySplitMergesIntoTheFilmOfOneRender) {
    for (const IntegratorKind kind : {IntegratorKind::path, IntegratorKind::bdpt, IntegratorKind::vcm}) {
        const RenderSettings rs = small_render(kind);
        const int passes = (rs.spp + chunk_spp(rs) - 1) / chunk_spp(rs);
        ASSERT_GE(passes, 8) << integrator_name(kind);
        const auto whole = test::render_film(cornell(), rs);
        ASSERT_GT(test::image_mean_y(*whole).mean, 0.0);
        const std::vector<std::vector<int>> splits = {
            {0, passes / 2, passes},                                      // 2 parts
            {0, 1, 3, passes},                                            // 3, uneven
            {0, 1, 2, 3, passes - 4, passes - 3, passes - 1, passes}};  // 7, uneven
        std::mt19937 shuffle(5);
        for (const std::vector<int>& cuts : splits) {
            std::vector<std::unique_ptr<Film>> parts = render_parts(rs, cuts);
            std::shuffle(parts.begin(), parts.end(), shuffle);  // merged in any order
            Film merged(rs.width, rs.height);
            for (const auto& part : parts) merged.merge(*part);
            EXPECT_TRUE(merged.save_state() == whole->save_state())
                << integrator_name(kind) << ", " << parts.size() << " parts";
        }
    }
}

/// Why the totals are exact: the parts' sums added as doubles give other bits depending on
/// the grouping, so a merge of floating-point sums could not match one render in general.
TEST(PartialFilms, FloatingPointSumsOfPartsDependOnTheGrouping) {
    const RenderSettings rs = small_render(IntegratorKind::path);
    const auto parts = render_parts(rs, {0, 2, 4, 8});
    const std::vector<double> a = parts[0]->xyz_sums(), b = parts[1]->xyz_sums(), c = parts[2]->xyz_sums();
    int differing = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differing += (a[i] + b[i]) + c[i] != a[i] + (b[i] + c[i]);
    EXPECT_GT(differing, 0);
}

TEST(PartialFilms, ExactSumIsIntegerArithmetic) {
    ExactSum s, t;
    for (const double v : {0.1, 1e-3, 7e20, 3.25}) s.add(v);
    for (const double v : {3.25, 7e20, 1e-3, 0.1}) t.add(v);
    EXPECT_EQ(s, t);  // any order, the same bits
    ExactSum carry;
    carry.add(0.75);
    carry.add(0.5);  // the fraction carries into the integer bits
    EXPECT_EQ(carry.whole, 1u);
    EXPECT_EQ(carry.fraction, 1ull << 62);
    EXPECT_EQ(carry.value(), 1.25);
    carry.add(0x1p64 - 2048.0);
    carry.add(2048.0);  // the integer bits carry into the high bits
    EXPECT_EQ(carry.high, 1u);
    EXPECT_EQ(carry.whole, 1u);
    EXPECT_EQ(carry.value(), 0x1p64 + 1.25);
    ExactSum big;
    big.add(0x1p127);
    big.add(0x1p127);  // 2^128: saturates rather than wrapping around to 0
    EXPECT_EQ(big.high, ~0ull);
    EXPECT_GT(big.value(), 3e38);
}

TEST(PartialFilms, ExactSumConversionMatchesTheFloorDefinition) {
    // add(double) places the mantissa with integer shifts; reference_add computes the same
    // truncation with floor and ldexp. Every binade from the subnormals to just below 2^128,
    // the word boundaries 2^-64, 1 and 2^64 with their neighbours, and random mantissas.
    std::vector<double> values = {0.0, -0.0, std::numeric_limits<double>::denorm_min(), 0x1p-1022, 0x1p-64,
                                  0x1p0, 0x1p64, 0x1p127, std::nextafter(0x1p128, 0.0)};
    for (const double edge : {0x1p-64, 0x1p-63, 1.0, 0x1p63, 0x1p64, 0x1p65})
        values.insert(values.end(), {std::nextafter(edge, 0.0), std::nextafter(edge, 1e300)});
    std::mt19937_64 random(17);
    for (int e = -1074; e < 128; ++e)
        for (int k = 0; k < 8; ++k) {
            const double mantissa = 1.0 + static_cast<double>(random() >> 11) * 0x1p-53;  // [1, 2)
            values.push_back(std::ldexp(mantissa, e));
        }
    ExactSum fast_total, reference_total;
    int mismatches = 0;
    for (const double v : values) {
        ExactSum fast, reference;
        fast.add(v);
        reference.reference_add(v);
        mismatches += !(fast == reference);
        fast_total.add(v);
        reference_total.reference_add(v);
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_EQ(fast_total, reference_total);
    // Negative control: a conversion that rounds instead of truncating differs.
    ExactSum rounded;
    rounded.add(ExactSum{0, 0, static_cast<std::uint64_t>(std::llround(0x1.8p-65 * 0x1p64))});
    ExactSum truncated;
    truncated.add(0x1.8p-65);
    EXPECT_NE(rounded, truncated);
}

// ---- The program: --passes A:B -o part.film and 'pathtracer merge' ----

class PartialFilmsCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() / ("spt-parts-" + std::to_string(getpid()) + "-" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    std::string path(const std::string& name) const { return (dir / name).string(); }
    /// Runs the program; the exit code, with stdout and stderr in log().
    int run(std::vector<std::string> args) const { return ::test::run(args, dir / "log"); }
    std::string log() const { return ::test::read_file(dir / "log"); }
    /// Renders `render` (program arguments) passes [a, b) into `name`.
    void part(const std::vector<std::string>& render, int a, int b, const std::string& name) const {
        std::vector<std::string> args = render;
        args.insert(args.end(), {"--passes", std::to_string(a) + ":" + std::to_string(b), "-o", path(name)});
        ASSERT_EQ(run(args), 0) << log();
    }
    /// Renders `render` whole into one.pfm, and in the parts `cuts` bounds (passes [cuts[i],
    /// cuts[i + 1])), merged last part first into merged.pfm and merged.film; the two images must be
    /// the same bytes.
    void expect_merged_parts_are_one_render(const std::vector<std::string>& render, const std::vector<int>& cuts) const {
        std::vector<std::string> one = render;
        one.insert(one.end(), {"-o", path("one.pfm")});
        ASSERT_EQ(run(one), 0) << log();
        std::vector<std::string> merge = {"merge"};
        for (std::size_t i = cuts.size() - 1; i-- > 0;) {
            part(render, cuts[i], cuts[i + 1], "p" + std::to_string(i) + ".film");
            merge.push_back(path("p" + std::to_string(i) + ".film"));
        }
        merge.insert(merge.end(), {"-o", path("merged.pfm"), "-o", path("merged.film"), "--quiet"});
        ASSERT_EQ(run(merge), 0) << log();
        EXPECT_EQ(::test::read_file(dir / "merged.pfm"), ::test::read_file(dir / "one.pfm"));
    }
    fs::path dir;
};

/// vcm: passes of one sample, so many passes are cheap.
const std::vector<std::string> kVcm = {"cornell", "--integrator", "vcm", "--width", "16", "--height", "12",
                                       "--spp", "9", "--seed", "3", "--quiet"};

TEST_F(PartialFilmsCli, MergedPartsAreTheImageOfOneRender) {
    // 100x80 pixels, passes of 4e6 / 8000 = 500 spp; depth 2 keeps them short.
    for (const char* integrator : {"path", "bdpt"}) {
        SCOPED_TRACE(integrator);
        expect_merged_parts_are_one_render({"cornell", "--integrator", integrator, "--spp", "501", "--width", "100",
                                            "--height", "80", "--max-depth", "2", "--seed", "4", "--quiet"},
                                           {0, 1, 2});  // passes 500, 1
    }
}

/// The merged film is the film of the whole render, header and checksum included (the
/// in-process test compares the films of every integrator; this, the files).
TEST_F(PartialFilmsCli, MergedVcmPartsAreTheFilmOfOneRender) {
    expect_merged_parts_are_one_render(kVcm, {0, 1, 2, 3, 5, 6, 8, 9});
    std::vector<std::string> whole = kVcm;
    whole.insert(whole.end(), {"-o", path("whole.film")});
    ASSERT_EQ(run(whole), 0) << log();
    EXPECT_EQ(::test::read_file(dir / "merged.film"), ::test::read_file(dir / "whole.film"));
}

/// Each bad part: exit 1, one message naming the file and the reason, no output written.
TEST_F(PartialFilmsCli, BadPartsAreRefusedAndNothingIsWritten) {
    part(kVcm, 0, 4, "a.film");
    part(kVcm, 4, 9, "b.film");
    part(kVcm, 3, 5, "overlap.film");
    std::vector<std::string> seed = kVcm;
    seed[std::find(seed.begin(), seed.end(), "--seed") - seed.begin() + 1] = "4";
    part(seed, 4, 9, "other_seed.film");
    std::vector<std::string> scene = kVcm;
    scene[0] = "cornell-point";
    part(scene, 4, 9, "other_scene.film");
    const std::string bytes = ::test::read_file(dir / "b.film");
    std::ofstream(dir / "truncated.film", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    std::string flipped = bytes;
    flipped[flipped.size() / 2] ^= 0x10;
    std::ofstream(dir / "corrupt.film", std::ios::binary) << flipped;
    std::vector<std::string> checkpoint = kVcm;
    checkpoint.insert(checkpoint.end(), {"--checkpoint", path("checkpoint.film"), "-o", path("c.pfm")});
    ASSERT_EQ(run(checkpoint), 0) << log();

    const struct {
        std::string second, reason;
    } cases[] = {{"overlap.film", "overlap those of"},
                 {"other_seed.film", "it holds another render than '" + path("a.film") + "' (seed 4, not 3)"},
                 {"other_scene.film", "(scene cornell-point, not cornell)"},
                 {"truncated.film", "checksum mismatch"},
                 {"corrupt.film", "checksum mismatch"},
                 {"checkpoint.film", "not a partial film"},
                 {"missing.film", "cannot open"}};
    for (const auto& c : cases) {
        EXPECT_EQ(run({"merge", path("a.film"), path(c.second), "-o", path("out.exr"), "-o", path("out.png")}), 1)
            << c.second << "\n" << log();
        const std::string message = log();
        EXPECT_NE(message.find("'" + path(c.second) + "'"), std::string::npos) << message;
        EXPECT_NE(message.find(c.reason), std::string::npos) << message;
        EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
        EXPECT_FALSE(fs::exists(dir / "out.exr") || fs::exists(dir / "out.png")) << c.second;
    }
}

/// A gap (passes no part holds): refused for images that cannot say how many samples they
/// hold, written to an .exr whose spp attribute and sampleRanges say it.
TEST_F(PartialFilmsCli, AGapNeedsAnImageThatSaysWhatItHolds) {
    part(kVcm, 0, 2, "a.film");
    part(kVcm, 5, 9, "b.film");
    EXPECT_EQ(run({"merge", path("a.film"), path("b.film"), "-o", path("out.png")}), 1);
    EXPECT_NE(log().find("samples 2-5 of the render are in no part"), std::string::npos) << log();
    EXPECT_FALSE(fs::exists(dir / "out.png"));
    ASSERT_EQ(run({"merge", path("b.film"), path("a.film"), "-o", path("out.exr")}), 0) << log();
    EXPECT_NE(log().find("warning: samples 2-5 of the render are in no part: the image holds 6 of 9 spp"),
              std::string::npos) << log();
    const std::string exr = ::test::read_file(dir / "out.exr");
    const int held = 6;
    std::string spp_attribute = std::string("spp") + '\0' + "int" + '\0' + std::string("\x04\0\0\0", 4);
    spp_attribute.append(reinterpret_cast<const char*>(&held), 4);
    EXPECT_NE(exr.find(spp_attribute), std::string::npos);
    EXPECT_NE(exr.find("0-2, 5-9"), std::string::npos);
}

TEST_F(PartialFilmsCli, UsageErrors) {
    const struct {
        std::vector<std::string> args;
        std::string message;
    } cases[] = {
        {{"--passes", "0:1", "-o", path("x.png")}, "--passes: needs .film outputs"},
        {{"--passes", "1:1", "-o", path("x.film")}, "--passes: expected A:B"},
        {{"-o", path("x.film"), "-o", path("x.png")}, ".film outputs cannot be mixed with images"},
        {{"--pass-spp", "2", "-o", path("x.film")}, "--pass-spp: not with .film outputs"},
        {{"--spp", "9", "--width", "8", "--height", "8", "--passes", "0:2", "-o", path("x.film")},
         "--passes: this render has 1 passes"},
        {{"merge", "-o", path("x.png")}, "merge: expected one or more partial films"},
        {{"merge", path("a.film"), "--spp", "4", "-o", path("x.png")}, "merge: --spp is not an output option"},
    };
    for (const auto& c : cases) {
        EXPECT_EQ(run(c.args), 2) << c.message;
        EXPECT_NE(log().find(c.message), std::string::npos) << log();
    }
}

/// A part records every file its scene read and the build: a mesh or texture replaced between
/// parts is refused, naming the file; the same files merge.
TEST_F(PartialFilmsCli, PartsOfChangedInputsAreRefusedNamingTheFile) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                            "end_header\n-1 -1 -1\n1 -1 -1\n0 1 -1\n3 0 1 2\n";
    const std::string texture = "P3\n2 1\n255\n255 0 0 0 0 255\n";
    std::ofstream(dir / "scene.json") << R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
      "image": {"width": 12, "height": 8, "spp": 4},
      "textures": {"t": {"type": "image", "file": "tex.ppm"}},
      "materials": {"grey": {"kd": 0.5}, "pic": {"kd": {"texture": "t"}}},
      "shapes": [{"type": "mesh", "file": "mesh.ply", "material": "grey"},
                 {"type": "sphere", "center": [0, 0, 0], "radius": 0.6, "material": "pic"}],
      "lights": [{"type": "point", "position": [0, 2, 2], "intensity": 5}]})";
    auto write_inputs = [&](const std::string& mesh, const std::string& tex) {
        std::ofstream(dir / "mesh.ply", std::ios::binary) << mesh;
        std::ofstream(dir / "tex.ppm", std::ios::binary) << tex;
    };
    const std::vector<std::string> render = {path("scene.json"), "--integrator", "vcm", "--seed", "2", "--quiet"};
    write_inputs(ply, texture);
    part(render, 0, 2, "a.film");
    part(render, 2, 4, "b.film");
    std::string moved = ply;
    moved.replace(moved.find("0 1 -1"), 6, "0 2 -1");
    write_inputs(moved, texture);
    part(render, 2, 4, "mesh.film");
    std::string recoloured = texture;
    recoloured.replace(recoloured.find("255 0 0"), 7, "0 255 0");
    write_inputs(ply, recoloured);
    part(render, 2, 4, "texture.film");
    for (const auto& [second, file] : {std::pair{"mesh.film", "mesh.ply"}, std::pair{"texture.film", "tex.ppm"}}) {
        EXPECT_EQ(run({"merge", path("a.film"), path(second), "-o", path("out.pfm")}), 1) << log();
        EXPECT_NE(log().find("cannot merge '" + path(second) + "': it holds another render than '" + path("a.film") +
                             "' (the file '" + path(file) + "' differs"),
                  std::string::npos) << log();
        EXPECT_FALSE(fs::exists(dir / "out.pfm"));
    }
    ASSERT_EQ(run({"merge", path("a.film"), path("b.film"), "-o", path("out.pfm")}), 0) << log();
    // And a checkpoint does not resume over a replaced mesh either.
    std::vector<std::string> checkpointed = render;
    checkpointed.insert(checkpointed.end(), {"--checkpoint", path("c.ckpt"), "-o", path("c.pfm")});
    write_inputs(ply, texture);
    ASSERT_EQ(run(checkpointed), 0) << log();
    write_inputs(moved, texture);
    std::vector<std::string> resumed = render;
    resumed.insert(resumed.end(), {"--resume", path("c.ckpt"), "-o", path("r.pfm")});
    EXPECT_EQ(run(resumed), 1);
    EXPECT_NE(log().find("the file '" + path("mesh.ply") + "' differs"), std::string::npos) << log();
}

/// The header of a part with `key`'s line replaced by `line` and the checksum recomputed (an
/// edit by hand that the checksum cannot catch).
std::string edited_part(const std::string& bytes, const std::string& key, const std::string& line) {
    const std::size_t at = bytes.find("\n" + key + " ");
    EXPECT_NE(at, std::string::npos) << key;
    const std::size_t end = bytes.find('\n', at + 1);
    std::string body = bytes.substr(0, at + 1) + line + bytes.substr(end, bytes.size() - 8 - end);
    const std::uint64_t sum = fnv1a64(body);
    body.append(reinterpret_cast<const char*>(&sum), sizeof sum);
    return body;
}

/// Every header field is range-checked: an edited part is refused with the field and its range
/// (not std::bad_alloc), and a part of another build (its build id) is refused.
TEST_F(PartialFilmsCli, EditedHeadersAreRefusedNamingTheField) {
    part(kVcm, 0, 4, "a.film");
    part(kVcm, 4, 9, "b.film");
    const std::string bytes = ::test::read_file(dir / "b.film");
    const struct {
        std::string key, line, message;
    } cases[] = {
        {"spp", "spp -5", "header field 'spp' is -5; expected an integer from 1 to 1000000"},
        {"size", "size 1000000 12", "header field 'width' is 1000000; expected an integer from 1 to 65536"},
        {"size", "size 65536 65536", "the film data"},
        {"seed", "seed x", "header field 'seed' is x"},
        {"samples", "samples 9 4", "header field 'samples' is 9 4"},
        {"samples", "samples 4 10", "header field 'samples' is 4 10"},
        {"integrator", "integrator magic", "header field 'integrator' is magic"},
        {"merge-radius", "merge-radius nan", "header field 'merge-radius' is nan"},
        {"spectral-bins", "spectral-bins 5000", "header field 'spectral-bins' is 5000"},
        {"max-depth", "max-depth -7", "header field 'max-depth' is -7"},
        {"dispersion", "dispersion maybe", "header field 'dispersion' is maybe; expected on or off"},
        {"scene", "scene 99:cornell", "header field 'scene' is malformed"},
        {"sampler", "colour red", "unknown header field 'colour'"},
        {"sampler", "spp 9", "header field 'spp' appears twice"},
        {"program", "program 0123456789abcdef", "another build of the program"},
    };
    for (const auto& c : cases) {
        std::ofstream(dir / "edited.film", std::ios::binary) << edited_part(bytes, c.key, c.line);
        EXPECT_EQ(run({"merge", path("a.film"), path("edited.film"), "-o", path("out.exr")}), 1) << c.line;
        EXPECT_NE(log().find("cannot merge '" + path("edited.film") + "': "), std::string::npos) << log();
        const std::string message = log();
        EXPECT_NE(message.find(c.message), std::string::npos) << c.line << "\n" << message;
        EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
        EXPECT_FALSE(fs::exists(dir / "out.exr")) << c.line;
    }
    // The unedited part (negative control of the helper) merges.
    std::ofstream(dir / "edited.film", std::ios::binary) << edited_part(bytes, "spp", "spp 9");
    EXPECT_EQ(run({"merge", path("a.film"), path("edited.film"), "-o", path("out.exr")}), 0) << log();
}

/// An interrupted part writes nothing (a part holds whole passes; a rerun makes it whole).
TEST_F(PartialFilmsCli, AnInterruptedPartIsNotWritten) {
    const pid_t pid = ::test::spawn({"cornell", "--width", "160", "--height", "120", "--spp", "100000",
                                     "--threads", "2", "--passes", "0:100", "-o", path("part.film")},
                                    dir / "log");
    ASSERT_TRUE(::test::wait_for_log(dir / "log", "progress")) << log();
    kill(pid, SIGINT);
    EXPECT_EQ(::test::wait_exit(pid), 130);
    EXPECT_NE(log().find("no partial film written"), std::string::npos) << log();
    EXPECT_FALSE(fs::exists(dir / "part.film") || fs::exists(dir / "part.partial.film"));
}

TEST_F(PartialFilmsCli, PrintPassesGivesTheSplit) {
    ASSERT_EQ(run({"cornell", "--width", "100", "--height", "80", "--spp", "1001", "--print-passes"}), 0);
    EXPECT_EQ(log(), "passes 3\nspp_per_pass 500\nspp 1001\n");
}

}  // namespace
}  // namespace spt
