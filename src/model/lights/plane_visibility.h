// The directions from a point that can reach an emitting infinite plane past the scene's other
// infinite planes (the Cornell walls), on the side a surface gathers light on: a convex
// spherical polygon, and its projected solid angle.
//
// From p (distance s > 0 from the emitting plane, m its unit normal turned towards it), the
// direction ω with ω·m > 0 meets the plane at x = p + ω·s/(ω·m). Another plane Q (unit
// normal q turned towards p, p at distance d > 0 from it) hides x iff x lies beyond Q, since
// the segment p–x then crosses it. q·x − offset = d + s·(q·ω)/(ω·m), and ω·m > 0, so x is
// seen past Q iff ω·(d·m + s·q) > 0: one hemisphere of directions per plane. With the surface's
// own hemisphere ω·ns > 0 and the plane's ω·m > 0 (their intersection is the lune of
// plane_light.h), the directions left are an intersection of hemispheres: a convex spherical
// polygon, found by clipping the lune (Sutherland–Hodgman on the sphere: a great circle cuts
// an arc where the signed distances of its ends change sign, at the positive combination
// a·|d_b| + b·|d_a|).
//
// Its projected solid angle (Lambert 1760; Arvo 1995, "Applications of irradiance tensors",
// eq. 8) is Φ = ½ Σ_edges θ_e (ns·u_e), θ_e the edge's arc and u_e the unit normal of its
// great circle on the polygon's side, exact for any convex polygon on one side of ns: the
// irradiance a unit radiance gives through it. The lune alone has Φ = π(1 + c)/2, c = ns·m.
//
// Edges are kept below 180°: a lune's two vertices are antipodal, so it starts as four
// vertices 90° apart, and a new edge longer than 90° gets its point 90° along (both halves
// then shorter than 180°, where the cross product names the great circle).
//
// The clipping depends on p only through the side of each blocker p lies on (its sign
// vector): the ceiling points seen past the blockers are the emitting plane's points on p's
// side of every blocker, a convex planar region (unbounded where the box is open). So it is
// built once per sign vector (PlaneRegion, visible_region: the same Sutherland–Hodgman clip,
// in the homogeneous coordinates (X, Y, W) of the plane, whose directions W ≥ 0 are a
// hemisphere; W = 0 are its points at infinity, and an edge between two of them is the
// plane's horizon). At p the polygon is the image of that region under the linear map
// (X, Y, W) ↦ X·t1 + Y·t2 + W·(o − p) (o the plane's point nearest the origin), which takes
// arcs below 180° to arcs below 180° and keeps the polygon convex; only the clip by the
// surface's own hemisphere ω·ns ≥ 0 remains, and only when a vertex lies below it.
//
// Accuracy: the polygon's vertices and Φ are float (relative error ~1e-6); where ns is within
// 1e-4 of m the lune is taken as ns's hemisphere, whose extra sliver (ω·m < 0) holds at most
// ~1e-4 of Φ.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

#include "core/fast_math.h"
#include "core/frame.h"
#include "core/math.h"
#include "core/simd.h"
#include "core/vec3.h"

namespace spt {

/// A plane that hides what lies beyond it: unit normal and offset (dot(normal, x) = offset).
struct PlaneBlocker {
    Vec3 normal;
    float offset = 0.f;
};

inline constexpr int kMaxPlaneBlockers = 8;
/// Vertices a clipped polygon can reach: the lune's 4, and per great circle at most one
/// more plus the point that splits its new edge.
inline constexpr int kMaxSphericalVertices = 4 + 2 * (kMaxPlaneBlockers + 1);

/// A vertex of a region of the emitting plane in homogeneous form: the point v/w (w > 0), or
/// for w = 0 the point at infinity in direction v. The direction from p towards it is v − w·p.
struct HomogeneousVertex {
    Vec3 v;
    float w = 0.f;
};

/// The part of the emitting plane seen past the blockers from the points on given sides of
/// them: a convex region, its vertices counter-clockwise about the plane's normal cross(t1,
/// t2) of visible_region; fewer than 3: nothing is seen.
struct PlaneRegion {
    static constexpr int kMaxCount = 4 + 2 * kMaxPlaneBlockers;
    std::array<HomogeneousVertex, kMaxCount> vertex{};
    int count = 0;
    /// The vertices again in lanes (VisibleLune::build transforms four at a time): component
    /// arrays of v and w, [0] in the order of `vertex`, [1] reversed; lanes past count hold
    /// (1, 0, 0, 0), whose directions are finite and ignored.
    static constexpr int kLanes = (kMaxCount + 3) / 4 * 4;
    alignas(16) float x[2][kLanes]{}, y[2][kLanes]{}, z[2][kLanes]{}, w[2][kLanes]{};

