// svetlo: the command line (contract: ../../../shared/CONTRACT.md, docs/cli.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <new>

#include "commands.h"
#include "svetlo/core/error.h"

#ifndef SVETLO_VERSION
#define SVETLO_VERSION "unknown"
#endif

int main(int argc, char** argv) {
    using namespace svetlo;
    CLI::App app{
        "svetlo: lighting, shading and shadows, every classical technique in one renderer"};
    app.set_version_flag("--version", std::string("svetlo ") + SVETLO_VERSION);
    app.require_subcommand(1);

    RenderArgs render;
    CLI::App* r = app.add_subcommand("render", "Render a scene to an image");
    r->add_option("scene", render.scene, "Scene file (JSON)")->required();
    r->add_option("-o,--output", render.output, "Output image: .png, .pfm or .exr");
    r->add_option("-e,--engine", render.engine, "raster, whitted, path or radiosity");
    r->add_option("-W,--width", render.width, "Film width in pixels");
    r->add_option("-H,--height", render.height, "Film height in pixels");
    r->add_option("-s,--spp", render.spp, "Samples per pixel");
    r->add_option("-t,--threads", render.threads, "Threads (0 = all cores)");
    r->add_option("--seed", render.seed, "Random seed");
    r->add_option("--time", render.time,
                  "Time budget in seconds (path): passes until it is spent, or --spp is reached");
    r->add_option("--set", render.sets, "Override a scene key: KEY=VALUE (dotted path)");
    r->add_option("--aov", render.aovs,
                  "Also write an AOV: NAME=FILE (depth, normal, albedo, visibility)");
    r->add_flag("-q,--quiet", render.quiet, "Print nothing but errors");

    InfoArgs info;
    CLI::App* i = app.add_subcommand("info", "Describe what a scene holds");
    i->add_option("scene", info.scene, "Scene file (JSON)")->required();
    i->add_option("--set", info.sets, "Override a scene key: KEY=VALUE");
    i->add_flag("--matrices", info.matrices,
                "Also print the rasterizer's view, projection and model matrices");

    BenchArgs bench;
    CLI::App* b =
        app.add_subcommand("bench", "Trace the same rays through acceleration structures");
    b->add_option("scene", bench.scene, "Scene file (JSON)")->required();
    b->add_option(
        "--accel", bench.accels,
        "Comma-separated list of none, grid, octree, bvh2, bvh4, bvh, embree (default: all built)");
    b->add_option("--rays", bench.rays, "primary or diffuse");
    b->add_option("-t,--threads", bench.threads, "Threads (0 = all cores)");
    b->add_option("-W,--width", bench.width, "Film width (rays per row)");
    b->add_option("-H,--height", bench.height, "Film height");
    b->add_option("--set", bench.sets, "Override a scene key: KEY=VALUE");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // One line in the contract's format; `svetlo SUBCOMMAND --help` shows the usage.
        std::fprintf(stderr, "svetlo: error: svetlo: command line: %s (see svetlo --help)\n",
                     e.what());
        return 2;
    }

    try {
        if (*r) return run_render(render);
        if (*i) return run_info(info);
        if (*b) return run_bench(bench);
    } catch (const Error& e) {
        std::fprintf(stderr, "svetlo: error: %s: %s: %s\n", e.file().c_str(), e.where().c_str(),
                     e.message().c_str());
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
