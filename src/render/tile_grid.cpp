// --tile's syntax, parsed and printed.
#include "render/tile_grid.h"

#include <charconv>

namespace spt {

namespace {

constexpr int kMaxTileSide = 65536;

std::optional<int> parse_side(std::string_view text) {
    int value = 0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || value < 1 || value > kMaxTileSide)
        return std::nullopt;
    return value;
}

/// "rows" or "rows:N" (likewise "columns"): the strip's thickness.
std::optional<int> parse_strip(std::string_view text, std::string_view name) {
    if (!text.starts_with(name)) return std::nullopt;
    text.remove_prefix(name.size());
    if (text.empty()) return 1;
    if (text.front() != ':') return std::nullopt;
    return parse_side(text.substr(1));
}

}  // namespace

std::optional<TileShape> parse_tile_shape(std::string_view text) {
    if (text == "pixel") return TileShape{1, 1};
    if (const std::optional<int> n = parse_strip(text, "rows")) return TileShape{0, *n};
    if (const std::optional<int> n = parse_strip(text, "columns")) return TileShape{*n, 0};
    if (const std::size_t x = text.find('x'); x != std::string_view::npos) {
        const std::optional<int> w = parse_side(text.substr(0, x)), h = parse_side(text.substr(x + 1));
        if (!w || !h) return std::nullopt;
        return TileShape{*w, *h};
    }
    if (const std::optional<int> n = parse_side(text)) return TileShape{*n, *n};
    return std::nullopt;
}

std::string tile_shape_name(TileShape shape) {
    if (shape.width == 0) return "rows:" + std::to_string(shape.height);
    if (shape.height == 0) return "columns:" + std::to_string(shape.width);
    return std::to_string(shape.width) + "x" + std::to_string(shape.height);
}

}  // namespace spt