    /// Fills the lanes from vertex[0, count).
    void make_lanes() {
        for (int order = 0; order < 2; ++order)
            for (int i = 0; i < kLanes; ++i) {
                const bool used = i < count;
                const HomogeneousVertex h = used ? vertex[static_cast<std::size_t>(order ? count - 1 - i : i)]
                                                 : HomogeneousVertex{{1.f, 0.f, 0.f}, 0.f};
                x[order][i] = h.v.x, y[order][i] = h.v.y, z[order][i] = h.v.z, w[order][i] = h.w;
            }
    }
};

/// Clips the convex spherical polygon v[0, n) (unit vertices counter-clockwise about the
/// inside: v_i × v_{i+1} points into it, every edge below 180°) to ω·g ≥ 0 in place; v must
/// hold n + 2 vertices. Returns the new count.
inline int clip_spherical_polygon(Vec3* v, int n_in, const Vec3& g) {
    Vec3 out[kMaxSphericalVertices + 2];
    int n = 0, exit = -1;
    for (int i = 0; i < n_in; ++i) {
        const Vec3& a = v[i];
        const Vec3& b = v[i + 1 == n_in ? 0 : i + 1];
        const float da = dot(a, g), db = dot(b, g);
        const bool in_a = da >= 0.f, in_b = db >= 0.f;
        if (in_a) out[n++] = a;
        if (in_a != in_b) {
            if (in_a) exit = n;
            out[n++] = normalize(a * std::fabs(db) + b * std::fabs(da));
        }
    }
    if (exit >= 0 && n >= 2) {
        // The new edge runs from the exit point counter-clockwise about g to the entry
        // point; past 90° it gets the point 90° along, g × exit.
        const Vec3 x = out[exit], e = out[(exit + 1) % n];
        if (dot(x, e) < 0.f) {
            for (int j = n; j > exit + 1; --j) out[j] = out[j - 1];
            out[exit + 1] = normalize(cross(g, x));
            ++n;
        }
    }
    int kept = 0;
    for (int i = 0; i < n; ++i) {  // drop repeated vertices (a corner on the circle)
        const Vec3& next = out[i + 1 == n ? 0 : i + 1];
        if (length_squared(cross(out[i], next)) > 1e-14f || dot(out[i], next) < 0.f) v[kept++] = out[i];
    }
    return kept;
}

class VisibleLune {
public:
    static constexpr int kMaxBlockers = kMaxPlaneBlockers;
    static constexpr int kMaxVertices = kMaxSphericalVertices;

