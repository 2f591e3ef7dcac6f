// The parameter bag's builders, look-up and read tracking.
#include "scene/scene_description.h"

namespace spt {

ParamValue ParamValue::null(TextPos pos) {
    ParamValue v;
    v.m_pos = pos;
    return v;
}

ParamValue ParamValue::boolean(bool b, TextPos pos) {
    ParamValue v;
    v.m_kind = Kind::Bool, v.m_bool = b, v.m_pos = pos;
    return v;
}

ParamValue ParamValue::number(double x, TextPos pos) {
    ParamValue v;
    v.m_kind = Kind::Number, v.m_number = x, v.m_pos = pos;
    return v;
}

ParamValue ParamValue::string(std::string s, TextPos pos) {
    ParamValue v;
    v.m_kind = Kind::String, v.m_string = std::move(s), v.m_pos = pos;
    return v;
}

ParamValue ParamValue::list(std::vector<ParamValue> items, TextPos pos) {
    ParamValue v;
    v.m_kind = Kind::List, v.m_items = std::move(items), v.m_pos = pos;
    return v;
}

ParamValue ParamValue::numbers(std::initializer_list<double> xs, TextPos pos) {
    ParamValue v = list({}, pos);
    for (double x : xs) v.m_items.push_back(number(x, pos));
    return v;
}

ParamValue ParamValue::vec3(const Vec3& p, TextPos pos) { return numbers({p.x, p.y, p.z}, pos); }

ParamValue ParamValue::dict(TextPos pos) {
    ParamValue v;
    v.m_kind = Kind::Dict, v.m_pos = pos;
    return v;
}

ParamValue ParamValue::dict(std::initializer_list<std::pair<std::string, ParamValue>> members, TextPos pos) {
    ParamValue v = dict(pos);
    for (const auto& [k, x] : members) v.set(k, x, x.pos());
    return v;
}

ParamValue& ParamValue::set(std::string key, ParamValue value, TextPos key_pos) {
    for (std::size_t i = 0; i < m_members.size(); ++i)
        if (m_members[i].first == key) {
            m_members[i].second = std::move(value);
            m_key_positions[i] = key_pos;
            return *this;
        }
    m_members.emplace_back(std::move(key), std::move(value));
    m_key_positions.push_back(key_pos);
    m_read.push_back(false);
    return *this;
}

ParamValue& ParamValue::add(std::string key, ParamValue value, TextPos key_pos) {
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
    for (std::size_t i = 0; i < m_members.size(); ++i)
        if (m_members[i].first == key) {
            m_read[i] = true;
            return &m_members[i].second;
        }
    return nullptr;
}

std::vector<std::string> ParamValue::unread_keys() const {
    std::vector<std::string> out;
    for (std::size_t i = 0; i < m_members.size(); ++i)
        if (!m_read[i]) out.push_back(m_members[i].first);
    return out;
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
