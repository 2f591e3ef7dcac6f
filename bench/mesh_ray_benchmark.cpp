// The C++ half of the Embree comparison (bench/embree_compare.py runs both halves): builds the
// BVH over a generated mesh, makes three ray sets (coherent camera rays, incoherent
// diffuse-bounce rays from surface points, shadow rays towards an area light), traces each with
// 1 and with all hardware threads, and writes the mesh, the rays and its answers to files so
// that Embree can trace the very same rays. Never run by the tests.
//   mesh_ray_benchmark (--triangles N | --ply FILE) [--rays N] [--repeat R] --out DIR
// A PLY model (a real scan, bench/fetch_models.py) is centred and scaled to fill the view, so
// the same camera, bounces and light apply.
// Files (little-endian float32, no header), KEY being N or the PLY's file name without
// extension: DIR/mesh-KEY.f32 (9 per triangle), DIR/rays-KEY-SET.f32 (o, d, t_max: 7 per
// ray), DIR/ours-KEY-SET.f32 (nearest t or inf; shadow: 1 blocked, 0 not); DIR/ours-KEY.json:
// build seconds, bytes, rays/s per set and thread count.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <exception>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "bench_timing.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "generated_mesh.h"
#include "geometry/aabb.h"
#include "geometry/bvh.h"
#include "io/ply_reader.h"

using namespace spt;
using spt::bench::rays_per_second;
using spt::bench::seconds_since;

namespace {

/// Resident memory of this process in bytes (/proc/self/statm), for the build's growth.
long resident_bytes() {
    long pages_total = 0, pages_resident = 0;
    if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2) pages_resident = 0;
        std::fclose(f);
    }
    return pages_resident * 4096;
}

void write_floats(const std::string& path, const std::vector<float>& v) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(float)));
    if (!out) {
        std::fprintf(stderr, "mesh_ray_benchmark: cannot write %s\n", path.c_str());
        std::exit(1);
    }
}

/// Pinhole camera rays over a square image of about n pixels, row by row (coherent).
std::vector<Ray> camera_rays(int n) {
    const int side = std::max(1, static_cast<int>(std::sqrt(double(n))));
    const Vec3 eye(0.f, 1.4f, 4.2f), target(0.f, -0.4f, 0.f);
    const Vec3 w = normalize(target - eye), u = normalize(cross(w, Vec3(0, 1, 0))), v = cross(u, w);
    const float half = std::tan(0.5f * 55.f * kPi / 180.f);
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(side) * side);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const float sx = (2.f * (x + 0.5f) / side - 1.f) * half, sy = (1.f - 2.f * (y + 0.5f) / side) * half;
            rays.push_back({eye, normalize(w + u * sx + v * sy), kInfinity});
        }
    return rays;
}

