// Typed, checked access to the parameters of a scene description (scene/scene_description.h)
// for the create functions: every failed expectation (wrong type, unknown key, out-of-range
// number...) becomes one LocatedError "file:line:column: what is wrong; expected what", with a
// "Did you mean" for near misses, at the position the reader recorded for the value.
#pragma once
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>
#include <string_view>
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
/// A user string quoted and shortened for messages (control characters shown as '?').
std::string quote_text(std::string_view s);
/// Shortest readable form of a number for messages.
std::string number_text(double v);

class ParamChecker {
public:
    explicit ParamChecker(const std::string& origin) : m_origin(origin) {}

    /// Throws the located error "origin:line:column: message".
    [[noreturn]] void fail(TextPos pos, const std::string& message) const {
        throw LocatedError(m_origin, pos, message);
    }
    [[noreturn]] void wrong_type(const ParamValue& v, const std::string& what, const std::string& expected) const {
        fail(v.pos(), what + " is " + ParamValue::kind_name(v.kind()) + "; expected " + expected);
    }

    const ParamValue& object(const ParamValue& v, const std::string& what) const {
        if (!v.is_object()) wrong_type(v, what, "an object");
        return v;
    }

    /// Unknown keys are errors (with the closest allowed key as a suggestion).
    void check_keys(const ParamValue& obj, const std::string& what, std::initializer_list<const char*> allowed) const {
        std::vector<std::string> names(allowed.begin(), allowed.end());
        for (std::size_t i = 0; i < obj.members().size(); ++i) {
            const std::string& key = obj.members()[i].first;
            if (std::find(names.begin(), names.end(), key) != names.end()) continue;
            fail(obj.key_pos(i), "unknown key " + quote_text(key) + " in " + what + "." + suggestion(key, names) +
                                  " Expected one of: " + join(names));
        }
    }

    /// The member `key` of `obj`, which must be present.
    const ParamValue& required(const ParamValue& obj, const char* key, const std::string& what) const {
        const ParamValue* v = obj.find(key);
        if (!v) fail(obj.pos(), what + " has no \"" + key + "\"; expected one");
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

protected:
    const std::string& m_origin;  ///< file name in messages
};

}  // namespace spt
