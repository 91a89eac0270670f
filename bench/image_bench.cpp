// Google Benchmark program for the viewer's encoders (docs/performance.md, "The viewer"):
// a 960 x 540 radiance image to an 8-bit JPEG (the frames sent while the view moves) and to
// a PNG (the still frame), each from its 8-bit sRGB codes, made first.
#include <benchmark/benchmark.h>

#include "svetlo/core/image.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/rng.h"

namespace svetlo {
namespace {

/// A frame like a render's: smooth shading in [0, 1.5] (some of it clipped), a checker
/// texture's edges and a little noise, the same each time.
const Image& frame() {
    static const Image image = [] {
        Image out(960, 540);
        Rng rng(7, 0);
        for (int j = 0; j < out.height; ++j)
            for (int i = 0; i < out.width; ++i) {
                const float shade = 1.5f * static_cast<float>(i + j) / (out.width + out.height);
                const float checker = ((i / 40 + j / 40) % 2) != 0 ? 1.0f : 0.4f;
                const float noise = 0.05f * rng.next_float();
                out.at(i, j) =
                    Color(shade * checker + noise, 0.8f * shade + noise, 0.3f * checker + noise);
            }
        return out;
    }();
    return image;
}

void jpeg(benchmark::State& state) {
    size_t bytes = 0;
    for (auto _ : state) {
        bytes = encode_jpeg(frame(), PixelMeaning::Radiance, 1.0f, 90).size();
        benchmark::DoNotOptimize(bytes);
    }
    state.counters["KiB"] = static_cast<double>(bytes) / 1024.0;
}

void png(benchmark::State& state) {
    size_t bytes = 0;
    for (auto _ : state) {
        bytes = encode_png(frame(), PixelMeaning::Radiance, 1.0f).size();
        benchmark::DoNotOptimize(bytes);
    }
    state.counters["KiB"] = static_cast<double>(bytes) / 1024.0;
}

BENCHMARK(jpeg)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(png)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace svetlo

BENCHMARK_MAIN();
