// No lost renders: an interrupted render writes its unfinished image beside each output
// (X.partial.ext) and never over it, checkpoints survive kill -9 at any moment (including in
// the middle of writing one), and a resumed render equals a straight one.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "exr_reader.h"
#include "program_process.h"

namespace {

namespace fs = std::filesystem;
using test::read_file;
using test::run;
using test::spawn;
using test::wait_exit;
using test::wait_for_log;

/// Interrupts a render (SIGINT) once it has written its first checkpoint `ck`: a fixed delay
/// raced the program's start-up, which varies with the build (a sanitizer build hashes its
/// larger executable for the build id the checkpoint records).
void interrupt_after_first_checkpoint(pid_t pid, const fs::path& ck) {
    for (int i = 0; i < 12000 && !fs::exists(ck); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    kill(pid, SIGINT);
}

class Checkpoint : public ::testing::Test {
protected:
    void SetUp() override {
        dir = test::fresh_test_dir("checkpoint");
    }
    void TearDown() override { fs::remove_all(dir); }
    std::vector<std::string> base_args(const std::string& out) const {
        return {"--width", "48", "--height", "40", "--spp", "24", "--pass-spp", "1", "--threads", "2",
                "--seed", "5", "--quiet", "-o", (dir / out).string()};
    }
    /// Renders far more samples than a test waits for, in passes of `pass_spp`, to these
    /// outputs (not quiet: the log shows when the render has started).
    pid_t spawn_long_render(int width, int height, int pass_spp,
                            const std::vector<std::string>& outputs,
                            const std::vector<std::string>& more = {}) const {
        std::vector<std::string> args = {"--width", std::to_string(width), "--height",
                                         std::to_string(height), "--spp", "100000", "--pass-spp",
                                         std::to_string(pass_spp), "--threads", "2"};
        for (const std::string& out : outputs) args.insert(args.end(), {"-o", (dir / out).string()});
        args.insert(args.end(), more.begin(), more.end());
        return spawn(args, dir / "log");
    }
    /// A render interrupted (SIGINT once its first checkpoint exists, checkpoints after every pass) and resumed
    /// writes the image of a straight run: args_for(out) is the command line for output `out`.
    template <class Args>
    void expect_interrupted_resume_equals_straight(const Args& args_for, const std::string& scene) {
        ASSERT_EQ(run(args_for("straight.pfm"), dir / "log"), 0) << read_file(dir / "log");
        std::vector<std::string> args = args_for("resumed.pfm");
        const std::string ck = (dir / "state.ckpt").string();
        fs::remove(ck);
        args.insert(args.end(), {"--checkpoint", ck, "--checkpoint-interval", "0"});
        const pid_t pid = spawn(args, dir / "log");
        interrupt_after_first_checkpoint(pid, ck);
        wait_exit(pid);
        ASSERT_TRUE(fs::exists(ck)) << scene;
        args.insert(args.end(), {"--resume", ck});
        ASSERT_EQ(run(args, dir / "log"), 0) << read_file(dir / "log");
        EXPECT_EQ(read_file(dir / "straight.pfm"), read_file(dir / "resumed.pfm")) << scene;
    }
    fs::path dir;
};

/// Width and height of a PFM file (0, 0 when it is not one).
std::pair<int, int> pfm_size(const std::string& bytes) {
    std::smatch m;
    if (!std::regex_search(bytes, m, std::regex("^PF\n(\\d+) (\\d+)\n"))) return {0, 0};
    return {std::stoi(m[1]), std::stoi(m[2])};
}

/// The samples per pixel the interrupt message gives for `path`: "wrote PATH (A to B of N
/// spp per pixel)" or "(B of N spp per pixel)" -> {A, B} (A = B in the second form);
/// {-1, -1} when the message does not name it.
std::pair<int, int> reported_spp(const std::string& log, const std::string& path) {
    const std::string prefix = "  wrote " + path + " (";
    const auto at = log.find(prefix);
    if (at == std::string::npos) return {-1, -1};
    std::smatch m;
    const std::string rest = log.substr(at + prefix.size());
    if (std::regex_search(rest, m, std::regex("^(\\d+) to (\\d+) of \\d+ spp per pixel\\)")))
        return {std::stoi(m[1]), std::stoi(m[2])};
    if (std::regex_search(rest, m, std::regex("^(\\d+) of \\d+ spp per pixel\\)")))
        return {std::stoi(m[1]), std::stoi(m[1])};
    return {-1, -1};
}

/// SIGINT: every output X.ext gets its unfinished image as X.partial.ext, whether X.ext
/// existed (left byte for byte as it was) or not (still absent); the message names each
/// partial file with its samples; exit status 130. (Previews after every pass show when the
/// first pass has ended; the interrupt then rewrites them with the latest film.)
TEST_F(Checkpoint, SigintWritesPartialNamesAndLeavesTheOutputsUntouched) {
    std::ofstream(dir / "keep.pfm", std::ios::binary) << "the image of an earlier render";
    const pid_t pid =
        spawn_long_render(48, 40, 1, {"keep.pfm", "new.png"}, {"--preview-interval", "0"});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!fs::exists(dir / "new.partial.png") && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    kill(pid, SIGINT);
    EXPECT_EQ(wait_exit(pid), 130);
    const std::string log = read_file(dir / "log");
    EXPECT_NE(log.find("interrupted by signal 2"), std::string::npos) << log;
    EXPECT_EQ(read_file(dir / "keep.pfm"), "the image of an earlier render");
    EXPECT_FALSE(fs::exists(dir / "new.png"));
    EXPECT_EQ(pfm_size(read_file(dir / "keep.partial.pfm")), std::make_pair(48, 40));
    EXPECT_EQ(read_file(dir / "new.partial.png").substr(1, 3), "PNG");
    for (const char* name : {"keep.partial.pfm", "new.partial.png"}) {
        const auto [fewest, most] = reported_spp(log, (dir / name).string());
        EXPECT_GE(fewest, 1) << name << ": the first pass had ended\n" << log;
        EXPECT_LE(fewest, most) << name << "\n" << log;
    }
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
    EXPECT_EQ(left.size(), 4u) << "keep.pfm, keep.partial.pfm, new.partial.png, log and nothing else";
}

TEST_F(Checkpoint, SigtermWritesPartialNamesAndExitsWith143) {
    const pid_t pid = spawn_long_render(160, 120, 500, {"out.png"});  // passes of 10M paths
    ASSERT_TRUE(wait_for_log(dir / "log", "progress")) << read_file(dir / "log");
    kill(pid, SIGTERM);
    EXPECT_EQ(wait_exit(pid), 143);
    EXPECT_TRUE(fs::exists(dir / "out.partial.png"));
    EXPECT_FALSE(fs::exists(dir / "out.png"));
}

/// An interrupt inside the first pass (tiles of 64 spp; the pass is 640x480x64 paths, many
/// seconds): the partial image holds the tiles finished, 0 samples elsewhere, and is written
/// like any other, its EXR header saying so (spp 0, sppPerPixel 0-64); the output is left as
/// it was.
TEST_F(Checkpoint, InterruptBeforeTheFirstPassEndsWritesThePartialName) {
    std::ofstream(dir / "keep.pfm", std::ios::binary) << "old";
    const pid_t pid = spawn_long_render(640, 480, 64, {"keep.pfm", "new.exr"});
    ASSERT_TRUE(wait_for_log(dir / "log", "progress")) << read_file(dir / "log");
    kill(pid, SIGINT);
    EXPECT_EQ(wait_exit(pid), 130);
    const std::string log = read_file(dir / "log");
    EXPECT_EQ(read_file(dir / "keep.pfm"), "old");
    EXPECT_EQ(pfm_size(read_file(dir / "keep.partial.pfm")), std::make_pair(640, 480));
    EXPECT_EQ(reported_spp(log, (dir / "keep.partial.pfm").string()), std::make_pair(0, 64)) << log;
    const std::string exr = read_file(dir / "new.partial.exr");
    std::size_t at = 0;
    const auto header = spt::exr_test::parse_exr_header(exr, at);
    ASSERT_TRUE(header.contains("sppPerPixel")) << "attributes of new.partial.exr";
    EXPECT_EQ(header.at("sppPerPixel").value, "0-64");
    EXPECT_EQ(spt::exr_test::le32(header.at("spp").value, 0), 0u);
    EXPECT_EQ(spt::exr_test::le32(header.at("sppRequested").value, 0), 100000u);
}

TEST_F(Checkpoint, InterruptedAndResumedEqualsStraightRun) {
    ASSERT_EQ(run(base_args("straight.pfm"), dir / "log"), 0);
    std::vector<std::string> args = base_args("resumed.pfm");
    const std::string ck = (dir / "state.ckpt").string();
    args.insert(args.end(), {"--checkpoint", ck, "--checkpoint-interval", "0"});
    const pid_t pid = spawn(args, dir / "log");
    interrupt_after_first_checkpoint(pid, ck);
    wait_exit(pid);
    ASSERT_TRUE(fs::exists(ck));
    std::vector<std::string> resume = args;
    resume.insert(resume.end(), {"--resume", ck});
    ASSERT_EQ(run(resume, dir / "log"), 0) << read_file(dir / "log");
    EXPECT_EQ(read_file(dir / "straight.pfm"), read_file(dir / "resumed.pfm"));
}

/// Depth of field (the built-in bokeh scene, vcm) and motion blur (motion, bdpt): the lens
/// points and shutter times come from each sample's own stream (and each light subpath's), so
/// a resumed render is still the straight one.
TEST_F(Checkpoint, ResumedThinLensAndMotionBlurRendersEqualStraightRuns) {
    for (const std::string scene : {"bokeh", "motion"}) {
        auto args_for = [&](const std::string& out) {
            std::vector<std::string> args = base_args(out);
            args.insert(args.begin(), scene);
            std::replace(args.begin(), args.end(), std::string("24"), std::string("128"));  // --spp
            return args;
        };
        expect_interrupted_resume_equals_straight(args_for, scene);
    }
}

// kill -9 at random moments while checkpoints are written after every pass (a large film so
// that most of the time goes into writing them); resume until a run completes. The final
// image must equal the straight run, whatever moments the kills hit.
TEST_F(Checkpoint, KillNineAtRandomMomentsThenResumeEqualsStraightRun) {
    auto args_for = [&](const std::string& out) {
        return std::vector<std::string>{"--width", "400", "--height", "300", "--spp", "48",
                                        "--pass-spp", "1", "--threads", "2", "--seed", "9",
                                        "--quiet", "-o", (dir / out).string()};
    };
    ASSERT_EQ(run(args_for("straight.pfm"), dir / "log"), 0);
    const std::string ck = (dir / "state.ckpt").string();
    std::vector<std::string> args = args_for("resumed.pfm");
    args.insert(args.end(), {"--checkpoint", ck, "--checkpoint-interval", "0"});
    std::mt19937 gen(1234);
    std::uniform_int_distribution<int> delay_ms(20, 250);
    int kills = 0, exit_code = -1;
    for (int attempt = 0; attempt < 40 && exit_code != 0; ++attempt) {
        std::vector<std::string> a = args;
        if (fs::exists(ck)) a.insert(a.end(), {"--resume", ck});
        const pid_t pid = spawn(a, dir / "log");
        if (attempt < 8) {  // the first runs are killed (unless they finish first); later ones finish
            std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(gen)));
            kill(pid, SIGKILL);
        }
        exit_code = wait_exit(pid);
        if (exit_code == 128 + SIGKILL) ++kills;
        ASSERT_TRUE(exit_code == 0 || exit_code == 128 + SIGKILL)
            << "exit " << exit_code << ": " << read_file(dir / "log");
    }
    ASSERT_EQ(exit_code, 0);
    EXPECT_GE(kills, 4);  // a fast machine may finish a run before its kill arrives
    EXPECT_EQ(read_file(dir / "straight.pfm"), read_file(dir / "resumed.pfm"));
}

