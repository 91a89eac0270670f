// The subcommands of the svetlo program, one file each. Each returns the exit status and
// throws svetlo::Error for bad input (main prints it as one line).
#pragma once

#include <string>
#include <vector>

#include "svetlo/job/overrides.h"
#include "svetlo/scene/pixel_trace.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {

// Numeric flags are kept as given (empty when absent) and checked by the commands
// (svetlo/job/limits.h), so that a bad value gets one line naming the flag.
struct RenderArgs {
    std::string scene;
    std::string output = "out.png";
    std::string engine;
    std::string width, height, spp, seed, threads, time;
    std::vector<std::string> sets;  // KEY=VALUE
    std::vector<std::string> aovs;  // NAME=FILE
    bool quiet = false;
    std::string crop;                       // X0,X1,Y0,Y1
    std::string mse_reference, mse_log;     // --mse-reference REF --mse-log LOG.csv
    std::string checkpoint;                 // --checkpoint FILE
    std::vector<std::string> command;       // the whole argument list, for the provenance
    const class MpiSession* mpi = nullptr;  // the MPI job (one process when null)
};

struct InfoArgs {
    std::string scene;
    std::vector<std::string> sets;
    bool matrices = false;  // also print the rasterizer's view, projection and model matrices
    bool json = false;      // for an image: the raw provenance object
};

struct BenchArgs {
    std::string scene;
    std::string accels;  // empty: every structure built in except brute force
    std::string rays = "primary";
    std::string threads, width, height;
    std::vector<std::string> sets;
};

struct DiffArgs {
    std::string a, b;  // b is the reference
    std::string metric, tolerance, output;
};

struct ReproduceArgs {
    std::string image, output;
    std::string threads;
    bool quiet = false;
};

struct CompareArgs {
    std::string scene;
    std::vector<std::string> techniques;  // SPECs
    std::string reference;                // SPEC or image; empty: path:render.spp=1024
    std::string html, png, json;
    std::string width, height, threads, seed;
    std::vector<std::string> sets;
    bool curves = false;
    bool quiet = false;
};

struct TraceArgs {
    std::string scene, pixel, sample, json, obj;
    std::string engine, width, height, spp, seed, threads;
    std::vector<std::string> sets;
};

struct ServeArgs {
    std::string target;  // a scene file or a folder of them (default: .)
    std::string port, host;
};

struct AssembleArgs {
    std::vector<std::string> parts;
    std::string output;
};

int run_render(const RenderArgs& args);
int run_diff(const DiffArgs& args);  // exits 0, 1 or 2 as Unix diff; prints its own errors
int run_reproduce(const ReproduceArgs& args);
int run_assemble(const AssembleArgs& args);
int run_compare(const CompareArgs& args);
int run_trace(const TraceArgs& args);
int run_serve(const ServeArgs& args);

/// svetlo info IMAGE: the provenance (--json: the raw object).
int run_image_info(const std::string& image, bool json);

struct RenderJob;
struct RenderResult;
/// The render's summary line on stderr.
void print_summary(const RenderJob& job, const RenderResult& result, const std::string& output);

/// svetlo trace's pixel sample, recorded by the scene's engine (engine: its name).
PixelTrace trace_pixel(const TraceArgs& args, std::string& engine);

int run_info(const InfoArgs& args);
int run_bench(const BenchArgs& args);

/// The flags that stand for scene keys, checked, as overrides after the --set ones (the flags
/// win): -e (render.engine), -W and -H (film), --seed (render.seed); empty ones are left out.
void add_flag_overrides(const std::string& file, const std::string& width,
                        const std::string& height, std::vector<Override>& overrides,
                        const std::string& engine = {}, const std::string& seed = {});

/// The thread count a -t flag asks for (0: every core; empty: 0).
int flag_threads(const std::string& file, const std::string& text);

}  // namespace svetlo
