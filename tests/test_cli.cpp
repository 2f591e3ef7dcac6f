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
#include <utility>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli/options.h"
#include "exr_reader.h"

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

/// The lines of a text, without their newlines.
std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

TEST_F(Cli, ListScenesDescribesTheBuiltins) {
    const RunResult r = run({"--list-scenes"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_TRUE(files().empty());
    // The default first, then every built-in scene file, one per line: name (the first word,
    // which scripts take), size, spp, integrator, summary.
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_GE(lines.size(), 3u) << r.out;
    EXPECT_EQ(lines[0].rfind("cornell ", 0), 0u) << r.out;
    auto line_of = [&](const std::string& name) {
        for (const std::string& l : lines)
            if (l.rfind(name + " ", 0) == 0) return l;
        return std::string();
    };
    const std::string cornell = line_of("cornell"), prism = line_of("prism");
    EXPECT_NE(cornell.find("512x512"), std::string::npos) << cornell;
    EXPECT_NE(cornell.find("128 spp"), std::string::npos) << cornell;
    EXPECT_NE(cornell.find(" path "), std::string::npos) << cornell;
    EXPECT_NE(cornell.find("Cornell box"), std::string::npos) << cornell;
    EXPECT_NE(prism.find(" vcm "), std::string::npos) << prism;  // the scene file's choice
    for (const char* name : {"cornell-point", "glass-spheres", "showcase"}) EXPECT_FALSE(line_of(name).empty()) << name;
    // A table: the size column starts at the same place on every line, however long the name.
    const std::size_t size_column = lines[0].find_first_not_of(' ', lines[0].find(' '));
    for (const std::string& l : lines) EXPECT_EQ(l.find_first_not_of(' ', l.find(' ')), size_column) << l;
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
        {{"--tonemap", "filmic"}, {"--tonemap", "filmic", "neutral"}},
        {{"--guiding", "maybe"}, {"--guiding", "maybe", "auto"}},
        {{"--guiding-field", "rgb"}, {"--guiding-field", "rgb", "spectral"}},
        {{"--auto-exposure=yes"}, {"--auto-exposure"}},
        {{"--white-balance", "D66"}, {"--white-balance", "D66", "25000K"}},
        {{"--white-balance", "500K"}, {"--white-balance", "500K"}},
        {{"--print-adaptation", "hot"}, {"--print-adaptation", "hot"}},
        {{"--scale", "0"}, {"--scale", "'0'"}},
        {{"--scale", "101"}, {"--scale", "101"}},
        {{"--scale", "2"}, {"--scale", "--width"}},  // tiny() gives --width and --height
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
        {{"--integrator", "bdtp"}, {"--integrator", "Did you mean \"bdpt\"?"}},
        {{"--light-sampling", "mix"}, {"--light-sampling", "Did you mean \"mis\"?"}},
        {{"--sampler", "sobel"}, {"--sampler", "independent or sobol", "Did you mean \"sobol\"?"}},
        {{"--sampler"}, {"--sampler"}},
        {{"--sp", "3"}, {"--sp", "Did you mean \"--spp\"?"}},
        {{"--integrater=vcm"}, {"--integrater", "Did you mean \"--integrator\"?"}},
        {{"cornel-point"}, {"cornel-point", "Did you mean \"cornell-point\"?"}},
        {{"prism", "-o", "b.exr", "--spectral-bands", "4"}, {"--spectral-bands", "chooses vcm, add --integrator path"}},
        {{"--merge-radius", "0"}, {"--merge-radius", "'0'"}},
        {{"--merge-radius", "-1"}, {"--merge-radius", "-1"}},
        {{"--merge-radius", "abc"}, {"--merge-radius", "abc"}},
        {{"--merge-radius", "nan"}, {"--merge-radius"}},
        {{"--merge-radius"}, {"--merge-radius"}},
        {{"--tile", "0"}, {"--tile", "'0'", "WxH"}},
        {{"--tile", "8x"}, {"--tile", "8x"}},
        {{"--tile", "65537"}, {"--tile", "65537"}},
        {{"--tile", "rows:0"}, {"--tile", "rows:0"}},
        {{"--tile", "rowsx"}, {"--tile", "rowsx"}},
        {{"--queue", "lockfree"}, {"--queue", "lockfree", "atomic"}},
        {{"--schedule", "wavefrnt"}, {"--schedule", "Did you mean \"wavefront\"?"}},
        {{"cornell-fog", "--schedule", "wavefront"}, {"--schedule wavefront", "participating media", "tiles"}},
        {{"textured", "--schedule", "wavefront"}, {"--schedule wavefront", "textures"}},
        {{"--integrator", "bdpt", "--schedule", "wavefront"}, {"--schedule wavefront", "bdpt"}},
        {{"--sampler", "sobol", "--schedule", "wavefront"}, {"--schedule wavefront", "the sobol sampler", "--sampler independent"}},
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

/// A file given for two roles where writing one destroys the other (the checkpoint and an
/// output, an output and the checkpoint it resumes from, an output and the unfinished image of
/// another) is refused before rendering: one line, exit 2, every existing file untouched. Paths
/// are compared after resolving ".", "..", symbolic links and hard links.
TEST_F(Cli, OneFileForTwoRolesIsRefusedBeforeRendering) {
    write_file(m_dir / "out.exr", "old image");
    write_file(m_dir / "ck.film", "old checkpoint");
    fs::create_directories(m_dir / "sub");
    fs::create_directory_symlink(m_dir, m_dir / "link");
    fs::create_symlink(m_dir / "out.exr", m_dir / "alias.exr");
    fs::create_hard_link(m_dir / "out.exr", m_dir / "hard.exr");
    const struct {
        std::vector<std::string> args;
        std::string message;
    } cases[] = {
        {{"--checkpoint", "out.exr", "-o", "out.exr"}, "-o 'out.exr' is the same file as --checkpoint 'out.exr'"},
        {{"-o", "out.exr", "--checkpoint", "./sub/../out.exr"}, "-o 'out.exr' is the same file as --checkpoint"},
        {{"-o", "out.exr", "--checkpoint", (m_dir / "out.exr").string()}, "is the same file as --checkpoint"},
        {{"-o", "out.exr", "--checkpoint", "link/out.exr"}, "is the same file as --checkpoint 'link/out.exr'"},
        {{"-o", "out.exr", "--checkpoint", "alias.exr"}, "is the same file as --checkpoint 'alias.exr'"},
        {{"-o", "out.exr", "--checkpoint", "hard.exr"}, "is the same file as --checkpoint 'hard.exr'"},
        {{"-o", "out.exr", "--checkpoint", "out.partial.exr"},
         "the unfinished image of -o 'out.partial.exr' is the same file as --checkpoint"},
        {{"-o", "out.exr", "-o", "link/out.partial.exr"},
         "the unfinished image of -o 'out.partial.exr' is the same file as -o 'link/out.partial.exr'"},
        {{"-o", "ck.film.exr", "--resume", "ck.film.exr"}, "-o 'ck.film.exr' is the same file as --resume"},
        {{"merge", "ck.film", "-o", "ck.film"}, "the part 'ck.film' is the same file as -o 'ck.film'"},
        {{"merge", "ck.film", "-o", "out.exr", "-o", "link/ck.film"}, "is the same file as -o 'link/ck.film'"},
    };
    for (const auto& c : cases) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exit_code, 2) << join(c.args) << "\n" << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << join(c.args) << "\n" << r.err;
        EXPECT_TRUE(is_one_line(r.err)) << r.err;
        EXPECT_EQ(read_file(m_dir / "out.exr"), "old image") << join(c.args);
        EXPECT_EQ(read_file(m_dir / "ck.film"), "old checkpoint") << join(c.args);
        EXPECT_FALSE(fs::exists(m_dir / "out.partial.exr")) << join(c.args);
    }
    // The checkpoint that is resumed is the one to replace: allowed.
    const RunResult first = run(tiny({"--checkpoint", "state.ckpt", "-o", "a.exr"}));
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const RunResult again = run(tiny({"--checkpoint", "state.ckpt", "--resume", "./state.ckpt", "-o", "a.exr"}));
    EXPECT_EQ(again.exit_code, 0) << again.err;
}

/// The summary's first line gives the samples the image holds, and what was asked for when a
/// time limit stopped the render before.
TEST_F(Cli, SummaryGivesTheSamplesDone) {
    const RunResult whole = run({"--width", "8", "--height", "8", "--spp", "3", "-o", "a.pfm"});
    ASSERT_EQ(whole.exit_code, 0) << whole.err;
    EXPECT_NE(whole.err.find("cornell: 8x8, 3 spp, "), std::string::npos) << whole.err;
    const RunResult limited = run({"--width", "32", "--height", "32", "--spp", "1000000", "--pass-spp", "1",
                                   "--time-limit", "1.5", "-o", "t.pfm"});
    ASSERT_EQ(limited.exit_code, 0) << limited.err;
    const std::string marker = "stopped by --time-limit 1.5 s after ";
    const auto at = limited.err.find(marker);
    ASSERT_NE(at, std::string::npos) << limited.err;
    const int spp = std::stoi(limited.err.substr(at + marker.size()));
    EXPECT_NE(limited.err.find("cornell: 32x32, " + std::to_string(spp) + " spp (of 1000000 requested), "),
              std::string::npos) << limited.err;
    // Progress follows the clock, not the 1000000 spp asked for: past half the time it shows
    // 50 % or more (at the pace of the spp it would show 0 %).
    int most = -1;
    const std::regex progress("progress +([0-9]+)%");
    for (auto it = std::sregex_iterator(limited.err.begin(), limited.err.end(), progress);
         it != std::sregex_iterator(); ++it)
        most = std::max(most, std::stoi((*it)[1]));
    EXPECT_GE(most, 50) << limited.err;
}

/// The path tracer cannot light a surface from a point light through glass: the summary says
/// once which integrator can; with vcm, or without the glass, it says nothing.
TEST_F(Cli, SummaryNamesTheIntegratorForMissedCaustics) {
    write_file(m_dir / "caustic.json", R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
      "image": {"width": 8, "height": 8, "spp": 1},
      "materials": {"grey": {"kd": 0.5}, "glass": {"kt": 1, "ior": 1.5}},
      "shapes": [{"type": "plane", "normal": [0, 1, 0], "point": [0, -1, 0], "material": "grey"},
                 {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "glass"}],
      "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 3}]})");
    const std::string note = "note: the path integrator renders no light from point or spot lights through "
                             "mirrors or glass (caustics); --integrator vcm (or bdpt) renders it";
    const RunResult path = run({"caustic.json", "-o", "a.pfm"});
    ASSERT_EQ(path.exit_code, 0) << path.err;
    const auto at = path.err.find(note);
    EXPECT_NE(at, std::string::npos) << path.err;
    EXPECT_EQ(path.err.find(note, at + 1), std::string::npos) << "once: " << path.err;
    const RunResult vcm = run({"caustic.json", "--integrator", "vcm", "-o", "a.pfm"});
    ASSERT_EQ(vcm.exit_code, 0) << vcm.err;
    EXPECT_EQ(vcm.err.find("note:"), std::string::npos) << vcm.err;
    std::string no_glass = read_file(m_dir / "caustic.json");
    no_glass.replace(no_glass.find("\"material\": \"glass\""), 19, "\"material\": \"grey\"");
    write_file(m_dir / "diffuse.json", no_glass);
    const RunResult diffuse = run({"diffuse.json", "-o", "a.pfm"});
    ASSERT_EQ(diffuse.exit_code, 0) << diffuse.err;
    EXPECT_EQ(diffuse.err.find("note:"), std::string::npos) << diffuse.err;
}

/// The summary says whether the render was guided and why; --guiding on where the path
/// integrator cannot be guided is refused before anything is written, naming what it needs.
TEST_F(Cli, GuidingIsReportedAndRefusedWhereUnsupported) {
    const RunResult plain = run({"--width", "8", "--height", "8", "--spp", "2", "-o", "a.pfm"});
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_NE(plain.err.find("guiding off (auto: "), std::string::npos) << plain.err;
    const RunResult guided =
        run({"--width", "8", "--height", "8", "--spp", "4", "--guiding", "on", "--guiding-field", "spectral", "-o", "g.pfm"});
    ASSERT_EQ(guided.exit_code, 0) << guided.err;
    EXPECT_NE(guided.err.find("guiding spectral (--guiding on)"), std::string::npos) << guided.err;
    const RunResult fog = run({"cornell-fog", "--width", "8", "--height", "8", "--guiding", "on", "-o", "f.pfm"});
    EXPECT_EQ(fog.exit_code, 2);
    EXPECT_NE(fog.err.find("expected a scene without participating media"), std::string::npos) << fog.err;
    EXPECT_FALSE(std::filesystem::exists(m_dir / "f.pfm"));
    const RunResult bdpt = run({"--integrator", "bdpt", "--width", "8", "--height", "8", "--spp", "1", "--guiding",
                                "on", "-o", "b.pfm"});
    ASSERT_EQ(bdpt.exit_code, 0) << bdpt.err;
    EXPECT_NE(bdpt.err.find("--guiding has no effect with the bdpt integrator"), std::string::npos) << bdpt.err;
}

/// --no-bvh measures what the BVH buys: refused, before anything is written, for a shape that
/// only the BVH intersects.
TEST_F(Cli, NoBvhIsRefusedForShapesOnlyTheBvhIntersects) {
    write_file(m_dir / "disk.json", R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
      "image": {"width": 8, "height": 8, "spp": 1},
      "materials": {"grey": {"kd": 0.5}},
      "shapes": [{"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1, "material": "grey"}],
      "lights": [{"type": "point", "position": [0, 0, 2], "intensity": 3}]})");
    const RunResult r = run({"disk.json", "--no-bvh", "-o", "a.pfm"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--no-bvh: scene"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(m_dir / "a.pfm"));
    EXPECT_EQ(run({"disk.json", "-o", "a.pfm"}).exit_code, 0);
}

TEST_F(Cli, PbrtFilesRenderAndStrictMakesTheirWarningsErrors) {
    write_file(m_dir / "ball.pbrt", "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 6\n"
                                    "Sampler \"independent\" \"integer pixelsamples\" 1\n"
                                    "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
                                    "LightSource \"point\" \"point3 from\" [0 0 2] \"rgb I\" [1 1 1]\n"
                                    "Shape \"sphere\" \"float radius\" 0.5 \"float zmax\" 0.2\n");
    const RunResult warned = run({"ball.pbrt", "-o", "a.pfm"});
    EXPECT_EQ(warned.exit_code, 0) << warned.err;
    EXPECT_NE(warned.err.find("ball.pbrt:7:35: \"zmax\" (a partial shape) is not supported"), std::string::npos) << warned.err;
    EXPECT_TRUE(fs::exists(m_dir / "a.pfm"));
    const RunResult strict = run({"ball.pbrt", "--strict", "-o", "b.pfm"});
    EXPECT_EQ(strict.exit_code, 2) << strict.err;
    EXPECT_NE(strict.err.find("--strict"), std::string::npos) << strict.err;
    EXPECT_FALSE(fs::exists(m_dir / "b.pfm"));
}

/// Width and height from a PNG file's IHDR chunk ({0, 0} when it is not a PNG).
std::pair<unsigned, unsigned> png_size(const fs::path& path) {
    const std::string png = read_file(path);
    if (png.size() < 24 || png.substr(0, 8) != std::string("\x89PNG\r\n\x1a\n", 8) ||
        png.substr(12, 4) != "IHDR")
        return {0, 0};
    const auto be32 = [&](std::size_t at) {
        return (unsigned(static_cast<unsigned char>(png[at])) << 24) |
               (unsigned(static_cast<unsigned char>(png[at + 1])) << 16) |
               (unsigned(static_cast<unsigned char>(png[at + 2])) << 8) |
               unsigned(static_cast<unsigned char>(png[at + 3]));
    };
    return {be32(16), be32(20)};
}

void expect_valid_images(const fs::path& dir, const std::string& stem, int w, int h) {
    EXPECT_EQ(png_size(dir / (stem + ".png")), std::make_pair(unsigned(w), unsigned(h)));

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

// Only --width or --height: the other side keeps the scene's aspect ratio (colorchecker is
// 240 x 160); --scale multiplies the scene's size.
TEST_F(Cli, ImageSizeKeepsTheScenesAspectRatio) {
    const std::vector<std::pair<std::vector<std::string>, std::pair<unsigned, unsigned>>> cases = {
        {{"--width", "48"}, {48, 32}},
        {{"--height", "8"}, {12, 8}},
        {{"--scale", "0.1"}, {24, 16}},
        {{"--width", "10", "--height", "10"}, {10, 10}},
    };
    for (const auto& [flags, size] : cases) {
        std::vector<std::string> args = {"colorchecker", "--spp", "1", "--quiet", "-o", "a.png"};
        args.insert(args.end(), flags.begin(), flags.end());
        const RunResult r = run(args);
        ASSERT_EQ(r.exit_code, 0) << join(flags) << "\n" << r.err;
        EXPECT_EQ(png_size(m_dir / "a.png"), size) << join(flags);
    }
}

// --tonemap and --auto-exposure act on the PNG only; --white-balance on every output. The
// summary names the automatic exposure.
TEST_F(Cli, DisplayFlagsReachTheRightOutputs) {
    const auto render = [&](const std::string& stem, std::vector<std::string> more) {
        std::vector<std::string> args = {"--width", "16", "--height", "16", "--spp", "2",
                                         "-o", stem + ".png", "-o", stem + ".pfm"};
        args.insert(args.end(), more.begin(), more.end());
        return run(args);
    };
    ASSERT_EQ(render("plain", {"--quiet"}).exit_code, 0);
    ASSERT_EQ(render("clip", {"--quiet", "--tonemap", "clip"}).exit_code, 0);
    ASSERT_EQ(render("neutral", {"--quiet", "--tonemap", "neutral"}).exit_code, 0);
    const RunResult automatic = render("auto", {"--auto-exposure"});
    ASSERT_EQ(automatic.exit_code, 0) << automatic.err;
    ASSERT_EQ(render("balanced", {"--quiet", "--white-balance", "3200K"}).exit_code, 0);
    const auto bytes = [&](const std::string& name) { return read_file(m_dir / name); };

    EXPECT_EQ(bytes("plain.png"), bytes("neutral.png"));  // neutral is the default
    EXPECT_NE(bytes("plain.png"), bytes("clip.png"));     // the cornell ceiling is above 1
    EXPECT_NE(bytes("plain.png"), bytes("auto.png"));
    for (const char* stem : {"clip", "neutral", "auto"})
        EXPECT_EQ(bytes("plain.pfm"), bytes(std::string(stem) + ".pfm")) << stem;
    EXPECT_NE(bytes("plain.pfm"), bytes("balanced.pfm"));
    EXPECT_NE(bytes("plain.png"), bytes("balanced.png"));
    // cornell's median luminance is about 0.8: the exposure goes down about two stops.
    const std::size_t at = automatic.err.find("auto exposure: -");
    ASSERT_NE(at, std::string::npos) << automatic.err;
    EXPECT_NE(automatic.err.find(" stops\n", at), std::string::npos) << automatic.err;
}

TEST_F(Cli, PrintAdaptationPrintsBothWhitesAndAMatrix) {
    const RunResult r = run({"--print-adaptation", "A", "--color-space", "acescg"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::istringstream in(r.out);
    std::string source, target;
    double xy[4] = {}, m[9] = {};
    in >> source >> xy[0] >> xy[1] >> target >> xy[2] >> xy[3];
    for (double& v : m) in >> v;
    ASSERT_TRUE(in) << r.out;
    EXPECT_EQ(source, "source_xy");
    EXPECT_EQ(target, "target_xy");
    EXPECT_DOUBLE_EQ(xy[0], 0.44758);  // illuminant A
    EXPECT_DOUBLE_EQ(xy[3], 0.33767);  // the ACES white
    EXPECT_GT(m[8], 2.0);              // blue boosted a lot from tungsten light
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 5) << r.out;
    EXPECT_TRUE(files().empty());
}

}  // namespace

namespace {

/// A tiny scene file asking for an integrator (`preset` is the JSON value of "integrator", or
/// empty for none): a diffuse box corner lit by a small emitting sphere.
std::string scene_with_integrator(const std::string& preset) {
    return std::string("{") + (preset.empty() ? "" : "\"integrator\": " + preset + ",") +
           "\"camera\": {\"position\": [0, 0, 3], \"look_at\": [0, 0, 0]},"
           "\"image\": {\"width\": 8, \"height\": 8, \"spp\": 4},"
           "\"materials\": {\"white\": {\"kd\": 0.7}, \"glass\": {\"kt\": 1, \"ior\": 1.5}},"
           "\"shapes\": [{\"type\": \"plane\", \"normal\": [0, 1, 0], \"point\": [0, -1, 0], \"material\": \"white\"},"
           "{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.5, \"material\": \"glass\"},"
           "{\"type\": \"sphere\", \"center\": [0, 1.5, 0], \"radius\": 0.2, \"emission\": 5}]}";
}

/// The summary's integrator line ("integrator bdpt (the scene's choice ...)").
std::string integrator_line(const std::string& err) {
    for (const std::string& line : lines_of(err))
        if (line.rfind("  integrator ", 0) == 0) return line;
    return "";
}

TEST_F(Cli, SceneChoosesItsIntegratorAndTheCommandLineOverrides) {
    write_file(m_dir / "chooses.json", scene_with_integrator("{\"type\": \"bdpt\", \"max_depth\": 3}"));
    write_file(m_dir / "plain.json", scene_with_integrator(""));
    const RunResult chosen = run({"chooses.json", "-o", "chosen.pfm"});
    ASSERT_EQ(chosen.exit_code, 0) << chosen.err;
    EXPECT_EQ(integrator_line(chosen.err).rfind("  integrator bdpt (the scene's choice", 0), 0u) << chosen.err;
    // The scene's settings are those of the same flags on the command line: the same bits.
    const RunResult flags = run({"plain.json", "--integrator", "bdpt", "--max-depth", "3", "-o", "flags.pfm"});
    ASSERT_EQ(flags.exit_code, 0) << flags.err;
    EXPECT_EQ(integrator_line(flags.err).rfind("  integrator bdpt (chosen by --integrator)", 0), 0u) << flags.err;
    EXPECT_EQ(read_file(m_dir / "chosen.pfm"), read_file(m_dir / "flags.pfm"));

    const RunResult plain = run({"plain.json", "-o", "plain.pfm"});
    EXPECT_EQ(integrator_line(plain.err).rfind("  integrator path (the default)", 0), 0u) << plain.err;
    const RunResult overridden = run({"chooses.json", "--integrator", "path", "--max-depth", "3", "-o", "over.pfm"});
    EXPECT_EQ(integrator_line(overridden.err).rfind("  integrator path (chosen by --integrator)", 0), 0u)
        << overridden.err;
    const RunResult path3 = run({"plain.json", "--max-depth", "3", "-o", "path3.pfm"});
    EXPECT_EQ(read_file(m_dir / "over.pfm"), read_file(m_dir / "path3.pfm"));
    EXPECT_NE(read_file(m_dir / "over.pfm"), read_file(m_dir / "chosen.pfm"));
}

TEST_F(Cli, NamesIgnoreCase) {
    ASSERT_EQ(run(tiny({"cornell-point", "--integrator", "BDPT", "-o", "upper.pfm"})).exit_code, 0);
    ASSERT_EQ(run(tiny({"cornell-point", "--integrator", "bdpt", "-o", "lower.pfm"})).exit_code, 0);
    ASSERT_EQ(run(tiny({"cornell-point", "-o", "path.pfm"})).exit_code, 0);
    EXPECT_EQ(read_file(m_dir / "upper.pfm"), read_file(m_dir / "lower.pfm"));
    EXPECT_NE(read_file(m_dir / "upper.pfm"), read_file(m_dir / "path.pfm"));
    EXPECT_EQ(run(tiny({"--light-sampling", "MIS", "-o", "a.pfm", "--color-space", "ACEScg"})).exit_code, 0);
    ASSERT_EQ(run(tiny({"--tonemap", "CLIP", "--white-balance", "d50", "-o", "upper.png"})).exit_code, 0);
    ASSERT_EQ(run(tiny({"--tonemap", "clip", "--white-balance", "D50", "-o", "lower.png"})).exit_code, 0);
    EXPECT_EQ(read_file(m_dir / "upper.png"), read_file(m_dir / "lower.png"));
}

TEST_F(Cli, FlagsWithoutEffectAreWarnedAbout) {
    struct Case {
        std::vector<std::string> args;
        std::string warning;  ///< empty: no warning expected
    };
    const std::vector<Case> cases = {
        {{"--merge-radius", "0.1", "-o", "a.pfm"}, "--merge-radius has no effect with the path integrator"},
        {{"--integrator", "vcm", "--merge-radius", "0.1", "-o", "a.pfm"}, ""},
        {{"--integrator", "bdpt", "--light-sampling", "bsdf", "-o", "a.pfm"}, "--light-sampling has no effect"},
        {{"--exposure", "1", "-o", "a.pfm"}, "--exposure has no effect without a .png output"},
        {{"--exposure", "1", "-o", "a.pfm", "-o", "a.png"}, ""},
        {{"--color-resolution", "255", "-o", "a.png"}, "--color-resolution has no effect without a .ppm output"},
        {{"--color-space", "xyz", "-o", "a.png"}, "--color-space has no effect with only .png outputs"},
        {{"--checkpoint-interval", "5", "-o", "a.png"}, "--checkpoint-interval has no effect without --checkpoint"},
        {{"--no-dispersion", "-o", "a.png"}, "--no-dispersion has no effect in a scene without dispersive glass"},
        {{"--no-bvh", "-o", "a.png"}, "--no-bvh has no effect in a scene this small"},
    };
    for (const Case& c : cases) {
        // --quiet silences the summary, not warnings.
        const RunResult r = run(tiny(c.args));
        EXPECT_EQ(r.exit_code, 0) << join(c.args) << "\n" << r.err;
        if (c.warning.empty()) {
            EXPECT_EQ(r.err, "") << join(c.args);
        } else {
            EXPECT_TRUE(is_one_line(r.err)) << join(c.args) << "\n" << r.err;
            EXPECT_EQ(r.err.rfind("pathtracer: warning: " + c.warning, 0), 0u) << join(c.args) << "\n" << r.err;
        }
    }
}

TEST_F(Cli, OpenRefractingMeshIsWarnedAboutByName) {
    // One triangle of glass: it cannot bound a volume.
    write_file(m_dir / "tri.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    write_file(m_dir / "s.json",
               "{\"camera\": {\"position\": [0, 0, 3], \"look_at\": [0, 0, 0]}, \"materials\": {\"glass\": "
               "{\"kt\": 1, \"ior\": 1.5}}, \"shapes\": [{\"type\": \"mesh\", \"file\": \"tri.ply\", \"material\": \"glass\"}]}");
    const RunResult r = run(tiny({"s.json", "-o", "s.png"}));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(is_one_line(r.err)) << r.err;
    EXPECT_NE(r.err.find("warning: mesh (shape 0)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("tri.ply"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not closed"), std::string::npos) << r.err;
}

TEST_F(Cli, SummaryGivesLoadTimeBvhTimeAndPeakMemory) {
    const RunResult r = run({"showcase", "--width", "8", "--height", "6", "--spp", "1", "-o", "s.png"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::regex line(R"(\n  scene loaded in [0-9.]+ s \(BVH built in [0-9.]+ s\); peak memory ([0-9]+) MiB\n)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.err, m, line)) << r.err;
    EXPECT_GT(std::stoi(m[1].str()), 0);
}

}  // namespace

namespace {

/// The flags ("--name") a text mentions.
std::set<std::string> flags_in(const std::string& text) {
    std::set<std::string> flags;
    const std::regex flag(R"(--[a-z][a-z0-9-]*)");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), flag); it != std::sregex_iterator(); ++it)
        flags.insert(it->str());
    return flags;
}

// The default scene is the one constant: what a command line without SCENE renders, what --help
// says it is, and a built-in scene.
TEST(CliFlags, TheDefaultSceneIsOneBuiltInName) {
    EXPECT_EQ(spt::Options{}.scene, spt::kDefaultScene);
    EXPECT_NE(spt::usage_text().find("(default: " + std::string(spt::kDefaultScene) + "; see"), std::string::npos);
    const std::vector<std::string> names = spt::builtin_scene_names();
    EXPECT_NE(std::find(names.begin(), names.end(), spt::kDefaultScene), names.end());
}

// "Did you mean" knows every flag, --help documents every flag, and the README's synopsis (the
// code block under "## Using it") lists every flag: a new flag missing from one fails here.
TEST(CliFlags, HelpReadmeAndSuggestionsKnowTheSameFlags) {
    const std::vector<std::string>& known = spt::known_flags();
    const std::set<std::string> known_set(known.begin(), known.end());
    EXPECT_EQ(flags_in(spt::usage_text()), known_set);
    const std::string readme = read_file(fs::path(SPT_SOURCE_DIR) / "README.md");
    const auto section = readme.find("## Using it");
    ASSERT_NE(section, std::string::npos);
    const auto open = readme.find("```", section), close = readme.find("```", open + 3);
    ASSERT_NE(close, std::string::npos);
    EXPECT_EQ(flags_in(readme.substr(open, close - open)), known_set);
    for (const std::string& f : known) {
        // Parsed (perhaps failing on its value), never "unknown option".
        try {
            spt::parse_options({f});
        } catch (const spt::UsageError& e) {
            EXPECT_EQ(std::string(e.what()).find("unknown option"), std::string::npos) << f << ": " << e.what();
        }
    }
}

}  // namespace

// ---- Spectral output, sensor and EXR metadata (src/cli/render_metadata.h) ----

namespace {

TEST_F(Cli, SpectralOutputRefusesWhatItCannotDo) {
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--spectral-bands", "4", "-o", "a.png"}, "--spectral-bands: needs an .exr output"},
        {{"--spectral-bands", "4", "-o", "a.exr", "--integrator", "bdpt"},
         "--spectral-bands: only with --integrator path"},
        {{"--spectral-bands", "4", "-o", "a.exr", "--checkpoint", "c"},
         "--checkpoint: not with --spectral-bands"},
        {{"--spectral-bands", "4", "-o", "a.exr", "--resume", "c"},
         "--resume: not with --spectral-bands"},
        {{"--spectral-range", "300:900", "-o", "a.exr"},
         "--spectral-range: needs --spectral-bands N"},
        {{"--spectral-bands", "4", "--spectral-range", "900:300", "-o", "a.exr"},
         "--spectral-range: expected MIN:MAX"},
        {{"--spectral-bands", "0", "-o", "a.exr"},
         "--spectral-bands: expected an integer from 1 to 4096"},
        {{"--sensor", "s.csv", "--color-space", "xyz"}, "--color-space: not with --sensor"},
    };
    for (const auto& [args, message] : cases) {
        const RunResult r = run(args);
        EXPECT_EQ(r.exit_code, 2) << join(args);
        EXPECT_NE(r.err.find(message), std::string::npos) << join(args) << ": " << r.err;
        EXPECT_TRUE(files().empty()) << join(args);
    }
}

TEST_F(Cli, BadSensorFileNamesLineAndColumnAndWritesNothing) {
    write_file(m_dir / "bad.csv", "# test\nwavelength_nm,r,g,b\n400,1,1,1\n500,1,oops,1\n");
    const RunResult r =
        run({"--width", "4", "--height", "4", "--spp", "1", "--sensor", "bad.csv", "-o", "a.exr"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("bad.csv:4:7: expected a number, got 'oops'"), std::string::npos) << r.err;
    EXPECT_EQ(files(), (std::set<std::string>{"bad.csv"}));
}

// The film's sums are the sensor's RGB: a checkpoint resumes only with the same curves.
TEST_F(Cli, CheckpointResumesOnlyWithTheSameSensor) {
    write_file(m_dir / "a.csv", "wavelength_nm,r,g,b\n400,1,1,0\n700,0,1,1\n");
    write_file(m_dir / "b.csv", "wavelength_nm,r,g,b\n400,1,1,0\n700,0,1,2\n");
    const std::vector<std::string> base = {"--width", "4", "--height", "4", "--spp",
                                           "2", "--quiet", "-o", "a.pfm"};
    auto with = [&](std::vector<std::string> more) {
        more.insert(more.begin(), base.begin(), base.end());
        return more;
    };
    ASSERT_EQ(run(with({"--sensor", "a.csv", "--checkpoint", "c.ckpt"})).exit_code, 0);
    const RunResult other = run(with({"--sensor", "b.csv", "--resume", "c.ckpt"}));
    EXPECT_NE(other.exit_code, 0);
    EXPECT_NE(other.err.find("cannot resume"), std::string::npos) << other.err;
    EXPECT_NE(run(with({"--resume", "c.ckpt"})).exit_code, 0);  // nor with the CIE observer
    EXPECT_EQ(run(with({"--sensor", "a.csv", "--resume", "c.ckpt"})).exit_code, 0);
}

// A scene whose lights need more bins than the default renders with them when the user does
// not choose (spectral/line_spectra.h); checkpoints record the bins used, so a render at
// another resolution never resumes it.
TEST_F(Cli, BinsChosenForTheLightsAreTheOnesRecorded) {
    const std::vector<std::string> base = {"colorchecker-f11", "--width", "6", "--height", "4", "--spp", "2"};
    auto with = [&](std::vector<std::string> more) {
        more.insert(more.begin(), base.begin(), base.end());
        return more;
    };
    const RunResult first = run(with({"--checkpoint", "c.ckpt", "-o", "a.pfm"}));
    ASSERT_EQ(first.exit_code, 0) << first.err;
    EXPECT_NE(first.err.find("64 spectral bins (the lights' narrow lines need them)"), std::string::npos) << first.err;
    const RunResult sixteen = run(with({"--spectral-bins", "16", "--resume", "c.ckpt", "-o", "b.pfm"}));
    EXPECT_NE(sixteen.exit_code, 0);
    EXPECT_NE(sixteen.err.find("cannot resume"), std::string::npos) << sixteen.err;
    EXPECT_EQ(run(with({"--spectral-bins", "64", "--resume", "c.ckpt", "-o", "b.pfm", "--quiet"})).exit_code, 0);
}

TEST_F(Cli, ExrHeaderCarriesTheRenderMetadata) {
    ASSERT_EQ(run({"--width", "4", "--height", "2", "--spp", "3", "--seed", "12345678901234",
                   "--quiet", "-o", "a.exr"})
                  .exit_code,
              0);
    const std::string exr = read_file(m_dir / "a.exr");
    std::size_t at = 0;
    const auto h = spt::exr_test::parse_exr_header(exr, at);
    auto text = [&](const char* name) {
        EXPECT_EQ(h.at(name).type, "string") << name;
        return h.at(name).value;
    };
    EXPECT_EQ(text("software"), std::string("pathtracer ") + SPT_VERSION);
    EXPECT_EQ(text("scene"), "cornell");
    EXPECT_EQ(text("integrator"), "path");
    EXPECT_EQ(text("seed"), "12345678901234");
    EXPECT_EQ(text("spectralBins"), "16");
    EXPECT_EQ(text("observer"), "CIE 1931 2 degree");
    EXPECT_EQ(text("capDate").size(), 19u);  // YYYY:MM:DD hh:mm:ss
    EXPECT_EQ(h.at("spp").type, "int");
    EXPECT_EQ(spt::exr_test::le32(h.at("spp").value, 0), 3u);
    EXPECT_EQ(h.at("renderTimeSeconds").type, "double");
    const double seconds = spt::exr_test::le_double(h.at("renderTimeSeconds").value, 0);
    EXPECT_TRUE(seconds >= 0 && seconds < 600) << seconds;
    EXPECT_EQ(h.count("spectralLayoutVersion"), 0u);  // no bands asked for
}

TEST_F(Cli, SpectralExrHoldsTheBandsAndWarnsWhereBinnedSpectraEnd) {
    const std::vector<std::string> base = {
        "--width", "4", "--height", "2", "--spp", "2", "--spectral-bands", "4",
        "--spectral-range", "300:1100", "-o", "a.exr", "-o", "a.png"};
    const RunResult binned = run(base);
    ASSERT_EQ(binned.exit_code, 0) << binned.err;
    EXPECT_NE(binned.err.find("warning: --spectral-range reaches beyond 360-830 nm"),
              std::string::npos);
    std::vector<std::string> exact = base;
    exact.insert(exact.end(), {"--spectral-bins", "exact"});
    const RunResult r = run(exact);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos);
    const auto channels = spt::exr_test::read_exr_channels(read_file(m_dir / "a.exr"), 4, 2);
    std::vector<std::string> names;
    for (const auto& [name, pixels] : channels) names.push_back(name);
    EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R", "S0.1000,000000nm", "S0.400,000000nm",
                                               "S0.600,000000nm", "S0.800,000000nm"}));
}

}  // namespace
