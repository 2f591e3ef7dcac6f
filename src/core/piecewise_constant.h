// Sampling proportional to a tabulated function: piecewise-constant densities on [0,1) and on
// the unit square (the inversion method over a CDF; the 2-D form is a marginal over rows and
// one conditional per row, as in pbrt-v4's PiecewiseConstant2D). Built to importance-sample
// images of up to 8192 × 4096 texels (environment maps).
//
// The contract, shared by both classes:
// - f must be finite and ≥ 0. A negative, NaN or infinite value throws std::invalid_argument:
//   callers validate their data first and report it with its location; the throw guards
//   against a caller that did not.
// - Running sums are accumulated in double (33 M cells of similar weight would stall a float
//   sum at 2^24 times the cell value); only the normalised CDF is stored, as float. Nothing
//   else is kept per cell: 4 bytes a cell (the function itself is not stored).
// - sample() and pdf() read the density of a cell from the same stored CDF, n·(cdf[i+1] −
//   cdf[i]), so pdf() is exactly the density that sample() draws from. A cell with f = 0 has
//   width 0: pdf 0, never sampled. A cell whose probability is below the float resolution of
//   the CDF where it lies (6e-8 near the top) can round to width 0 too, or to twice its
//   weight: the sampler is then slightly less ideal but never inconsistent with pdf(), so
//   estimators (and MIS weights) stay unbiased. The 2-D table keeps every CDF short (a row,
//   or the column of row sums), which keeps this rare.
// - f all zero: sampling is uniform, pdf 1 everywhere, integral() 0 (whether an all-zero
//   function is an error is the caller's decision).
// - u is clamped to [0, 1 − 2^-24] (NaN to 0), so a sample is always in [0,1), and
//   floor(x·n) is exactly the sampled cell (the rounding of (cell + t)/n to float is undone
//   when it crosses a cell boundary).
// - pdf(x) accepts x in [0,1]; x = 1 counts as the last cell (a direction can map exactly to
//   the square's edge). Outside [0,1] or NaN: 0.
// - n ≥ 1 and n ≤ 2^24 cells per dimension (every cell must contain a float x).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/no_init_allocator.h"
#include "core/parallel_rows.h"

namespace spt {

namespace piecewise_detail {

inline constexpr int kMaxCells = 1 << 24;
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

inline void check_cell_count(long long n, const char* what) {
    if (n < 1 || n > kMaxCells)
        throw std::invalid_argument(std::string(what) + ": " + std::to_string(n) +
                                    " cells; expected 1 to 2^24");
}

/// Σ f in double, after checking every value is finite and ≥ 0.
template <typename T>
double checked_sum(std::span<const T> f, const char* what, std::size_t index_offset = 0) {
    double sum = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) {
        const T v = f[i];
        if (!(v >= T(0)) || !std::isfinite(v))
            throw std::invalid_argument(std::string(what) + ": f[" + std::to_string(index_offset + i) +
                                        "] = " + std::to_string(double(v)) + "; expected a finite value >= 0");
        sum += double(v);
    }
    return sum;
}

/// Writes the normalised CDF of f (f.size() + 1 values, from 0 to exactly 1) given its sum.
/// The running sum repeats checked_sum's order, so the last value divides to exactly 1.
template <typename T>
void write_cdf(std::span<const T> f, double sum, float* cdf) {
    const std::size_t n = f.size();
    cdf[0] = 0.f;
    if (sum > 0.0) {
        double running = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            running += double(f[i]);
            cdf[i + 1] = static_cast<float>(running / sum);
        }
    } else {
        for (std::size_t i = 1; i <= n; ++i) cdf[i] = static_cast<float>(double(i) / double(n));
    }
    cdf[n] = 1.f;
}

/// floor(x·n) without rounding: x has 24 significant bits and n ≤ 2^24, so the double
/// product is exact.
inline int floor_cell(float x, int n) { return static_cast<int>(static_cast<double>(x) * n); }

/// Density (w.r.t. x) of cell i: its CDF width times the cell count.
inline float cell_density(const float* cdf, int n, int i) { return (cdf[i + 1] - cdf[i]) * static_cast<float>(n); }

inline float sample_cdf(const float* cdf, int n, float u, float* pdf, int* cell) {
    if (!(u >= 0.f)) u = 0.f;
    if (!(u < 1.f)) u = kOneMinusEpsilon;
    // The cell with cdf[i] ≤ u < cdf[i+1]: cdf[0] = 0 and cdf[n] = 1 bound it, and its width
    // is > 0, so a cell of zero weight is never chosen.
    const int i = static_cast<int>(std::upper_bound(cdf + 1, cdf + n + 1, u) - (cdf + 1));
    const double lo = cdf[i], width = double(cdf[i + 1]) - lo;
    const double t = std::min((double(u) - lo) / width, 1.0);
    float x = static_cast<float>((i + t) / n);
    // Rounding to float may land on a neighbouring cell's side of a boundary (one ulp at most).
    while (floor_cell(x, n) > i) x = std::nextafter(x, 0.f);
    while (floor_cell(x, n) < i) x = std::nextafter(x, 1.f);
    if (pdf) *pdf = cell_density(cdf, n, i);
    if (cell) *cell = i;
    return x;
}

inline float pdf_cdf(const float* cdf, int n, float x) {
    if (!(x >= 0.f && x <= 1.f)) return 0.f;
    return cell_density(cdf, n, std::min(floor_cell(x, n), n - 1));
}

}  // namespace piecewise_detail

