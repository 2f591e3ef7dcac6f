// Atomic whole-file write: temporary file in the same directory, flush, fsync, rename.
#include "io/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace spt {

namespace {

std::runtime_error write_error(const std::string& path, int err) {
    return std::runtime_error("cannot write '" + path + "': " + std::strerror(err));
}

/// Writes bytes to a fresh temporary file beside `path`; returns its name (throws on failure).
std::string write_temporary(const std::string& path, const std::string& bytes) {
    // Same directory as the target so that rename() stays on one file system and is atomic;
    // pid + counter keep concurrent writers (processes or threads) off each other's files.
    static std::atomic<unsigned> counter{0};
    const std::string tmp =
        path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    std::FILE* file = std::fopen(tmp.c_str(), "wbx");  // x: never clobber an existing file
    if (!file) throw write_error(path, errno);

    int err = 0;
    auto note = [&err](bool ok) {
        if (!ok && err == 0) err = errno != 0 ? errno : EIO;  // keep the first error
    };
    errno = 0;
    note(std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size());
    note(std::fflush(file) == 0);
    note(::fsync(::fileno(file)) == 0);  // contents on disk before the rename publishes them
    note(std::fclose(file) == 0);
    if (err != 0) {
        std::remove(tmp.c_str());
        throw write_error(path, err);
    }
    return tmp;
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& bytes) {
    write_files_atomically({{path, bytes}});
}

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files) {
    // Every file is written in full before any is published: a failure on one leaves all the
    // existing targets untouched.
    // A target that is a directory would fail at rename time, after earlier files were
    // replaced: refuse it before anything is written.
    for (const auto& file : files) {
        struct stat st;
        if (::stat(file.first.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) throw write_error(file.first, EISDIR);
    }
    std::vector<std::string> temporaries;
    try {
        for (const auto& [path, bytes] : files) temporaries.push_back(write_temporary(path, bytes));
    } catch (...) {
        for (const std::string& tmp : temporaries) std::remove(tmp.c_str());
        throw;
    }
    for (std::size_t i = 0; i < files.size(); ++i) {
        if (std::rename(temporaries[i].c_str(), files[i].first.c_str()) != 0) {
            const int err = errno;
            for (std::size_t j = i; j < files.size(); ++j) std::remove(temporaries[j].c_str());
            throw write_error(files[i].first, err);
        }
    }
}

}  // namespace spt
