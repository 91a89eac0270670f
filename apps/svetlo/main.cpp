// svetlo: the command line (docs/cli.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <new>

#include "commands.h"
#include "distributed.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/job/engines.h"

#ifndef SVETLO_VERSION
#define SVETLO_VERSION "unknown"
#endif

namespace svetlo {
namespace {

/// The registry's engines, "raster, whitted, path or radiosity", for the help of -e.
std::string every_engine() {
    return engines_with([](const Capabilities&) { return true; });
}

/// svetlo render's options.
CLI::App* add_render(CLI::App& app, RenderArgs& a, int argc, char** argv, const MpiSession& mpi) {
    CLI::App* s = app.add_subcommand("render", "Render a scene to an image");
    s->add_option("scene", a.scene, "Scene file (JSON)")->required();
    s->add_option("-o,--output", a.output, "Output image: .png, .pfm or .exr");
    s->add_option("-e,--engine", a.engine, every_engine());
    s->add_option("-W,--width", a.width, "Film width in pixels");
    s->add_option("-H,--height", a.height, "Film height in pixels");
    s->add_option("-s,--spp", a.spp, "Samples per pixel");
    s->add_option("-t,--threads", a.threads, "Threads (0 = all cores)");
    s->add_option("--seed", a.seed, "Random seed");
    s->add_option("--time", a.time,
                  "Time budget in seconds (path): passes until it is spent, or --spp is reached");
    s->add_option("--set", a.sets, "Override a scene key: KEY=VALUE (dotted path)");
    s->add_option("--aov", a.aovs,
                  "Also write an AOV: NAME=FILE (depth, normal, albedo, visibility)");
    s->add_flag("-q,--quiet", a.quiet, "Print nothing but errors");
    s->add_option("--crop", a.crop,
                  "Render only the pixels X0 <= i < X1, Y0 <= j < Y1: X0,X1,Y0,Y1");
    s->add_option("--mse-reference", a.mse_reference,
                  "Reference image for --mse-log (PNG, PFM or EXR)");
    s->add_option("--mse-log", a.mse_log,
                  "Write spp,seconds,mse,relmse after each pass to this CSV file");
    s->add_option("--checkpoint", a.checkpoint,
                  "Save the path tracer's passes after each (progressive radiosity's solve about "
                  "once a second) to FILE, and resume from it (docs/cli.md)");
    a.command.assign(argv, argv + argc);
    a.mpi = &mpi;
    return s;
}

/// svetlo info's options.
CLI::App* add_info(CLI::App& app, InfoArgs& a) {
    CLI::App* s = app.add_subcommand(
        "info", "Describe what a scene holds, or how an image (PNG, PFM, EXR) was made");
    s->add_option("scene", a.scene, "Scene file (JSON) or image")->required();
    s->add_flag("--json", a.json, "For an image: print its provenance as JSON");
    s->add_option("--set", a.sets, "Override a scene key: KEY=VALUE");
    s->add_flag("--matrices", a.matrices,
                "Also print the rasterizer's view, projection and model matrices");
    return s;
}

/// svetlo bench's options.
CLI::App* add_bench(CLI::App& app, BenchArgs& a) {
    CLI::App* s =
        app.add_subcommand("bench", "Trace the same rays through acceleration structures");
    s->add_option("scene", a.scene, "Scene file (JSON)")->required();
    s->add_option(
        "--accel", a.accels,
        "Comma-separated list of none, grid, octree, bvh2, bvh4, bvh, embree (default: all built)");
    s->add_option("--rays", a.rays, "primary or diffuse");
    s->add_option("-t,--threads", a.threads, "Threads (0 = all cores)");
    s->add_option("-W,--width", a.width, "Film width (rays per row)");
    s->add_option("-H,--height", a.height, "Film height");
    s->add_option("--set", a.sets, "Override a scene key: KEY=VALUE");
    return s;
}

/// svetlo diff's options.
CLI::App* add_diff(CLI::App& app, DiffArgs& a) {
    CLI::App* s = app.add_subcommand(
        "diff", "Compare two images: MAE, RMSE, relMSE and FLIP; exits 0, 1 or 2 as diff");
    s->add_option("a", a.a, "Test image")->required();
    s->add_option("b", a.b, "Reference image")->required();
    s->add_option("--metric", a.metric, "mae, rmse, relmse or flip (default: print all)");
    s->add_option("--tolerance", a.tolerance, "Largest value that counts as equal (0)");
    s->add_option("-o,--output", a.output, "Write the per-pixel error image");
    return s;
}

/// svetlo reproduce's options.
CLI::App* add_reproduce(CLI::App& app, ReproduceArgs& a) {
    CLI::App* s =
        app.add_subcommand("reproduce", "Render an image again from the provenance inside it");
    s->add_option("image", a.image, "An image svetlo wrote")->required();
    s->add_option("-o,--output", a.output, "Output image")->required();
    s->add_option("-t,--threads", a.threads, "Threads (default: the original's)");
    s->add_flag("-q,--quiet", a.quiet, "Print nothing but errors");
    return s;
}

/// svetlo assemble's options.
CLI::App* add_assemble(CLI::App& app, AssembleArgs& a) {
    CLI::App* s = app.add_subcommand("assemble", "Put crops of one render back together");
    s->add_option("parts", a.parts, "Crops written by render --crop")->required();
    s->add_option("-o,--output", a.output, "Output image")->required();
    return s;
}

/// svetlo compare's options.
CLI::App* add_compare(CLI::App& app, CompareArgs& a) {
    CLI::App* s = app.add_subcommand(
        "compare", "Render a scene under several techniques and write a comparison sheet");
    s->add_option("scene", a.scene, "Scene file (JSON)")->required();
    s->add_option("-T,--technique", a.techniques,
                  "A technique: ENGINE[:KEY=VALUE]... (raster:render.shading=gouraud)")
        ->required();
    s->add_option("--reference", a.reference,
                  "The reference: a SPEC or an image (default path:render.spp=1024)");
    s->add_option("-o,--output", a.html, "The sheet as one HTML file");
    s->add_option("--png", a.png, "The sheet as a PNG grid");
    s->add_option("--json", a.json, "The metrics as JSON");
    s->add_option("-W,--width", a.width, "Film width in pixels");
    s->add_option("-H,--height", a.height, "Film height in pixels");
    s->add_option("-t,--threads", a.threads, "Threads (0 = all cores)");
    s->add_option("--seed", a.seed, "Random seed");
    s->add_option("--set", a.sets, "Override a scene key for every technique: KEY=VALUE");
    s->add_flag("--curves", a.curves,
                "Also plot the error of progressive techniques (path) against time");
    s->add_flag("-q,--quiet", a.quiet, "Print nothing but errors");
    return s;
}

/// svetlo trace's options.
CLI::App* add_trace(CLI::App& app, TraceArgs& a) {
    CLI::App* s = app.add_subcommand("trace", "Print the rays of one pixel sample");
    s->add_option("scene", a.scene, "Scene file (JSON)")->required();
    s->add_option("--pixel", a.pixel, "The pixel: X,Y")->required();
    s->add_option("--sample", a.sample, "Which of its samples (0)");
    s->add_option("--json", a.json, "Write the trace as JSON");
    s->add_option("--obj", a.obj, "Write the rays as OBJ line segments");
    s->add_option("-e,--engine", a.engine, every_engine());
    s->add_option("-W,--width", a.width, "Film width in pixels");
    s->add_option("-H,--height", a.height, "Film height in pixels");
    s->add_option("-s,--spp", a.spp, "Samples per pixel of the render traced (1)");
    s->add_option("--seed", a.seed, "Random seed");
    s->add_option("-t,--threads", a.threads, "Threads (0 = all cores)");
    s->add_option("--set", a.sets, "Override a scene key: KEY=VALUE");
    return s;
}

/// svetlo serve's options.
CLI::App* add_serve(CLI::App& app, ServeArgs& a) {
    CLI::App* s = app.add_subcommand("serve", "A live browser viewer of a scene folder");
    s->add_option("target", a.target, "A scene file, or a folder of scenes (.)");
    s->add_option("--port", a.port, "Port (8080; 0: any free port)");
    s->add_option("--host", a.host, "Address to listen on (127.0.0.1)");
    return s;
}

}  // namespace
}  // namespace svetlo

