#include "spectral/metal_catalog.h"

#include <cctype>

#include "spectral/catalog_lookup.h"

namespace spt {

std::vector<std::string> metal_names() { return {"Au", "Ag", "Cu", "Al"}; }

std::optional<MetalInfo> find_metal(std::string_view symbol) {
    for (const std::string& name : metal_names()) {
        if (!same_ignoring_case(name, symbol)) continue;
        std::string file = "metal_" + name + ".csv";
        for (char& c : file) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        const SpectralTable& t = embedded_spectral_table(file);
        return MetalInfo{name, column_spectrum(t, "eta"), column_spectrum(t, "k"),
                         t.comments.empty() ? std::string() : t.comments.front()};
    }
    return std::nullopt;
}

}  // namespace spt
