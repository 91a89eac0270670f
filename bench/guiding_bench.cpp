// Google Benchmark program for path guiding's lookups (docs/path.md, "What a guided pass
// costs"): what a guided bounce pays on top of an unguided one. A field over the unit cube is
// trained on a light from one corner, a few thousand records a region, over three
// iterations, as a render's training shapes one; then, per lookup, the region and facing of a
// point (GuidingField::at), a draw from its tree with the draw's density (Guide::sample), the
// density of a direction (Guide::pdf, what MIS asks for every light sample) and a record
// (GuidingField::record). Points, normals and directions are drawn beforehand, the same each
// run.
#include <benchmark/benchmark.h>

#include <vector>

#include "svetlo/core/rng.h"
#include "svetlo/core/sampling.h"
#include "svetlo/pt/guiding_field.h"

namespace svetlo {
namespace {

constexpr int kLookups = 4096;  // per batch; a power of two

struct Inputs {
    std::vector<vec3> points, normals, directions;
    std::vector<vec2> u;
};

const Inputs& inputs() {
    static const Inputs in = [] {
        Inputs s;
        Rng rng(11, 3);
        for (int k = 0; k < kLookups; ++k) {
            s.points.emplace_back(rng.next_float(), rng.next_float(), rng.next_float());
            const vec3 n = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
            s.normals.push_back(n);
            s.directions.push_back(sample_uniform_sphere(vec2(rng.next_float(), rng.next_float())));
            s.u.emplace_back(rng.next_float(), rng.next_float());
        }
        return s;
    }();
    return in;
}

/// The radiance a point receives from direction wi: a bright lobe toward the corner (1,1,1)
/// over a dim sky, so that the trees refine toward it.
float radiance(vec3 p, vec3 wi) {
    const vec3 to_light = glm::normalize(vec3(1.0f) - p + vec3(1e-3f));
    return 1.0f + 200.0f * std::pow(std::max(0.0f, glm::dot(wi, to_light)), 40.0f);
}

/// A field trained over iterations of 1, 2 and 4 passes of 400 000 records each (about 230
/// regions at the end).
const GuidingField& field() {
    static const GuidingField trained = [] {
        Bounds3 cube;
        cube.extend(vec3(0.0f));
        cube.extend(vec3(1.0f));
        GuidingField f(cube);
        Rng rng(5, 7);
        for (int passes : {1, 2, 4}) {
            for (int k = 0; k < 400000 * passes; ++k) {
                const vec3 p(rng.next_float(), rng.next_float(), rng.next_float());
                const vec3 n = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
                const vec3 wi = sample_uniform_sphere(vec2(rng.next_float(), rng.next_float()));
                // Uniform directions: the pdf is 1 / (4 pi).
                f.record(f.at(p, n), wi, radiance(p, wi) * 4.0f * kPi);
            }
            f.refine(passes);
        }
        return f;
    }();
    return trained;
}

/// What `f` finds at each of the inputs' points and normals.
std::vector<Guide> guides_at(const GuidingField& f) {
    const Inputs& in = inputs();
    std::vector<Guide> guides;
    for (int k = 0; k < kLookups; ++k) guides.push_back(f.at(in.points[k], in.normals[k]));
    return guides;
}

void at(benchmark::State& state) {
    const GuidingField& f = field();
    const Inputs& in = inputs();
    int k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(f.at(in.points[k], in.normals[k]));
        k = (k + 1) & (kLookups - 1);
    }
    state.counters["regions"] = f.regions();
}

void draw(benchmark::State& state) {
    const Inputs& in = inputs();
    const std::vector<Guide> guides = guides_at(field());
    int k = 0;
    for (auto _ : state) {
        float pdf = 0.0f;
        if (guides[k]) benchmark::DoNotOptimize(guides[k].sample(in.u[k], pdf));
        benchmark::DoNotOptimize(pdf);
        k = (k + 1) & (kLookups - 1);
    }
}

void density(benchmark::State& state) {
    const Inputs& in = inputs();
    const std::vector<Guide> guides = guides_at(field());
    int k = 0;
    for (auto _ : state) {
        if (guides[k]) benchmark::DoNotOptimize(guides[k].pdf(in.directions[k]));
        k = (k + 1) & (kLookups - 1);
    }
}

void record(benchmark::State& state) {
    // Into a copy, so that the field the other benchmarks read stays as trained.
    GuidingField f = field();
    const Inputs& in = inputs();
    const std::vector<Guide> guides = guides_at(f);
    int k = 0;
    for (auto _ : state) {
        f.record(guides[k], in.directions[k], 0.5f);
        k = (k + 1) & (kLookups - 1);
    }
}

BENCHMARK(at);
BENCHMARK(draw);
BENCHMARK(density);
BENCHMARK(record);

}  // namespace
}  // namespace svetlo

BENCHMARK_MAIN();
