// The malformed-input corpus (tests/malformed/, expectations in expected.tsv): the real program
// must reject each file with exit status 1 and one line "file:line:column: message" containing
// the expected text, write no image, and never crash. PLY files are wrapped in a scene as a
// mesh, image files (.png, .ppm, .pfm, .exr) as a texture.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool is_image(const fs::path& p) {
    const std::string ext = p.extension().string();
    return ext == ".png" || ext == ".ppm" || ext == ".pfm" || ext == ".exr";
}

struct Case {
    std::string file, expected;
};

std::vector<Case> load_cases() {
    std::vector<Case> cases;
    std::ifstream in(fs::path(SPT_TEST_DIR) / "malformed" / "expected.tsv");
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const auto tab = line.find('\t');
        cases.push_back({line.substr(0, tab), tab == std::string::npos ? "" : line.substr(tab + 1)});
    }
    return cases;
}

TEST(MalformedCorpus, EveryFileIsListedAndTheCorpusIsLarge) {
    const std::vector<Case> cases = load_cases();
    EXPECT_GE(cases.size(), 60u);
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(fs::path(SPT_TEST_DIR) / "malformed")) {
        const std::string ext = e.path().extension().string();
        if (ext != ".json" && ext != ".ply" && !is_image(e.path())) continue;
        ++files;
        const std::string name = e.path().filename().string();
        EXPECT_TRUE(std::any_of(cases.begin(), cases.end(), [&](const Case& c) { return c.file == name; }))
            << name << " has no line in expected.tsv";
    }
    EXPECT_EQ(files, cases.size());
}

TEST(MalformedCorpus, EachFileGivesOneLocatedErrorAndNoImage) {
    const fs::path dir = fs::temp_directory_path() / ("spt_malformed_" + std::to_string(::getpid()));
    const fs::path work = dir / "work", logs = dir / "logs";
    fs::remove_all(dir);
    fs::create_directories(work);
    fs::create_directories(logs);
    const std::regex located(R"(^[^\n]+:[0-9]+:[0-9]+: [^\n]+\n$)");
    for (const Case& c : load_cases()) {
        SCOPED_TRACE(c.file);
        const fs::path input = fs::path(SPT_TEST_DIR) / "malformed" / c.file;
        fs::path scene = input;
        if (input.extension() == ".ply") {
            scene = logs / "wrapper.json";
            std::ofstream(scene) << "{\"camera\": {\"position\": [0, 0, 3], \"look_at\": [0, 0, 0]},\n"
                                    " \"materials\": {\"m\": {\"kd\": 0.5}},\n"
                                    " \"shapes\": [{\"type\": \"mesh\", \"file\": \""
                                 << input.string() << "\", \"material\": \"m\"}]}\n";
        }
        if (is_image(input)) {
            scene = logs / "wrapper.json";
            std::ofstream(scene) << "{\"camera\": {\"position\": [0, 0, 3], \"look_at\": [0, 0, 0]},\n"
                                    " \"textures\": {\"t\": {\"type\": \"image\", \"file\": \""
                                 << input.string() << "\"}},\n"
                                    " \"materials\": {\"m\": {\"kd\": {\"texture\": \"t\"}}},\n"
                                    " \"shapes\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"m\"}]}\n";
        }
        const std::string cmd = "cd " + quote(work.string()) + " && " + quote(SPT_PATHTRACER) + " " +
                                quote(scene.string()) + " --width 4 --height 4 --spp 1 --quiet -o out.png >" +
                                quote((logs / "out").string()) + " 2>" + quote((logs / "err").string()) + " </dev/null";
        const int status = std::system(cmd.c_str());
        ASSERT_TRUE(status != -1 && WIFEXITED(status));
        const std::string err = read_all(logs / "err");
        EXPECT_EQ(WEXITSTATUS(status), 1) << err;
        EXPECT_TRUE(std::regex_match(err, located)) << err;
        EXPECT_NE(err.find(c.expected), std::string::npos) << "expected \"" << c.expected << "\" in: " << err;
        EXPECT_TRUE(fs::is_empty(work)) << "an image was written";
        fs::remove_all(work);
        fs::create_directories(work);
    }
    if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

}  // namespace

namespace {

/// Runs the program in `cwd`; returns the exit code (stderr to `err`).
int run_in(const fs::path& cwd, const std::string& args, std::string& err) {
    const fs::path log = fs::temp_directory_path() / ("spt_scene_cli_" + std::to_string(::getpid()) + ".err");
    const std::string cmd = "cd " + quote(cwd.string()) + " && " + quote(SPT_PATHTRACER) + " " + args + " 2>" +
                            quote(log.string()) + " >/dev/null </dev/null";
    const int status = std::system(cmd.c_str());
    err = read_all(log);
    fs::remove(log);
    return (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
}

TEST(SceneFiles, BuiltinNamesAndRelativePathsBothRender) {
    const fs::path dir = fs::temp_directory_path() / ("spt_scene_files_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    std::string err;
    // A built-in scene from a folder without any scene files: it is compiled in.
    EXPECT_EQ(run_in(dir, "prism --width 8 --height 6 --spp 1 --quiet -o p.png", err), 0) << err;
    EXPECT_TRUE(fs::exists(dir / "p.png"));
    // A scene file by relative path, whose mesh is found next to the scene file.
    fs::copy_file(fs::path(SPT_TEST_DIR) / ".." / "scenes" / "showcase.json", dir / "sub" / "my.json");
    fs::copy_file(fs::path(SPT_TEST_DIR) / ".." / "scenes" / "prism.ply", dir / "sub" / "prism.ply");
    fs::copy_file(fs::path(SPT_TEST_DIR) / ".." / "scenes" / "octahedron.ply", dir / "sub" / "octahedron.ply");
    EXPECT_EQ(run_in(dir, "sub/my.json --width 8 --height 6 --spp 1 --quiet", err), 0) << err;
    EXPECT_TRUE(fs::exists(dir / "my.png"));  // default output named after the file
    // The same file without its mesh: a located error, exit 1.
    fs::remove(dir / "sub" / "octahedron.ply");
    EXPECT_EQ(run_in(dir, "sub/my.json --quiet -o q.png", err), 1);
    EXPECT_EQ(err.rfind("sub/my.json:", 0), 0u) << err;
    EXPECT_NE(err.find("cannot read mesh \"octahedron.ply\""), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "q.png"));
    // A missing scene file is exit 1 with file:1:1; an unknown name is a usage error (2).
    EXPECT_EQ(run_in(dir, "missing.json --quiet", err), 1);
    EXPECT_EQ(err.rfind("missing.json:1:1: cannot read the scene file: no such file", 0), 0u) << err;
    EXPECT_EQ(run_in(dir, "cornel --quiet", err), 2);
    EXPECT_NE(err.find("cornell"), std::string::npos) << err;
    fs::remove_all(dir);
}

}  // namespace
