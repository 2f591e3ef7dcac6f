// A discrete distribution over lights, proportional to given weights (their power): the
// choice of one light per next-event estimate, or of a light subpath's origin.
#pragma once
#include <algorithm>
#include <vector>

namespace spt {

class LightDistribution {
public:
    /// weights[i] ≥ 0 for light i; lights of weight 0 are never chosen.
    void build(const std::vector<float>& weights) {
        m_prob.assign(weights.size(), 0.f);
        m_cdf.clear();
        m_index.clear();
        double total = 0;
        for (float w : weights) total += w > 0.f ? w : 0.f;
        if (!(total > 0)) return;
        double running = 0;
        for (std::size_t i = 0; i < weights.size(); ++i) {
            if (!(weights[i] > 0.f)) continue;
            running += weights[i];
            m_prob[i] = static_cast<float>(weights[i] / total);
            m_cdf.push_back(static_cast<float>(running / total));
            m_index.push_back(static_cast<int>(i));
        }
        m_cdf.back() = 1.f;
    }

    bool empty() const { return m_index.empty(); }
    /// How many lights it can choose.
    std::size_t size() const { return m_index.size(); }
    /// The light for u in [0, 1), with its probability in `prob`.
    int sample(float u, float& prob) const {
        const auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), u);
        const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - m_cdf.begin()), m_index.size() - 1);
        prob = m_prob[static_cast<std::size_t>(m_index[k])];
        return m_index[k];
    }
    /// Probability of choosing light i (0 for lights outside the distribution).
    float probability(int i) const {
        return i >= 0 && static_cast<std::size_t>(i) < m_prob.size() ? m_prob[static_cast<std::size_t>(i)] : 0.f;
    }

private:
    std::vector<float> m_prob;  ///< per light index
    std::vector<float> m_cdf;   ///< over the lights of non-zero weight, in index order
    std::vector<int> m_index;   ///< their light indices
};

}  // namespace spt
