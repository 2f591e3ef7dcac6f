// How a pass's pixels are cut into tiles, the unit of work a worker takes from the queue.
#pragma once
#include <algorithm>
#include <optional>
#include <string>
#include <string_view>

namespace spt {

/// Tile size in pixels; 0 stands for the image's whole width (rows) or height (columns).
struct TileShape {
    int width = 32, height = 32;
    bool operator==(const TileShape&) const = default;
};

/// The pixels [x0, x1) × [y0, y1) of one tile.
struct TileRect {
    int x0, y0, x1, y1;
};

/// The tiles of a width × height image, numbered row by row of tiles (the order the producer
/// queues them and splats are merged in).
class TileGrid {
public:
    TileGrid(int width, int height, TileShape shape)
        : m_width(width), m_height(height), m_tile_w(std::min(shape.width > 0 ? shape.width : width, width)),
          m_tile_h(std::min(shape.height > 0 ? shape.height : height, height)),
          m_columns((width + m_tile_w - 1) / m_tile_w), m_rows((height + m_tile_h - 1) / m_tile_h) {}

    int count() const { return m_columns * m_rows; }
    TileRect tile(int index) const {
        const int x0 = index % m_columns * m_tile_w, y0 = index / m_columns * m_tile_h;
        return {x0, y0, std::min(x0 + m_tile_w, m_width), std::min(y0 + m_tile_h, m_height)};
    }

private:
    int m_width, m_height, m_tile_w, m_tile_h, m_columns, m_rows;
};

/// --tile's syntax: N (N×N), WxH, rows[:N] (whole-width strips N rows tall, default 1),
/// columns[:N] (whole-height strips N columns wide) or pixel (1×1); sizes 1 to 65536.
/// nullopt for anything else.
std::optional<TileShape> parse_tile_shape(std::string_view text);

/// The shape written back in --tile's syntax (for the summary and the benchmark table).
std::string tile_shape_name(TileShape shape);

}  // namespace spt