int main(int argc, char** argv) {
    using namespace svetlo;
    // Under mpirun: the MPI job (docs/distributed.md); rank 0 alone prints errors.
    const MpiSession mpi(argc, argv);
    CLI::App app{
        "svetlo: lighting, shading and shadows, every classical technique in one renderer"};
    app.set_version_flag("--version", std::string("svetlo ") + SVETLO_VERSION);
    app.require_subcommand(1);

    RenderArgs render;
    InfoArgs info;
    BenchArgs bench;
    DiffArgs diff;
    ReproduceArgs reproduce;
    AssembleArgs assemble;
    CompareArgs compare;
    TraceArgs trace_args;
    ServeArgs serve_args;
    CLI::App* r = add_render(app, render, argc, argv, mpi);
    CLI::App* i = add_info(app, info);
    CLI::App* b = add_bench(app, bench);
    CLI::App* d = add_diff(app, diff);
    CLI::App* rp = add_reproduce(app, reproduce);
    CLI::App* as = add_assemble(app, assemble);
    CLI::App* cmp = add_compare(app, compare);
    CLI::App* trace = add_trace(app, trace_args);
    CLI::App* serve = add_serve(app, serve_args);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // One line in the format of docs/cli.md; `svetlo SUBCOMMAND --help` shows the usage.
        std::fprintf(stderr, "svetlo: error: svetlo: command line: %s (see svetlo --help)\n",
                     e.what());
        return 2;
    }

    try {
        if (*r) return run_render(render);
        if (*i) {
            if (is_image_path(info.scene)) return run_image_info(info.scene, info.json);
            return run_info(info);
        }
        if (*d) return run_diff(diff);
        if (*rp) return run_reproduce(reproduce);
        if (*as) return run_assemble(assemble);
        if (*cmp) return run_compare(compare);
        if (*trace) return run_trace(trace_args);
        if (*serve) return run_serve(serve_args);
        if (*b) return run_bench(bench);
    } catch (const Error& e) {
        if (mpi.rank() == 0) {
            std::fprintf(stderr, "svetlo: error: %s: %s: %s\n", e.file().c_str(), e.where().c_str(),
                         e.message().c_str());
        }
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "svetlo: error: %s: memory: out of memory\n",
                     render.scene.empty() ? "svetlo" : render.scene.c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "svetlo: error: svetlo: internal: %s\n", e.what());
        return 1;
    }
    return 0;
}
