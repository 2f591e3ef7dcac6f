#include "model/lights/hosek_wilkie.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "spectral/cie.h"
#include "spectral/spectral_table.h"

namespace spt {

namespace {

constexpr int kParams = 9;                     // A … I, data order A B C D E F G I H
constexpr int kControlPoints = 6;              // quintic Bézier
constexpr int kTurbidities = 10;               // 1 … 10
constexpr int kSkyValues = 2 * kTurbidities * kControlPoints * kParams;  // then the L_M curves
constexpr int kSunPieces = 45, kSunOrder = 4;  // cubic pieces over elevation
constexpr double kHalfPi = 1.5707963267948966;

/// The table, checked once for the layout tools/hosek_wilkie_tables.py writes.
const SpectralTable& checked_table(const std::string& name, const std::string& first_column,
                                   const std::string& last_column, std::size_t columns) {
    const SpectralTable& t = embedded_spectral_table(name);
    if (t.columns.size() != columns || t.wavelengths_nm.size() != kSkyChannels ||
        t.column_names.at(1) != first_column || t.column_names.back() != last_column)
        throw std::runtime_error("spectra/" + name + " is not the Hosek-Wilkie table layout; expected " +
                                 std::to_string(columns) + " columns from " + first_column + " to " + last_column);
    for (int c = 0; c < kSkyChannels; ++c)
        if (t.wavelengths_nm[static_cast<std::size_t>(c)] != kSkyFirstChannelNm + kSkyChannelStepNm * c)
            throw std::runtime_error("spectra/" + name + ": channel wavelengths; expected 320, 360, ..., 720 nm");
    return t;
}

const SpectralTable& sky_table() {
    static const SpectralTable& t = checked_table("hosek_wilkie_sky.csv", "a0_t1_k0_A", "a1_t10_k5_L",
                                                  kSkyValues + 2 * kTurbidities * kControlPoints);
    return t;
}
const SpectralTable& sun_table() {
    static const SpectralTable& t =
        checked_table("hosek_wilkie_sun.csv", "t1_s0_c3", "ld5", kTurbidities * kSunPieces * kSunOrder + 6);
    return t;
}

/// The two integer turbidities (0-based) around T and the upper one's weight.
void turbidity_lerp(double turbidity, int& lower, double& w) {
    const double t = std::clamp(turbidity, 1.0, 10.0);
    lower = std::min(static_cast<int>(t), kTurbidities - 1) - 1;
    w = t - (lower + 1);
}

/// The quintic Bézier curve of 6 control points at x ∈ [0, 1].
double bezier5(const double p[kControlPoints], double x) {
    static constexpr double binomial[kControlPoints] = {1, 5, 10, 10, 5, 1};
    double sum = 0;
    for (int k = 0; k < kControlPoints; ++k)
        sum += binomial[k] * std::pow(1 - x, kControlPoints - 1 - k) * std::pow(x, k) * p[k];
    return sum;
}

}  // namespace

HosekWilkieSky HosekWilkieSky::make(double elevation, double turbidity, double albedo) {
    const SpectralTable& table = sky_table();
    const double x = std::cbrt(std::clamp(elevation, 0.0, kHalfPi) / kHalfPi);
    const double a = std::clamp(albedo, 0.0, 1.0);
    int t0 = 0;
    double wt = 0;
    turbidity_lerp(turbidity, t0, wt);
    HosekWilkieSky sky;
    for (int c = 0; c < kSkyChannels; ++c) {
        // value(q) of parameter q (0…8, data order; 9: L_M) blended over albedo and turbidity.
        double value[kParams + 1] = {};
        for (int ai = 0; ai < 2; ++ai)
            for (int ti = 0; ti < 2; ++ti) {
                const double w = (ai ? a : 1 - a) * (ti ? wt : 1 - wt);
                if (w == 0) continue;
                const int turb = std::min(t0 + ti, kTurbidities - 1);
                for (int q = 0; q <= kParams; ++q) {
                    double p[kControlPoints];
                    for (int k = 0; k < kControlPoints; ++k) {
                        const int column = q < kParams
                                               ? ((ai * kTurbidities + turb) * kControlPoints + k) * kParams + q
                                               : kSkyValues + (ai * kTurbidities + turb) * kControlPoints + k;
                        p[k] = table.columns[static_cast<std::size_t>(column)][static_cast<std::size_t>(c)];
                    }
                    value[q] += w * bezier5(p, x);
                }
            }
        Channel& ch = sky.channels[static_cast<std::size_t>(c)];
        ch.A = static_cast<float>(value[0]);
        ch.B = static_cast<float>(value[1]);
        ch.C = static_cast<float>(value[2]);
        ch.D = static_cast<float>(value[3]);
        ch.E = static_cast<float>(value[4]);
        ch.F = static_cast<float>(value[5]);
        ch.G = static_cast<float>(value[6]);
        ch.I = static_cast<float>(value[7]);  // the data stores I before H
        ch.H = static_cast<float>(value[8]);
        ch.L_M = static_cast<float>(value[9]);
    }
    return sky;
}

HosekWilkieSun HosekWilkieSun::make(double elevation, double turbidity) {
    const SpectralTable& table = sun_table();
    const double eta = std::clamp(elevation, 0.0, kHalfPi);
    const int piece = std::min(static_cast<int>(std::cbrt(eta / kHalfPi) * kSunPieces), kSunPieces - 1);
    const double start = std::pow(static_cast<double>(piece) / kSunPieces, 3.0) * kHalfPi;
    const double dx = eta - start;
    int t0 = 0;
    double wt = 0;
    turbidity_lerp(turbidity, t0, wt);
    HosekWilkieSun sun;
    const std::size_t limb_column = static_cast<std::size_t>(kTurbidities * kSunPieces * kSunOrder);
    for (int c = 0; c < kSkyChannels; ++c) {
        const std::size_t row = static_cast<std::size_t>(c);
        double value = 0;
        for (int ti = 0; ti < 2; ++ti) {
            const double w = ti ? wt : 1 - wt;
            if (w == 0) continue;
            const int turb = std::min(t0 + ti, kTurbidities - 1);
            // Coefficients stored highest power first.
            const std::size_t first = static_cast<std::size_t>((turb * kSunPieces + piece) * kSunOrder);
            double poly = 0;
            for (int k = 0; k < kSunOrder; ++k) poly = poly * dx + table.columns[first + static_cast<std::size_t>(k)][row];
            value += w * poly;
        }
        sun.centre[row] = static_cast<float>(std::max(value, 0.0));
        for (int k = 0; k < 6; ++k)
            sun.limb[row][static_cast<std::size_t>(k)] = static_cast<float>(table.columns[limb_column + static_cast<std::size_t>(k)][row]);
    }
    return sun;
}

std::array<double, kSkyChannels> sky_channel_mean_weights() {
    std::array<double, kSkyChannels> w{};
    for (int k = 0; k <= 40; ++k) {
        const SkyChannelLerp l = sky_channel_lerp(380.f + 10.f * static_cast<float>(k));
        w[static_cast<std::size_t>(l.lower)] += (1.0 - l.upper_weight) / 41.0;
        w[static_cast<std::size_t>(l.lower) + 1] += l.upper_weight / 41.0;
    }
    return w;
}

std::array<double, kSkyChannels> sky_channel_luminance_weights() {
    const Observer& cie = Cie1931::get();
    std::array<double, kSkyChannels> w{};
    for (int i = 0; i < Observer::kRows; ++i) {
        const float lambda = kLambdaMin + static_cast<float>(i);
        const double y = cie.cmf(lambda).y / cie.y_integral();
        const SkyChannelLerp l = sky_channel_lerp(lambda);
        w[static_cast<std::size_t>(l.lower)] += (1.0 - l.upper_weight) * y;
        w[static_cast<std::size_t>(l.lower) + 1] += l.upper_weight * y;
    }
    return w;
}

}  // namespace spt
