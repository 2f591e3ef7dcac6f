// Binding material parameters to textures. A parameter is texturable when it has a line in
// texturable_parameters() below: the BSDF type, its name in scene files, and a pointer to the
// member (a Spectrum or a float). The loader binds {"texture": NAME} values through that
// table, and Scene::textured_bsdf sets the member to the texture's value at each hit. So a
// new BSDF type's parameter (a roughness, a film thickness) becomes texturable with one line:
//   {bsdf_index<RoughConductorBsdf>(), "roughness", nullptr, &float_member<RoughConductorBsdf, &RoughConductorBsdf::roughness>},
// plus the loader reading that key through TextureParser::bind (see scene/texture_parser.h).
#pragma once
#include <cstddef>
#include <string_view>
#include <variant>
#include <vector>

#include "model/bsdfs/bsdf.h"

namespace spt {

/// The position of BSDF type B in the closed set `Bsdf`.
template <typename B, std::size_t I = 0>
constexpr std::size_t bsdf_index() {
    if constexpr (std::is_same_v<std::variant_alternative_t<I, Bsdf>, B>) return I;
    else return bsdf_index<B, I + 1>();
}

template <typename B, Spectrum B::*Member>
Spectrum* spectrum_member(Bsdf& bsdf) {
    return &(std::get<B>(bsdf).*Member);
}
template <typename B, float B::*Member>
float* float_member(Bsdf& bsdf) {
    return &(std::get<B>(bsdf).*Member);
}
/// A float inside a member struct (the GGX α of `ggx`, the thickness of `film`).
template <typename B, typename Part, Part B::*Outer, float Part::*Inner>
float* nested_float_member(Bsdf& bsdf) {
    return &((std::get<B>(bsdf).*Outer).*Inner);
}

/// A parameter that a texture may drive: exactly one of `spectrum` and `number` is set.
struct TexturableParameter {
    std::size_t bsdf;        ///< bsdf_index of the type that has it
    std::string_view name;   ///< its key in scene files
    Spectrum* (*spectrum)(Bsdf&);
    float* (*number)(Bsdf&);
};

inline const std::vector<TexturableParameter>& texturable_parameters() {
    static const std::vector<TexturableParameter> list = {
        {bsdf_index<DiffuseBsdf>(), "kd", &spectrum_member<DiffuseBsdf, &DiffuseBsdf::kd>, nullptr},
        {bsdf_index<LobeMixBsdf>(), "kd", &spectrum_member<LobeMixBsdf, &LobeMixBsdf::kd>, nullptr},
        {bsdf_index<LobeMixBsdf>(), "ks", &spectrum_member<LobeMixBsdf, &LobeMixBsdf::ks>, nullptr},
        {bsdf_index<LobeMixBsdf>(), "kt", &spectrum_member<LobeMixBsdf, &LobeMixBsdf::kt>, nullptr},
        {bsdf_index<ConductorBsdf>(), "roughness", nullptr,
         &nested_float_member<ConductorBsdf, GgxDistribution, &ConductorBsdf::ggx, &GgxDistribution::alpha>},
        {bsdf_index<DielectricBsdf>(), "roughness", nullptr,
         &nested_float_member<DielectricBsdf, GgxDistribution, &DielectricBsdf::ggx, &GgxDistribution::alpha>},
        {bsdf_index<PlasticBsdf>(), "kd", &spectrum_member<PlasticBsdf, &PlasticBsdf::kd>, nullptr},
        {bsdf_index<PlasticBsdf>(), "roughness", nullptr,
         &nested_float_member<PlasticBsdf, GgxDistribution, &PlasticBsdf::ggx, &GgxDistribution::alpha>},
        {bsdf_index<ConductorBsdf>(), "film thickness_nm", nullptr,
         &nested_float_member<ConductorBsdf, ThinFilm, &ConductorBsdf::film, &ThinFilm::thickness_nm>},
        {bsdf_index<DielectricBsdf>(), "film thickness_nm", nullptr,
         &nested_float_member<DielectricBsdf, ThinFilm, &DielectricBsdf::film, &ThinFilm::thickness_nm>},
        {bsdf_index<ThinSheetBsdf>(), "thickness_nm", nullptr,
         &nested_float_member<ThinSheetBsdf, ThinFilm, &ThinSheetBsdf::film, &ThinFilm::thickness_nm>},
    };
    return list;
}

/// The texturable parameter `name` of the BSDF type at `bsdf_type`, or nullptr.
inline const TexturableParameter* find_texturable(std::size_t bsdf_type, std::string_view name) {
    for (const TexturableParameter& p : texturable_parameters())
        if (p.bsdf == bsdf_type && p.name == name) return &p;
    return nullptr;
}

/// One bound parameter of a material: set from `texture` (an index into Scene::textures).
struct TextureBinding {
    const TexturableParameter* parameter;
    int texture;
};

}  // namespace spt
