// svetlo bench SCENE.json [--accel LIST] [--rays primary|diffuse] [--threads N]
// Traces one fixed set of rays through each acceleration structure and prints
// `accel=NAME build_ms=X mrays_per_s=Y hits=Z` per structure. Primary rays go through the
// pixel centres of the film; diffuse rays leave each primary hit in a cosine-distributed
// direction (incoherent rays, as a path tracer's second bounce).
#include <atomic>
#include <chrono>
#include <cstdio>
#include <sstream>

#include "commands.h"
#include "svetlo/core/error.h"
#include "svetlo/core/parallel.h"
#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/geometry/scene_geometry.h"
#include "svetlo/rt/camera.h"
#include "svetlo/rt/rt_scene.h"

namespace svetlo {

namespace {

using Clock = std::chrono::steady_clock;

std::vector<Ray> make_rays(const Scene& scene, const Geometry& g, const Accel& reference,
                           bool diffuse, int threads) {
    int w = scene.film.width, h = scene.film.height;
    CameraRays camera(scene.camera, w, h);
    std::vector<Ray> rays(static_cast<size_t>(w) * h);
    std::vector<char> keep(rays.size(), 1);
    parallel_ranges(rays.size(), threads, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
            int i = static_cast<int>(k % w), j = static_cast<int>(k / w);
            Ray ray = camera.generate((i + 0.5f) / w, (j + 0.5f) / h);
            if (!diffuse) {
                rays[k] = ray;
                continue;
            }
            Hit hit;
            if (!reference.intersect(ray, hit)) {
                keep[k] = 0;
                continue;
            }
            SurfaceHit s = g.surface(ray, hit);
            vec3 n = glm::dot(s.ng, ray.d) < 0.0f ? s.ng : -s.ng;
            Rng rng = pixel_rng(scene.render.seed, k);
            vec3 local = sample_cosine_hemisphere(rng.next_2d());
            vec3 dir = Frame::from_normal(n).to_world(local);
            rays[k] = Ray{offset_ray_origin(s.p, n, dir), dir, kInfinity};
        }
    });
    std::vector<Ray> out;
    out.reserve(rays.size());
    for (size_t k = 0; k < rays.size(); ++k) {
        if (keep[k]) out.push_back(rays[k]);
    }
    return out;
}

uint64_t trace_all(const Accel& accel, const std::vector<Ray>& rays, int threads) {
    std::atomic<uint64_t> hits{0};
    parallel_ranges(rays.size(), threads, [&](size_t begin, size_t end) {
        uint64_t local = 0;
        Hit hit;
        for (size_t k = begin; k < end; ++k) local += accel.intersect(rays[k], hit) ? 1 : 0;
        hits += local;
    });
    return hits.load();
}

}  // namespace

int run_bench(const BenchArgs& args) {
    std::vector<Override> overrides = parse_sets(args.sets, args.scene);
    add_flag_overrides(args.scene, args.width, args.height, overrides);
    const int threads = flag_threads(args.scene, args.threads);
    if (args.rays != "primary" && args.rays != "diffuse") {
        throw Error(args.scene, "--rays", "expected primary or diffuse, not '" + args.rays + "'");
    }
    std::vector<std::string> names;
    const std::vector<std::string> known = accel_names();
    std::string accels = args.accels;
    if (accels.empty()) {
        // Default: every structure but brute force, which takes hours on a large mesh.
        for (size_t k = 1; k < known.size(); ++k) accels += (k > 1 ? "," : "") + known[k];
    }
    std::stringstream list(accels);
    for (std::string name; std::getline(list, name, ',');) {
        if (std::find(known.begin(), known.end(), name) == known.end()) {
            std::string available;
            for (const std::string& k : known) available += (available.empty() ? "" : ", ") + k;
            throw Error(args.scene, "--accel",
                        "unknown accelerator '" + name + "' (available: " + available + ")");
        }
        names.push_back(name);
    }
    Scene scene = load_scene(args.scene, overrides);
    LightSet lights(scene);
    Geometry g = build_geometry(object_pointers(scene.objects, lights.area_light_quads()));
    place_instances(scene, g);
    std::unique_ptr<Accel> reference = make_accel("bvh", g, threads);
    std::vector<Ray> rays = make_rays(scene, g, *reference, args.rays == "diffuse", threads);
    reference.reset();
    std::fprintf(stderr, "svetlo bench: %zu %s rays, %u primitives, %d threads\n", rays.size(),
                 args.rays.c_str(), g.primitive_count(), resolve_threads(threads));
    for (const std::string& name : names) {
        auto t0 = Clock::now();
        std::unique_ptr<Accel> accel = make_accel(name, g, threads);
        double build_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        // Repeat the trace until 0.3 s have passed for a stable figure (one pass at least).
        uint64_t hits = 0;
        int passes = 0;
        double seconds = 0.0;
        do {
            auto t1 = Clock::now();
            hits = trace_all(*accel, rays, threads);
            seconds += std::chrono::duration<double>(Clock::now() - t1).count();
            ++passes;
        } while (seconds < 0.3 && passes < 50);
        double mrays =
            seconds > 0.0 ? static_cast<double>(rays.size()) * passes / seconds * 1e-6 : 0.0;
        std::printf("accel=%s build_ms=%.3f mrays_per_s=%.6g hits=%llu\n", name.c_str(), build_ms,
                    mrays, static_cast<unsigned long long>(hits));
        std::fflush(stdout);
        std::fprintf(stderr, "  %s (%s): %.1f MiB structure, %.1f MiB geometry\n", name.c_str(),
                     accel_description(name).c_str(),
                     static_cast<double>(accel->memory_bytes()) / (1 << 20),
                     static_cast<double>(g.memory_bytes()) / (1 << 20));
    }
    return 0;
}

}  // namespace svetlo