/// f ≥ 0 on [0,1) in n equal cells; sampling proportional to f.
class PiecewiseConstant1D {
public:
    PiecewiseConstant1D() = default;
    explicit PiecewiseConstant1D(std::vector<float> f) {
        piecewise_detail::check_cell_count(static_cast<long long>(f.size()), "PiecewiseConstant1D");
        const std::span<const float> values(f);
        const double sum = piecewise_detail::checked_sum(values, "PiecewiseConstant1D");
        m_cdf.resize(f.size() + 1);
        piecewise_detail::write_cdf(values, sum, m_cdf.data());
        m_integral = sum / static_cast<double>(f.size());
    }

    /// x in [0,1) for u in [0,1); *pdf = density at x (w.r.t. x), *cell = its cell (either pointer may be null).
    float sample(float u, float* pdf, int* cell) const {
        return piecewise_detail::sample_cdf(m_cdf.data(), size(), u, pdf, cell);
    }
    /// The density sample() draws x with; 0 in cells of f = 0 and outside [0,1].
    float pdf(float x) const { return piecewise_detail::pdf_cdf(m_cdf.data(), size(), x); }
    /// ∫ f over [0,1) (the mean of f), summed in double.
    float integral() const { return static_cast<float>(m_integral); }
    int size() const { return static_cast<int>(m_cdf.size()) - 1; }
    /// Bytes held (the CDF).
    std::size_t memory_bytes() const { return m_cdf.capacity() * sizeof(float); }

private:
    std::vector<float> m_cdf;  ///< n + 1 values, 0 to 1
    double m_integral = 0.0;
};

/// f ≥ 0 over the unit square in nu × nv cells, f[v * nu + u] (row v = 0 first).
/// Sampling picks a row from the marginal (row sums), then a cell within the row.
class PiecewiseConstant2D {
public:
    PiecewiseConstant2D() = default;
    /// `threads`: the rows' CDFs are built in parallel (core/parallel_rows.h); the table is
    /// the same for any count.
    PiecewiseConstant2D(const std::vector<float>& f, int nu, int nv, int threads = 1)
        : PiecewiseConstant2D(std::span<const float>(f), nu, nv, threads) {}
    PiecewiseConstant2D(std::span<const float> f, int nu, int nv, int threads = 1) : m_nu(nu), m_nv(nv) {
        piecewise_detail::check_cell_count(nu, "PiecewiseConstant2D (columns)");
        piecewise_detail::check_cell_count(nv, "PiecewiseConstant2D (rows)");
        const std::size_t row_length = static_cast<std::size_t>(nu);
        if (f.size() != row_length * static_cast<std::size_t>(nv))
            throw std::invalid_argument("PiecewiseConstant2D: " + std::to_string(f.size()) + " values; expected " +
                                        std::to_string(nu) + " x " + std::to_string(nv));
        m_conditional_cdf.resize((row_length + 1) * static_cast<std::size_t>(nv));
        std::vector<double> row_sums(static_cast<std::size_t>(nv));
        parallel_rows(nv, threads, [&](int v) {
            const std::span<const float> row(f.data() + row_length * v, row_length);
            row_sums[v] = piecewise_detail::checked_sum(row, "PiecewiseConstant2D", row_length * v);
            piecewise_detail::write_cdf(row, row_sums[v], row_cdf(v));
        });
        const std::span<const double> sums(row_sums);
        const double total = piecewise_detail::checked_sum(sums, "PiecewiseConstant2D (row sums)");
        m_marginal_cdf.resize(static_cast<std::size_t>(nv) + 1);
        piecewise_detail::write_cdf(sums, total, m_marginal_cdf.data());
        m_integral = total / (static_cast<double>(nu) * nv);
    }

    /// (x, y) in [0,1)² (x along nu, y along nv); *pdf = density w.r.t. area of the unit square.
    /// u1 picks the row, u0 the cell within it; floor(x·nu), floor(y·nv) is the sampled cell.
    std::array<float, 2> sample(float u0, float u1, float* pdf) const {
        float pdf_y = 0.f, pdf_x = 0.f;
        int row = 0;
        const float y = piecewise_detail::sample_cdf(m_marginal_cdf.data(), m_nv, u1, &pdf_y, &row);
        const float x = piecewise_detail::sample_cdf(row_cdf(row), m_nu, u0, &pdf_x, nullptr);
        if (pdf) *pdf = pdf_y * pdf_x;
        return {x, y};
    }
    /// The density sample() draws (x, y) with; 0 in cells of f = 0 and outside [0,1]².
    float pdf(float x, float y) const {
        const float pdf_y = piecewise_detail::pdf_cdf(m_marginal_cdf.data(), m_nv, y);
        if (pdf_y == 0.f) return 0.f;  // also y outside [0,1]: no row to read
        const int row = std::min(piecewise_detail::floor_cell(y, m_nv), m_nv - 1);
        return pdf_y * piecewise_detail::pdf_cdf(row_cdf(row), m_nu, x);
    }
    /// ∫ f over the unit square (the mean of f), summed in double.
    float integral() const { return static_cast<float>(m_integral); }
    int nu() const { return m_nu; }
    int nv() const { return m_nv; }
    /// Bytes held: (nu + 1)·nv + nv + 1 floats.
    std::size_t memory_bytes() const {
        return (m_conditional_cdf.capacity() + m_marginal_cdf.capacity()) * sizeof(float);
    }

private:
    float* row_cdf(int v) { return m_conditional_cdf.data() + (static_cast<std::size_t>(m_nu) + 1) * v; }
    const float* row_cdf(int v) const {
        return m_conditional_cdf.data() + (static_cast<std::size_t>(m_nu) + 1) * v;
    }

    int m_nu = 0, m_nv = 0;
    std::vector<float, NoInitAllocator<float>> m_conditional_cdf;  ///< nv rows of nu + 1 values, each 0 to 1
    std::vector<float> m_marginal_cdf;     ///< nv + 1 values, 0 to 1
    double m_integral = 0.0;
};

}  // namespace spt
