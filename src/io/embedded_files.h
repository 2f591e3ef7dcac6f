// Data files compiled into the program (spectra/*.csv, scenes/*), see cmake/embed_files.cmake.
#pragma once
#include <cstddef>
#include <string_view>

namespace spt {

struct EmbeddedFile {
    const char* name;  ///< path relative to the source tree, e.g. "spectra/cie_1931_2deg.csv"
    const char* text;
    /// Binary files (PNG images, which hold zero bytes): their size in bytes. Text files: 0,
    /// their text ends at its null byte.
    std::size_t size;

    std::string_view bytes() const { return size > 0 ? std::string_view(text, size) : std::string_view(text); }
};

extern const EmbeddedFile kEmbeddedSpectra[];
extern const std::size_t kEmbeddedSpectra_count;
extern const EmbeddedFile kEmbeddedScenes[];
extern const std::size_t kEmbeddedScenes_count;

/// The embedded file with this relative name, or nullptr.
const EmbeddedFile* find_embedded(std::string_view name);

}  // namespace spt
