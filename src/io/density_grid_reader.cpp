// The density grid text format (documented in the header): a tokenizer that keeps line and
// column for messages, then the header, the sizes and the values, each checked.
#include "io/density_grid_reader.h"

#include <charconv>
#include <cmath>

#include "io/located_error.h"

namespace spt {

namespace {

/// Splits the text into whitespace-separated tokens, skipping comments, keeping positions.
class Tokens {
public:
    Tokens(std::string_view text, const std::string& origin) : m_text(text), m_origin(origin) {}

    /// The next token, or an empty view at the end of the text.
    std::string_view next() {
        skip_blanks();
        m_start = m_pos_here;
        const std::size_t begin = m_i;
        while (m_i < m_text.size() && !is_blank(m_text[m_i]) && m_text[m_i] != '#') advance();
        return m_text.substr(begin, m_i - begin);
    }
    [[noreturn]] void fail(const std::string& message) const { throw LocatedError(m_origin, m_start, message); }

private:
    static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
    void advance() {
        if (m_text[m_i] == '\n') ++m_pos_here.line, m_pos_here.column = 1;
        else ++m_pos_here.column;
        ++m_i;
    }
    void skip_blanks() {
        while (m_i < m_text.size()) {
            if (m_text[m_i] == '#') {
                while (m_i < m_text.size() && m_text[m_i] != '\n') advance();
            } else if (is_blank(m_text[m_i])) {
                advance();
            } else {
                break;
            }
        }
    }
    std::string_view m_text;
    const std::string& m_origin;
    std::size_t m_i = 0;
    TextPos m_pos_here, m_start;
};

int grid_size(Tokens& tokens, const char* axis) {
    const std::string_view t = tokens.next();
    int n = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size() || n < 1 || n > 512)
        tokens.fail(std::string("grid size ") + axis + " is '" + std::string(t) +
                    "'; expected an integer in [1, 512]");
    return n;
}

}  // namespace

DensityGrid parse_density_grid(std::string_view text, const std::string& origin) {
    Tokens tokens(text, origin);
    if (tokens.next() != "spt-density-grid" || tokens.next() != "1")
        tokens.fail("not a density grid; expected the header 'spt-density-grid 1'");
    DensityGrid g;
    g.nx = grid_size(tokens, "NX");
    g.ny = grid_size(tokens, "NY");
    g.nz = grid_size(tokens, "NZ");
    const std::size_t count = static_cast<std::size_t>(g.nx) * g.ny * g.nz;
    g.values.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::string_view t = tokens.next();
        if (t.empty())
            tokens.fail("the grid ends after " + std::to_string(i) + " values; expected " + std::to_string(count) +
                        " (NX·NY·NZ)");
        float v = 0.f;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v) || v < 0.f)
            tokens.fail("density value '" + std::string(t) + "' is not a finite number >= 0");
        g.values.push_back(v);
    }
    if (!tokens.next().empty())
        tokens.fail("more than the " + std::to_string(count) + " values NX·NY·NZ announces; expected the end of the file");
    return g;
}

}  // namespace spt
