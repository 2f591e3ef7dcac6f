// Live previews: the partial-name rule, preview files that are always whole images and are
// removed when the render finishes, their spacing, and a final image they do not change.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli/output_names.h"
#include "io/image_writer.h"
#include "program_process.h"

namespace {

namespace fs = std::filesystem;
using test::read_file;
using test::run;
using test::spawn;
using test::wait_exit;

TEST(PartialName, InsertsPartialBeforeTheExtensionOfTheFileName) {
    struct Case {
        const char* path;
        const char* partial;
    };
    const Case cases[] = {
        {"b.png", "b.partial.png"},
        {"a/b.png", "a/b.partial.png"},
        {"/abs/dir/img.PFM", "/abs/dir/img.partial.PFM"},
        {"x.tar.exr", "x.tar.partial.exr"},          // only the last dot starts the extension
        {"dir.d/b.ppm", "dir.d/b.partial.ppm"},      // dots in folders are not extensions
        {"dir.d/noext", "dir.d/noext.partial"},      // no extension: appended
        {"noext", "noext.partial"},
        {"../up.png", "../up.partial.png"},
        {".png", ".partial.png"},                    // the writers read ".png" as a PNG too
        {"keep.partial.png", "keep.partial.partial.png"},
    };
    for (const Case& c : cases) {
        const std::string partial = spt::partial_output_name(c.path);
        EXPECT_EQ(partial, c.partial) << c.path;
        // The partial file has the output's format (the writers choose it by extension).
        EXPECT_EQ(spt::image_format_from_path(partial), spt::image_format_from_path(c.path)) << c.path;
    }
    EXPECT_EQ(spt::partial_output_names({"a.png", "b/c.exr"}),
              (std::vector<std::string>{"a.partial.png", "b/c.partial.exr"}));
}

class Preview : public ::testing::Test {
protected:
    void SetUp() override {
        dir = test::fresh_test_dir("preview");
    }
    void TearDown() override { fs::remove_all(dir); }
    std::vector<std::string> args(int width, int height, int spp,
                                  const std::vector<std::string>& more) const {
        std::vector<std::string> a = {"--width", std::to_string(width), "--height",
                                      std::to_string(height), "--spp", std::to_string(spp),
                                      "--threads", "2", "--seed", "3"};
        a.insert(a.end(), more.begin(), more.end());
        return a;
    }
    std::string path(const std::string& name) const { return (dir / name).string(); }
    fs::path dir;
};

/// While the render runs, out.partial.pfm appears, and every read of it finds a whole PFM
/// (written aside and renamed: never half an image); at the end out.pfm is written and the
/// preview removed. The "preview:" line names the file and the interval.
TEST_F(Preview, FilesAreWholeDuringTheRenderAndRemovedAtTheEnd) {
    const int w = 48, h = 40;
    const pid_t pid =
        spawn(args(w, h, 400, {"--pass-spp", "1", "--preview-interval", "0", "-o", path("out.pfm")}),
              dir / "log");
    const std::size_t whole = std::string("PF\n48 40\n-1.0\n").size() + std::size_t(w) * h * 12;
    int seen = 0, broken = 0;
    while (waitpid(pid, nullptr, WNOHANG) == 0) {
        const std::string bytes = read_file(dir / "out.partial.pfm");  // empty if absent
        if (!bytes.empty()) {
            ++seen;
            if (bytes.size() != whole || bytes.rfind("PF\n48 40\n", 0) != 0) ++broken;
        }
    }
    EXPECT_GT(seen, 0) << "no preview was seen during the render\n" << read_file(dir / "log");
    EXPECT_EQ(broken, 0) << "of " << seen << " reads";
    EXPECT_TRUE(fs::exists(dir / "out.pfm"));
    EXPECT_FALSE(fs::exists(dir / "out.partial.pfm")) << "the finished render removes its preview";
    const std::string log = read_file(dir / "log");
    EXPECT_NE(log.find("preview: " + path("out.partial.pfm") + " every 0 s"), std::string::npos) << log;
}

/// A finished render removes only the preview files it wrote: the unfinished image of an
/// earlier, interrupted run stays when this run writes no previews.
TEST_F(Preview, ARunWithoutPreviewsLeavesAnEarlierPartialFile) {
    std::ofstream(dir / "out.partial.pfm", std::ios::binary) << "earlier";
    ASSERT_EQ(run(args(8, 8, 2, {"--quiet", "-o", path("out.pfm")}), dir / "log"), 0);
    EXPECT_EQ(read_file(dir / "out.partial.pfm"), "earlier");
    // A run with previews removes the partial files it wrote. A preview still queued when the
    // render ends is dropped (the final image follows), so this run has 128 passes to be sure
    // of writing one even on a loaded machine (8 × 8 × 2 in one pass wrote none, at times).
    ASSERT_EQ(run(args(32, 32, 128, {"--quiet", "--preview-interval", "0", "--pass-spp", "1", "-o", path("out.pfm")}),
                  dir / "log"),
              0);
    EXPECT_FALSE(fs::exists(dir / "out.partial.pfm"));
}

/// Previews read the film between passes only, and the passes they ask for (timed, or one
/// sample each) do not change the image: the final files are identical, byte for byte, to a
/// render without previews, for the path and the bidirectional integrator.
TEST_F(Preview, PreviewsDoNotChangeTheImage) {
    for (const std::string integrator : {"path", "bdpt"}) {
        auto render = [&](const std::string& name, std::vector<std::string> more) {
            more.insert(more.end(), {"--quiet", "--integrator", integrator, "-o", path(name + ".pfm"), "-o",
                                     path(name + ".png")});
            EXPECT_EQ(run(args(64, 48, 24, more), dir / "log"), 0) << read_file(dir / "log");
        };
        render("plain", {});
        render("every_pass", {"--preview-interval", "0", "--pass-spp", "1"});
        render("timed", {"--preview-interval", "0.002"});  // timed passes, a preview after nearly each
        for (const std::string ext : {".pfm", ".png"}) {
            const std::string plain = read_file(dir / ("plain" + ext));
            ASSERT_FALSE(plain.empty());
            EXPECT_EQ(read_file(dir / ("every_pass" + ext)), plain) << integrator << ext;
            EXPECT_EQ(read_file(dir / ("timed" + ext)), plain) << integrator << ext;
        }
    }
}

/// Modification time of a file in seconds (0 when absent).
double mtime_seconds(const fs::path& p) {
    struct stat st;
    if (::stat(p.c_str(), &st) != 0) return 0;
    return double(st.st_mtim.tv_sec) + 1e-9 * double(st.st_mtim.tv_nsec);
}

/// --preview-interval S: previews at most every S seconds, and (the passes being timed to
/// S/2) regularly: a bdpt render on two threads, whose automatic passes (4 million paths)
/// take over ten seconds, still gets a preview about every S. The test watches until six
/// previews are written (or 60 s pass: on a loaded machine the program may start late), and
/// measures the gaps between writes from the file's modification times, on average (a write
/// can end late).
TEST_F(Preview, IntervalSpacesThePreviews) {
    const double interval = 0.3;
    const std::size_t wanted = 6;
    const pid_t pid = spawn(args(400, 300, 100000,
                                 {"--integrator", "bdpt", "--preview-interval", "0.3", "-o", path("out.pfm")}),
                            dir / "log");
    std::vector<double> writes;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (writes.size() < wanted && std::chrono::steady_clock::now() < give_up) {
        const double t = mtime_seconds(dir / "out.partial.pfm");
        if (t > 0 && (writes.empty() || t != writes.back())) writes.push_back(t);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    kill(pid, SIGINT);
    EXPECT_EQ(wait_exit(pid), 130);
    ASSERT_GE(writes.size(), wanted) << "previews in 60 s, interval 0.3 s\n" << read_file(dir / "log");
    // A preview starts S after the last one started, but the file's time is when its writing
    // ended, and encoding time varies (under ASan on a loaded machine one gap measured 0.17 s
    // after a late write): the spacing is checked on average, each gap only against previews
    // written back to back. Without timed passes the gaps would be a whole pass (seconds).
    const double mean_gap = (writes.back() - writes.front()) / double(writes.size() - 1);
    EXPECT_GT(mean_gap, interval - 0.05) << writes.size() << " previews";
    EXPECT_LT(mean_gap, 4 * interval) << "previews wait for whole passes";
    for (std::size_t i = 1; i < writes.size(); ++i)
        EXPECT_GT(writes[i] - writes[i - 1], interval / 4) << "previews " << i - 1 << " and " << i;
}

}  // namespace