    /// p at distance s > 0 from the emitting plane, m its normal towards it, ns the gathering
    /// side's normal (1 + ns·m > 0); blockers[0, count) the other planes (at most kMaxBlockers).
    VisibleLune(const Vec3& p, const Vec3& ns, const Vec3& m, double s, const PlaneBlocker* blockers, int count)
        : m_ns(ns) {
        make_lune(ns, m);
        m_g[m_constraints++] = m;
        for (int i = 0; i < count && m_vertices >= 3; ++i) {
            const PlaneBlocker& b = blockers[i];
            const double d = double(b.normal.x) * p.x + double(b.normal.y) * p.y + double(b.normal.z) * p.z -
                             b.offset;
            // p on Q (its own surface): rays leave Q, it hides nothing.
            if (std::fabs(d) <= 1e-5 * std::max(1.0, std::fabs(double(b.offset)))) continue;
            const Vec3 q = d > 0.0 ? b.normal : -b.normal;
            // Parallel to the emitting plane (a floor under a ceiling): g is along ±m; behind p or
            // beyond the plane it hides nothing, between them everything.
            if (const float qm = dot(q, m); std::fabs(qm) >= 1.f - 1e-7f) {
                if (qm > 0.f || std::fabs(d) > s) continue;
                m_vertices = 0;
                break;
            }
            const Vec3 g = m * static_cast<float>(std::fabs(d)) + q * static_cast<float>(s);
            const float g_len = length(g);
            if (!(g_len > 0.f)) continue;
            const Vec3 gu = g / g_len;
            m_g[m_constraints++] = gu;
            clip(gu);
        }
        if (m_vertices < 3) m_vertices = 0;
        pack_vertices();
        finish(false);
        pack_constraints();
    }

    /// The same polygon from the region of the emitting plane that p's sides of the blockers
    /// see (visible_region): its vertices' directions from p (in reverse order when the map of
    /// the top of the file turns the orientation, `reverse`), clipped by ns's hemisphere only
    /// when a vertex lies below it.
    VisibleLune(const Vec3& p, const Vec3& ns, const PlaneRegion& region, bool reverse) {
        build(p, ns, region, reverse);
    }
    /// Empty (for a slot that build() fills later).
    constexpr VisibleLune() = default;

    /// Makes this the polygon of the constructor above (in place: no copy of the arrays).
    void build(const Vec3& p, const Vec3& ns, const PlaneRegion& region, bool reverse) {
        m_ns = ns;
        const int n = region.count;
        bool below = false;
        // Four vertices at a time, each lane the scalar operations of one vertex (the same
        // bits): e = v − p·w, d = e·(1/|e|).
        const int order = reverse ? 1 : 0;
        for (int i0 = 0; i0 < n; i0 += 4) {
            const Float4 vx = load4(&region.x[order][i0]), vy = load4(&region.y[order][i0]);
            const Float4 vz = load4(&region.z[order][i0]), vw = load4(&region.w[order][i0]);
            const Float4 ex = vx - p.x * vw, ey = vy - p.y * vw, ez = vz - p.z * vw;
            const Float4 inv = 1.f / sqrt4(ex * ex + ey * ey + ez * ez);
            const Float4 dx = ex * inv, dy = ey * inv, dz = ez * inv;
            // A vertex on ns's horizon (a region's corner on the wall p lies on) is off it
            // by rounding only: the sliver below, ∫ω·ns over it of order 1e-10 of Φ, is kept.
            const int used = n - i0 < 4 ? n - i0 : 4;
            below |= (lane_bits(dx * ns.x + dy * ns.y + dz * ns.z < -1e-5f) & ((1u << used) - 1u)) != 0;
            m_vx[i0 / 4] = dx, m_vy[i0 / 4] = dy, m_vz[i0 / 4] = dz;
        }
        m_vertices = n;
        if (below && n >= 3) {
            for (int i = 0; i < n; ++i) m_v[i] = vertex(i);
            clip(ns);
            pack_vertices();
        }
        if (m_vertices < 3) m_vertices = 0;
        // A convex polygon with edges below 180° holds ω iff ω is on the inner side of
        // every edge's great circle: the constraints are the edges' normals v_i × v_{i+1},
        // which finish() computes for Lambert's formula anyway and keeps.
        m_constraints = m_vertices;
        finish(true);
    }

