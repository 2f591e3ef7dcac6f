// Running the pathtracer program (SPT_PATHTRACER) as a child process that a test can signal,
// watch and wait for: the interrupt, preview and display-server tests.
#pragma once
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

namespace test {

/// A fresh empty directory for the running test: temp/spt-<prefix>-<pid>-<test name> (the
/// caller removes it in TearDown).
inline std::filesystem::path fresh_test_dir(const std::string& prefix) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() /
        ("spt-" + prefix + "-" + std::to_string(getpid()) + "-" +
         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Starts the program with stdout/stderr sent to `log`; returns its pid.
inline pid_t spawn(const std::vector<std::string>& args, const std::filesystem::path& log) {
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
inline int wait_exit(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}

inline int run(const std::vector<std::string>& args, const std::filesystem::path& log) {
    return wait_exit(spawn(args, log));
}

/// Waits until `log` contains `text` (true) or `seconds` have passed (false). Without --quiet
/// the program prints its first "progress" line once a pass has run 0.2 s, after it has
/// started catching SIGINT and SIGTERM: waiting for it makes an interrupt land in the render.
inline bool wait_for_log(const std::filesystem::path& log, const std::string& text,
                         double seconds = 60) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < deadline) {
        if (read_file(log).find(text) != std::string::npos) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

}  // namespace test
