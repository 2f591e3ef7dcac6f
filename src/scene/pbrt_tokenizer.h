// The lexical layer of pbrt-v4 scene files: words (directive names, numbers, true/false),
// double-quoted strings, and the brackets of value lists, each with its line:column. `#` starts
// a comment to the end of the line. What the tokens mean is the reader's business
// (scene/pbrt_scene_reader.h).
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "io/located_error.h"

namespace spt {

struct PbrtToken {
    enum class Kind { Word, String, OpenBracket, CloseBracket };
    Kind kind = Kind::Word;
    std::string_view text;  ///< a word as written; a string without its quotes (escapes kept)
    TextPos pos;
};

class PbrtTokenizer {
public:
    /// `origin` names the text in messages.
    PbrtTokenizer(std::string_view text, std::string origin) : m_text(text), m_origin(std::move(origin)) {}

    /// The next token, or nullopt at the end of the text. Throws LocatedError for a string
    /// that is never closed or holds a line break.
    std::optional<PbrtToken> next();
    /// The next token without consuming it.
    std::optional<PbrtToken> peek();
    /// Where the next token starts (the end of the text when there is none).
    TextPos here();
    const std::string& origin() const { return m_origin; }

private:
    std::string_view m_text;
    std::string m_origin;
    std::size_t m_i = 0;
    int m_line = 1;
    std::size_t m_line_start = 0;
    std::optional<PbrtToken> m_peeked;

    void skip_space_and_comments();
    TextPos position() const { return {m_line, static_cast<int>(m_i - m_line_start) + 1}; }
};

/// A string token's text with pbrt's escapes (\n \t \\ \" ...) resolved.
std::string pbrt_unescape(std::string_view quoted_contents);

}  // namespace spt
