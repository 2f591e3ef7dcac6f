#include "scene/pbrt_tokenizer.h"

namespace spt {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
bool ends_word(char c) { return is_space(c) || c == '"' || c == '[' || c == ']' || c == '#'; }

}  // namespace

void PbrtTokenizer::skip_space_and_comments() {
    while (m_i < m_text.size()) {
        const char c = m_text[m_i];
        if (c == '\n') {
            ++m_i, ++m_line, m_line_start = m_i;
        } else if (is_space(c)) {
            ++m_i;
        } else if (c == '#') {
            while (m_i < m_text.size() && m_text[m_i] != '\n') ++m_i;
        } else {
            return;
        }
    }
}

TextPos PbrtTokenizer::here() {
    if (m_peeked) return m_peeked->pos;
    skip_space_and_comments();
    return position();
}

std::optional<PbrtToken> PbrtTokenizer::peek() {
    if (!m_peeked) m_peeked = next();
    return m_peeked;
}

std::optional<PbrtToken> PbrtTokenizer::next() {
    if (m_peeked) {
        std::optional<PbrtToken> t = m_peeked;
        m_peeked.reset();
        return t;
    }
    skip_space_and_comments();
    if (m_i >= m_text.size()) return std::nullopt;
    PbrtToken t;
    t.pos = position();
    const char c = m_text[m_i];
    if (c == '[' || c == ']') {
        t.kind = c == '[' ? PbrtToken::Kind::OpenBracket : PbrtToken::Kind::CloseBracket;
        t.text = m_text.substr(m_i++, 1);
        return t;
    }
    if (c == '"') {
        const std::size_t start = ++m_i;
        while (true) {
            if (m_i >= m_text.size())
                throw LocatedError(m_origin, t.pos, "string never closed; expected a closing '\"'");
            const char d = m_text[m_i];
            if (d == '\n')
                throw LocatedError(m_origin, t.pos, "string runs past the end of its line; expected a closing '\"' on the same line");
            if (d == '\\' && m_i + 1 < m_text.size() && m_text[m_i + 1] != '\n') {
                m_i += 2;
                continue;
            }
            if (d == '"') break;
            ++m_i;
        }
        t.kind = PbrtToken::Kind::String;
        t.text = m_text.substr(start, m_i - start);
        ++m_i;
        return t;
    }
    const std::size_t start = m_i;
    while (m_i < m_text.size() && !ends_word(m_text[m_i])) ++m_i;
    t.kind = PbrtToken::Kind::Word;
    t.text = m_text.substr(start, m_i - start);
    return t;
}

std::string pbrt_unescape(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '\\' || i + 1 == s.size()) {
            out += s[i];
            continue;
        }
        switch (const char e = s[++i]) {
            case 'n': out += '\n'; break;
            case 't': out += '\t'; break;
            case 'r': out += '\r'; break;
            case 'b': out += '\b'; break;
            case 'f': out += '\f'; break;
            default: out += e; break;  // \\, \" and \' stand for themselves
        }
    }
    return out;
}

}  // namespace spt
