// Pearson chi-square goodness-of-fit test for the statistical tests (sampling routines against
// their densities). Cells with a small expected count are pooled as in pbrt-v4's
// bsdfs_test.cpp (expected < 5 breaks the chi-square approximation); the p-value is the
// regularized upper incomplete gamma function Q(dof/2, X²/2), implemented here.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace spt_test {

/// Regularized upper incomplete gamma function Q(a, x) = Γ(a, x)/Γ(a), for a > 0, x ≥ 0.
/// Series for x < a + 1, Lentz's continued fraction otherwise (Numerical Recipes §6.2); both
/// converge to double precision in at most a few hundred terms for the a, x used in tests.
inline double regularized_gamma_q(double a, double x) {
    if (!(a > 0.0) || !(x >= 0.0)) throw std::domain_error("regularized_gamma_q: a > 0, x >= 0");
    if (x == 0.0) return 1.0;
    const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
    constexpr double kEps = 1e-16;
    constexpr int kMaxIterations = 100000;
    if (x < a + 1.0) {
        // P(a, x) = e^{-x} x^a / Γ(a+1) · Σ_n x^n / ((a+1)(a+2)...(a+n))
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < kMaxIterations; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::fabs(term) < std::fabs(sum) * kEps) break;
        }
        return std::max(0.0, 1.0 - sum * std::exp(log_prefactor));
    }
    // Q(a, x) = e^{-x} x^a / Γ(a) · 1/(x+1−a− 1·(1−a)/(x+3−a− 2·(2−a)/(x+5−a− ...)))
    constexpr double kTiny = std::numeric_limits<double>::min() / kEps;
    double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
    for (int i = 1; i < kMaxIterations; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < kTiny) d = kTiny;
        c = b + an / c;
        if (std::fabs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1.0) < kEps) break;
    }
    return std::exp(log_prefactor) * h;
}

/// Survival function of the chi-square distribution with k degrees of freedom.
inline double chi2_survival(double statistic, int dof) {
    return regularized_gamma_q(0.5 * dof, 0.5 * std::max(0.0, statistic));
}

struct Chi2Result {
    double statistic = 0.0;
    int dof = 0;                   ///< cells after pooling − 1 − fitted parameters
    double p_value = 1.0;
    int cells = 0;                 ///< cells after pooling
    double observed_in_empty = 0;  ///< observations in cells whose expected count is exactly 0
};

/// Pearson's X² of observed against expected counts (same total). Cells are sorted by expected
/// count; those with expected < min_expected are pooled together (and the pool merged into the
/// next larger cell while it is still below min_expected). Cells with expected 0 are left out of
/// the statistic, but their observations are reported: any of them refutes the density.
inline Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected,
                            int fitted_parameters = 0, double min_expected = 5.0) {
    if (observed.size() != expected.size() || observed.empty())
        throw std::invalid_argument("chi2_test: observed and expected must have the same size");
    std::vector<std::size_t> order(observed.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
    Chi2Result r;
    double pool_obs = 0.0, pool_exp = 0.0;
    auto add_cell = [&](double obs, double expect) {
        r.statistic += (obs - expect) * (obs - expect) / expect;
        ++r.cells;
    };
    for (std::size_t i : order) {
        const double obs = observed[i], expect = expected[i];
        if (expect < 0.0) throw std::invalid_argument("chi2_test: negative expected count");
        if (expect == 0.0) {
            r.observed_in_empty += obs;
        } else if (expect < min_expected || (pool_exp > 0.0 && pool_exp < min_expected)) {
            pool_obs += obs, pool_exp += expect;
        } else {
            add_cell(obs, expect);
        }
    }
    if (pool_exp > 0.0) add_cell(pool_obs, pool_exp);
    r.dof = r.cells - 1 - fitted_parameters;
    r.p_value = r.dof > 0 ? chi2_survival(r.statistic, r.dof) : 1.0;
    return r;
}

}  // namespace spt_test
