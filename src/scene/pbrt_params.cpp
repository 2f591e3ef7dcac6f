#include "scene/pbrt_params.h"

#include <charconv>
#include <cmath>
#include <sstream>

namespace spt {

namespace {

const char* const kTypes[] = {"integer", "float",   "point2", "vector2", "point3", "vector3", "normal3", "normal",
                              "point",   "vector",  "bool",   "string",  "texture", "spectrum", "rgb", "blackbody"};

bool known_type(const std::string& t) {
    for (const char* k : kTypes)
        if (t == k) return true;
    return false;
}

/// pbrt-v4's synonyms, so the accessors see one name per kind.
std::string canonical_type(const std::string& t) {
    if (t == "point") return "point3";
    if (t == "vector") return "vector3";
    if (t == "normal") return "normal3";
    return t;
}

std::vector<std::string> split_words(const std::string& s) {
    std::istringstream in(s);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

bool is_number_type(const std::string& t) {
    return t != "bool" && t != "string" && t != "texture" && t != "spectrum";
}

}  // namespace

PbrtParams PbrtParams::read(PbrtTokenizer& tokens, std::uint32_t file) {
    PbrtParams params;
    params.origin = tokens.origin();
    const auto fail = [&](TextPos at, const std::string& m) { throw LocatedError(tokens.origin(), at, m); };
    while (true) {
        const std::optional<PbrtToken> decl = tokens.peek();
        if (!decl || decl->kind != PbrtToken::Kind::String) return params;
        tokens.next();
        PbrtParam p;
        p.pos = SourcePos::in_file(decl->pos, file);
        const std::vector<std::string> words = split_words(std::string(decl->text));
        if (words.size() != 2)
            fail(decl->pos, "parameter declaration \"" + std::string(decl->text) +
                                "\" is not a type and a name; expected \"TYPE NAME\" such as \"float radius\"");
        if (!known_type(words[0]))
            fail(decl->pos, "unknown parameter type \"" + words[0] + "\"; expected one of integer, float, point2, vector2, "
                            "point3, vector3, normal3, bool, string, texture, spectrum, rgb, blackbody");
        p.type = canonical_type(words[0]);
        p.name = words[1];
        for (const PbrtParam& q : params.m_params)
            if (q.name == p.name) fail(decl->pos, "parameter \"" + p.name + "\" given twice; expected each parameter once");

        const auto value = [&](const PbrtToken& t) {
            if (t.kind == PbrtToken::Kind::String) {
                if (p.type == "bool") {
                    if (t.text != "true" && t.text != "false")
                        fail(t.pos, "bool value \"" + std::string(t.text) + "\"; expected true or false");
                    p.bools.push_back(t.text == "true");
                    return;
                }
                if (is_number_type(p.type))
                    fail(t.pos, "a string for the " + p.type + " parameter \"" + p.name + "\"; expected numbers");
                p.strings.push_back(pbrt_unescape(t.text));
                return;
            }
            if (t.kind != PbrtToken::Kind::Word)
                fail(t.pos, "unexpected '" + std::string(t.text) + "'; expected a value of \"" + p.name + "\"");
            if (p.type == "bool") {
                if (t.text != "true" && t.text != "false")
                    fail(t.pos, "bool value '" + std::string(t.text) + "'; expected true or false");
                p.bools.push_back(t.text == "true");
                return;
            }
            if (p.type == "string" || p.type == "texture")
                fail(t.pos, "'" + std::string(t.text) + "' for the " + p.type + " parameter \"" + p.name +
                                "\"; expected a string in double quotes");
            double x = 0;
            const char* first = t.text.data();
            const char* last = first + t.text.size();
            if (first != last && *first == '+') ++first;
            const auto [ptr, ec] = std::from_chars(first, last, x);
            if (ec != std::errc() || ptr != last || !std::isfinite(x))
                fail(t.pos, "'" + std::string(t.text) + "' is not a finite number; expected a value of \"" + p.name + "\"");
            if (p.type == "integer" && x != std::floor(x))
                fail(t.pos, "'" + std::string(t.text) + "' for the integer parameter \"" + p.name + "\"; expected an integer");
            p.numbers.push_back(x);
        };

        const std::optional<PbrtToken> first = tokens.next();
        if (!first) fail(tokens.here(), "end of file after \"" + std::string(decl->text) + "\"; expected its value");
        if (first->kind == PbrtToken::Kind::OpenBracket) {
            while (true) {
                const std::optional<PbrtToken> t = tokens.next();
                if (!t) fail(first->pos, "'[' never closed; expected ']' after the values of \"" + p.name + "\"");
                if (t->kind == PbrtToken::Kind::CloseBracket) break;
                value(*t);
            }
        } else {
            value(*first);
        }
        if (p.size() == 0) fail(decl->pos, "parameter \"" + p.name + "\" has no values; expected at least one");
        params.m_params.push_back(std::move(p));
    }
}

const PbrtParam* PbrtParams::find(const std::string& name) const {
    for (const PbrtParam& p : m_params)
        if (p.name == name) {
            const_cast<PbrtParam&>(p).used = true;
            return &p;
        }
    return nullptr;
}

bool PbrtParams::has(const std::string& name) const {
    for (const PbrtParam& p : m_params)
        if (p.name == name) return true;
    return false;
}

const PbrtParam& PbrtParams::one(const PbrtParam& p, std::initializer_list<const char*> types, std::size_t count) const {
    bool ok = false;
    std::string names;
    for (const char* t : types) {
        ok |= p.type == t;
        names += (names.empty() ? "" : " or ") + std::string(t);
    }
    if (!ok)
        throw LocatedError(origin, p.pos.text_pos(),
                           "parameter \"" + p.name + "\" is declared " + p.type + "; expected " + names);
    if (count && p.size() != count)
        throw LocatedError(origin, p.pos.text_pos(),
                           "parameter \"" + p.name + "\" has " + std::to_string(p.size()) + " values; expected " +
                               std::to_string(count));
    return p;
}

double PbrtParams::get_float(const std::string& name, double fallback) const {
    const PbrtParam* p = find(name);
    return p ? one(*p, {"float", "integer"}, 1).numbers[0] : fallback;
}

int PbrtParams::get_int(const std::string& name, int fallback) const {
    const PbrtParam* p = find(name);
    if (!p) return fallback;
    const double x = one(*p, {"integer"}, 1).numbers[0];
    if (std::fabs(x) > 2e9) throw LocatedError(origin, p->pos.text_pos(), "integer \"" + name + "\" is out of range; expected at most 2e9");
    return static_cast<int>(x);
}

bool PbrtParams::get_bool(const std::string& name, bool fallback) const {
    const PbrtParam* p = find(name);
    return p ? one(*p, {"bool"}, 1).bools[0] : fallback;
}

std::string PbrtParams::get_string(const std::string& name, const std::string& fallback) const {
    const PbrtParam* p = find(name);
    return p ? one(*p, {"string"}, 1).strings[0] : fallback;
}

std::optional<DVec3> PbrtParams::get_point3(const std::string& name) const {
    const PbrtParam* p = find(name);
    if (!p) return std::nullopt;
    const PbrtParam& q = one(*p, {"point3", "vector3", "normal3"}, 3);
    return DVec3{q.numbers[0], q.numbers[1], q.numbers[2]};
}

std::vector<double> PbrtParams::get_numbers(const std::string& name, std::initializer_list<const char*> types,
                                            std::size_t multiple_of) const {
    const PbrtParam* p = find(name);
    if (!p) return {};
    const PbrtParam& q = one(*p, types, 0);
    if (q.numbers.size() % multiple_of != 0)
        throw LocatedError(origin, p->pos.text_pos(),
                           "parameter \"" + name + "\" has " + std::to_string(q.numbers.size()) +
                               " values; expected a multiple of " + std::to_string(multiple_of));
    return q.numbers;
}

std::vector<const PbrtParam*> PbrtParams::unused() const {
    std::vector<const PbrtParam*> out;
    for (const PbrtParam& p : m_params)
        if (!p.used) out.push_back(&p);
    return out;
}

}  // namespace spt
