// svetlo: the command line (docs/cli.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <new>

#include "commands.h"
#include "distributed.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"

#ifndef SVETLO_VERSION
#define SVETLO_VERSION "unknown"
#endif

int main(int argc, char** argv) {
    using namespace svetlo;
    // Under mpirun: the MPI job (docs/distributed.md); rank 0 alone prints errors.
    const MpiSession mpi(argc, argv);
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
    r->add_option("--crop", render.crop,
                  "Render only the pixels X0 <= i < X1, Y0 <= j < Y1: X0,X1,Y0,Y1");
    r->add_option("--mse-reference", render.mse_reference,
                  "Reference image for --mse-log (PNG, PFM or EXR)");
    r->add_option("--mse-log", render.mse_log,
                  "Write spp,seconds,mse,relmse after each pass to this CSV file");
    r->add_option("--checkpoint", render.checkpoint,
                  "Save the path tracer's passes after each (progressive radiosity's solve about "
                  "once a second) to FILE, and resume from it (docs/cli.md)");
    render.command.assign(argv, argv + argc);
    render.mpi = &mpi;

    InfoArgs info;
    CLI::App* i = app.add_subcommand(
        "info", "Describe what a scene holds, or how an image (PNG, PFM, EXR) was made");
    i->add_option("scene", info.scene, "Scene file (JSON) or image")->required();
    i->add_flag("--json", info.json, "For an image: print its provenance as JSON");
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

    DiffArgs diff;
    CLI::App* d = app.add_subcommand(
        "diff", "Compare two images: MAE, RMSE, relMSE and FLIP; exits 0, 1 or 2 as diff");
    d->add_option("a", diff.a, "Test image")->required();
    d->add_option("b", diff.b, "Reference image")->required();
    d->add_option("--metric", diff.metric, "mae, rmse, relmse or flip (default: print all)");
    d->add_option("--tolerance", diff.tolerance, "Largest value that counts as equal (0)");
    d->add_option("-o,--output", diff.output, "Write the per-pixel error image");

    ReproduceArgs reproduce;
    CLI::App* rp =
        app.add_subcommand("reproduce", "Render an image again from the provenance inside it");
    rp->add_option("image", reproduce.image, "An image svetlo wrote")->required();
    rp->add_option("-o,--output", reproduce.output, "Output image")->required();
    rp->add_option("-t,--threads", reproduce.threads, "Threads (default: the original's)");
    rp->add_flag("-q,--quiet", reproduce.quiet, "Print nothing but errors");

    AssembleArgs assemble;
    CLI::App* as = app.add_subcommand("assemble", "Put crops of one render back together");
    as->add_option("parts", assemble.parts, "Crops written by render --crop")->required();
    as->add_option("-o,--output", assemble.output, "Output image")->required();

    CompareArgs compare;
    CLI::App* cmp = app.add_subcommand(
        "compare", "Render a scene under several techniques and write a comparison sheet");
    cmp->add_option("scene", compare.scene, "Scene file (JSON)")->required();
    cmp->add_option("-T,--technique", compare.techniques,
                    "A technique: ENGINE[:KEY=VALUE]... (raster:render.shading=gouraud)")
        ->required();
    cmp->add_option("--reference", compare.reference,
                    "The reference: a SPEC or an image (default path:render.spp=1024)");
    cmp->add_option("-o,--output", compare.html, "The sheet as one HTML file");
    cmp->add_option("--png", compare.png, "The sheet as a PNG grid");
    cmp->add_option("--json", compare.json, "The metrics as JSON");
    cmp->add_option("-W,--width", compare.width, "Film width in pixels");
    cmp->add_option("-H,--height", compare.height, "Film height in pixels");
    cmp->add_option("-t,--threads", compare.threads, "Threads (0 = all cores)");
    cmp->add_option("--seed", compare.seed, "Random seed");
    cmp->add_option("--set", compare.sets, "Override a scene key for every technique: KEY=VALUE");
    cmp->add_flag("--curves", compare.curves,
                  "Also plot the error of progressive techniques (path) against time");
    cmp->add_flag("-q,--quiet", compare.quiet, "Print nothing but errors");

    TraceArgs trace_args;
    CLI::App* trace = app.add_subcommand("trace", "Print the rays of one pixel sample");
    trace->add_option("scene", trace_args.scene, "Scene file (JSON)")->required();
    trace->add_option("--pixel", trace_args.pixel, "The pixel: X,Y")->required();
    trace->add_option("--sample", trace_args.sample, "Which of its samples (0)");
    trace->add_option("--json", trace_args.json, "Write the trace as JSON");
    trace->add_option("--obj", trace_args.obj, "Write the rays as OBJ line segments");
    trace->add_option("-e,--engine", trace_args.engine, "raster, whitted, path or radiosity");
    trace->add_option("-W,--width", trace_args.width, "Film width in pixels");
    trace->add_option("-H,--height", trace_args.height, "Film height in pixels");
    trace->add_option("-s,--spp", trace_args.spp, "Samples per pixel of the render traced (1)");
    trace->add_option("--seed", trace_args.seed, "Random seed");
    trace->add_option("-t,--threads", trace_args.threads, "Threads (0 = all cores)");
    trace->add_option("--set", trace_args.sets, "Override a scene key: KEY=VALUE");

    ServeArgs serve_args;
    CLI::App* serve = app.add_subcommand("serve", "A live browser viewer of a scene folder");
    serve->add_option("target", serve_args.target, "A scene file, or a folder of scenes (.)");
    serve->add_option("--port", serve_args.port, "Port (8080; 0: any free port)");
    serve->add_option("--host", serve_args.host, "Address to listen on (127.0.0.1)");

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
