// Data files compiled into the program (spectra/*.csv, scenes/*), see cmake/embed_files.cmake.
#pragma once
#include <cstddef>
#include <string_view>

namespace spt {

struct EmbeddedFile {
    const char* name;  ///< path relative to the source tree, e.g. "spectra/cie_1931_2deg.csv"
    const char* text;
};

extern const EmbeddedFile kEmbeddedSpectra[];
extern const std::size_t kEmbeddedSpectra_count;
extern const EmbeddedFile kEmbeddedScenes[];
extern const std::size_t kEmbeddedScenes_count;

/// The embedded file with this relative name, or nullptr.
const EmbeddedFile* find_embedded(std::string_view name);

}  // namespace spt
