// An emitting infinite plane (the Cornell ceiling): Le from both sides. It has no finite
// area, so next-event estimation samples a direction, and every direction of the half-space
// facing the plane (m·ω > 0, m its normal turned towards it) reaches it with radiance Le.
// At a reference point that gathers light on one side (normal ns), the integrand of a
// Lambertian surface is Le·(ρ/π)·cos θ over the lune where both ns·ω > 0 and m·ω > 0, so
// the sampler draws exactly that: cosine-weighted about ns, restricted to the lune. Seen
// from above (Malley), the lune is the part of the unit disk with x > −c·√(1 − y²)
// (c = ns·m, x towards m's tangent part), each row (1 + c) times as wide as the half
// disk x ∈ [0, √(1 − y²)]: a point uniform in the half disk, stretched along its row,
// is uniform in the lune. Its density is cos θ / (π(1 + c)/2), and a diffuse surface's
// estimate Le·ρ·(1 + c)/2 (the view factor) is the same for every sample: only shadows
// leave noise. Where both sides gather light (a transmitting BSDF), directions are
// cosine-weighted about m instead; every one reaches the plane, the density falling to 0
// towards its horizon, where it recedes. It cannot start light subpaths (no area to sample).
//
// The scene's other infinite planes (the Cornell walls) hide most of the lune: seen from the
// floor of the box, two thirds of its directions end on a wall, and the lune sampler's
// shadow rays found them blocked. With such planes (`blockers`), the sampler draws from the
// lune minus what they hide (plane_visibility.h: a convex spherical polygon whose projected
// solid angle Φ is exact), still ∝ cos θ: it draws directions of a lune that holds the
// polygon until one lies in it, at most kMaxTries times. That lune is the one of ns and m,
// or, where smaller, the one of ns and the great circle of one of the polygon's edges (its
// normal g: any edge's circle bounds a convex polygon; the same lune sampler with c = ns·g,
// chosen from the polygon alone, so pdf_li makes the same choice; with cheaper normalising
// it took 3.5 % of the instructions per path). Each try is accepted with probability
// A = Φ/(π(1 + c)/2), so a direction of the polygon has density
//     pdf(ω) = cos θ / Φ · (1 − (1 − A)^kMaxTries)
// and no sample is returned with probability (1 − A)^kMaxTries (then the estimate is 0: the
// density accounts for it, so the estimator stays unbiased). A diffuse surface's sample then
// gives Le·ρ·Φ/π (divided by that factor) for every direction: only the finite shapes' shadows
// (and the tries' cap) leave noise. The first try takes (u1, u2) (stratified by the sampler);
// later tries hash them into new numbers (a deterministic function of the first: a
// pseudo-random stream, as good as independent for a hash with full avalanche). When every
// other plane blocks, no sampled direction crosses one on its way to this plane, so the
// shadow ray tests only the finite shapes (LightSample::past_planes).
//
// Cost: the polygon comes from the region of the plane seen from p's sides of the blockers,
// built for every sign vector when the scene is finalized (plane_visibility.h), and is
// remembered per thread for the density the MIS weight of the next bounce asks for
// (visible_from); the edges' angles come from a series (fast_math.h), not atan2f: together
// they cut the instructions per path by about 43 % (docs/PERFORMANCE.md, "Light
// samplers"). The work is then
// done four at a time in SIMD lanes, each lane the operations of the scalar code so the bits
// stay the same (tests/test_lights.cpp compares with the one-at-a-time sampler): the blockers'
// sides, the polygon's vertices and edges (Lambert's formula), and the tries, four per round
// with the first that lands taken (one branch per round instead of a mispredicted one per
// try); the sample is written into the caller's LightSample (copying a returned optional
// stalled on store forwarding). The portable build (SSE2: no blends, no 32-bit lane
// multiply) runs about 3 % more instructions per path for the lanes than the native one
// (AVX-512).
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <cstring>

#include "core/fast_math.h"
#include "core/frame.h"
#include "core/sampling.h"
#include "geometry/plane.h"
#include "model/lights/light_sample.h"
#include "model/lights/plane_visibility.h"
#include "spectral/spectrum.h"

