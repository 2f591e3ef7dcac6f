// Guided sampling at a path vertex: one-sample MIS of the learned field
// (render/guiding/guiding_field.h) and the BSDF (Müller et al. 2017, §5.1; Veach 1997, §9.2.4):
// with probability α (the choice of the vertex's spatial leaf, guiding_field.h) the direction
// is drawn from the field's distribution at the vertex, else from the BSDF, and the two are weighted by the balance heuristic over
//   p(ω) = α·p_guide(ω) + (1 − α)·p_bsdf(ω),
// p_bsdf being the BSDF's MIS density (bsdf.h's pdf()), which is also the density next-event
// estimation's weights see for this vertex. A guided sample carries f·|cos| / p(ω); a BSDF
// sample its own weight (f·|cos| over the density it was truly drawn with, which for a lobe
// mix is not pdf(): bsdf.h) times p_bsdf / p(ω), so the weights of the two strategies sum to
// 1 whatever the BSDF's lobe choice. A delta lobe (which the guide cannot produce) has
// probability (1 − α) times its own.
//
// The guide is used at vertices with a non-delta lobe where the field has energy for the
// vertex's channel (the hero's wavelength band in a spectral field); elsewhere the BSDF
// alone samples, with its usual density, so nothing changes there. At a vertex whose BSDF
// only reflects, the field is sampled in product with the clamped cosine around the shading
// normal on wo's side (render/guiding/directional_tree.h): a spatial cell holds surfaces of
// many orientations, and without the product half of its directions would point into this one.
#pragma once
#include <optional>

#include "core/sample_dimensions.h"
#include "model/bsdfs/bsdf.h"
#include "render/guiding/guide_bands.h"
#include "render/guiding/guiding_field.h"

namespace spt {

/// What the path kernel is given: the field to sample from (after its first iteration) and
/// whether this sample records into it (training iterations).
struct PathGuide {
    GuidingField* field = nullptr;
    bool sample = false;
    bool record = false;
};

/// The field's distribution at one vertex.
class VertexGuide {
public:
    VertexGuide() = default;
    /// The guide at hit point p for the hero wavelength; `reflect_side`: the normal of the
    /// cosine product (null for BSDFs that transmit). `sample` false: only the leaf, for
    /// records; `record`: the path records into the field.
    VertexGuide(const GuidingField& field, const Vec3& p, float hero_nm, bool sample, bool record,
                const Vec3* reflect_side)
        : m_leaf(field.leaf_of(p)), m_channel(field.channels() == 1 ? 0 : guide_band(hero_nm)),
          m_has_side(reflect_side != nullptr) {
        if (m_has_side) m_side = *reflect_side;
        // A leaf that chose α = 0 samples the BSDF alone: it needs the guide's densities only
        // while recording, to reconsider its α.
        if (sample && (record || field.guide_fraction(m_leaf) > 0.f) &&
            field.sampling_tree(m_leaf).usable(m_channel, side())) {
            m_tree = &field.sampling_tree(m_leaf);
            m_fraction = field.guide_fraction(m_leaf);
        }
    }
    int leaf() const { return m_leaf; }
    /// α: the probability of sampling the guide.
    float fraction() const { return m_fraction; }
    bool usable() const { return m_tree != nullptr; }
    /// A direction drawn from the field (usable) and its solid-angle density.
    Vec3 sample(float u1, float u2, float& pdf) const {
        const SquarePoint s = m_tree->sample(m_channel, u1, u2, pdf, side());
        pdf *= kInv4Pi;
        return square_to_direction(s);
    }
    /// The solid-angle density of drawing w.
    float pdf(const Vec3& w) const {
        return m_tree ? m_tree->pdf(m_channel, direction_to_square(w), side()) * kInv4Pi : 0.f;
    }
    /// The density of the mixture with BSDF density `pdf_bsdf` at w.
    float mixture_pdf(const Vec3& w, float pdf_bsdf) const {
        return m_tree ? m_fraction * pdf(w) + (1.f - m_fraction) * pdf_bsdf : pdf_bsdf;
    }

private:
    static constexpr float kInv4Pi = 0.0795774715459476679f;
    const Vec3* side() const { return m_has_side ? &m_side : nullptr; }

    const DirectionalTree* m_tree = nullptr;
    int m_leaf = 0, m_channel = 0;
    float m_fraction = 0.f;
    bool m_has_side = false;
    Vec3 m_side;
};

/// The two densities of a guided vertex's sampled direction (for the choice of α).
struct GuidedDensities {
    float guide = 0.f, bsdf = 0.f;
};

/// The direction the path continues in from a vertex with a non-delta lobe, the guide
/// usable: the mixture above, from the same three numbers as sample_bounce (the first picks
/// guide or BSDF, then serves as the BSDF's lobe number, rescaled); `densities` gets the
/// two densities of a non-delta sample's direction.
template <class Sampler>
[[gnu::always_inline]] inline std::optional<BsdfSample> sample_guided_bounce(const Bsdf& bsdf, const Hit& hit,
                                                                              const Vec3& wo,
                                                                              SampledWavelengths& lambda, int depth,
                                                                              const VertexGuide& guide,
                                                                              Sampler& rng,
                                                                              GuidedDensities& densities) {
    const float alpha = guide.fraction();
    seek_dimension(rng, dims::bounce(depth, dims::kBsdfLobe));
    const float u_choice = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    if (dot(wo, hit.ns) == 0.f) return std::nullopt;  // as bsdf_sample
    if (u_choice < alpha) {
        float pdf_guide = 0.f;
        const Vec3 wi = guide.sample(u1, u2, pdf_guide);
        const SampledSpectrum f = bsdf_eval(bsdf, wo, wi, hit.ns, lambda, TransportMode::radiance);
        const float pdf_bsdf = bsdf_pdf(bsdf, wo, wi, hit.ns, lambda.lambda[0]);
        const float pdf = alpha * pdf_guide + (1.f - alpha) * pdf_bsdf;
        if (f.is_zero() || !(pdf > 0.f)) return std::nullopt;
        densities = {pdf_guide, pdf_bsdf};
        const bool same_side = (dot(wo, hit.n) > 0.f) == (dot(wi, hit.n) > 0.f);
        // eta_scale stays 1: it only steers roulette, which stays unbiased with any survival.
        return BsdfSample{wi, f / pdf, pdf,
                          {static_cast<std::uint8_t>(BsdfFlags::non_delta |
                                                     (same_side ? BsdfFlags::reflection : BsdfFlags::transmission))},
                          1.f};
    }
    const float u_lobe = std::min((u_choice - alpha) / (1.f - alpha), 0x1.fffffep-1f);
    std::optional<BsdfSample> bs = bsdf_sample(bsdf, wo, hit.ns, lambda, u_lobe, u1, u2, TransportMode::radiance);
    if (!bs) return bs;
    if (bs->is_delta()) {
        bs->weight = bs->weight / (1.f - alpha);
        return bs;
    }
    densities = {guide.pdf(bs->wi), bs->pdf};
    const float pdf = alpha * densities.guide + (1.f - alpha) * densities.bsdf;
    if (!(pdf > 0.f)) return std::nullopt;
    bs->weight = bs->weight * (bs->pdf / pdf);
    bs->pdf = pdf;
    return bs;
}

}  // namespace spt
