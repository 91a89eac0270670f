// The subcommands of the svetlo program, one file each. Each returns the exit status and
// throws svetlo::Error for bad input (main prints it as one line).
#pragma once

#include <string>
#include <vector>

#include "svetlo/scene/scene_loader.h"

namespace svetlo {

struct RenderArgs {
    std::string scene;
    std::string output = "out.png";
    std::string engine;
    int width = 0, height = 0, spp = 0;
    long long seed = -1;
    int threads = 0;
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
    int threads = 0;
    int width = 0, height = 0;
    std::vector<std::string> sets;
};

int run_render(const RenderArgs& args);
int run_info(const InfoArgs& args);
int run_bench(const BenchArgs& args);

/// --set KEY=VALUE strings (and the flags that stand for scene keys) as overrides.
std::vector<Override> parse_sets(const std::vector<std::string>& sets, const std::string& file);

}  // namespace svetlo
