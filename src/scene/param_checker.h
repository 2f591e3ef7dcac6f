// Typed, checked access to the parameters of a scene description (scene/scene_description.h)
// for the create functions: every failed expectation (wrong type, unknown key, out-of-range
// number...) becomes one LocatedError "file:line:column: what is wrong; expected what", with a
// "Did you mean" for near misses, at the position the reader recorded for the value.
//
// Unknown keys are found by reading, not by lists: each create function looks its keys up
// (ParamValue::find marks them read) and ends with all_read(), so a key is accepted exactly
// when the code that builds the entity reads it, and each key is named once, where it is read.
// A create function therefore looks up every key it accepts on every branch (and refuses, with
// its own message, those that do not apply to the branch taken), and looks up keys that are
// each other's near misses ("sigma_a", "sigma_s") before it requires one of them.
#pragma once
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/text.h"
#include "core/vec3.h"
#include "scene/scene_description.h"

namespace spt {

/// Largest coordinate or length accepted in a scene: far beyond any sensible scene, small
/// enough that products of coordinates stay finite in float.
inline constexpr double kMaxSceneCoordinate = 1e15;

/// "a, b, c".
std::string join(const std::vector<std::string>& words);
/// "\"a\", \"b\" or \"c\"".
std::string quoted_alternatives(const std::vector<std::string>& words);
/// A user string quoted and shortened for messages (control characters shown as '?').
std::string quote_text(std::string_view s);
/// Shortest readable form of a number for messages.
std::string number_text(double v);

class ParamChecker {
public:
    /// `files`: the description's file table, which SourcePos::file indexes.
    explicit ParamChecker(SourceFiles files) : m_files(std::move(files)) {}

    /// Throws the located error "file:line:column: message", naming the file `pos` came from.
    [[noreturn]] void fail(SourcePos pos, const std::string& message) const {
        throw LocatedError(pos.file < m_files.size() ? m_files[pos.file] : "(unnamed file)", pos.text_pos(), message);
    }
    [[noreturn]] void wrong_type(const ParamValue& v, const std::string& what, const std::string& expected) const {
        fail(v.pos(), what + " is " + ParamValue::kind_name(v.kind()) + "; expected " + expected);
    }

    const ParamValue& object(const ParamValue& v, const std::string& what) const {
        if (!v.is_object()) wrong_type(v, what, "an object");
        return v;
    }

    /// Called when the code that builds `obj` is done with it: a key it did not read is an
    /// error at that key, suggesting the closest key it reads and listing them all.
    void all_read(const ParamValue& obj, const std::string& what) const {
        for (std::size_t i = 0; i < obj.members().size(); ++i) {
            if (obj.was_read(i)) continue;
            const std::string& key = obj.members()[i].first;
            const std::vector<std::string>& known = obj.asked_keys();
            fail(obj.key_pos(i), "unknown key " + quote_text(key) + " in " + what + "." + suggestion(key, known) +
                                     (known.empty() ? " Expected no keys" : " Expected one of: " + join(known)));
        }
    }

    /// Called before failing because none of `wanted` is in `obj`: a key not read so far that
    /// is a near miss of one of them is the likelier mistake, reported as unknown at its
    /// position.
    void misspelt(const ParamValue& obj, const std::string& what, std::initializer_list<const char*> wanted) const {
        const std::vector<std::string> names(wanted.begin(), wanted.end());
        for (std::size_t i = 0; i < obj.members().size(); ++i) {
            if (obj.was_read(i)) continue;
            const std::string& key = obj.members()[i].first;
            const std::string hint = suggestion(key, names);
            if (hint.empty()) continue;
            fail(obj.key_pos(i), "unknown key " + quote_text(key) + " in " + what + "." + hint + " Expected " +
                                     quoted_alternatives(names) + ", which " + what + " needs");
        }
    }

    /// Looks up keys that are each other's near misses before any of them is required, so
    /// that a missing one is not taken for a misspelling of another (misspelt()).
    static void look_up(const ParamValue& obj, std::initializer_list<const char*> keys) {
        for (const char* key : keys) obj.find(key);
    }

    /// The member `key` of `obj`, which must be present.
    const ParamValue& required(const ParamValue& obj, const char* key, const std::string& what) const {
        const ParamValue* v = obj.find(key);
        if (!v) {
            misspelt(obj, what, {key});
            fail(obj.pos(), what + " has no \"" + key + "\"; expected one");
        }
        return *v;
    }

    double number(const ParamValue& v, const std::string& what) const {
        if (!v.is_number()) wrong_type(v, what, "a number");
        return v.as_number();
    }
    double number_in(const ParamValue& v, const std::string& what, double lo, double hi, bool lo_open = false) const {
        const double x = number(v, what);
        if (x < lo || x > hi || (lo_open && x == lo))
            fail(v.pos(), what + " is " + number_text(x) + "; expected a number in " + (lo_open ? "(" : "[") +
                              number_text(lo) + ", " + number_text(hi) + "]");
        return x;
    }
    int integer_in(const ParamValue& v, const std::string& what, int lo, int hi) const {
        const double x = number(v, what);
        if (x != std::floor(x) || x < lo || x > hi)
            fail(v.pos(), what + " is " + number_text(x) + "; expected an integer from " + std::to_string(lo) +
                              " to " + std::to_string(hi));
        return static_cast<int>(x);
    }
    const std::string& string(const ParamValue& v, const std::string& what) const {
        if (!v.is_string()) wrong_type(v, what, "a string");
        return v.as_string();
    }
    double optional_number(const ParamValue& obj, const char* key, double fallback, const std::string& what) const {
        const ParamValue* v = obj.find(key);
        return v ? number(*v, what + " " + key) : fallback;
    }

    /// Array of exactly n numbers.
    std::vector<double> numbers(const ParamValue& v, const std::string& what, std::size_t n) const {
        if (!v.is_array() || v.items().size() != n)
            fail(v.pos(), what + " is " + (v.is_array() ? "an array of " + std::to_string(v.items().size()) + " values" : ParamValue::kind_name(v.kind())) +
                              "; expected an array of " + std::to_string(n) + " numbers");
        std::vector<double> out;
        for (const ParamValue& x : v.items()) out.push_back(number(x, "an element of " + what));
        return out;
    }

    /// [x, y, z] with each |coordinate| ≤ kMaxSceneCoordinate.
    Vec3 point(const ParamValue& v, const std::string& what) const {
        const std::vector<double> c = numbers(v, what, 3);
        for (double x : c)
            if (std::fabs(x) > kMaxSceneCoordinate)
                fail(v.pos(), what + " has a coordinate of " + number_text(x) + "; expected magnitudes up to 1e15");
        return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
    }
    /// A point that is not the zero vector (not normalised).
    Vec3 direction(const ParamValue& v, const std::string& what) const {
        const Vec3 d = point(v, what);
        const double len = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
        if (!(len > 1e-30)) fail(v.pos(), what + " is the zero vector; expected a non-zero direction");
        return d;
    }

    const SourceFiles& files() const { return m_files; }

private:
    SourceFiles m_files;
};

}  // namespace spt
