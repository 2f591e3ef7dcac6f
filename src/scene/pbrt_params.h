// A pbrt-v4 directive's parameter list ("float radius" 2 "rgb reflectance" [.8 .2 .1] ...),
// read from the tokens, with typed access that marks what was used: whatever the reader did not
// use is reported back as a located warning, so nothing in a file is dropped silently.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/dvec3.h"
#include "scene/pbrt_tokenizer.h"
#include "scene/scene_description.h"

namespace spt {

struct PbrtParam {
    std::string type;  ///< as declared: "float", "rgb", "spectrum", ... ("point" is "point3")
    std::string name;
    SourcePos pos;     ///< of the "type name" string
    std::vector<double> numbers;
    std::vector<std::string> strings;
    std::vector<bool> bools;
    mutable bool used = false;  ///< read by the reader (reported as unsupported if not)

    std::size_t size() const { return numbers.size() + strings.size() + bools.size(); }
};

class PbrtParams {
public:
    PbrtParams() = default;
    /// Reads "type name" value pairs until the next token that is not a string; `file` is the
    /// text's index in the description's file table.
    static PbrtParams read(PbrtTokenizer& tokens, std::uint32_t file);

    /// The parameter `name` (marked used), or nullptr.
    const PbrtParam* find(const std::string& name) const;
    /// Each accessor checks the declared type and the number of values, and throws LocatedError
    /// (named by `origin`) when they do not fit.
    double get_float(const std::string& name, double fallback) const;
    int get_int(const std::string& name, int fallback) const;
    bool get_bool(const std::string& name, bool fallback) const;
    std::string get_string(const std::string& name, const std::string& fallback) const;
    std::optional<DVec3> get_point3(const std::string& name) const;
    /// Every value of a number parameter of one of `types`, a multiple of `multiple_of` many
    /// (empty when absent).
    std::vector<double> get_numbers(const std::string& name, std::initializer_list<const char*> types,
                                    std::size_t multiple_of) const;
    /// Whether `name` is present (without marking it used).
    bool has(const std::string& name) const;

    /// The parameters nothing asked for, for the reader's warnings.
    std::vector<const PbrtParam*> unused() const;
    const std::vector<PbrtParam>& all() const { return m_params; }

    /// The text the positions refer to, for messages.
    std::string origin;

private:
    std::vector<PbrtParam> m_params;
    const PbrtParam& one(const PbrtParam& p, std::initializer_list<const char*> types, std::size_t count) const;
};

}  // namespace spt