namespace spt {

struct PlaneLight {
    Plane plane;
    Spectrum Le;  ///< radiance, both sides
    /// A surface that rays hit, of infinite area: no sample_le (it starts no light subpath).
    static constexpr LightType type = LightType::area;
    /// Both sides emit, always (the lune samplers assume it).
    static constexpr bool two_sided = true;
    /// The radius of the scene's bounding sphere: the plane's power for light selection is
    /// what it sends into a disk of that radius, π·Le·πR² (it has no finite power).
    float scene_radius = 1.f;
    /// The scene's other infinite planes that hide what lies beyond them (Scene::finalize
    /// fills them; at most VisibleLune::kMaxBlockers); none: the lune sampler alone.
    std::array<PlaneBlocker, VisibleLune::kMaxBlockers> blockers{};
    int blocker_count = 0;
    /// True when the blockers are every plane of the scene but this one: then no sampled
    /// direction crosses a plane before reaching this one.
    bool blocks_every_plane = false;
    /// Tries of the sampler of the lune minus what the blockers hide.
    static constexpr int kMaxTries = 16;
    /// The region of this plane seen past the blockers for each sign vector (bit i: the
    /// side of blocker i the point lies on), 2^blocker_count of them, and the plane's
    /// tangents they are built in (prepare_regions, after the blockers are set).
    std::vector<PlaneRegion> regions{};
    Vec3 region_t1{}, region_t2{};
    /// dot(cross(t1, t2), normal) (±1): with side(p), whether the map to p's directions
    /// turns the regions' orientation.
    float region_handedness = 1.f;
    /// Names this light's regions for visible_from's memo (unique per prepare_regions; 0: none).
    std::uint64_t region_serial = 0;
    /// The blockers in lanes for visible_from's side tests (prepare_regions): normals and
    /// offsets in double and the normals in float, and the distance below which a point
    /// counts as on a blocker; zero past blocker_count.
    struct BlockerLanes {
        std::array<double, VisibleLune::kMaxBlockers> nx{}, ny{}, nz{}, offset{}, on_tolerance{};
        std::array<float, VisibleLune::kMaxBlockers> fnx{}, fny{}, fnz{};
    } blocker_lanes{};

    /// Builds `regions` from the blockers (Scene::finalize).
    void prepare_regions() {
        const Frame f(plane.normal);
        region_t1 = f.s, region_t2 = f.t;
        region_handedness = dot(cross(f.s, f.t), plane.normal) >= 0.f ? 1.f : -1.f;
        static std::atomic<std::uint64_t> serials{0};
        region_serial = ++serials;
        static_assert(VisibleLune::kMaxBlockers % 4 == 0);
        blocker_lanes = {};
        for (int i = 0; i < blocker_count; ++i) {
            const std::size_t k = static_cast<std::size_t>(i);
            const PlaneBlocker& b = blockers[k];
            blocker_lanes.nx[k] = b.normal.x, blocker_lanes.ny[k] = b.normal.y, blocker_lanes.nz[k] = b.normal.z;
            blocker_lanes.offset[k] = b.offset;
            blocker_lanes.on_tolerance[k] = 1e-5 * std::max(1.0, std::fabs(double(b.offset)));
            blocker_lanes.fnx[k] = b.normal.x, blocker_lanes.fny[k] = b.normal.y, blocker_lanes.fnz[k] = b.normal.z;
        }
        regions.assign(blocker_count > 0 ? std::size_t(1) << blocker_count : 0, PlaneRegion{});
        for (std::size_t signs = 0; signs < regions.size(); ++signs)
            regions[signs] = visible_region(plane.normal, plane.offset, f.s, f.t, blockers.data(), blocker_count,
                                            static_cast<unsigned>(signs));
    }