    bool empty() const { return !(m_projected_area > 0.f); }
    /// The tightest lune about ns that holds the polygon among those cut by its edges' great
    /// circles (any edge's circle bounds a convex polygon): its unit normal g towards the
    /// polygon and c = ns·g (the lune's projected area is π(1 + c)/2); c = 2 without edges.
    const Vec3& bound_normal() const { return m_bound; }
    float bound_c() const { return m_bound_c; }
    /// True if ω (unit, ω·ns > 0 assumed) is in the polygon: on the plane's side and past every blocker.
    bool contains(const Vec3& w) const {
        // Four constraints at a time (lanes past m_constraints hold g = 0: 0 ≥ 0 passes).
        const Float4 wx = splat4(w.x), wy = splat4(w.y), wz = splat4(w.z);
        for (int k = 0; k * 4 < m_constraints; ++k)
            if (lane_bits(wx * m_gx[k] + wy * m_gy[k] + wz * m_gz[k] >= 0.f) != 0xfu) return false;
        return true;
    }
    /// contains() for four directions in lanes (components wx, wy, wz): a mask, all ones in
    /// the lanes it holds (each lane the scalar test's operations).
    Int4 contains(const Float4& wx, const Float4& wy, const Float4& wz) const {
        Int4 inside = Int4{} - 1;
        for (int i = 0; i < m_constraints; ++i) {
            const float gx = m_gx[i / 4][i % 4], gy = m_gy[i / 4][i % 4], gz = m_gz[i / 4][i % 4];
            inside &= wx * gx + wy * gy + wz * gz >= 0.f;
        }
        return inside;
    }
    float area() const { return m_projected_area; }
    int vertex_count() const { return m_vertices; }
    Vec3 vertex(int i) const { return {m_vx[i / 4][i % 4], m_vy[i / 4][i % 4], m_vz[i / 4][i % 4]}; }

private:
    /// The lune as four vertices 90° apart, counter-clockwise about the inside (v_i × v_{i+1}
    /// points into it): b, the point of ns's horizon nearest m, −b, the point of m's horizon
    /// nearest ns, with b = m × ns / |m × ns|.
    void make_lune(const Vec3& ns, const Vec3& m) {
        const Vec3 mxn = cross(m, ns);
        const float len = length(mxn);
        if (len < 1e-4f) {  // m along ns: ns's whole hemisphere (the caller excludes m = −ns)
            const Frame f(ns);
            m_v[0] = f.s, m_v[1] = f.t, m_v[2] = -f.s, m_v[3] = -f.t;
        } else {
            const Vec3 b = mxn / len;
            m_v[0] = b;
            m_v[1] = normalize(cross(ns, b));  // ns's horizon, on m's side
            m_v[2] = -b;
            m_v[3] = normalize(cross(b, m));   // m's horizon, on ns's side
        }
        m_vertices = 4;
    }

    /// Keeps the part with ω·g ≥ 0.
    void clip(const Vec3& g) { m_vertices = clip_spherical_polygon(m_v, m_vertices, g); }

    Vec3 m_ns;
    /// The vertices in lanes (components of vertices 4k … 4k + 3; lanes past m_vertices are
    /// ignored), and as vectors where a clip works on them (m_v: scratch of the clipping).
    static constexpr int kVertexGroups = (kMaxVertices + 2 + 3) / 4;
    Float4 m_vx[kVertexGroups]{}, m_vy[kVertexGroups]{}, m_vz[kVertexGroups]{};
    Vec3 m_v[kMaxVertices + 2];
    int m_vertices = 0;
    /// Copies m_v[0, m_vertices) into the lanes.
    void pack_vertices() {
        for (int i = 0; i < m_vertices; ++i)
            m_vx[i / 4][i % 4] = m_v[i].x, m_vy[i / 4][i % 4] = m_v[i].y, m_vz[i / 4][i % 4] = m_v[i].z;
    }
    Vec3 m_g[kMaxVertices + 2];  ///< the clipping constructor's constraints ω·g ≥ 0 (scratch of pack_constraints)
    int m_constraints = 0;
    /// m_g in lanes for contains(): components of constraints 4k … 4k + 3, zero past m_constraints.
    static constexpr int kConstraintGroups = (kMaxVertices + 2 + 3) / 4;
    Float4 m_gx[kConstraintGroups]{}, m_gy[kConstraintGroups]{}, m_gz[kConstraintGroups]{};
    /// Copies m_g[0, m_constraints) into the lanes.
    void pack_constraints() {
        for (int k = 0; k * 4 < m_constraints; ++k)
            for (int j = 0; j < 4; ++j) {
                const int i = 4 * k + j;
                const Vec3 g = i < m_constraints ? m_g[i] : Vec3(0.f, 0.f, 0.f);
                m_gx[k][j] = g.x, m_gy[k][j] = g.y, m_gz[k][j] = g.z;
            }
    }
    float m_projected_area = 0.f;
    Vec3 m_bound;
    float m_bound_c = 2.f;

