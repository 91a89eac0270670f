// Google Benchmark programs for the ray-tracing core: build rate (triangles per second,
// single- and multi-threaded) and closest-hit traversal of primary and diffuse rays for every
// acceleration structure (grid, octree, binary and wide BVH, Embree), all on the same rays,
// on the Stanford bunny (69,451 triangles) three times over (208,353 triangles); and shadow
// rays toward a point light, one by one and in packets (Accel::occluded_toward).
#include <benchmark/benchmark.h>

#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/geometry/accel.h"
#include "svetlo/geometry/bvh.h"
#include "svetlo/scene/mesh_file.h"

namespace svetlo {
namespace {

const Geometry& bunnies() {
    static const Geometry g = [] {
        Geometry out;
        MeshFile f = read_mesh_file(SVETLO_SHARED_DATA "/bunny/bun_zipper.ply");
        for (int copy = 0; copy < 3; ++copy) {
            auto base = static_cast<uint32_t>(out.positions.size());
            for (vec3 p : f.mesh.positions)
                out.positions.push_back(p + vec3(0.2f * copy, 0.0f, 0.0f));
            for (uint32_t i : f.mesh.indices) out.indices.push_back(base + i);
            out.triangle_material.resize(out.indices.size() / 3, 0);
        }
        return out;
    }();
    return g;
}

void build(benchmark::State& state, const std::string& name) {
    const Geometry& g = bunnies();
    for (auto _ : state) {
        std::unique_ptr<Accel> accel = make_accel(name, g, static_cast<int>(state.range(0)));
        benchmark::DoNotOptimize(accel.get());
    }
    state.counters["Mtris/s"] =
        benchmark::Counter(static_cast<double>(g.triangle_count()) * state.iterations() * 1e-6,
                           benchmark::Counter::kIsRate);
}

/// Rays from a ring of viewpoints toward the bunnies (primary), or leaving their first hits
/// in cosine-distributed directions (diffuse).
std::vector<Ray> make_rays(const Bvh& bvh, bool diffuse) {  // NOLINT: copies are cheap here
    const Geometry& g = bunnies();
    Rng rng(1, 2);
    std::vector<Ray> rays;
    vec3 target(0.2f, 0.1f, 0.0f);
    while (rays.size() < 100000) {
        float a = 2.0f * kPi * rng.next_float();
        vec3 o = target + vec3(0.6f * std::cos(a), 0.1f, 0.6f * std::sin(a));
        vec3 p =
            target + 0.15f * (vec3(rng.next_float(), rng.next_float(), rng.next_float()) - 0.5f);
        Ray r{o, glm::normalize(p - o), kInfinity};
        if (!diffuse) {
            rays.push_back(r);
            continue;
        }
        Hit hit;
        if (!bvh.intersect(r, hit)) continue;
        SurfaceHit s = g.surface(r, hit);
        vec3 n = glm::dot(s.ng, r.d) < 0.0f ? s.ng : -s.ng;
        vec3 d = Frame::from_normal(n).to_world(sample_cosine_hemisphere(rng.next_2d()));
        rays.push_back(Ray{offset_ray_origin(s.p, n, d), d, kInfinity});
    }
    return rays;
}

/// The rays, made once with the binary BVH and shared by every structure.
const std::vector<Ray>& rays(bool diffuse) {
    static const std::vector<Ray> primary = [] { return make_rays(Bvh(bunnies()), false); }();
    static const std::vector<Ray> incoherent = [] { return make_rays(Bvh(bunnies()), true); }();
    return diffuse ? incoherent : primary;
}

void trace(benchmark::State& state, const std::string& name) {
    const Geometry& g = bunnies();
    std::unique_ptr<Accel> accel = make_accel(name, g, 1);
    const std::vector<Ray>& r = rays(state.range(0) == 1);
    int64_t hits = 0;
    for (auto _ : state) {
        Hit hit;
        for (const Ray& ray : r) hits += accel->intersect(ray, hit);
    }
    benchmark::DoNotOptimize(hits);
    state.SetLabel(state.range(0) == 1 ? "diffuse" : "primary");
    state.counters["Mrays/s"] = benchmark::Counter(
        static_cast<double>(r.size()) * state.iterations() * 1e-6, benchmark::Counter::kIsRate);
}

/// Shadow rays toward a point light from the visible points of a 256 x 256 view of the
/// bunnies, in blocks of 8 x 8 pixels (as the rasterizer's raytraced shadows cast them).
struct ShadowRays {
    vec3 light;
    std::vector<Ray> rays;
    std::vector<size_t> block_start;  // each block's first ray, and the end
};

const ShadowRays& shadow_rays() {
    static const ShadowRays s = [] {
        const Geometry& g = bunnies();
        const Bvh bvh(g);
        ShadowRays out;
        const vec3 target(0.2f, 0.1f, 0.0f), eye = target + vec3(0.0f, 0.15f, 0.5f);
        out.light = target + vec3(0.3f, 0.8f, 0.2f);
        const Frame view = Frame::from_normal(glm::normalize(target - eye));
        constexpr int kSide = 256, kBlock = 8;
        for (int by = 0; by < kSide; by += kBlock) {
            for (int bx = 0; bx < kSide; bx += kBlock) {
                out.block_start.push_back(out.rays.size());
                for (int y = by; y < by + kBlock; ++y) {
                    for (int x = bx; x < bx + kBlock; ++x) {
                        const vec3 d = view.to_world(vec3(0.5f * (x + 0.5f) / kSide - 0.25f,
                                                          0.5f * (y + 0.5f) / kSide - 0.25f, 1.0f));
                        const Ray r{eye, glm::normalize(d), kInfinity};
                        Hit hit;
                        if (!bvh.intersect(r, hit)) continue;
                        const SurfaceHit sh = g.surface(r, hit);
                        const vec3 n = glm::dot(sh.ng, r.d) < 0.0f ? sh.ng : -sh.ng;
                        const vec3 o = offset_ray_origin(sh.p, n, out.light - sh.p);
                        out.rays.push_back(Ray{o, out.light - o, 1.0f});
                    }
                }
            }
        }
        out.block_start.push_back(out.rays.size());
        return out;
    }();
    return s;
}

void shadow(benchmark::State& state, const std::string& name) {
    const ShadowRays& s = shadow_rays();
    std::unique_ptr<Accel> accel = make_accel(name, bunnies(), 1);
    const bool packets = state.range(0) == 1;
    int64_t blocked = 0;
    bool answers[64];
    for (auto _ : state) {
        if (!packets) {
            for (const Ray& ray : s.rays) blocked += accel->occluded(ray);
            continue;
        }
        for (size_t b = 0; b + 1 < s.block_start.size(); ++b) {
            const size_t first = s.block_start[b], n = s.block_start[b + 1] - first;
            accel->occluded_toward(s.light, s.rays.data() + first, n, answers);
            for (size_t k = 0; k < n; ++k) blocked += answers[k];
        }
    }
    benchmark::DoNotOptimize(blocked);
    state.SetLabel(packets ? "packets of 8 x 8" : "one by one");
    state.counters["Mrays/s"] =
        benchmark::Counter(static_cast<double>(s.rays.size()) * state.iterations() * 1e-6,
                           benchmark::Counter::kIsRate);
}

}  // namespace
}  // namespace svetlo

int main(int argc, char** argv) {
    using namespace svetlo;
    for (const std::string& name : accel_names()) {
        if (name == "none") continue;  // brute force: hours on this mesh
        benchmark::RegisterBenchmark(("Build/" + name).c_str(), build, name)
            ->Arg(1)
            ->Arg(2)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    for (const std::string& name : accel_names()) {
        if (name == "none") continue;
        benchmark::RegisterBenchmark(("Trace/" + name).c_str(), trace, name)
            ->Arg(0)
            ->Arg(1)
            ->Unit(benchmark::kMillisecond);
    }
    for (const char* name : {"bvh", "embree"}) {
        benchmark::RegisterBenchmark((std::string("Shadow/") + name).c_str(), shadow, name)
            ->Arg(0)
            ->Arg(1)
            ->Unit(benchmark::kMillisecond);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
