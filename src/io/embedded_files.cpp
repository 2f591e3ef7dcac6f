// Look-up of the files compiled into the program.
#include "io/embedded_files.h"

namespace spt {

const EmbeddedFile* find_embedded(std::string_view name) {
    for (std::size_t i = 0; i < kEmbeddedSpectra_count; ++i)
        if (name == kEmbeddedSpectra[i].name) return &kEmbeddedSpectra[i];
    for (std::size_t i = 0; i < kEmbeddedScenes_count; ++i)
        if (name == kEmbeddedScenes[i].name) return &kEmbeddedScenes[i];
    return nullptr;
}

}  // namespace spt
