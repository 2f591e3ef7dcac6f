// The refraction chain through a smooth dielectric sphere, and the single mirror reflection
// off a sphere, as one-dimensional problems: the light paths x → (refract in) → (refract
// out) → y, or x → (reflect) → y, between two points outside a sphere of centre c, radius R
// and relative index η > 1 (inside over outside), and the density of the direction leaving x
// per unit area at y. Used by specular next-event estimation (render/caustic_nee.h):
// caustics seen on diffuse surfaces under glass balls and beside shiny ones.
//
// Why one dimension. Refraction keeps a ray in its plane of incidence, which contains the
// surface normal, so for a sphere it contains c: the whole chain lies in the plane through
// x, c and y (Walter, Zhao, Novák, Bala 2009, "Single scattering in refractive media with
// triangle mesh boundaries", solve the same kind of chain as a low-dimensional root search;
// Hanika, Droske, Fascione 2015, "Manifold next event estimation", and Zeltner, Georgiev,
// Jakob 2020, "Specular manifold sampling", solve general chains by Newton iteration on the
// specular manifold, whose roots they may miss; here the sphere's symmetry reduces it to a
// scalar equation whose roots are all bracketed).
//
// The plane's frame: origin x, axis e1 = (c − x)/D (D = |c − x|), e2 the direction of y's
// component perpendicular to e1; y = (y_a, ρ_y) with ρ_y ≥ 0 its distance from the axis.
// Parameter: the signed entry angle θ ∈ [−π/2, π/2] (angle of incidence; its sign says on
// which side of the axis the ray passes). With η' = 1/η, everything follows in closed form:
//   direction leaving x at angle α from the axis:  sin α = (R/D)·sin θ
//   refraction angle inside:                       sin θt = sin θ/η
//   exit point at polar angle (about c)            φ2 = α − θ + 2θt
//   exit direction at angle                        β  = α − 2(θ − θt)   (deflection 2(θ − θt))
// and the chain reaches y exactly where g(θ) = e(β) × (y − P2(θ)) = 0 with y ahead of the exit
// point (e(β)·(y − P2) > 0); g is the signed distance of y from the exit ray. Differentiating
// (with α' = R·cos θ/(D·cos α), θt' = cos θ/(η·cos θt), and β − φ2 = −θ):
//   g'(θ) = −β'·e(β)·(y − P2) − R·φ2'·cos θ,   β' = α' − 2 + 2θt',  φ2' = α' − 1 + 2θt'.
//
// The measure conversion (the Jacobian). The configuration is symmetric about the axis x–c:
// directions leaving x are (α, φ) with φ the rotation about the axis, dω_x = sin|α|·dα·dφ. At
// y the bundle of exit rays of dα·dφ has, perpendicular to the central ray, the width
// |∂y⊥/∂α|·dα in the plane (∂y⊥/∂α = −dg/dα: the rate at which the exit ray sweeps past the
// fixed point y) and ρ_y·dφ across it (rotating about the axis moves the ray's point at y by
// ρ_y·dφ, perpendicular to the plane). A surface element dA_y with normal n_y at angle θ_y to
// the exit ray intercepts the cross-section |cos θ_y|·dA_y, so
//   |dω_x/dA_y| = |cos θ_y|·sin|α| / (|dg/dα|·ρ_y) = |cos θ_y|·sin|α|·α' / (|g'(θ)|·ρ_y).
// Degenerate cases: y on the axis (ρ_y → 0) makes the solutions a ring (a set of measure zero
// on the light: no roots are returned below a relative ρ_y of 1e-9); α → 0 (the ray along the
// axis) gives a density → 0, which is finite; a fold of the map (g' = 0: y on the caustic
// surface) gives |dω/dA| → ∞: an integrable singularity that the caller's MIS against BSDF
// sampling tames (its weight → 0 where this density → ∞).
//
// The reflection chain x → (reflect at P1) → y (Alhazen's billiard problem: up to four
// solutions on the whole circle; with P1 on the side of the sphere x sees and y ahead of
// the reflected ray the test never found more than one in 3000 random configurations, as
// expected of a convex mirror's single virtual image). The mirror law keeps the ray in the plane of incidence, which contains the
// normal and so c: the same plane and frame, the same parameter θ (the signed angle of
// incidence at P1) and the same α (sin α = (R/D)·sin θ: the ray's distance from c is
// D·sin α = R·sin θ). The normal at P1 = c + R·e(φ1) points back at x's side rotated by the
// incidence, φ1 = π + α − θ (θ = 0: the point of the sphere nearest x), and the reflected
// ray leaves at β = π + α − 2θ (θ = 0: straight back). These are the refraction chain's
// formulas with θt = π/2 held fixed (φ2 = α − θ + 2θt = φ1, β = α − 2(θ − θt)), so one code
// evaluates both: the tables hold sin θt = 1, cos θt = 0, and θt' = 0 in the derivative,
//   g'(θ) = −β'·e(β)·(y − P1) − R·φ1'·cos θ,   β' = α' − 2,  φ1' = α' − 1
// (d/dθ of e(β) × w is β'·e⊥(β) × w − e(β) × dP1/dθ; e⊥(β) × w = −e(β)·w; dP1/dθ =
// R·φ1'·e⊥(φ1) and e(β) × e⊥(φ1) = cos(β − φ1) = cos θ). The Jacobian's derivation above
// uses only the axial symmetry of the configuration about x–c and the map θ ↦ the outgoing
// ray, both of which reflection shares, so |dω_x/dA_y| = |cos θ_y|·sin|α|·α'/(|g'(θ)|·ρ_y)
// holds unchanged (the test compares it with a 3-D finite difference). The exit ray turns by
// |β'|·π/kCells ≤ 2π/16 per cell, so the "ahead" filter of the scan below holds as well.
// SphereChainRoot: entry = exit = P1, cos_in = cos θ, cos_t = 0 (no refraction).
//
// Root finding: the sign of g is evaluated at kCells + 1 equally spaced θ (π/kCells apart;
// everything that depends on θ and η alone is tabulated once per sphere, SphereChainNodes, so
// a node costs one square root, and the loop vectorises) and each cell whose ends differ in
// sign is refined by Newton's method safeguarded by bisection, in double, to |Δθ| < 1e-13.
// Sign changes where y lies behind the exit ray (e(β)·(y − P2) < 0) are roots of g but not
// chains: rejected after refinement. A root is missed only when its cell holds an even
// number of sign changes: two roots closer than π/kCells = 0.196 rad in θ, which happens
// near a fold (where two roots merge) or, for a forward and a backward root, with y close to
// the sphere. kCells = 16: the count test (dense scan of 20 000 cells, 3000 random
// configurations, tests/test_sphere_caustics.cpp) misses 4 of 777 roots, all in pairs at
// folds (32 cells miss none, but cost 10 % more time per path for a relMSE equal within
// the noise). The caller stays exact regardless: the BSDF-sampling side of MIS
// asks this same solver whether it would have found the path's root (find_matching_root)
// and gives weight 1 when not.
//
// Error: the roots are exact to double rounding of the closed form (the test traces each
// found direction through the sphere with Snell's law in 3-D and finds it within 1e-6 of y).
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/dvec3.h"

