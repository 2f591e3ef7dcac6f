// Chi-square of sampled directions against a density: cells of equal solid angle over a cone
// of directions about an axis (n_theta bands in cos θ, n_phi sectors in φ), plus one cell for
// everything outside the cone (and for samples that produced no direction). The expected count
// of a cell is the density integrated on a sub × sub midpoint grid of it; the outside cell
// gets what remains of 1.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "chi2.h"
#include "core/frame.h"

namespace spt_test {

class ConeHistogram {
public:
    /// cos_max = −1: the whole sphere of directions.
    ConeHistogram(const spt::Vec3& axis, double cos_max, int n_theta, int n_phi)
        : m_frame(axis), m_cos_max(cos_max), m_theta(n_theta), m_phi(n_phi),
          m_observed(static_cast<std::size_t>(n_theta * n_phi + 1), 0.0) {}

    /// The unit direction at (cos θ, φ) about the axis.
    spt::Vec3 direction(double cos_theta, double phi) const {
        const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
        return spt::normalize(
            m_frame.to_world({float(s * std::cos(phi)), float(s * std::sin(phi)), float(cos_theta)}));
    }

    /// Expected counts of n samples of the solid-angle density pdf(direction).
    template <typename Pdf>
    std::vector<double> expected(Pdf pdf, int n, int sub) const {
        std::vector<double> e(m_observed.size(), 0.0);
        const double dc = (1.0 - m_cos_max) / m_theta, dphi = 2 * std::numbers::pi / m_phi;
        double inside = 0;
        for (int i = 0; i < m_theta; ++i)
            for (int j = 0; j < m_phi; ++j) {
                double sum = 0;
                for (int a = 0; a < sub; ++a)
                    for (int b = 0; b < sub; ++b)
                        sum += pdf(direction(m_cos_max + dc * (i + (a + 0.5) / sub), dphi * (j + (b + 0.5) / sub)));
                const double p = sum / (sub * sub) * dc * dphi;
                e[static_cast<std::size_t>(i * m_phi + j)] = p * n;
                inside += p;
            }
        e.back() = std::max(0.0, 1.0 - inside) * n;
        return e;
    }

    void add(const spt::Vec3& w) {
        const spt::Vec3 l = m_frame.to_local(w);
        const double c = std::clamp(double(l.z), -1.0, 1.0);
        if (c < m_cos_max) return add_outside();
        double phi = std::atan2(double(l.y), double(l.x));
        if (phi < 0) phi += 2 * std::numbers::pi;
        const int i = std::min(m_theta - 1, int((c - m_cos_max) / (1.0 - m_cos_max) * m_theta));
        const int j = std::min(m_phi - 1, int(phi / (2 * std::numbers::pi) * m_phi));
        m_observed[static_cast<std::size_t>(i * m_phi + j)] += 1;
    }
    void add_outside() { m_observed.back() += 1; }
    const std::vector<double>& observed() const { return m_observed; }

private:
    spt::Frame m_frame;
    double m_cos_max;
    int m_theta, m_phi;
    std::vector<double> m_observed;
};

}  // namespace spt_test