    /// The directions from p that reach the plane past the blockers (p at signed distance s,
    /// s ≠ 0), on ns's side: the region of p's sign vector seen from p. A point on a blocker
    /// (where the clipping construction ignores it) takes the side ns faces: the blocker then
    /// cuts along ns's own horizon, which the polygon is clipped by anyway.
    ///
    /// Remembered per thread with what it was built from (this light's regions, p and ns,
    /// compared bit for bit): the path loop asks again, for the same vertex, when the MIS
    /// weight of the ray its BSDF sample sent to this plane needs pdf_li, and gets the very
    /// same polygon without building it twice (integrators need not carry it across the
    /// bounce). The reference stays valid until the thread's next call.
    const VisibleLune& visible_from(const Vec3& p, const Vec3& ns, double s) const {
        struct Memo {
            std::uint64_t serial = 0;
            Vec3 p, ns;
            VisibleLune visible;
        };
        thread_local Memo memo;
        if (memo.serial == region_serial && same_bits(memo.p, p) && same_bits(memo.ns, ns)) return memo.visible;
        // Bit i: p's side of blocker i, d = n·p − offset > 0 in double, or where p lies on
        // it (|d| within its tolerance) the side ns faces, n·ns ≥ 0 (float). Four blockers
        // at a time, each lane the scalar operations.
        unsigned signs = 0;
        const Double4 px = Double4{} + double(p.x), py = Double4{} + double(p.y), pz = Double4{} + double(p.z);
        for (int g = 0; g * 4 < blocker_count; ++g) {
            const BlockerLanes& bl = blocker_lanes;
            const std::size_t o = static_cast<std::size_t>(4 * g);
            Double4 nx, ny, nz, offset, tolerance;
            std::memcpy(&nx, &bl.nx[o], sizeof nx), std::memcpy(&ny, &bl.ny[o], sizeof ny);
            std::memcpy(&nz, &bl.nz[o], sizeof nz), std::memcpy(&offset, &bl.offset[o], sizeof offset);
            std::memcpy(&tolerance, &bl.on_tolerance[o], sizeof tolerance);
            const Double4 d = nx * px + ny * py + nz * pz - offset;
            const Double4 abs_d = reinterpret_cast<Double4>(reinterpret_cast<Long4>(d) & std::int64_t(0x7fffffffffffffff));
            const Float4 faces = load4(&bl.fnx[o]) * ns.x + load4(&bl.fny[o]) * ns.y + load4(&bl.fnz[o]) * ns.z;
            const unsigned on = lane_bits(abs_d <= tolerance), positive = lane_bits(d > Double4{});
            const unsigned bits = (on & lane_bits(faces >= 0.f)) | (~on & positive);
            signs |= (bits & 0xfu) << (4 * g);
        }
        signs &= (1u << blocker_count) - 1u;
        memo.visible.build(p, ns, regions[signs], double(region_handedness) * s > 0.0);
        memo.serial = region_serial, memo.p = p, memo.ns = ns;
        return memo.visible;
    }

    float power() const { return kPi * kPi * scene_radius * scene_radius * mean_over_visible(Le); }
    float spectral_power(float lambda_nm) const { return kPi * kPi * scene_radius * scene_radius * Le.eval(lambda_nm); }

    /// Radiance leaving the plane at p (normal n) along w: the same from both sides.
    SampledSpectrum L(const Vec3& /*p*/, const Vec3& /*n*/, const Vec3& /*w*/, const SampledWavelengths& lambda) const {
        return Le.sample(lambda);
    }

    /// Signed distance of p from the plane along its normal (double: p may lie far away).
    double side(const Vec3& p) const {
        return double(plane.normal.x) * p.x + double(plane.normal.y) * p.y + double(plane.normal.z) * p.z -
               plane.offset;
    }
    /// Unit normal of the plane turned towards it from p; zero when p lies on the plane.
    Vec3 towards(const Vec3& p) const {
        const double s = side(p);
        if (s == 0.0) return {};
        return s > 0.0 ? -plane.normal : plane.normal;
    }

    /// Below this 1 + c the lune is empty for a float sampler (the plane lies behind the
    /// gathering side): no sample, density 0.
    static constexpr float kMinLune = 1e-6f;

    /// sample_li into caller storage `ls`, a default LightSample (light.h's contract).
    bool sample_li(const LightSampleContext& ctx, const SampledWavelengths& lambda, float u1, float u2,
                   LightSample& ls) const {
        const double s = side(ctx.p);
        if (s == 0.0) return false;
        const Vec3 m = s > 0.0 ? -plane.normal : plane.normal;
        if (ctx.both_sides) {
            const Vec3 local = sample_cosine_hemisphere(u1, u2);
            if (!(local.z > 0.f)) return false;
            ls.wi = Frame(m).to_world(local);
            ls.pdf = local.z * kInvPi;
        } else {
            const float c = dot(ctx.ns, m);
            if (!(1.f + c > kMinLune)) return false;
            if (blocker_count == 0) {
                ls.wi = lune_direction(ctx.ns, m, c, u1, u2);
                const float cos_n = dot(ls.wi, ctx.ns);
                if (!(cos_n > 0.f) || !(dot(ls.wi, m) > 0.f)) return false;
                ls.pdf = lune_pdf(cos_n, c);
            } else {
                const VisibleLune& visible = visible_from(ctx.p, ctx.ns, s);
                if (visible.empty()) return false;
                float cos_n = 0.f;
                bool found = false;
                // From the tightest lune that holds the polygon (fewer tries). Four tries at a
                // time, one per lane, each lane the operations of the scalar try (Lune::direction,
                // retry_numbers, contains: the same bits), and the first that lands is taken, as
                // if they were made one after the other: one branch per four tries, not a
                // mispredicted one per try.
                const float c_lune = sampling_c(visible, c);
                const Lune lune(ctx.ns, c_lune == c ? m : visible.bound_normal(), c_lune);
                static_assert(kMaxTries % 4 == 0);
                for (int k0 = 0; k0 < kMaxTries && !found; k0 += 4) {
                    Float4 v1, v2, wx, wy, wz;
                    retry_numbers(u1, u2, k0, v1, v2);
                    lune.direction(v1, v2, wx, wy, wz);
                    const Float4 cos4 = wx * ctx.ns.x + wy * ctx.ns.y + wz * ctx.ns.z;
                    const unsigned landed = lane_bits((cos4 > 0.f) & (wx * m.x + wy * m.y + wz * m.z > 0.f) &
                                                      visible.contains(wx, wy, wz));
                    if (landed) {
                        const int j = std::countr_zero(landed);
                        ls.wi = Vec3(wx[j], wy[j], wz[j]);
                        cos_n = cos4[j];
                        found = true;
                    }
                }
                if (!found) return false;
                ls.pdf = visible_pdf(cos_n, c_lune, visible.area());
                ls.past_planes = blocks_every_plane;
            }
        }
        // The distance along wi: |side| / cos θ to the plane (the shadow ray needs no point on it).
        ls.plane_distance = static_cast<float>(std::fabs(s) / dot(ls.wi, m));
        if (!std::isfinite(ls.plane_distance) || !(ls.plane_distance > 0.f)) return false;
        ls.L = Le.sample(lambda);
        return true;
    }

