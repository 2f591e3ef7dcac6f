// A position in a text and the error that names it: every reader's and checker's message is
// "file:line:column: what is wrong; expected what".
#pragma once
#include <stdexcept>
#include <string>

namespace spt {

/// Position in a text: 1-based line and column (columns count bytes).
struct TextPos {
    int line = 1, column = 1;
};

/// An error located in a named text; what() is "origin:line:column: message".
class LocatedError : public std::runtime_error {
public:
    LocatedError(const std::string& origin, TextPos pos, const std::string& message)
        : std::runtime_error(origin + ":" + std::to_string(pos.line) + ":" +
                             std::to_string(pos.column) + ": " + message),
          m_origin(origin), m_pos(pos), m_message(message) {}
    const std::string& origin() const { return m_origin; }
    TextPos pos() const { return m_pos; }
    const std::string& message() const { return m_message; }

private:
    std::string m_origin;
    TextPos m_pos;
    std::string m_message;
};

}  // namespace spt
