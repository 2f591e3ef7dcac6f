// The axis-aligned infinite planes of a scene (the walls of most scenes), tested two at a
// time. Every ray meets them, so they get their own layout: per axis, the plane coordinates
// in pairs (padded with NaN, which no comparison accepts), each pair tested with one
// two-lane double operation and selects instead of branches (which wall is nearest is
// random from ray to ray, so branches would mispredict). In double, like every other shape:
// where two surfaces nearly meet, a float t could pick the wrong one
// (tests/hard_cases/nearly_parallel_planes.json).
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "geometry/ray.h"

namespace spt {

class AxisPlanes {
public:
    /// Adds the plane `index` lying at coordinate `position` on `axis` (0 = x, 1 = y, 2 = z).
    void add(int axis, double position, int index) {
        // The first two planes of each axis go to a fixed slot (tested in straight-line code:
        // a box has two walls per axis); further ones to the overflow list.
        int& count = m_count[axis];
        Pair* pair = &m_first[axis];
        if (count >= 2) {
            if (count % 2 == 0) {  // this axis needs a new pair
                m_open_extra[axis] = m_more.size();
                m_more.push_back({axis, empty_pair()});
            }
            pair = &m_more[m_open_extra[axis]].pair;
        }
        pair->position[count % 2] = position;
        pair->index[count % 2] = index;
        ++count;
    }
    void clear() { *this = AxisPlanes{}; }

    /// Nearest plane with 0 < t < t_best: lowers t_best and sets best (a plane index) when
    /// one is found, leaves them unchanged otherwise.
    [[gnu::always_inline]] void nearest(const Ray& ray, double& t_best, int& best) const {
        // One reciprocal per axis: a multiply per plane instead of a division. The sign of t
        // stays exact; a zero direction gives ±inf or NaN, both rejected by the comparisons.
        Double2 t_min = splat(t_best), i_min = splat(best);
        test(m_first[0], splat(ray.o.x), splat(1.0 / ray.d.x), t_min, i_min);
        test(m_first[1], splat(ray.o.y), splat(1.0 / ray.d.y), t_min, i_min);
        test(m_first[2], splat(ray.o.z), splat(1.0 / ray.d.z), t_min, i_min);
        if (!m_more.empty()) [[unlikely]] test_more(ray, t_min, i_min);
        // The nearer lane; on a tie (coincident planes) the lower plane index, as a list
        // tested in order would give. Chosen in the vector registers: as a branch it
        // mispredicts about every other ray (which wall is hit is random).
        const Double2 t_other = __builtin_shufflevector(t_min, t_min, 1, 0);
        const Double2 i_other = __builtin_shufflevector(i_min, i_min, 1, 0);
        const Long2 other_nearer = (t_other < t_min) | ((t_other == t_min) & (i_other < i_min));
        t_best = (other_nearer ? t_other : t_min)[0];
        best = static_cast<int>((other_nearer ? i_other : i_min)[0]);
    }

    /// True if a plane lies at 0 < t < t_max along the ray (shadow rays).
    [[gnu::always_inline]] bool any_hit(const Ray& ray) const {
        double t_best = ray.t_max;
        int best = -1;
        nearest(ray, t_best, best);
        return best >= 0;
    }

private:
    using Double2 = double __attribute__((vector_size(16)));
    using Long2 = std::int64_t __attribute__((vector_size(16)));
    static constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
    static Double2 splat(double v) { return Double2{v, v}; }

    /// Two planes of one axis. Plane indices are kept as doubles (exact below 2^53) so that
    /// the selects work on the same registers as the distances.
    struct Pair {
        Double2 position;
        Double2 index;
    };
    struct Extra {
        int axis;
        Pair pair;
    };
    static Pair empty_pair() { return {Double2{kNan, kNan}, Double2{-1, -1}}; }

    [[gnu::always_inline]] static void test(const Pair& p, Double2 o, Double2 inv, Double2& t_min,
                                            Double2& i_min) {
        const Double2 t = (p.position - o) * inv;
        const Long2 nearer = (t > 0.0) & (t < t_min);
        t_min = nearer ? t : t_min;
        i_min = nearer ? p.index : i_min;
    }

    /// The planes beyond two per axis; out of line, so that the common case keeps its
    /// per-axis values in registers.
    [[gnu::noinline]] void test_more(const Ray& ray, Double2& t_min, Double2& i_min) const {
        const Double2 o[3] = {splat(ray.o.x), splat(ray.o.y), splat(ray.o.z)};
        const Double2 inv[3] = {splat(1.0 / ray.d.x), splat(1.0 / ray.d.y), splat(1.0 / ray.d.z)};
        for (const Extra& e : m_more) test(e.pair, o[e.axis], inv[e.axis], t_min, i_min);
    }

    Pair m_first[3] = {empty_pair(), empty_pair(), empty_pair()};
    int m_count[3] = {0, 0, 0};
    std::size_t m_open_extra[3] = {0, 0, 0};  ///< each axis's last pair in m_more
    std::vector<Extra> m_more;
};

}  // namespace spt
