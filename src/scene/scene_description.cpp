// The parameter bag's builders, look-up and read tracking.
#include "scene/scene_description.h"

#include <algorithm>

namespace spt {

ParamValue ParamValue::null(SourcePos pos) {
    ParamValue v;
    v.m_pos = pos;
    return v;
}

ParamValue ParamValue::boolean(bool b, SourcePos pos) {
    ParamValue v;
    v.m_kind = Kind::Bool, v.m_bool = b, v.m_pos = pos;
    return v;
}

ParamValue ParamValue::number(double x, SourcePos pos) {
    ParamValue v;
    v.m_kind = Kind::Number, v.m_number = x, v.m_pos = pos;
    return v;
}

ParamValue ParamValue::string(std::string s, SourcePos pos) {
    ParamValue v;
    v.m_kind = Kind::String, v.m_string = std::move(s), v.m_pos = pos;
    return v;
}

ParamValue ParamValue::list(std::vector<ParamValue> items, SourcePos pos) {
    ParamValue v;
    v.m_kind = Kind::List, v.m_items = std::move(items), v.m_pos = pos;
    return v;
}

ParamValue ParamValue::numbers(std::initializer_list<double> xs, SourcePos pos) {
    ParamValue v = list({}, pos);
    for (double x : xs) v.m_items.push_back(number(x, pos));
    return v;
}

ParamValue ParamValue::vec3(const Vec3& p, SourcePos pos) { return numbers({p.x, p.y, p.z}, pos); }

ParamValue ParamValue::dict(SourcePos pos) {
    ParamValue v;
    v.m_kind = Kind::Dict, v.m_pos = pos;
    return v;
}

ParamValue ParamValue::dict(std::initializer_list<std::pair<std::string, ParamValue>> members, SourcePos pos) {
    ParamValue v = dict(pos);
    for (const auto& [k, x] : members) v.set(k, x, x.pos());
    return v;
}

ParamValue& ParamValue::set(std::string key, ParamValue value, std::optional<SourcePos> key_position) {
    const SourcePos key_pos = key_position.value_or(value.pos());
    for (std::size_t i = 0; i < m_members.size(); ++i)
        if (m_members[i].first == key) {
            m_members[i].second = std::move(value);
            m_key_positions[i] = key_pos;
            m_read[i] = false;
            return *this;
        }
    m_members.emplace_back(std::move(key), std::move(value));
    m_key_positions.push_back(key_pos);
    m_read.push_back(false);
    return *this;
}

ParamValue& ParamValue::add(std::string key, ParamValue value, SourcePos key_pos) {
    m_members.emplace_back(std::move(key), std::move(value));
    m_key_positions.push_back(key_pos);
    m_read.push_back(false);
    return *this;
}

ParamValue& ParamValue::push(ParamValue value) {
    m_items.push_back(std::move(value));
    return *this;
}

const ParamValue* ParamValue::find(std::string_view key) const {
    if (std::find(m_asked.begin(), m_asked.end(), key) == m_asked.end()) m_asked.emplace_back(key);
    for (std::size_t i = 0; i < m_members.size(); ++i)
        if (m_members[i].first == key) {
            m_read[i] = true;
            return &m_members[i].second;
        }
    return nullptr;
}

const ParamValue* ParamValue::peek(std::string_view key) const {
    for (const auto& [k, v] : m_members)
        if (k == key) return &v;
    return nullptr;
}

std::vector<std::string> ParamValue::unread_keys() const {
    std::vector<std::string> out;
    for (std::size_t i = 0; i < m_members.size(); ++i)
        if (!m_read[i]) out.push_back(m_members[i].first);
    return out;
}

std::uint32_t SceneDescription::add_file(const std::string& file_name) {
    for (std::size_t i = 0; i < files.size(); ++i)
        if (files[i] == file_name) return static_cast<std::uint32_t>(i);
    files.push_back(file_name);
    return static_cast<std::uint32_t>(files.size() - 1);
}

const char* ParamValue::kind_name(Kind k) {
    switch (k) {
        case Kind::Null: return "null";
        case Kind::Bool: return "a boolean";
        case Kind::Number: return "a number";
        case Kind::String: return "a string";
        case Kind::List: return "an array";
        case Kind::Dict: return "an object";
    }
    return "?";
}

}  // namespace spt