    float pdf_li(const LightSampleContext& ctx, const Vec3& wi) const {
        const double s = side(ctx.p);
        if (s == 0.0) return 0.f;
        const Vec3 m = s > 0.0 ? -plane.normal : plane.normal;
        if (ctx.both_sides) return cosine_hemisphere_pdf(dot(wi, m));
        const float c = dot(ctx.ns, m), cos_n = dot(wi, ctx.ns);
        if (!(1.f + c > kMinLune) || !(cos_n > 0.f) || !(dot(wi, m) > 0.f)) return 0.f;
        if (blocker_count == 0) return lune_pdf(cos_n, c);
        const VisibleLune& visible = visible_from(ctx.p, ctx.ns, s);
        if (visible.empty() || !visible.contains(wi)) return 0.f;
        return visible_pdf(cos_n, sampling_c(visible, c), visible.area());
    }

    /// The lune's frame: ns, the tangent t towards m and b = ns × t, with c = ns·m; made once
    /// for all the tries at a point.
    struct Lune {
        Vec3 ns, t, b;
        float c;
        Lune(const Vec3& ns_, const Vec3& m, float c_) : ns(ns_), c(c_) {
            // Tangent towards m (any tangent when m is along ns: then the lune is the whole
            // hemisphere and the row stretch is 2 with offset −c·w = −w, or the lune is empty).
            t = m - ns * c;
            const float t_len = length(t);
            t = t_len > 1e-6f ? t / t_len : Frame(ns).s;
            b = cross(ns, t);
        }
        /// A direction of the lune, cosine-weighted about ns (see the top of the file): a
        /// point uniform in the half disk x ≥ 0 (polar, the angle φ = π(u2 − ½) from the
        /// series of φ/2 and the double-angle formulas), stretched along its row.
        Vec3 direction(float u1, float u2) const {
            float sin_half = 0.f, cos_half = 0.f;
            sincos_quarter_pi(2.f * u2 - 1.f, sin_half, cos_half);
            const float r = std::sqrt(u1);
            const float y = r * (2.f * sin_half * cos_half), x_half = r * ((cos_half - sin_half) * (cos_half + sin_half));
            const float w = safe_sqrt(1.f - y * y);
            const float x = std::clamp(-c * w + (1.f + c) * x_half, -w, w);
            const float z = safe_sqrt(1.f - x * x - y * y);
            const Vec3 d = t * x + b * y + ns * z;
            return d * (1.f / length(d));
        }
        /// direction() for four pairs (u1, u2) in lanes: the components of the four directions
        /// (each lane the scalar operations; std::clamp and safe_sqrt's selects as they are).
        void direction(const Float4& u1, const Float4& u2, Float4& dx, Float4& dy, Float4& dz) const {
            Float4 sin_half, cos_half;
            sincos_quarter_pi(2.f * u2 - 1.f, sin_half, cos_half);
            const Float4 r = sqrt4(u1);
            const Float4 y = r * (2.f * sin_half * cos_half), x_half = r * ((cos_half - sin_half) * (cos_half + sin_half));
            const Float4 zero{};
            const Float4 w2 = 1.f - y * y;
            const Float4 w = sqrt4(zero < w2 ? w2 : zero);
            const Float4 x0 = -c * w + (1.f + c) * x_half, neg_w = -w;
            const Float4 x = x0 < neg_w ? neg_w : (w < x0 ? w : x0);
            const Float4 z2 = 1.f - x * x - y * y;
            const Float4 z = sqrt4(zero < z2 ? z2 : zero);
            const Float4 ex = t.x * x + b.x * y + ns.x * z, ey = t.y * x + b.y * y + ns.y * z,
                         ez = t.z * x + b.z * y + ns.z * z;
            const Float4 inv = 1.f / sqrt4(ex * ex + ey * ey + ez * ez);
            dx = ex * inv, dy = ey * inv, dz = ez * inv;
        }
    };
    static Vec3 lune_direction(const Vec3& ns, const Vec3& m, float c, float u1, float u2) {
        return Lune(ns, m, c).direction(u1, u2);
    }