TEST_F(Checkpoint, CorruptCheckpointIsRefusedWithAClearError) {
    const std::string ck = (dir / "state.ckpt").string();
    std::vector<std::string> args = base_args("a.pfm");
    args.insert(args.end(), {"--checkpoint", ck});
    ASSERT_EQ(run(args, dir / "log"), 0);
    std::string bytes = read_file(ck);
    std::ofstream(ck, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    std::vector<std::string> resume = base_args("b.pfm");
    resume.insert(resume.end(), {"--resume", ck});
    EXPECT_EQ(run(resume, dir / "log"), 1);
    EXPECT_NE(read_file(dir / "log").find("cannot resume from"), std::string::npos) << read_file(dir / "log");
    EXPECT_FALSE(fs::exists(dir / "b.pfm"));
}

/// The Sobol sampler's numbers are a function of (seed, pixel, sample, dimension): a resumed
/// render is the straight one, on a pinhole scene and with lens and shutter dimensions.
TEST_F(Checkpoint, ResumedSobolRendersEqualStraightRuns) {
    for (const std::string scene : {"cornell", "bokeh", "motion"}) {
        auto args_for = [&](const std::string& out) {
            std::vector<std::string> args = base_args(out);
            args.insert(args.begin(), scene);
            args.insert(args.end(), {"--sampler", "sobol", "--integrator", "path"});
            return args;
        };
        expect_interrupted_resume_equals_straight(args_for, scene);
    }
}

/// A checkpoint of one sampler does not continue with the other: the message names it.
TEST_F(Checkpoint, ResumeWithTheOtherSamplerIsRefused) {
    const std::string ck = (dir / "state.ckpt").string();
    std::vector<std::string> args = base_args("a.pfm");
    args.insert(args.end(), {"--checkpoint", ck, "--sampler", "sobol"});
    ASSERT_EQ(run(args, dir / "log"), 0);
    std::vector<std::string> resume = base_args("b.pfm");
    resume.insert(resume.end(), {"--sampler", "independent", "--resume", ck});
    EXPECT_EQ(run(resume, dir / "log"), 1);
    const std::string log = read_file(dir / "log");
    EXPECT_NE(log.find("sampler sobol, not independent"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(dir / "b.pfm"));
}

TEST_F(Checkpoint, ResumeWithOtherSettingsIsRefused) {
    const std::string ck = (dir / "state.ckpt").string();
    std::vector<std::string> args = base_args("a.pfm");
    args.insert(args.end(), {"--checkpoint", ck});
    ASSERT_EQ(run(args, dir / "log"), 0);
    std::vector<std::string> resume = base_args("b.pfm");
    resume[11] = "6";  // another seed
    resume.insert(resume.end(), {"--resume", ck});
    EXPECT_EQ(run(resume, dir / "log"), 1);
    EXPECT_NE(read_file(dir / "log").find("seed 5"), std::string::npos) << read_file(dir / "log");
}

}  // namespace