namespace spt {

/// One solution of the chain x → sphere → sphere → y (refraction) or x → sphere → y (reflection).
struct SphereChainRoot {
    DVec3 wx;         ///< unit direction leaving x
    DVec3 entry;      ///< entry point on the sphere
    DVec3 exit;       ///< exit point on the sphere
    DVec3 w_exit;     ///< unit direction leaving the exit point (towards y)
    double cos_in;    ///< cos θ: angle of incidence at entry (from outside) ≥ 0
    double cos_t;     ///< cos θt: angle of the chord to the normal inside (incidence at exit)
    double sin_theta;  ///< sin θ, the solver's variable
    double theta;      ///< the signed parameter θ
    /// |dω_x/dA_⊥|: the direction density per unit area perpendicular to the exit ray at y
    /// (multiply by |cos θ_y| for the density per unit area of a surface at y).
    double dw_dAperp;
};

/// What the grid of θ needs that depends on θ and η alone, per node θ_k = −π/2 + k·π/kCells:
/// sin θ and the unit complex numbers e^{i(2θt − 2θ)} and e^{i(2θt − θ)} (θt = π/2 for the
/// reflection chain).
struct SphereChainNodes {
    static constexpr int kCells = 16;
    double eta = 0;
    bool reflect = false;  ///< the reflection chain x → P1 → y (eta unused)
    double s[kCells + 1], q2r[kCells + 1], q2i[kCells + 1], pr[kCells + 1], pi[kCells + 1];

