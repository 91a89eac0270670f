// The subcommands of the svetlo program, one file each. Each returns the exit status and
// throws svetlo::Error for bad input (main prints it as one line).
#pragma once

#include <string>
#include <vector>

#include "svetlo/scene/scene_loader.h"

namespace svetlo {

// Numeric flags are kept as given (empty when absent) and checked by the commands (flags.h),
// so that a bad value gets one line naming the flag.
struct RenderArgs {
    std::string scene;
    std::string output = "out.png";
    std::string engine;
    std::string width, height, spp, seed, threads, time;
    std::vector<std::string> sets;  // KEY=VALUE
    std::vector<std::string> aovs;  // NAME=FILE
    bool quiet = false;
};

struct InfoArgs {
    std::string scene;
    std::vector<std::string> sets;
    bool matrices = false;  // also print the rasterizer's view, projection and model matrices
};

struct BenchArgs {
    std::string scene;
    std::string accels;  // empty: every structure built in except brute force
    std::string rays = "primary";
    std::string threads, width, height;
    std::vector<std::string> sets;
};

int run_render(const RenderArgs& args);
int run_info(const InfoArgs& args);
int run_bench(const BenchArgs& args);

/// --set KEY=VALUE strings as overrides.
std::vector<Override> parse_sets(const std::vector<std::string>& sets, const std::string& file);

/// The flags that stand for scene keys (-W, -H, and for render --spp and --seed), checked, as
/// overrides after the --set ones: the flags win.
void add_flag_overrides(const std::string& file, const std::string& width,
                        const std::string& height, std::vector<Override>& overrides);

/// The thread count a -t flag asks for (0: every core; empty: 0).
int flag_threads(const std::string& file, const std::string& text);

}  // namespace svetlo
