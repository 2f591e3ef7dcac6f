// Atomic whole-file write: temporary file in the same directory, flush, fsync, rename.
#include "io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace spt {

void write_file_atomically(const std::string& path, const std::string& bytes) {
    // Same directory as the target so that rename() stays on one file system and is atomic;
    // pid + counter keep concurrent writers (processes or threads) off each other's files.
    static std::atomic<unsigned> counter{0};
    const std::string tmp =
        path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);

    auto fail = [&](int err) {
        return std::runtime_error("cannot write '" + path + "': " + std::strerror(err));
    };
    std::FILE* file = std::fopen(tmp.c_str(), "wbx");  // x: never clobber an existing file
    if (!file) throw fail(errno);

    int err = 0;
    auto note = [&err](bool ok) {
        if (!ok && err == 0) err = errno != 0 ? errno : EIO;  // keep the first error
    };
    errno = 0;
    note(std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size());
    note(std::fflush(file) == 0);
    note(::fsync(::fileno(file)) == 0);  // contents on disk before the rename publishes them
    note(std::fclose(file) == 0);
    if (err == 0) note(std::rename(tmp.c_str(), path.c_str()) == 0);
    if (err != 0) {
        std::remove(tmp.c_str());
        throw fail(err);
    }
}

}  // namespace spt