    /// The refraction chain's table for index eta_ > 1.
    explicit SphereChainNodes(double eta_ = 1.5) : SphereChainNodes(eta_, false) {}
    /// The reflection chain's table (one for every sphere).
    static SphereChainNodes reflection() { return SphereChainNodes(0.0, true); }

private:
    SphereChainNodes(double eta_, bool reflect_) : eta(eta_), reflect(reflect_) {
        for (int k = 0; k <= kCells; ++k) {
            const double t = -0.5 * kPiDouble + k * (kPiDouble / kCells);
            const double sk = std::sin(t), ck = std::cos(t);
            const double st = reflect ? 1.0 : sk / eta, ct = reflect ? 0.0 : std::sqrt(std::max(0.0, 1.0 - st * st));
            const double qr = ct * ck + st * sk, qi = st * ck - ct * sk;  // e^{i(θt − θ)}
            s[k] = sk;
            q2r[k] = qr * qr - qi * qi, q2i[k] = 2.0 * qr * qi;
            pr[k] = qr * ct - qi * st, pi[k] = qr * st + qi * ct;
        }
    }
};

/// The chain problem for one sphere: the frame and the constants of g.
class SphereChain {
public:
    static constexpr int kCells = SphereChainNodes::kCells;
    static constexpr int kMaxRoots = 8;  ///< more are dropped (never seen; the caller stays exact)

    /// x and y must be outside the sphere (else no roots); nodes.eta > 1 is the index, or
    /// nodes.reflect chooses the reflection chain.
    SphereChain(const DVec3& x, const DVec3& c, double R, const SphereChainNodes& nodes, const DVec3& y)
        : m_x(x), m_c(c), m_R(R), m_eta(nodes.eta), m_nodes(&nodes), m_reflect(nodes.reflect) {
        const double eta = m_eta;
        const DVec3 axis = c - x;
        m_D = length(axis);
        const DVec3 xy = y - x;
        m_ok = m_D > R && length(y - c) > R && (eta > 1.0 || m_reflect);
        if (!m_ok) return;
        m_e1 = axis * (1.0 / m_D);
        m_ya = dot(xy, m_e1);
        const DVec3 perp = xy - m_e1 * m_ya;
        m_rho = length(perp);
        m_ok = m_rho > 1e-9 * (m_D + length(xy));
        if (m_ok) m_e2 = perp * (1.0 / m_rho);
    }

    bool valid() const { return m_ok; }
    double rho_y() const { return m_rho; }
    const DVec3& e1() const { return m_e1; }
    const DVec3& e2() const { return m_e2; }

    /// Every root (forward: y ahead of the exit ray), in increasing θ; returns their number.
    int solve(SphereChainRoot out[kMaxRoots]) const {
        if (!m_ok) return 0;
        // g at every node (the closed form of eval() with the tabulated parts).
        const SphereChainNodes& t = *m_nodes;
        const double r_over_d = m_R / m_D, R = m_R, ya_d = m_ya - m_D, rho = m_rho;
        double g[kCells + 1], along[kCells + 1];
        for (int k = 0; k <= kCells; ++k) {
            const double sa = r_over_d * t.s[k];
            const double ca = std::sqrt(1.0 - sa * sa);
            const double br = ca * t.q2r[k] - sa * t.q2i[k], bi = ca * t.q2i[k] + sa * t.q2r[k];
            const double fr = ca * t.pr[k] - sa * t.pi[k], fi = ca * t.pi[k] + sa * t.pr[k];
            const double wa = ya_d - R * fr, wh = rho - R * fi;
            g[k] = br * wh - bi * wa;
            along[k] = br * wa + bi * wh;
        }
        int n = 0;
        double h_prev = g[0];
        for (int k = 1; k <= kCells && n < kMaxRoots; ++k) {
            const double h = g[k];
            // A sign change with y behind the exit ray at both ends is a backward root: a root
            // where y is ahead lies within the cell only if the exit ray turns by more than
            // π/2 across it, which no cell away from grazing incidence does.
            if (((h_prev < 0.0) != (h < 0.0) || h == 0.0) && (along[k - 1] > 0.0 || along[k] > 0.0)) {
                const double s = refine(t.s[k - 1], h_prev, t.s[k], h);
                if ((n == 0 || s - out[n - 1].sin_theta > 1e-12) && make_root(s, out[n])) ++n;
            }
            h_prev = h;
        }
        return n;
    }

