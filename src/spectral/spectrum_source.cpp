// Exact evaluation of the analytic spectral sources.
#include "spectral/spectrum_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace spt {

SpectrumSource SpectrumSource::constant(double value) {
    SpectrumSource s;
    s.kind = Kind::Constant;
    s.p[0] = value;
    return s;
}
SpectrumSource SpectrumSource::gaussian(double center_nm, double width_nm, double scale, double offset) {
    SpectrumSource s;
    s.kind = Kind::Gaussian;
    s.p[0] = center_nm, s.p[1] = width_nm, s.p[2] = scale, s.p[3] = offset;
    return s;
}
SpectrumSource SpectrumSource::sigmoid(double center_nm, double width_nm, double scale, double offset) {
    SpectrumSource s;
    s.kind = Kind::Sigmoid;
    s.p[0] = center_nm, s.p[1] = width_nm, s.p[2] = scale, s.p[3] = offset;
    return s;
}
SpectrumSource SpectrumSource::blackbody(double kelvin, double scale, double normalize_nm) {
    SpectrumSource s;
    s.kind = Kind::Blackbody;
    s.p[0] = kelvin, s.p[1] = scale, s.p[2] = normalize_nm;
    return s;
}
SpectrumSource SpectrumSource::piecewise_linear(std::vector<std::pair<double, double>> points) {
    SpectrumSource s;
    s.kind = Kind::PiecewiseLinear;
    s.table = std::move(points);
    return s;
}
SpectrumSource SpectrumSource::cauchy(double a, double b_um2, double c_um4) {
    SpectrumSource s;
    s.kind = Kind::Cauchy;
    s.p[0] = a, s.p[1] = b_um2, s.p[2] = c_um4;
    return s;
}
SpectrumSource SpectrumSource::sellmeier(double b1, double b2, double b3, double c1, double c2,
                                         double c3) {
    SpectrumSource s;
    s.kind = Kind::Sellmeier;
    s.p[0] = b1, s.p[1] = b2, s.p[2] = b3, s.p[3] = c1, s.p[4] = c2, s.p[5] = c3;
    return s;
}
SpectrumSource SpectrumSource::rgb_sigmoid(double c0, double c1, double c2, double scale) {
    SpectrumSource s;
    s.kind = Kind::RgbSigmoid;
    s.p[0] = c0, s.p[1] = c1, s.p[2] = c2, s.p[3] = scale;
    return s;
}

SpectrumSource SpectrumSource::product(std::vector<SpectrumSource> factors, double scale) {
    SpectrumSource s;
    s.kind = Kind::Product;
    s.p[0] = scale;
    s.factors = std::move(factors);
    return s;
}

double planck(double lambda_nm, double kelvin) {
    constexpr double c = 299792458.0, h = 6.62607015e-34, kb = 1.380649e-23;
    const double l = lambda_nm * 1e-9;
    return (2.0 * h * c * c) / (std::pow(l, 5) * std::expm1((h * c) / (l * kb * kelvin)));
}

double SpectrumSource::eval(double lambda) const {
    switch (kind) {
        case Kind::Constant:
            return p[0];
        case Kind::Gaussian: {
            const double x = (lambda - p[0]) / p[1];
            return p[3] + p[2] * std::exp(-x * x);
        }
        case Kind::Sigmoid:
            return p[3] + p[2] / (1.0 + std::exp(-(lambda - p[0]) / p[1]));
        case Kind::Blackbody:
            return p[1] * planck(lambda, p[0]) / planck(p[2], p[0]);
        case Kind::PiecewiseLinear: {
            if (table.empty()) return 0.0;
            if (lambda <= table.front().first) return table.front().second;
            if (lambda >= table.back().first) return table.back().second;
            const auto it = std::upper_bound(table.begin(), table.end(), lambda,
                                             [](double l, const auto& e) { return l < e.first; });
            const auto& [l1, v1] = *it;
            const auto& [l0, v0] = *(it - 1);
            return v0 + (v1 - v0) * (lambda - l0) / (l1 - l0);
        }
        case Kind::Cauchy: {
            const double l2 = (lambda * 1e-3) * (lambda * 1e-3);
            return p[0] + p[1] / l2 + p[2] / (l2 * l2);
        }
        case Kind::Sellmeier: {
            const double l2 = (lambda * 1e-3) * (lambda * 1e-3);
            const double n2 = 1.0 + p[0] * l2 / (l2 - p[3]) + p[1] * l2 / (l2 - p[4]) +
                              p[2] * l2 / (l2 - p[5]);
            return std::sqrt(std::max(n2, 0.0));
        }
        case Kind::RgbSigmoid: {
            // Polynomial in normalised wavelength t ∈ [0, 1] over 360–830 nm keeps the
            // coefficients of order one (Jakob & Hanika 2019 use λ directly).
            const double t = (lambda - 360.0) / 470.0;
            const double x = (p[0] * t + p[1]) * t + p[2];
            return p[3] * (0.5 + x / (2.0 * std::sqrt(1.0 + x * x)));
        }
        case Kind::Product: {
            double v = p[0];
            for (const SpectrumSource& f : factors) v *= f.eval(lambda);
            return v;
        }
    }
    return 0.0;
}

bool SpectrumSource::is_constant() const {
    switch (kind) {
        case Kind::Constant: return true;
        case Kind::Gaussian:
        case Kind::Sigmoid: return p[2] == 0.0;
        case Kind::Cauchy: return p[1] == 0.0 && p[2] == 0.0;
        case Kind::PiecewiseLinear:
            return std::all_of(table.begin(), table.end(),
                               [&](const auto& e) { return e.second == table.front().second; });
        case Kind::RgbSigmoid: return p[0] == 0.0 && p[1] == 0.0;
        case Kind::Product:
            return std::all_of(factors.begin(), factors.end(), [](const SpectrumSource& f) { return f.is_constant(); });
        default: return false;
    }
}

std::string SpectrumSource::describe() const {
    char buf[160];
    switch (kind) {
        case Kind::Constant: std::snprintf(buf, sizeof buf, "constant %g", p[0]); break;
        case Kind::Gaussian: std::snprintf(buf, sizeof buf, "gaussian(%g nm, %g nm)", p[0], p[1]); break;
        case Kind::Sigmoid: std::snprintf(buf, sizeof buf, "sigmoid(%g nm, %g nm)", p[0], p[1]); break;
        case Kind::Blackbody: std::snprintf(buf, sizeof buf, "blackbody %g K", p[0]); break;
        case Kind::PiecewiseLinear: std::snprintf(buf, sizeof buf, "table of %zu points", table.size()); break;
        case Kind::Cauchy: std::snprintf(buf, sizeof buf, "cauchy A=%g", p[0]); break;
        case Kind::Sellmeier: std::snprintf(buf, sizeof buf, "sellmeier B1=%g", p[0]); break;
        case Kind::RgbSigmoid: std::snprintf(buf, sizeof buf, "rgb sigmoid"); break;
        case Kind::Product: {
            std::string text = "product of (";
            for (std::size_t i = 0; i < factors.size(); ++i) text += (i ? ", " : "") + factors[i].describe();
            std::snprintf(buf, sizeof buf, ") times %g", p[0]);
            return text + buf;
        }
    }
    return buf;
}

}  // namespace spt