    /// Φ (Lambert's formula, top of the file) and the bounding edge from the vertices' lanes;
    /// edges_are_constraints: the constraints' lanes become the edges' v_i × v_{i+1} (the
    /// region's polygon, whose constraints they are).
    void finish(bool edges_are_constraints);
};

inline void VisibleLune::finish(bool edges_are_constraints) {
    double sum = 0.0;
    m_bound_c = 2.f;
    float gx = 0.f, gy = 0.f, gz = 0.f, g_inv = 0.f;  // the bounding edge's axb and 1/sin θ
    bool bounded = false;
    const int n = m_vertices;
    // Four edges at a time, each lane the scalar operations of one edge (the same bits; the
    // sum and the bound in edge order, as before): axb = a × b, sin θ = |axb|, θ from atan2
    // in double, θ/sin θ, axb·ns. Lanes past n get axb = 0 and are left out of the sums.
    for (int i0 = 0; i0 < n; i0 += 4) {
        const int used = n - i0 < 4 ? n - i0 : 4;
        const int k = i0 / 4;
        const Float4 ax = m_vx[k], ay = m_vy[k], az = m_vz[k];
        // b: each lane's next vertex; a rotation of the lanes for the polygons of 3 and 4
        // vertices (nearly all), gathered from the lanes otherwise.
        Float4 bx, by, bz;
        if (n == 3) {
            bx = __builtin_shufflevector(ax, ax, 1, 2, 0, 3), by = __builtin_shufflevector(ay, ay, 1, 2, 0, 3);
            bz = __builtin_shufflevector(az, az, 1, 2, 0, 3);
        } else if (n == 4) {
            bx = __builtin_shufflevector(ax, ax, 1, 2, 3, 0), by = __builtin_shufflevector(ay, ay, 1, 2, 3, 0);
            bz = __builtin_shufflevector(az, az, 1, 2, 3, 0);
        } else {
            for (int j = 0; j < 4; ++j) {
                const int i = i0 + j + 1 >= n ? i0 + j + 1 - n : i0 + j + 1;
                bx[j] = m_vx[i / 4][i % 4], by[j] = m_vy[i / 4][i % 4], bz[j] = m_vz[i / 4][i % 4];
            }
        }
        // Lanes past n: axb = 0 (contains() passes them).
        const Int4 lane_used = Int4{0, 1, 2, 3} < used;
        const Float4 zero{};
        const Float4 cx = lane_used ? ay * bz - az * by : zero, cy = lane_used ? az * bx - ax * bz : zero,
                     cz = lane_used ? ax * by - ay * bx : zero;
        const Float4 sin_t = sqrt4(cx * cx + cy * cy + cz * cz);
        const Float4 cos_t = ax * bx + ay * by + az * bz;
        Double4 theta_d;
        atan2_nonnegative(__builtin_convertvector(sin_t, Double4), __builtin_convertvector(cos_t, Double4), theta_d);
        const Float4 theta = __builtin_convertvector(theta_d, Float4);
        const Float4 ratio = sin_t > 1e-7f ? theta / sin_t : splat4(1.f);  // θ / sin θ → 1
        const Float4 axb_ns = cx * m_ns.x + cy * m_ns.y + cz * m_ns.z;
        if (edges_are_constraints) m_gx[i0 / 4] = cx, m_gy[i0 / 4] = cy, m_gz[i0 / 4] = cz;
        // The bound: each edge's c = axb·ns · (1/sin θ) in lanes, the edge taken by the same
        // comparisons in edge order as selects (which edge wins is data: as branches, they
        // were mispredicted about once per polygon).
        const Float4 inv = 1.f / sin_t, bound_c = axb_ns * inv;
        for (int j = 0; j < used; ++j) {
            sum += double(ratio[j]) * axb_ns[j];
            const bool tighter = (sin_t[j] > 1e-6f) & (axb_ns[j] < m_bound_c * sin_t[j]);
            m_bound_c = tighter ? bound_c[j] : m_bound_c;
            gx = tighter ? cx[j] : gx, gy = tighter ? cy[j] : gy, gz = tighter ? cz[j] : gz;
            g_inv = tighter ? inv[j] : g_inv;
            bounded |= tighter;
        }
    }
    if (bounded) m_bound = Vec3(gx, gy, gz) * g_inv;
    m_projected_area = n ? static_cast<float>(0.5 * sum) : 0.f;
}


/// The region of the plane dot(normal, x) = offset (tangents t1, t2, with cross(t1, t2) =
/// ±normal) seen past the blockers from points on their sides `signs` (bit i set: the side
/// blocker i's normal points to): the plane's points on those sides, clipped in the plane's
/// homogeneous coordinates (X, Y, W), x = X·t1 + Y·t2 + W·o, starting from the hemisphere
/// W ≥ 0 (four points at infinity 90° apart, counter-clockwise about W). A blocker parallel
/// to the plane leaves all of it or none.
inline PlaneRegion visible_region(const Vec3& normal, float offset, const Vec3& t1, const Vec3& t2,
                                  const PlaneBlocker* blockers, int count, unsigned signs) {
    const Vec3 o = normal * offset;
    Vec3 h[kMaxSphericalVertices + 2] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    int n = 4;
    for (int i = 0; i < count && n >= 3; ++i) {
        const bool positive = (signs >> i) & 1u;
        const Vec3 q = positive ? blockers[i].normal : -blockers[i].normal;
        const float q_offset = positive ? blockers[i].offset : -blockers[i].offset;
        const Vec3 g(dot(q, t1), dot(q, t2), dot(q, o) - q_offset);
        if (std::fabs(dot(q, normal)) >= 1.f - 1e-7f) {
            if (g.z < 0.f) n = 0;  // the whole plane beyond the blocker
            continue;
        }
        n = clip_spherical_polygon(h, n, normalize(g));
    }
    // Drop the vertices that lie on the arc between their neighbours (the ends of a strip's
    // sides where the back wall cut it off): each costs an edge at every point. Only where
    // the merged edge stays well below 180° (dot > −0.9), which the map to p's directions keeps.
    for (int k = 0; n > 3 && k < n;) {
        const Vec3& a = h[k == 0 ? n - 1 : k - 1];
        const Vec3& c = h[k + 1 == n ? 0 : k + 1];
        if (std::fabs(dot(cross(a, c), h[k])) < 1e-6f && dot(a, c) > -0.9f && dot(a, h[k]) > dot(a, c) &&
            dot(c, h[k]) > dot(a, c)) {
            for (int j = k; j + 1 < n; ++j) h[j] = h[j + 1];
            --n;
        } else {
            ++k;
        }
    }
    PlaneRegion region;
    if (n < 3) return region;
    for (int k = 0; k < n; ++k) region.vertex[static_cast<std::size_t>(k)] = {t1 * h[k].x + t2 * h[k].y + o * h[k].z, h[k].z};
    region.count = n;
    region.make_lanes();
    return region;
}

}  // namespace spt
