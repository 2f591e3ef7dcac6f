// Fitting the three coefficients of the rgb_sigmoid reflectance to an RGB colour under D65.
#include "spectral/rgb_to_spectrum.h"

#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "spectral/color_space.h"
#include "spectral/catalog_lookup.h"

namespace spt {

namespace {

/// D65-weighted colour matching functions at 1 nm over 360–830 nm, normalised so that a
/// perfect white has Y = 1, and the D65 white point they define.
struct D65Weights {
    std::vector<double> t;        ///< normalised wavelength of each sample, as in rgb_sigmoid
    std::vector<double> wx, wy, wz;
    Xyz white;
    Matrix3 rgb_to_xyz, xyz_to_rgb;

    static const D65Weights& get() {
        static const D65Weights w;
        return w;
    }

private:
    D65Weights() {
        const SpectralTable& cmf = embedded_spectral_table("cie_1931_2deg.csv");
        const SpectralTable& d65 = embedded_spectral_table("cie_d65.csv");
        const SpectrumSource illuminant = column_spectrum(d65, "value");
        const auto &xs = cmf.column("x_bar"), &ys = cmf.column("y_bar"), &zs = cmf.column("z_bar");
        double norm = 0;
        for (std::size_t i = 0; i < cmf.wavelengths_nm.size(); ++i) {
            const double l = cmf.wavelengths_nm[i];
            const double s = illuminant.eval(l);
            t.push_back((l - 360.0) / 470.0);
            wx.push_back(s * xs[i]), wy.push_back(s * ys[i]), wz.push_back(s * zs[i]);
            norm += s * ys[i];
        }
        for (std::size_t i = 0; i < t.size(); ++i) {
            wx[i] /= norm, wy[i] /= norm, wz[i] /= norm;
            white.x += wx[i], white.y += wy[i], white.z += wz[i];
        }
        const double sum = white.x + white.y + white.z;
        const ColorSpace cs = make_color_space("srgb-d65-table", {0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06},
                                               {white.x / sum, white.y / sum});
        rgb_to_xyz = cs.to_xyz;
        xyz_to_rgb = cs.from_xyz;
    }
};

double lab_f(double r) {
    constexpr double d = 6.0 / 29.0;
    return r > d * d * d ? std::cbrt(r) : r / (3 * d * d) + 4.0 / 29.0;
}
double lab_f_prime(double r) {
    constexpr double d = 6.0 / 29.0;
    return r > d * d * d ? 1.0 / (3.0 * std::cbrt(r * r)) : 1.0 / (3 * d * d);
}

/// Lab of the sigmoid spectrum with coefficients c, and its 3×3 Jacobian d Lab / d c.
void lab_and_jacobian(const double c[3], double lab[3], double jac[3][3]) {
    const D65Weights& w = D65Weights::get();
    double xyz[3] = {0, 0, 0}, dxyz[3][3] = {};  // dxyz[i][j] = d XYZ_i / d c_j
    for (std::size_t k = 0; k < w.t.size(); ++k) {
        const double t = w.t[k];
        const double x = (c[0] * t + c[1]) * t + c[2];
        const double q = 1.0 + x * x;
        const double v = 0.5 + x / (2.0 * std::sqrt(q));
        const double dv = 0.5 / (q * std::sqrt(q));  // d s / d x
        const double basis[3] = {t * t, t, 1.0};
        const double wk[3] = {w.wx[k], w.wy[k], w.wz[k]};
        for (int i = 0; i < 3; ++i) {
            xyz[i] += v * wk[i];
            for (int j = 0; j < 3; ++j) dxyz[i][j] += dv * basis[j] * wk[i];
        }
    }
    const double white[3] = {w.white.x, w.white.y, w.white.z};
    double f[3], df[3];
    for (int i = 0; i < 3; ++i) f[i] = lab_f(xyz[i] / white[i]), df[i] = lab_f_prime(xyz[i] / white[i]) / white[i];
    lab[0] = 116 * f[1] - 16, lab[1] = 500 * (f[0] - f[1]), lab[2] = 200 * (f[1] - f[2]);
    for (int j = 0; j < 3; ++j) {
        const double fx = df[0] * dxyz[0][j], fy = df[1] * dxyz[1][j], fz = df[2] * dxyz[2][j];
        jac[0][j] = 116 * fy, jac[1][j] = 500 * (fx - fy), jac[2][j] = 200 * (fy - fz);
    }
}

/// Solves the 3×3 system a·x = b by Cramer's rule; false if singular.
bool solve3(const double a[3][3], const double b[3], double x[3]) {
    const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if (!(std::fabs(det) > 1e-300) || !std::isfinite(det)) return false;
    for (int k = 0; k < 3; ++k) {
        double m[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m[i][j] = j == k ? b[i] : a[i][j];
        x[k] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) / det;
    }
    return true;
}

double norm3(const double v[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/// Levenberg-Marquardt on the Lab residual from the start coefficients c; returns the final
/// residual norm (ΔE*ab).
double fit_lab(const double target[3], double c[3], int max_iterations) {
    double lab[3], jac[3][3];
    lab_and_jacobian(c, lab, jac);
    double r[3] = {lab[0] - target[0], lab[1] - target[1], lab[2] - target[2]};
    double err = norm3(r);
    double lambda = 1e-3;
    for (int it = 0; it < max_iterations && err > 1e-7; ++it) {
        // (JᵀJ + λ·diag(JᵀJ)) δ = −Jᵀr
        double jtj[3][3], jtr[3];
        for (int i = 0; i < 3; ++i) {
            jtr[i] = 0;
            for (int k = 0; k < 3; ++k) jtr[i] -= jac[k][i] * r[k];
            for (int j = 0; j < 3; ++j) {
                jtj[i][j] = 0;
                for (int k = 0; k < 3; ++k) jtj[i][j] += jac[k][i] * jac[k][j];
            }
        }
        bool improved = false;
        for (int attempt = 0; attempt < 30 && !improved; ++attempt) {
            double a[3][3], delta[3];
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) a[i][j] = jtj[i][j] + (i == j ? lambda * (jtj[i][i] + 1e-12) : 0.0);
            if (!solve3(a, jtr, delta)) {
                lambda *= 10;
                continue;
            }
            double c_new[3] = {c[0] + delta[0], c[1] + delta[1], c[2] + delta[2]};
            double lab_new[3], jac_new[3][3];
            lab_and_jacobian(c_new, lab_new, jac_new);
            double r_new[3] = {lab_new[0] - target[0], lab_new[1] - target[1], lab_new[2] - target[2]};
            const double err_new = norm3(r_new);
            if (std::isfinite(err_new) && err_new < err) {
                for (int i = 0; i < 3; ++i) {
                    c[i] = c_new[i], r[i] = r_new[i];
                    for (int j = 0; j < 3; ++j) jac[i][j] = jac_new[i][j];
                }
                err = err_new;
                lambda = std::max(lambda * 0.1, 1e-12);
                improved = true;
            } else {
                lambda *= 10;
            }
        }
        if (!improved) break;
    }
    return err;
}

std::array<double, 3> fit_coefficients(const std::array<double, 3>& rgb) {
    // Start from the grey of the same mean, which a constant x reproduces exactly, and walk
    // towards the target: each step starts from the previous solution (continuation).
    const double g = (rgb[0] + rgb[1] + rgb[2]) / 3.0;
    const double u = 2.0 * g - 1.0;
    double c[3] = {0, 0, u / std::sqrt(std::max(1e-300, 1.0 - u * u))};
    constexpr int kSteps = 16;
    double err = 0;
    for (int step = 1; step <= kSteps; ++step) {
        const double s = double(step) / kSteps;
        const std::array<double, 3> mid = {g + s * (rgb[0] - g), g + s * (rgb[1] - g), g + s * (rgb[2] - g)};
        const auto lab = xyz_d65_to_lab(linear_srgb_to_xyz_d65(mid));
        err = fit_lab(lab.data(), c, step == kSteps ? 500 : 50);
    }
    if (!(err < 1e-4))
        throw std::runtime_error("RGB reflectance fit did not converge (residual ΔE*ab " + std::to_string(err) + ")");
    return {c[0], c[1], c[2]};
}

}  // namespace

Xyz reflectance_xyz_d65(const SpectrumSource& reflectance) {
    const D65Weights& w = D65Weights::get();
    Xyz xyz;
    for (std::size_t k = 0; k < w.t.size(); ++k) {
        const double v = reflectance.eval(360.0 + static_cast<double>(k));
        xyz.x += v * w.wx[k], xyz.y += v * w.wy[k], xyz.z += v * w.wz[k];
    }
    return xyz;
}

Xyz linear_srgb_to_xyz_d65(const std::array<double, 3>& rgb) {
    const Matrix3& m = D65Weights::get().rgb_to_xyz;
    return {m[0][0] * rgb[0] + m[0][1] * rgb[1] + m[0][2] * rgb[2],
            m[1][0] * rgb[0] + m[1][1] * rgb[1] + m[1][2] * rgb[2],
            m[2][0] * rgb[0] + m[2][1] * rgb[1] + m[2][2] * rgb[2]};
}

std::array<double, 3> xyz_d65_to_linear_srgb(const Xyz& xyz) {
    return apply(D65Weights::get().xyz_to_rgb, xyz);
}

std::array<double, 3> xyz_d65_to_lab(const Xyz& xyz) {
    const Xyz& w = D65Weights::get().white;
    const double fx = lab_f(xyz.x / w.x), fy = lab_f(xyz.y / w.y), fz = lab_f(xyz.z / w.z);
    return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double refine_rgb_sigmoid(const std::array<double, 3>& rgb, std::array<double, 3>& c, int max_iterations) {
    const auto lab = xyz_d65_to_lab(linear_srgb_to_xyz_d65(rgb));
    return fit_lab(lab.data(), c.data(), max_iterations);
}

SpectrumSource rgb_to_spectrum(const std::array<double, 3>& rgb) {
    for (double v : rgb)
        if (!std::isfinite(v) || v < 0.0 || v > 1.0)
            throw std::invalid_argument("RGB reflectance components must be finite and in [0, 1]");
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) return SpectrumSource::constant(rgb[0]);
    static std::mutex mutex;
    static std::map<std::array<double, 3>, std::array<double, 3>> cache;
    {
        const std::lock_guard lock(mutex);
        if (auto it = cache.find(rgb); it != cache.end())
            return SpectrumSource::rgb_sigmoid(it->second[0], it->second[1], it->second[2]);
    }
    const std::array<double, 3> c = fit_coefficients(rgb);
    const std::lock_guard lock(mutex);
    cache.emplace(rgb, c);
    return SpectrumSource::rgb_sigmoid(c[0], c[1], c[2]);
}

}  // namespace spt