    /// c = ns·axis of the lune the sampler of the polygon draws from: the plane's own (c), or
    /// the polygon's bounding edge (VisibleLune::bound_c) where that lune is smaller by more
    /// than rounding and not empty.
    static float sampling_c(const VisibleLune& visible, float c) {
        const float b = visible.bound_c();
        return b < c - 1e-3f && b > -1.f + 1e-3f ? b : c;
    }

    /// Density of the sampler of the lune minus what the blockers hide, for a direction in
    /// it: cos θ/Φ times the chance that one of the tries lands in it.
    static float visible_pdf(float cos_n, float c, float projected_area) {
        const float accept = std::min(1.f, projected_area / (0.5f * kPi * (1.f + c)));
        // (1 − A)^16 by four squarings (a pow call cost more than the rest of the density;
        // relative error ~30 ulp of a number that 1 − it barely feels).
        static_assert(kMaxTries == 16);
        float miss_all = 1.f - accept;
        miss_all *= miss_all, miss_all *= miss_all, miss_all *= miss_all, miss_all *= miss_all;
        return cos_n / projected_area * (1.f - miss_all);
    }

    /// retry_numbers for tries k0 … k0 + 3 in lanes (lane 0 of k0 = 0: the first try's own
    /// (u1, u2)); each lane the scalar operations.
    static void retry_numbers(float u1, float u2, int k0, Float4& v1, Float4& v2) {
        auto mix = [](UInt4 h) {
            h ^= h >> 16, h *= 0x85ebca6bu, h ^= h >> 13, h *= 0xc2b2ae35u, h ^= h >> 16;
            return h;
        };
        const UInt4 k = UInt4{0, 1, 2, 3} + std::uint32_t(k0);
        const UInt4 b1 = UInt4{} + std::bit_cast<std::uint32_t>(u1), b2 = UInt4{} + std::bit_cast<std::uint32_t>(u2);
        const UInt4 seed = mix(b1 ^ mix(b2 + 0x9e3779b9u * k));
        // Below 2^24: exact as signed integers, converted exactly.
        v1 = to_float4(reinterpret_cast<Int4>(mix(seed) >> 8)) * 0x1p-24f;
        v2 = to_float4(reinterpret_cast<Int4>(mix(seed ^ 0x68e31da4u) >> 8)) * 0x1p-24f;
        if (k0 == 0) v1[0] = u1, v2[0] = u2;
    }

    /// Try k's two numbers, hashed from the first try's (murmur3's 32-bit finaliser: each
    /// output bit depends on every input bit).
    static void retry_numbers(float u1, float u2, int k, float& v1, float& v2) {
        auto mix = [](std::uint32_t h) {
            h ^= h >> 16, h *= 0x85ebca6bu, h ^= h >> 13, h *= 0xc2b2ae35u, h ^= h >> 16;
            return h;
        };
        const std::uint32_t seed = mix(std::bit_cast<std::uint32_t>(u1) ^ mix(std::bit_cast<std::uint32_t>(u2) +
                                                                              0x9e3779b9u * std::uint32_t(k)));
        v1 = float(mix(seed) >> 8) * 0x1p-24f;
        v2 = float(mix(seed ^ 0x68e31da4u) >> 8) * 0x1p-24f;
    }

    static bool same_bits(const Vec3& a, const Vec3& b) {
        return std::bit_cast<std::uint32_t>(a.x) == std::bit_cast<std::uint32_t>(b.x) &&
               std::bit_cast<std::uint32_t>(a.y) == std::bit_cast<std::uint32_t>(b.y) &&
               std::bit_cast<std::uint32_t>(a.z) == std::bit_cast<std::uint32_t>(b.z);
    }

    /// Solid-angle density of the lune sampler: cos θ over the lune's projected area π(1 + c)/2.
    static float lune_pdf(float cos_n, float c) { return 2.f * cos_n / (kPi * (1.f + c)); }
};

}  // namespace spt
