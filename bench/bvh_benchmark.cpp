// BVH benchmark (not part of the tests): build time and rays/s on a generated mesh of
// ≥ 1M triangles (a displaced, finely tessellated sphere), with 1 and 2 threads, and the
// speed-up of the BVH over brute force for 10, 100 and 10,000 random spheres.
//   bvh_benchmark [--triangles N] [--rays N]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <thread>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "geometry/bvh.h"
#include "bench_timing.h"

using namespace spt;
using spt::bench::rays_per_second;
using spt::bench::seconds_since;

namespace {

/// A UV sphere of about n triangles with a bumpy radius (so the mesh is not trivially regular).
std::vector<Triangle> bumpy_sphere(int n) {
    const int rings = static_cast<int>(std::sqrt(n / 2.0)), segments = rings;
    auto vertex = [&](int i, int j) {
        const double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segments;
        const double r = 1.0 + 0.05 * std::sin(7 * th) * std::cos(11 * ph) + 0.02 * std::sin(40 * ph + 3 * th);
        return Vec3(float(r * std::sin(th) * std::cos(ph)), float(r * std::cos(th)), float(r * std::sin(th) * std::sin(ph)));
    };
    std::vector<Triangle> tris;
    tris.reserve(2 * rings * segments);
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const Vec3 a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
            const Triangle t0{a, b, c, 0}, t1{a, c, d, 0};
            if (!t0.is_degenerate()) tris.push_back(t0);
            if (!t1.is_degenerate()) tris.push_back(t1);
        }
    return tris;
}

/// Rays from random points on a sphere of radius 3 towards random points near the centre.
std::vector<Ray> random_rays(int n, std::uint64_t seed) {
    Rng rng(seed, 0, 0);
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        const Vec3 o = sample_uniform_sphere(rng.uniform(), rng.uniform()) * 3.f;
        const Vec3 target = sample_uniform_sphere(rng.uniform(), rng.uniform()) * (1.2f * rng.uniform());
        r = {o, normalize(target - o), kInfinity};
    }
    return rays;
}

}  // namespace

int main(int argc, char** argv) {
    int n_triangles = 1'000'000, n_rays = 1'000'000;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--triangles")) n_triangles = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--rays")) n_rays = std::atoi(argv[i + 1]);
    }

    // ---------------------------------------------------------------- large mesh
    const std::vector<Triangle> mesh = bumpy_sphere(n_triangles);
    Bvh bvh;
    auto t0 = std::chrono::steady_clock::now();
    const BvhBuildStats stats = bvh.build(BvhShapes::of_arrays(mesh));
    const double build_s = seconds_since(t0);
    std::printf("mesh: %zu triangles; BVH build %.3f s (%d nodes, %d leaves, depth %d)\n", mesh.size(), build_s,
                stats.nodes, stats.leaves, stats.max_depth);
    const std::vector<Ray> rays = random_rays(n_rays, 1);
    auto trace_mesh = [&](std::size_t, const Ray& r) {
        double t = r.t_max;
        BvhHit h;
        return bvh.intersect(r, BvhShapes::of_arrays(mesh), t, h) ? 1 : 0;
    };
    auto shadow_mesh = [&](std::size_t, const Ray& r) { return bvh.occluded(r, BvhShapes::of_arrays(mesh)) ? 1 : 0; };
    for (int threads : {1, 2}) {
        long hits = 0;
        const double rps = rays_per_second(rays, threads, trace_mesh, hits);
        long hits2 = 0;
        const double rps2 = rays_per_second(rays, threads, shadow_mesh, hits2);
        std::printf("  %d thread%s: nearest hit %.2f Mrays/s, occluded %.2f Mrays/s (%.1f%% hit)\n", threads,
                    threads > 1 ? "s" : " ", rps * 1e-6, rps2 * 1e-6, 100.0 * hits / rays.size());
    }

    // ---------------------------------------------------------------- spheres: brute force vs BVH
    std::printf("random spheres (1 thread, nearest hit):\n");
    for (int n : {10, 100, 10000}) {
        Rng rng(n, 0, 0);
        std::vector<Sphere> spheres;
        const float r = 0.5f / std::cbrt(float(n));  // about the same covered volume for every n
        for (int i = 0; i < n; ++i)
            spheres.push_back({Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 2.f - Vec3(1, 1, 1),
                               r * (0.5f + rng.uniform()), 0});
        Bvh sb;
        sb.build(BvhShapes::of_arrays(spheres));
        const int m = n >= 10000 ? 20000 : 400000;
        const std::vector<Ray> srays = random_rays(m, 2);
        auto brute = [&](std::size_t, const Ray& ray) {
            double t = ray.t_max;
            for (const Sphere& s : spheres) t = std::min(t, s.intersect_t(ray));
            return t < ray.t_max ? 1 : 0;
        };
        auto tree = [&](std::size_t, const Ray& ray) {
            double t = ray.t_max;
            BvhHit h;
            return sb.intersect(ray, BvhShapes::of_arrays(spheres), t, h) ? 1 : 0;
        };
        long h1 = 0, h2 = 0;
        const double a = rays_per_second(srays, 1, brute, h1), b = rays_per_second(srays, 1, tree, h2);
        std::printf("  %5d spheres: brute force %.2f Mrays/s, BVH %.2f Mrays/s, speed-up %.1fx%s\n", n, a * 1e-6,
                    b * 1e-6, b / a, h1 == h2 ? "" : " (HIT COUNTS DIFFER)");
    }
    return 0;
}
