// Command-line tests: run the program (SPT_PATHTRACER) in a fresh temporary directory and check
// exit codes, messages, and which files it leaves behind.
//
// Conventions checked: exit 0 on success, 2 on a usage error (bad flag or value, unknown scene),
// non-zero on a run-time error; an error is one line on stderr naming the flag; a failing run
// creates no file and leaves existing files untouched.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#ifndef SPT_PATHTRACER
#error "SPT_PATHTRACER must name the pathtracer program"
#endif
#ifndef SPT_VERSION
#error "SPT_VERSION must be defined"
#endif

namespace {

namespace fs = std::filesystem;

struct RunResult {
    int exit_code = -1;
    std::string out, err;
};

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_file(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

std::string join(const std::vector<std::string>& args) {
    std::string s;
    for (const std::string& a : args) s += (s.empty() ? "" : " ") + a;
    return s;
}

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        const fs::path base = fs::temp_directory_path() /
                              ("spt_cli_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(base);
        m_dir = base / "work";
        m_logs = base / "logs";
        fs::create_directories(m_dir);
        fs::create_directories(m_logs);
        m_base = base;
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(m_base, ec);
    }

    /// Runs the program with `args` in the work directory (stdout/stderr go to the logs
    /// directory, so the work directory shows exactly what the program wrote).
    RunResult run(const std::vector<std::string>& args) const {
        std::string cmd = "cd " + quote(m_dir.string()) + " && " + quote(SPT_PATHTRACER);
        for (const std::string& a : args) cmd += " " + quote(a);
        cmd += " >" + quote((m_logs / "out").string()) + " 2>" + quote((m_logs / "err").string()) +
               " </dev/null";
        const int status = std::system(cmd.c_str());
        RunResult r;
        r.exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
        r.out = read_file(m_logs / "out");
        r.err = read_file(m_logs / "err");
        return r;
    }

    /// Names of the files in the work directory.
    std::set<std::string> files() const {
        std::set<std::string> names;
        for (const auto& e : fs::directory_iterator(m_dir)) names.insert(e.path().filename().string());
        return names;
    }

    fs::path m_base, m_dir, m_logs;
};

bool is_one_line(const std::string& s) {
    return !s.empty() && s.back() == '\n' && std::count(s.begin(), s.end(), '\n') == 1;
}

/// Fast render settings, so a parser that wrongly accepts a value finishes quickly and the
/// test sees the image it wrote.
const std::vector<std::string> kTiny = {"--width", "4", "--height", "4", "--spp", "1", "--quiet"};

std::vector<std::string> tiny(std::vector<std::string> more) {
    std::vector<std::string> args = kTiny;
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

TEST_F(Cli, HelpExitsZeroAndListsOptions) {
    for (const std::string flag : {"--help", "-h"}) {
        const RunResult r = run({flag});
        EXPECT_EQ(r.exit_code, 0) << flag;
        EXPECT_NE(r.out.find("--spectral-bins"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("--spp"), std::string::npos);
        EXPECT_NE(r.out.find("-o"), std::string::npos);
        EXPECT_EQ(r.err, "");
        EXPECT_TRUE(files().empty());
    }
}

TEST_F(Cli, VersionPrintsTheVersion) {
    const RunResult r = run({"--version"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find(SPT_VERSION), std::string::npos) << r.out;
    EXPECT_TRUE(is_one_line(r.out)) << r.out;
    EXPECT_EQ(r.err, "");
    EXPECT_TRUE(files().empty());
}

TEST_F(Cli, ListScenesNamesTheBuiltins) {
    const RunResult r = run({"--list-scenes"});
    EXPECT_EQ(r.exit_code, 0);
    // The default first, then every built-in scene file, one per line.
    EXPECT_EQ(r.out.rfind("cornell\n", 0), 0u) << r.out;
    for (const char* name : {"\ncornell-point\n", "\nprism\n", "\nglass-spheres\n"})
        EXPECT_NE(r.out.find(name), std::string::npos) << r.out;
    EXPECT_TRUE(files().empty());
}

struct BadCase {
    std::vector<std::string> args;
    std::vector<std::string> must_mention;  ///< the flag (and the bad value where there is one)
};

TEST_F(Cli, BadArgumentsExitTwoWithOneLineNamingTheFlag) {
    const std::vector<BadCase> cases = {
        {{"--spp", "0"}, {"--spp", "'0'"}},
        {{"--spp", "abc"}, {"--spp", "abc"}},
        {{"--spp=0"}, {"--spp"}},
        {{"--spp", "12abc"}, {"--spp", "12abc"}},
        {{"--spp", "99999999999999999999"}, {"--spp"}},
        {{"--spectral-bins", "0"}, {"--spectral-bins"}},
        {{"--spectral-bins", "5000"}, {"--spectral-bins", "5000"}},
        {{"--spectral-bins", "exactly"}, {"--spectral-bins"}},
        {{"--width", "-3"}, {"--width", "-3"}},
        {{"--height", "0"}, {"--height"}},
        {{"--width", "65537"}, {"--width"}},
        {{"--threads", "x"}, {"--threads", "x"}},
        {{"--threads", "0"}, {"--threads"}},
        {{"--seed", "-1"}, {"--seed"}},
        {{"--max-depth", "-2"}, {"--max-depth"}},
        {{"--exposure", "nan"}, {"--exposure"}},
        {{"--color-space", "cmyk"}, {"--color-space", "cmyk"}},
        {{"--bogus"}, {"--bogus"}},
        {{"-x"}, {"-x"}},
        {{"-o", "out.bmp"}, {"-o", "out.bmp"}},
        {{"--output", "noextension"}, {"--output", "noextension"}},
        {{"nosuchscene"}, {"nosuchscene", "cornell"}},
        {{"cornell", "cornell-point"}, {"cornell-point"}},
        {{"--quiet=yes"}, {"--quiet"}},
        {{"--pass-spp", "0"}, {"--pass-spp"}},
        {{"--checkpoint-interval", "-1"}, {"--checkpoint-interval"}},
        {{"--checkpoint", ""}, {"--checkpoint"}},
        {{"--time-limit", "0"}, {"--time-limit"}},
        {{"--time-limit", "-5"}, {"--time-limit"}},
        {{"--time-limit", "soon"}, {"--time-limit", "soon"}},
        {{"--preview-interval", "-1"}, {"--preview-interval", "-1"}},
        {{"--preview-interval", "often"}, {"--preview-interval", "often"}},
        {{"--preview-interval"}, {"--preview-interval"}},
        {{"--display-server", "host:0"}, {"--display-server", "host:0"}},
        {{"--display-server", "host:65536"}, {"--display-server", "host:65536"}},
        {{"--display-server", ":14158"}, {"--display-server", ":14158"}},
        {{"--display-server", ""}, {"--display-server"}},
        {{"-o", "img.partial.png"}, {"-o", "img.partial.png"}},  // where img.png's unfinished image goes
        {{"--spp"}, {"--spp"}},  // missing value at the end
        {{"-o"}, {"-o"}},
        {{"--spectral-bins"}, {"--spectral-bins"}},
        {{"--integrator", "foo"}, {"--integrator", "foo", "vcm"}},
        {{"--merge-radius", "0"}, {"--merge-radius", "'0'"}},
        {{"--merge-radius", "-1"}, {"--merge-radius", "-1"}},
        {{"--merge-radius", "abc"}, {"--merge-radius", "abc"}},
        {{"--merge-radius", "nan"}, {"--merge-radius"}},
        {{"--merge-radius"}, {"--merge-radius"}},
    };
    for (const BadCase& c : cases) {
        // The bad arguments come last (so "missing value" cases really are at the end), after
        // a valid output, which must not be written.
        const RunResult r = run(tiny([&] {
            std::vector<std::string> a = {"-o", "img.png"};
            a.insert(a.end(), c.args.begin(), c.args.end());
            return a;
        }()));
        const std::string what = join(c.args);
        EXPECT_EQ(r.exit_code, 2) << what << "\nstderr: " << r.err;
        EXPECT_TRUE(is_one_line(r.err)) << what << "\nstderr: " << r.err;
        for (const std::string& m : c.must_mention)
            EXPECT_NE(r.err.find(m), std::string::npos) << what << ": message should mention " << m
                                                        << "\nstderr: " << r.err;
        EXPECT_EQ(r.out, "") << what;
        EXPECT_TRUE(files().empty()) << what << ": a failing run created files";
        for (const std::string& f : files()) fs::remove_all(m_dir / f);
    }
}

/// The vcm integrator is accepted, with or without a merging radius, and renders an image
/// with no rejected samples.
TEST_F(Cli, VcmIntegratorAndMergeRadiusAreAccepted) {
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{"--integrator", "vcm"}, {"--integrator=vcm", "--merge-radius", "0.05"},
          {"--integrator", "vcm", "--merge-radius=1e-3"}}) {
        const RunResult r = run({"cornell-point", "--width", "8", "--height", "8", "--spp", "2", "-o", "v.pfm",
                                 extra[0], extra.size() > 1 ? extra[1] : "--quiet",
                                 extra.size() > 2 ? extra[2] : "--quiet",
                                 extra.size() > 3 ? extra[3] : "--quiet"});
        EXPECT_EQ(r.exit_code, 0) << join(extra) << "\nstderr: " << r.err;
        EXPECT_EQ(files(), std::set<std::string>{"v.pfm"}) << join(extra);
        for (const std::string& f : files()) fs::remove_all(m_dir / f);
    }
    const RunResult loud = run({"cornell-point", "--width", "8", "--height", "8", "--spp", "2", "-o", "w.pfm",
                                "--integrator", "vcm"});
    EXPECT_EQ(loud.exit_code, 0) << loud.err;
    EXPECT_NE(loud.err.find("rejected samples: 0 non-finite, 0 negative"), std::string::npos) << loud.err;
}

/// Without --quiet too, a usage error prints nothing but the one line (no progress bar).
TEST_F(Cli, UsageErrorIsOneLineWithoutQuiet) {
    const RunResult r = run({"--width", "8", "--height", "8", "--spp", "0"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(is_one_line(r.err)) << r.err;
    EXPECT_EQ(r.err.rfind("pathtracer: ", 0), 0u) << r.err;
}

TEST_F(Cli, ExistingOutputIsUntouchedAfterUsageError) {
    write_file(m_dir / "keep.png", "precious bytes");
    const RunResult r = run(tiny({"-o", "keep.png", "--spp", "0"}));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(read_file(m_dir / "keep.png") == "precious bytes") << "keep.png was modified";
    EXPECT_EQ(files(), std::set<std::string>{"keep.png"});
}

/// A run-time failure (an output in a folder that does not exist) is reported on one line
/// naming the file, with a non-zero exit code, and creates nothing.
TEST_F(Cli, UnwritableOutputFailsCleanly) {
    const RunResult r = run(tiny({"-o", "no_such_dir/out.png"}));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(is_one_line(r.err)) << r.err;
    EXPECT_NE(r.err.find("no_such_dir/out.png"), std::string::npos) << r.err;
    EXPECT_TRUE(files().empty());
}

/// A failing run must leave existing files alone even when the failure comes from another
/// output: here the first output exists, the second cannot be written.
TEST_F(Cli, ExistingOutputIsUntouchedWhenAnotherOutputFails) {
    write_file(m_dir / "keep.png", "precious bytes");
    const RunResult r = run(tiny({"-o", "keep.png", "-o", "no_such_dir/out.png"}));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("no_such_dir/out.png"), std::string::npos) << r.err;
    EXPECT_TRUE(read_file(m_dir / "keep.png") == "precious bytes")
        << "the run failed (exit " << r.exit_code << ") but replaced the existing keep.png";
    EXPECT_EQ(files(), std::set<std::string>{"keep.png"});
}

/// The same when the second output names an existing directory: the image can be encoded but
/// not put in place, and the first output must still be untouched.
TEST_F(Cli, ExistingOutputIsUntouchedWhenAnotherOutputIsADirectory) {
    write_file(m_dir / "keep.png", "precious bytes");
    fs::create_directory(m_dir / "sub.png");
    const RunResult r = run(tiny({"-o", "keep.png", "-o", "sub.png"}));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(is_one_line(r.err)) << r.err;
    EXPECT_NE(r.err.find("sub.png"), std::string::npos) << r.err;
    EXPECT_TRUE(read_file(m_dir / "keep.png") == "precious bytes")
        << "the run failed (exit " << r.exit_code << ") but replaced the existing keep.png";
    EXPECT_TRUE(fs::is_directory(m_dir / "sub.png"));
    EXPECT_EQ(files(), (std::set<std::string>{"keep.png", "sub.png"})) << "temporary files left behind";
}

/// The same output named twice is written once, successfully.
TEST_F(Cli, RepeatedIdenticalOutputIsFine) {
    const RunResult r = run(tiny({"-o", "a.pfm", "-o", "a.pfm"}));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(files(), std::set<std::string>{"a.pfm"});
    EXPECT_EQ(read_file(m_dir / "a.pfm").substr(0, 3), "PF\n");
}

void expect_valid_images(const fs::path& dir, const std::string& stem, int w, int h) {
    const std::string png = read_file(dir / (stem + ".png"));
    ASSERT_GE(png.size(), 24u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_EQ(png.substr(12, 4), "IHDR");
    const auto be32 = [&](std::size_t at) {
        return (unsigned(static_cast<unsigned char>(png[at])) << 24) |
               (unsigned(static_cast<unsigned char>(png[at + 1])) << 16) |
               (unsigned(static_cast<unsigned char>(png[at + 2])) << 8) |
               unsigned(static_cast<unsigned char>(png[at + 3]));
    };
    EXPECT_EQ(be32(16), unsigned(w));
    EXPECT_EQ(be32(20), unsigned(h));

    const std::string pfm = read_file(dir / (stem + ".pfm"));
    const std::string pfm_header = "PF\n" + std::to_string(w) + " " + std::to_string(h) + "\n";
    EXPECT_EQ(pfm.substr(0, pfm_header.size()), pfm_header);
    // Header, scale line, then 3 floats per pixel.
    const std::size_t scale_end = pfm.find('\n', pfm_header.size());
    ASSERT_NE(scale_end, std::string::npos);
    EXPECT_EQ(pfm.size() - scale_end - 1, std::size_t(w) * h * 3 * 4);

    const std::string ppm = read_file(dir / (stem + ".ppm"));
    EXPECT_EQ(ppm.substr(0, 3), "P3\n");
    EXPECT_NE(ppm.find(std::to_string(w) + " " + std::to_string(h) + "\n"), std::string::npos);

    const std::string exr = read_file(dir / (stem + ".exr"));
    ASSERT_GE(exr.size(), 8u);
    EXPECT_EQ(exr.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));
}

TEST_F(Cli, TinyRenderWritesEveryRequestedFormat) {
    const RunResult r = run({"--width", "8", "--height", "6", "--spp", "2", "-o", "a.png", "-o",
                             "a.pfm", "-o", "a.ppm", "-o", "a.exr"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(files(), (std::set<std::string>{"a.png", "a.pfm", "a.ppm", "a.exr"}));
    expect_valid_images(m_dir, "a", 8, 6);
    // The summary reports the global invariant: no rejected samples.
    EXPECT_NE(r.err.find("rejected samples: 0 non-finite, 0 negative"), std::string::npos) << r.err;
    for (const std::string f : {"a.png", "a.pfm", "a.ppm", "a.exr"})
        EXPECT_NE(r.err.find("wrote " + f), std::string::npos) << r.err;
}

TEST_F(Cli, OutputFlagFormsAndRepeats) {
    const RunResult r = run(tiny({"cornell-point", "--output=b.pfm", "--output", "b.png", "-o",
                                  "c.PPM", "--seed=3", "--threads=2", "--spectral-bins=exact"}));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(files(), (std::set<std::string>{"b.pfm", "b.png", "c.PPM"}));
    EXPECT_EQ(r.err, "") << "--quiet must silence the summary";
    EXPECT_EQ(r.out, "");
}

TEST_F(Cli, DefaultOutputIsNamedAfterTheScene) {
    EXPECT_EQ(run(tiny({})).exit_code, 0);
    EXPECT_EQ(run(tiny({"cornell-point"})).exit_code, 0);
    EXPECT_EQ(files(), (std::set<std::string>{"cornell.png", "cornell-point.png"}));
}

TEST_F(Cli, ExistingOutputIsReplacedOnSuccess) {
    write_file(m_dir / "x.pfm", "old");
    const RunResult r = run(tiny({"-o", "x.pfm"}));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_file(m_dir / "x.pfm").substr(0, 3), "PF\n");
    EXPECT_EQ(files(), std::set<std::string>{"x.pfm"}) << "no temporary file may remain";
}

/// --time-limit stops at a pass boundary (not at --spp), writes the image of the passes done
/// and says so; the image equals a render asked for that many spp. (How close to the limit
/// it ends depends on the machine's load: not asserted.)
TEST_F(Cli, TimeLimitStopsAtAPassBoundary) {
    const RunResult r = run({"--width", "32", "--height", "32", "--spp", "1000000", "--pass-spp", "1",
                             "--time-limit", "1", "--seed", "4", "-o", "t.pfm"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string marker = "stopped by --time-limit 1 s after ";
    const auto at = r.err.find(marker);
    ASSERT_NE(at, std::string::npos) << r.err;
    const int spp = std::stoi(r.err.substr(at + marker.size()));
    EXPECT_GT(spp, 0);
    EXPECT_LT(spp, 1000000);
    const RunResult same = run({"--width", "32", "--height", "32", "--spp", std::to_string(spp), "--seed",
                                "4", "--quiet", "-o", "u.pfm"});
    ASSERT_EQ(same.exit_code, 0) << same.err;
    EXPECT_EQ(read_file(m_dir / "t.pfm"), read_file(m_dir / "u.pfm"));
}

/// Same seed: identical bytes for any thread count; another seed: different bytes.
TEST_F(Cli, OutputIsDeterministic) {
    const std::vector<std::string> common = {"--width", "16", "--height", "16", "--spp", "4",
                                             "--quiet", "--seed", "5"};
    auto with = [&](std::vector<std::string> more) {
        std::vector<std::string> a = common;
        a.insert(a.end(), more.begin(), more.end());
        return a;
    };
    ASSERT_EQ(run(with({"--threads", "1", "-o", "t1.pfm"})).exit_code, 0);
    ASSERT_EQ(run(with({"--threads", "2", "-o", "t2.pfm"})).exit_code, 0);
    ASSERT_EQ(run(with({"--threads", "3", "--seed", "6", "-o", "s6.pfm"})).exit_code, 0);
    const std::string t1 = read_file(m_dir / "t1.pfm"), t2 = read_file(m_dir / "t2.pfm");
    EXPECT_FALSE(t1.empty());
    EXPECT_EQ(t1, t2);
    EXPECT_NE(t1, read_file(m_dir / "s6.pfm"));
}

}  // namespace

namespace {

// A PNG is sRGB by definition: --color-space changes the linear outputs, never the PNG.
TEST_F(Cli, PngIsSrgbWhateverTheColorSpace) {
    const std::vector<std::string> base = {"--width", "8", "--height", "8", "--spp", "2", "--quiet"};
    std::vector<std::string> a = base, b = base;
    a.insert(a.end(), {"-o", "srgb.png", "-o", "srgb.pfm"});
    b.insert(b.end(), {"--color-space", "xyz", "-o", "xyz.png", "-o", "xyz.pfm"});
    ASSERT_EQ(run(a).exit_code, 0);
    ASSERT_EQ(run(b).exit_code, 0);
    EXPECT_EQ(read_file(m_dir / "srgb.png"), read_file(m_dir / "xyz.png"));
    EXPECT_NE(read_file(m_dir / "srgb.pfm"), read_file(m_dir / "xyz.pfm"));
}

}  // namespace