    /// The evaluation at θ (refinement, tests and the dense scan).
    struct Eval {
        double h = 0;      ///< g/|y − P2|: the sine of the angle at which the exit ray misses y
        double g = 0;      ///< signed distance of y from the exit ray
        double along = 0;  ///< e(β)·(y − P2)
        double dg = 0;     ///< dg/dθ
        double sa = 0, ca = 0, ct = 0, alpha_p = 0;
        double p2a = 0, p2h = 0, da = 0, dh = 0;  ///< exit point and direction in the plane
    };
    Eval eval(double s, double c) const {
        Eval e;
        const double sa = m_R / m_D * s;
        const double ca = std::sqrt(std::max(0.0, 1.0 - sa * sa));
        // θt: refracted, or π/2 for the reflection chain (see the header).
        const double st = m_reflect ? 1.0 : s / m_eta;
        const double ct = m_reflect ? 0.0 : std::sqrt(std::max(0.0, 1.0 - st * st));
        // q = e^{i(θt − θ)}
        const double qr = ct * c + st * s, qi = st * c - ct * s;
        // e^{iβ} = e^{iα}·q², e^{iφ2} = e^{iα}·q·e^{iθt}
        const double q2r = qr * qr - qi * qi, q2i = 2.0 * qr * qi;
        const double br = ca * q2r - sa * q2i, bi = ca * q2i + sa * q2r;
        const double pr0 = qr * ct - qi * st, pi0 = qr * st + qi * ct;
        const double fr = ca * pr0 - sa * pi0, fi = ca * pi0 + sa * pr0;
        e.p2a = m_D + m_R * fr;
        e.p2h = m_R * fi;
        e.da = br, e.dh = bi;
        const double wa = m_ya - e.p2a, wh = m_rho - e.p2h;
        e.g = br * wh - bi * wa;
        e.along = br * wa + bi * wh;
        e.h = e.g / std::sqrt(wa * wa + wh * wh);
        const double alpha_p = m_R * c / (m_D * ca);
        const double theta_t_p = m_reflect ? 0.0 : c / (m_eta * ct);
        const double beta_p = alpha_p - 2.0 + 2.0 * theta_t_p;
        const double phi2_p = alpha_p - 1.0 + 2.0 * theta_t_p;
        e.dg = -beta_p * e.along - m_R * phi2_p * c;
        e.sa = sa, e.ca = ca, e.ct = ct, e.alpha_p = alpha_p;
        return e;
    }

    /// Builds the root at θ (false when y is not ahead of the exit ray there).
    bool make_root(double s, SphereChainRoot& r) const {
        const double c = std::sqrt(std::max(0.0, 1.0 - s * s));
        const Eval e = eval(s, c);
        if (!(e.along > 0.0) || !(std::fabs(e.h) < 1e-9)) return false;
        r.sin_theta = s;
        r.theta = std::asin(s);
        r.wx = m_e1 * e.ca + m_e2 * e.sa;
        // Entry at polar angle φ1 = π + α − θ about c.
        const double er = -(e.ca * c + e.sa * s), ei = -(e.sa * c - e.ca * s);
        r.entry = m_c + (m_e1 * er + m_e2 * ei) * m_R;
        r.exit = m_x + m_e1 * e.p2a + m_e2 * e.p2h;
        r.w_exit = m_e1 * e.da + m_e2 * e.dh;
        r.cos_in = c;
        r.cos_t = e.ct;
        // |dω/dA⊥| = sin|α|·α' / (|g'|·ρ_y); at a fold (g' = 0) infinite.
        r.dw_dAperp = std::fabs(e.sa) * e.alpha_p / (std::fabs(e.dg) * m_rho);
        return true;
    }