/// The triangles of a PLY file, centred on the origin with their longest side 4 long, so that
/// the model fills most of the camera's view (the generated terrain fills all of it), its up
/// (+y) kept. Degenerate triangles are dropped, as the
/// renderer's loader drops them.
std::vector<Triangle> ply_mesh(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) {
        std::fprintf(stderr, "mesh_ray_benchmark: cannot read %s\n", path.c_str());
        std::exit(1);
    }
    PlyMesh ply;
    try {
        ply = parse_ply(bytes, path);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mesh_ray_benchmark: %s\n", e.what());
        std::exit(1);
    }
    Aabb box;
    for (const Vec3& p : ply.positions) box.expand(p);
    const Vec3 centre = 0.5f * (box.lo + box.hi), size = box.hi - box.lo;
    const float scale = 4.f / std::max({size.x, size.y, size.z});
    std::vector<Triangle> out;
    out.reserve(ply.triangles.size());
    for (const auto& t : ply.triangles) {
        auto at = [&](std::uint32_t i) { return (ply.positions[i] - centre) * scale; };
        const Triangle tri{at(t[0]), at(t[1]), at(t[2]), 0};
        if (!tri.is_degenerate()) out.push_back(tri);
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    int n_triangles = 1'000'000, n_rays = 400'000, repeat = 3;
    std::string out_dir, ply_path;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--triangles")) n_triangles = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--ply")) ply_path = argv[i + 1];
        else if (!std::strcmp(argv[i], "--rays")) n_rays = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--repeat")) repeat = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--out")) out_dir = argv[i + 1];
    }
    if (out_dir.empty() || n_triangles < 100 || n_rays < 1 || repeat < 1) {
        std::fprintf(stderr, "usage: mesh_ray_benchmark (--triangles N (>= 100) | --ply FILE) [--rays N] [--repeat R] --out DIR\n");
        return 2;
    }
    const std::vector<Triangle> mesh = ply_path.empty() ? spt::bench::generated_mesh(n_triangles) : ply_mesh(ply_path);
    const std::string key = ply_path.empty() ? std::to_string(n_triangles)
                                             : std::filesystem::path(ply_path).stem().string();
    {
        std::vector<float> v;
        v.reserve(mesh.size() * 9);
        for (const Triangle& t : mesh)
            for (const Vec3& p : {t.p0, t.p1, t.p2}) v.insert(v.end(), {p.x, p.y, p.z});
        write_floats(out_dir + "/mesh-" + key + ".f32", v);
    }
    const BvhShapes shapes = BvhShapes::of_arrays(mesh);

    // Build: the best of `repeat` (the machine may be busy), and the memory it holds.
    Bvh bvh;
    double build_s = kInfinity;
    long rss_growth = 0;
    BvhBuildStats stats;
    for (int r = 0; r < repeat; ++r) {
        bvh = Bvh{};
        const long rss0 = resident_bytes();
        const auto t0 = std::chrono::steady_clock::now();
        stats = bvh.build(shapes);
        build_s = std::min(build_s, seconds_since(t0));
        rss_growth = resident_bytes() - rss0;
    }

    // Ray sets. Surface points for the bounces and shadow rays: random camera hits.
    std::vector<Ray> sets[3];
    sets[0] = camera_rays(n_rays);
    std::vector<Hit> surface;
    for (const Ray& r : sets[0]) {
        double t = r.t_max;
        BvhHit h;
        if (!bvh.intersect(r, shapes, t, h)) continue;
        Hit hit = mesh[h.prim.index()].make_hit(h.tri);
        if (dot(hit.n, r.d) > 0.f) hit.n = -hit.n;  // the side the camera sees
        surface.push_back(hit);
    }
    if (surface.empty()) {
        std::fprintf(stderr, "mesh_ray_benchmark: the camera sees nothing\n");
        return 1;
    }
    Rng rng(12345, 0, 0);
    for (int i = 0; i < n_rays; ++i) {
        const Hit& hit = surface[std::min<std::size_t>(surface.size() - 1, rng.uniform() * surface.size())];
        const Vec3 w = Frame(hit.n).to_world(sample_cosine_hemisphere(rng.uniform(), rng.uniform()));
        sets[1].push_back(spawn_ray(hit, w));
        const Vec3 light(4.f * rng.uniform() - 2.f, 4.f, 4.f * rng.uniform() - 2.f);
        sets[2].push_back(spawn_ray_to(hit, light));
    }

    const char* names[3] = {"camera", "diffuse", "shadow"};
    std::vector<int> thread_counts = {1};
    if (const int hw = static_cast<int>(std::thread::hardware_concurrency()); hw > 1) thread_counts.push_back(hw);
    std::printf("ours: %zu triangles, build %.3f s, %d wide nodes, %d leaves, tree %.1f bytes/triangle, "
                "resident growth %.1f bytes/triangle\n",
                mesh.size(), build_s, stats.nodes, stats.leaves, double(bvh.memory_bytes()) / mesh.size(),
                double(rss_growth) / mesh.size());
    std::string json = "{\"triangles\": " + std::to_string(mesh.size()) + ", \"build_s\": " + std::to_string(build_s) +
                       ", \"tree_bytes\": " + std::to_string(bvh.memory_bytes()) +
                       ", \"rss_bytes\": " + std::to_string(rss_growth) + ", \"sets\": {";
    for (int s = 0; s < 3; ++s) {
        const std::vector<Ray>& rays = sets[s];
        std::vector<float> flat, answers(rays.size());
        flat.reserve(rays.size() * 7);
        for (const Ray& r : rays) flat.insert(flat.end(), {r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.t_max});
        write_floats(out_dir + "/rays-" + key + "-" + names[s] + ".f32",
                     flat);
        auto nearest = [&](std::size_t i, const Ray& r) {
            double t = r.t_max;
            BvhHit h;
            const bool hit = bvh.intersect(r, shapes, t, h);
            answers[i] = hit ? static_cast<float>(t) : kInfinity;
            return hit ? 1 : 0;
        };
        auto any = [&](std::size_t i, const Ray& r) {
            const bool hit = bvh.occluded(r, shapes);
            answers[i] = hit ? 1.f : 0.f;
            return hit ? 1 : 0;
        };
        json += std::string(s ? ", " : "") + "\"" + names[s] + "\": {";
        for (std::size_t k = 0; k < thread_counts.size(); ++k) {
            double best = 0.0;
            long hits = 0;
            for (int r = 0; r < repeat; ++r)
                best = std::max(best, s == 2 ? rays_per_second(rays, thread_counts[k], any, hits)
                                             : rays_per_second(rays, thread_counts[k], nearest, hits));
            std::printf("ours: %-7s %d thread%s %7.3f Mrays/s (%.1f %% hit)\n", names[s], thread_counts[k],
                        thread_counts[k] > 1 ? "s" : " ", best * 1e-6, 100.0 * hits / rays.size());
            json += (k ? ", \"" : "\"") + std::to_string(thread_counts[k]) + "\": " + std::to_string(best);
        }
        json += "}";
        write_floats(out_dir + "/ours-" + key + "-" + names[s] + ".f32", answers);
    }
    json += "}}\n";
    std::ofstream(out_dir + "/ours-" + key + ".json") << json;
    return 0;
}
