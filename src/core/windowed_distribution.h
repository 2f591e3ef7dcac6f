// Sampling a piecewise-constant function on the unit square restricted to a window
// [x0, x1] × [y0, y1] that may cut through its cells: an environment seen through a portal
// (Bitterli et al. 2015, "Portal-masked environment map sampling") is sampled over the
// rectangle of directions the portal subtends from the shading point, different at every
// point, so no fixed CDF serves. pbrt-v4's WindowedPiecewiseConstant2D does the same with
// bisection over a summed-area table.
//
// Here: a summed-area table S in double of the cell integrals, so that the integral
// F(x, y) = ∫₀ˣ∫₀ʸ f is known exactly at cell corners; F is bilinear inside each cell (f is
// constant there), so its bilinear interpolation is the exact integral at any point and the
// integral over any window is four look-ups. Sampling inverts the window's marginal in x
// (linear inside a column: a binary search over column edges, then one division) and then
// the conditional in y of the chosen column (the same over row edges). The density of a
// point is f(its cell) / ∫_window f, which is what sample() draws from.
//
// Contract: f finite and ≥ 0 (else std::invalid_argument); the window is clamped to the
// unit square; a window of zero integral has no sample and density 0; pdf() is 0 outside
// the window. Memory: 4 bytes a cell for f, 8 for S.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace spt {

class WindowedPiecewiseConstant2D {
public:
    struct Window {
        float x0 = 0.f, y0 = 0.f, x1 = 1.f, y1 = 1.f;
    };

    WindowedPiecewiseConstant2D() = default;
    /// f: nx × ny values, row-major; row j covers y ∈ [j/ny, (j+1)/ny), column i x ∈ [i/nx, (i+1)/nx).
    WindowedPiecewiseConstant2D(std::vector<float> f, int nx, int ny) : m_f(std::move(f)), m_nx(nx), m_ny(ny) {
        if (nx < 1 || ny < 1 || m_f.size() != static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny))
            throw std::invalid_argument("windowed distribution: " + std::to_string(m_f.size()) + " values for " +
                                        std::to_string(nx) + " x " + std::to_string(ny) + " cells; expected one per cell");
        const std::size_t w = static_cast<std::size_t>(nx) + 1;
        m_sat.assign(w * (static_cast<std::size_t>(ny) + 1), 0.0);
        const double cell = 1.0 / (double(nx) * double(ny));
        for (int j = 0; j < ny; ++j) {
            double row = 0.0;
            for (int i = 0; i < nx; ++i) {
                const float v = m_f[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)];
                if (!(v >= 0.f) || !std::isfinite(v))
                    throw std::invalid_argument("windowed distribution: f[" + std::to_string(j) + "][" + std::to_string(i) +
                                                "] = " + std::to_string(v) + "; expected a finite value >= 0");
                row += double(v) * cell;
                m_sat[(static_cast<std::size_t>(j) + 1) * w + static_cast<std::size_t>(i) + 1] =
                    m_sat[static_cast<std::size_t>(j) * w + static_cast<std::size_t>(i) + 1] + row;
            }
        }
    }

    int nx() const { return m_nx; }
    int ny() const { return m_ny; }

    /// ∫ f over the window (clamped to the unit square).
    double integral(Window w) const {
        w = clamped(w);
        if (!(w.x1 > w.x0) || !(w.y1 > w.y0)) return 0.0;
        return F(w.x1, w.y1) - F(w.x0, w.y1) - F(w.x1, w.y0) + F(w.x0, w.y0);
    }

    /// A point (x, y) of the window with density f / ∫_window f (written to `pdf`), from
    /// u0 (x) and u1 (y) in [0, 1); false when the window holds nothing.
    bool sample(float u0, float u1, Window w, float& x, float& y, float& pdf) const {
        w = clamped(w);
        if (!(w.x1 > w.x0) || !(w.y1 > w.y0)) return false;
        // The window's mass left of x (y over the window): linear in x inside a column. At a
        // column's edge it needs two values of S per window edge, not four: the binary search
        // below reads only edges.
        const RowLerp r0 = row_lerp(w.y0), r1 = row_lerp(w.y1);
        const double left_of_x0 = F(w.x0, w.y1) - F(w.x0, w.y0);
        auto left_of = [&](double xs) { return F(xs, w.y1) - F(xs, w.y0) - left_of_x0; };
        auto left_of_edge = [&](int i) { return F_at_column_edge(i, r1) - F_at_column_edge(i, r0) - left_of_x0; };
        const double total = left_of(w.x1);
        if (!(total > 0.0)) return false;
        int column = 0;
        const double xs =
            invert(left_of, left_of_edge, std::clamp(double(u0), 0.0, 1.0) * total, w.x0, w.x1, m_nx, column);
        x = inside_cell(xs, column, m_nx);
        // The chosen column's mass below y, within the window's rows.
        const double c0 = double(column) / m_nx, c1 = double(column + 1) / m_nx;
        const double below_y0 = F(c1, w.y0) - F(c0, w.y0);
        auto below = [&](double ys) { return F(c1, ys) - F(c0, ys) - below_y0; };
        auto below_edge = [&](int j) { return S(column + 1, j) - S(column, j) - below_y0; };
        const double column_total = below(w.y1);
        if (!(column_total > 0.0)) return false;
        int row = 0;
        const double ys =
            invert(below, below_edge, std::clamp(double(u1), 0.0, 1.0) * column_total, w.y0, w.y1, m_ny, row);
        y = inside_cell(ys, row, m_ny);
        pdf = static_cast<float>(double(value(column, row)) / total);
        return pdf > 0.f;
    }

    /// The density sample() draws the point (x, y) with from window w.
    float pdf(float x, float y, Window w) const { return density(x, y, w, integral(w)); }
    /// The same for a caller that has the window's integral at hand.
    float density(float x, float y, Window w, double window_integral) const {
        w = clamped(w);
        if (!(x >= w.x0 && x <= w.x1 && y >= w.y0 && y <= w.y1) || !(window_integral > 0.0)) return 0.f;
        return static_cast<float>(double(value(cell_of(x, m_nx), cell_of(y, m_ny))) / window_integral);
    }

