// The rasterizer's shadow techniques next to llvmpipe (shadow_bench.cpp).
#pragma once

namespace svetlo::bench {

/// Prints the shadow workloads' frame times on `threads` threads (median of `frames`).
void shadow_benchmarks(int threads, int frames);

}  // namespace svetlo::bench