    /// The index of the root among `roots` whose direction leaving x is nearest to the unit
    /// vector w, if within `tolerance` (distance between unit vectors, about the angle), or −1.
    /// For weighting a path that BSDF sampling found against this solver.
    static int find_matching_root(const SphereChainRoot* roots, int n, const DVec3& w, double tolerance) {
        int best = -1;
        double best_d = tolerance;
        for (int i = 0; i < n; ++i) {
            const double d = length(roots[i].wx - w);
            if (d < best_d) best_d = d, best = i;
        }
        return best;
    }

private:
    /// The root of g in [ta, tb] (sines of θ; g(ta) and g(tb) of opposite signs): Newton's
    /// method from the secant's guess, each step kept inside the bracket (else bisection).
    /// Working in s = sin θ needs no trigonometry: cos θ = √(1 − s²), dg/ds = g'(θ)/cos θ.
    double refine(double ta, double ha, double tb, double hb) const {
        if (hb == 0.0) return tb;
        double t = ta + (tb - ta) * (ha / (ha - hb));
        if (!(t > ta && t < tb)) t = 0.5 * (ta + tb);
        for (int it = 0; it < 60; ++it) {
            const double c = std::sqrt(std::max(0.0, 1.0 - t * t));
            const Eval e = eval(t, c);
            if (e.g == 0.0) break;
            if ((e.g < 0.0) == (ha < 0.0)) ta = t, ha = e.g;
            else tb = t;
            if (tb - ta < 1e-13) break;
            double next = 0.5 * (ta + tb);
            const double step = e.g * c / e.dg;
            const double tn = t - step;
            if (std::isfinite(tn) && tn > ta && tn < tb) next = tn;
            if (std::fabs(step) < 1e-13) {  // converged: t − step, kept in the bracket
                t = std::clamp(tn, ta, tb);
                break;
            }
            t = next;
        }
        return t;
    }

    DVec3 m_x, m_c, m_e1, m_e2;
    double m_R, m_eta;
    const SphereChainNodes* m_nodes;
    bool m_reflect = false;
    double m_D = 0, m_ya = 0, m_rho = 0;
    bool m_ok = false;
};

/// The first point where the ray x + t·w (w unit, x outside) meets the sphere, for the 3-D
/// tracers below: false when it misses.
inline bool first_sphere_hit(const DVec3& x, const DVec3& w, const DVec3& c, double R, DVec3& p) {
    const DVec3 oc = x - c;
    const double b = dot(oc, w), cc = dot(oc, oc) - R * R;
    const double disc = b * b - cc;
    if (disc < 0.0) return false;
    const double t1 = -b - std::sqrt(disc);
    if (t1 <= 0.0) return false;
    p = x + w * t1;
    return true;
}

/// A ray x + t·w traced through the sphere with Snell's law in 3-D (entry, chord, exit), for
/// tests: false when it misses the sphere or is totally reflected.
inline bool trace_through_sphere(const DVec3& x, const DVec3& w, const DVec3& c, double R, double eta, DVec3& exit,
                                 DVec3& w_exit) {
    auto refract3 = [](const DVec3& d, const DVec3& n, double eta_rel, DVec3& out) {
        // d arrives against n (dot(d, n) < 0); eta_rel = η_t/η_i.
        const double ci = -dot(d, n);
        const double s2 = (1.0 - ci * ci) / (eta_rel * eta_rel);
        if (s2 >= 1.0) return false;
        out = normalize(d * (1.0 / eta_rel) + n * (ci / eta_rel - std::sqrt(1.0 - s2)));
        return true;
    };
    DVec3 p1;
    if (!first_sphere_hit(x, w, c, R, p1)) return false;
    DVec3 d1;
    if (!refract3(w, (p1 - c) * (1.0 / R), eta, d1)) return false;
    // Inside: the far intersection of p1 + t·d1.
    const double t2 = -2.0 * dot(p1 - c, d1);
    exit = p1 + d1 * t2;
    return refract3(d1, -((exit - c) * (1.0 / R)), 1.0 / eta, w_exit);
}

/// A ray x + t·w mirrored off the sphere in 3-D, for tests: false when it misses the sphere.
inline bool reflect_off_sphere(const DVec3& x, const DVec3& w, const DVec3& c, double R, DVec3& p, DVec3& w_out) {
    if (!first_sphere_hit(x, w, c, R, p)) return false;
    const DVec3 n = (p - c) * (1.0 / R);
    w_out = normalize(w - n * (2.0 * dot(w, n)));
    return true;
}

}  // namespace spt