private:
    std::vector<float> m_f;
    std::vector<double> m_sat;  ///< (nx + 1) × (ny + 1): ∫ f over [0, i/nx] × [0, j/ny]
    int m_nx = 0, m_ny = 0;

    static Window clamped(Window w) {
        w.x0 = std::clamp(w.x0, 0.f, 1.f), w.x1 = std::clamp(w.x1, 0.f, 1.f);
        w.y0 = std::clamp(w.y0, 0.f, 1.f), w.y1 = std::clamp(w.y1, 0.f, 1.f);
        return w;
    }
    static int cell_of(double t, int n) { return std::clamp(static_cast<int>(t * n), 0, n - 1); }
    /// t as a float that cell_of still places in `cell` (rounding to float can carry a point
    /// at a cell's edge into its neighbour, of another density).
    static float inside_cell(double t, int cell, int n) {
        float f = static_cast<float>(t);
        while (cell_of(f, n) > cell) f = std::nextafter(f, 0.f);
        while (cell_of(f, n) < cell) f = std::nextafter(f, 1.f);
        return f;
    }
    float value(int i, int j) const {
        return m_f[static_cast<std::size_t>(j) * static_cast<std::size_t>(m_nx) + static_cast<std::size_t>(i)];
    }
    double S(int i, int j) const {
        return m_sat[static_cast<std::size_t>(j) * (static_cast<std::size_t>(m_nx) + 1) + static_cast<std::size_t>(i)];
    }
    /// ∫₀ˣ∫₀ʸ f: bilinear in the cell's corners, exact for a piecewise-constant f.
    double F(double x, double y) const {
        const double gx = x * m_nx, gy = y * m_ny;
        const int i = std::clamp(static_cast<int>(gx), 0, m_nx - 1), j = std::clamp(static_cast<int>(gy), 0, m_ny - 1);
        const double fx = gx - i, fy = gy - j;
        return (S(i, j) * (1 - fx) + S(i + 1, j) * fx) * (1 - fy) + (S(i, j + 1) * (1 - fx) + S(i + 1, j + 1) * fx) * fy;
    }
    /// A row of S and the fraction of the way to the next, for F(·, y).
    struct RowLerp {
        int j;
        double f;
    };
    RowLerp row_lerp(double y) const {
        const double gy = y * m_ny;
        const int j = std::clamp(static_cast<int>(gy), 0, m_ny - 1);
        return {j, gy - j};
    }
    /// F(i / nx, y), the row given by row_lerp(y).
    double F_at_column_edge(int i, const RowLerp& r) const { return S(i, r.j) * (1 - r.f) + S(i, r.j + 1) * r.f; }
    /// The t in [a, b] where the non-decreasing, cell-wise linear `mass` (mass(a) = 0) reaches
    /// `target` < mass(b); `cell` gets the cell (of n over [0, 1]) it lies in. `mass_at_edge(k)`
    /// is mass(k / n), for the edges strictly inside (a, b) that the search reads.
    template <class Mass, class MassAtEdge>
    static double invert(const Mass& mass, const MassAtEdge& mass_at_edge, double target, double a, double b, int n,
                         int& cell) {
        // The first cell whose upper edge (clipped to b) holds more than the target. Inside the
        // loop mid < hi ≤ ⌈b·n⌉ − 1, so the edge mid + 1 lies below b.
        int lo = cell_of(a, n), hi = std::max(lo, std::min(n - 1, static_cast<int>(std::ceil(b * n)) - 1));
        while (lo < hi) {
            const int mid = (lo + hi) / 2;
            if (mass_at_edge(mid + 1) > target) hi = mid;
            else lo = mid + 1;
        }
        cell = lo;
        const double s0 = std::max(a, double(lo) / n), s1 = std::min(b, double(lo + 1) / n);
        const double m0 = mass(s0), m1 = mass(s1);
        const double t = m1 > m0 ? s0 + (target - m0) / (m1 - m0) * (s1 - s0) : s0;
        return std::clamp(t, s0, s1);
    }
};

}  // namespace spt
