// No lost renders: interrupted renders write their image, checkpoints survive kill -9 at any
// moment (including in the middle of writing one), and a resumed render equals a straight one.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Starts the program with stdout/stderr sent to `log`; returns its pid.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
    const pid_t pid = fork();
    if (pid == 0) {
        FILE* f = std::fopen(log.c_str(), "w");
        if (f) dup2(fileno(f), STDERR_FILENO), dup2(fileno(f), STDOUT_FILENO);
        std::vector<char*> argv;
        std::string program = SPT_PATHTRACER;
        argv.push_back(program.data());
        std::vector<std::string> copy = args;
        for (std::string& a : copy) argv.push_back(a.data());
        argv.push_back(nullptr);
        execv(program.c_str(), argv.data());
        _exit(127);
    }
    return pid;
}

/// Waits for the process; returns its exit code, or 128 + signal when killed.
int wait_exit(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}

int run(const std::vector<std::string>& args, const fs::path& log) { return wait_exit(spawn(args, log)); }

class Checkpoint : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() /
              ("spt-checkpoint-" + std::to_string(getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    std::vector<std::string> base_args(const std::string& out) const {
        return {"--width", "48", "--height", "40", "--spp", "24", "--pass-spp", "1", "--threads", "2",
                "--seed", "5", "--quiet", "-o", (dir / out).string()};
    }
    fs::path dir;
};

TEST_F(Checkpoint, SigintWritesTheImageSoFarAndExitsNonZero) {
    std::vector<std::string> args = base_args("partial.pfm");
    args[5] = "100000";  // far more samples than the test waits for
    const pid_t pid = spawn(args, dir / "log");
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    kill(pid, SIGINT);
    EXPECT_EQ(wait_exit(pid), 130);
    EXPECT_TRUE(fs::exists(dir / "partial.pfm"));
    EXPECT_NE(read_file(dir / "log").find("interrupted by signal 2"), std::string::npos)
        << read_file(dir / "log");
}

TEST_F(Checkpoint, SigtermExitsWith143) {
    std::vector<std::string> args = base_args("partial.png");
    args[5] = "100000";
    const pid_t pid = spawn(args, dir / "log");
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    kill(pid, SIGTERM);
    EXPECT_EQ(wait_exit(pid), 143);
    EXPECT_TRUE(fs::exists(dir / "partial.png"));
}

TEST_F(Checkpoint, InterruptedAndResumedEqualsStraightRun) {
    ASSERT_EQ(run(base_args("straight.pfm"), dir / "log"), 0);
    std::vector<std::string> args = base_args("resumed.pfm");
    const std::string ck = (dir / "state.ckpt").string();
    args.insert(args.end(), {"--checkpoint", ck, "--checkpoint-interval", "0"});
    const pid_t pid = spawn(args, dir / "log");
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    kill(pid, SIGINT);
    wait_exit(pid);
    ASSERT_TRUE(fs::exists(ck));
    std::vector<std::string> resume = args;
    resume.insert(resume.end(), {"--resume", ck});
    ASSERT_EQ(run(resume, dir / "log"), 0) << read_file(dir / "log");
    EXPECT_EQ(read_file(dir / "straight.pfm"), read_file(dir / "resumed.pfm"));
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
