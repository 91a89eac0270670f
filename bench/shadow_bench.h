// The rasterizer's shadow techniques next to llvmpipe (shadow_bench.cpp).
#pragma once

namespace svetlo::bench {

/// Prints the shadow workloads' frame times on `threads` threads (median of `frames`).
void shadow_benchmarks(int threads, int frames);

/// svetlo alone, for a profiler: `frames` frames of one workload ("map", "zfail", "zpass" or
/// "depth"); false for an unknown name.
bool shadow_profile(const char* workload, int threads, int frames);

}  // namespace svetlo::bench
