// svetlo render SCENE.json [-o OUT] [--engine E] [--width W] [--height H] [--spp N]
//               [--time SECONDS] [--threads N] [--seed S] [--set KEY=VALUE]... [--aov NAME=FILE]...
//               [--quiet] [--crop X0,X1,Y0,Y1] [--mse-reference REF --mse-log LOG.csv]
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <optional>

#include "commands.h"
#include "distributed.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/image_metrics.h"
#include "svetlo/core/parallel.h"
#include "svetlo/core/progress.h"
#include "svetlo/core/sha256.h"
#include "svetlo/job/checkpoint.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/interrupt.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/overrides.h"
#include "svetlo/job/render_job.h"

namespace svetlo {

void add_flag_overrides(const std::string& file, const std::string& width,
                        const std::string& height, std::vector<Override>& overrides,
                        const std::string& engine, const std::string& seed) {
    add_key_overrides(file, RequestKeys{engine, width, height, {}, seed}, kFlagNames, overrides);
}

int flag_threads(const std::string& file, const std::string& text) {
    return text.empty() ? 0 : static_cast<int>(flag_integer(file, "-t", text, 0, kMaxThreads));
}

namespace {

/// The render command's flags as scene overrides: --set, then --engine, -W, -H, --spp, --seed
/// (the flags win).
std::vector<Override> render_overrides(const RenderArgs& args) {
    std::vector<Override> overrides = parse_sets(args.sets, args.scene);
    add_key_overrides(args.scene,
                      RequestKeys{args.engine, args.width, args.height, args.spp, args.seed},
                      kFlagNames, overrides);
    return overrides;
}

/// --mse-reference REF --mse-log LOG.csv: after each pass, `spp,seconds,mse,relmse` against
/// the reference (the crop's pixels of it when the reference is the full film). The lines
/// are kept and written with the image, whole or not at all.
class MseLog {
public:
    MseLog(const RenderArgs& args, const RenderJob& job) {
        if (args.mse_reference.empty() != args.mse_log.empty()) {
            throw Error(args.scene, args.mse_log.empty() ? "--mse-reference" : "--mse-log",
                        "needs --mse-reference and --mse-log together");
        }
        if (args.mse_log.empty()) return;
        check_creatable(args.mse_log, "--mse-log");
        reference_ = read_image(args.mse_reference, "--mse-reference").image;
        const Crop c = film_window(job.scene, job.options);
        if (reference_.width == job.scene.film.width && reference_.height == job.scene.film.height)
            reference_ = crop_image(reference_, c.x0, c.y0, c.width(), c.height());
        if (reference_.width != c.width() || reference_.height != c.height()) {
            char why[128];
            std::snprintf(why, sizeof why, "is %d x %d; the render is %d x %d", reference_.width,
                          reference_.height, c.width(), c.height());
            throw Error(args.mse_reference, "--mse-reference", why);
        }
        path_ = args.mse_log;
        text_ = "spp,seconds,mse,relmse\n";
    }

    bool active() const { return !path_.empty(); }
    /// The line of one pass; the single-pass engines log once, after the render.
    void log(int spp, double seconds, const Image& image) {
        PixelMetrics m = pixel_metrics(image, reference_);
        char line[160];
        std::snprintf(line, sizeof line, "%d,%.6f,%.9g,%.9g\n", spp, seconds, m.rmse * m.rmse,
                      m.relmse);
        text_ += line;
    }
    void write() const {
        if (active()) write_text_file(path_, text_, "--mse-log");
    }

private:
    Image reference_;
    std::string path_, text_;
};

/// The summary's words on a render shared among `processes` (mpirun).
std::string distributed_detail(const DistributedStats& distributed, int processes) {
    char detail[200];
    std::snprintf(detail, sizeof detail, "%d processes, %d tiles (%d on rank 0), %.1f MiB sent",
                  processes, distributed.tiles, distributed.rank0_tiles,
                  static_cast<double>(distributed.bytes) / (1 << 20));
    if (distributed.exchanged > 0) {
        const size_t used = std::strlen(detail);
        std::snprintf(detail + used, sizeof detail - used, ", %.1f MiB exchanged in the setup",
                      static_cast<double>(distributed.exchanged) / (1 << 20));
    }
    return detail;
}

/// Says on stderr where a render resumed from its checkpoint, if it did.
void report_resumption(const std::string& path, const CheckpointFile* checkpoint, int resumed_tiles,
                       const Capabilities& engine) {
    if (checkpoint && resumed_tiles > 0) {
        std::fprintf(stderr, "svetlo: resumed from %s with %d tiles done\n", path.c_str(),
                     resumed_tiles);
    } else if (checkpoint && checkpoint->resumed_passes() > 0) {
        // The radiosity solve's passes are its shots.
        std::fprintf(stderr, "svetlo: resumed from %s after %s %d\n", path.c_str(),
                     engine.progressive ? "pass" : "shot", checkpoint->resumed_passes());
    }
}

/// --checkpoint: read and checked before the render (one line for a file of another run).
/// Every rank reads it; rank 0 (the `speaker`) alone writes it. Under mpirun the path
/// tracer's tiles are saved as they come in (distributed.h), the radiosity solve by the
/// engine. Returns whether the checkpoint holds tiles rather than the engine's state.
bool open_checkpoint(const RenderArgs& args, RenderJob& job, const Capabilities& engine,
                     bool speaker, std::optional<CheckpointFile>& checkpoint) {
    if (args.checkpoint.empty()) return false;
    if (!engine.checkpoints) {
        throw Error(args.scene, "--checkpoint",
                    "needs an engine that keeps one (" +
                        engines_with([](const Capabilities& c) { return c.checkpoints; }) + "); " +
                        engine.name + " does not");
    }
    const bool tiles = job.run.processes > 1 && !engine.whole_frame;
    checkpoint.emplace(args.checkpoint, job,
                       tiles ? CheckpointFile::Layout::Tiles : CheckpointFile::Layout::Engine,
                       speaker);
    if (!tiles) job.options.checkpoint = &checkpoint->callbacks();
    return tiles;
}

}  // namespace

int run_render(const RenderArgs& args) {
    std::vector<Override> overrides = render_overrides(args);
    const int threads = flag_threads(args.scene, args.threads);
    const double time_budget = flag_seconds(args.scene, "--time", args.time);

    // Check every output before the (possibly long) render.
    check_writable(args.output, "-o");
    // The scene first: reading it checks the file (a device, a folder) before it is hashed.
    // A model file is read once: for its framing, then for the render.
    FileCache meshes;
    nlohmann::json json = effective_scene_json(args.scene, overrides, &meshes);
    RenderJob job = make_job(std::move(json), args.scene, sha256_file(args.scene), &meshes);
    const Scene& scene = job.scene;
    job.run.command = args.command;
    if (!args.crop.empty())
        job.options.crop = parse_crop(args.crop, args.scene, scene.film.width, scene.film.height);
    request_aovs(job, args.aovs, args.output);
    // An unknown engine, before the checks below; a progressive one for --time.
    const Capabilities& engine = capabilities_of(scene.render.engine, args.scene);
    if (time_budget > 0.0) set_time_budget(job, time_budget, args.scene, "--time");
    // Many processes (mpirun): every rank checks all of the above, so that bad input ends
    // them all alike; rank 0 alone writes and speaks.
    const int processes = args.mpi ? args.mpi->size() : 1;
    const bool speaker = !args.mpi || args.mpi->rank() == 0;
    if (processes > 1) {
        if (time_budget > 0.0)
            throw Error(args.scene, "--time", "renders on one process only (not under mpirun)");
        if (!args.mse_log.empty())
            throw Error(args.scene, "--mse-log", "renders on one process only (not under mpirun)");
    }
    job.run.processes = processes;
    std::optional<CheckpointFile> checkpoint;
    const bool tiles = open_checkpoint(args, job, engine, speaker, checkpoint);
    RenderOptions& options = job.options;
    options.threads = threads;
    options.spp_caps_time = !args.spp.empty();  // the scene's spp does not cap --time
    options.progress = !args.quiet && stderr_is_terminal() && processes == 1;
    MseLog mse(args, job);
    if (mse.active()) {
        options.on_pass = [&](int passes, double seconds, const Image& image) {
            mse.log(passes, seconds, image);
        };
    }
    InterruptGuard interrupt;
    options.cancel = &interrupt.flag();
    DistributedStats distributed;
    RenderResult result = processes > 1 ? run_job_distributed(job, *args.mpi, distributed,
                                                              tiles ? &*checkpoint : nullptr)
                                        : run_job(job);
    if (!speaker) return 0;
    if (processes > 1) {
        const std::string detail = distributed_detail(distributed, processes);
        result.stats.detail =
            result.stats.detail.empty() ? detail : result.stats.detail + ", " + detail;
    }
    if (mse.active() && result.stats.passes == 0)
        mse.log(reached_spp(job, result), result.stats.seconds, result.color);
    job.run.interrupted = interrupt.signal() != 0;
    write_job_outputs(job, result, args.output);
    mse.write();
    if (!args.quiet) print_summary(job, result, args.output);
    if (!args.quiet) {
        report_resumption(args.checkpoint, checkpoint ? &*checkpoint : nullptr,
                          distributed.resumed_tiles, engine);
    }
    if (job.run.interrupted && !args.quiet) {
        std::fprintf(stderr, "svetlo: interrupted: wrote the %d passes done to %s\n",
                     reached_spp(job, result), args.output.c_str());
    }
    return interrupt.exit_status();
}

void print_summary(const RenderJob& job, const RenderResult& result, const std::string& output) {
    const Scene& scene = job.scene;
    const Crop crop = film_window(scene, job.options);
    double per_second = result.stats.seconds > 0.0 ? 1e-6 / result.stats.seconds : 0.0;
    char rate[160];
    if (result.stats.triangles > 0) {
        std::snprintf(rate, sizeof rate, "%.2f Mtris/s",
                      static_cast<double>(result.stats.triangles) * per_second);
    } else if (result.stats.passes > 0) {  // a path per pixel and pass
        double paths = static_cast<double>(result.stats.passes) * crop.width() *
                       static_cast<double>(crop.height());
        std::snprintf(rate, sizeof rate, "%.2f Mpaths/s, %.2f Mrays/s", paths * per_second,
                      static_cast<double>(result.stats.rays) * per_second);
    } else {
        std::snprintf(rate, sizeof rate, "%.2f Mrays/s",
                      static_cast<double>(result.stats.rays) * per_second);
    }
    // The engine's own account: in place of the rays, or after the paths.
    std::string account = rate;
    if (!result.stats.detail.empty()) {
        account =
            result.stats.passes > 0 ? account + ", " + result.stats.detail : result.stats.detail;
    }
    std::string dropped;  // samples that were not finite, left out of their pixels
    if (result.stats.nonfinite > 0)
        dropped = ", " + std::to_string(result.stats.nonfinite) + " non-finite samples dropped";
    std::string window;
    if (!(crop == Crop::full(scene.film.width, scene.film.height))) {
        window = " (crop " + std::to_string(crop.x0) + "," + std::to_string(crop.x1) + "," +
                 std::to_string(crop.y0) + "," + std::to_string(crop.y1) + ")";
    }
    std::fprintf(stderr,
                 "svetlo: %s %dx%d%s, %d spp, %d threads: setup %.3f s, render %.3f s, %s%s -> "
                 "%s\n",
                 scene.render.engine.c_str(), scene.film.width, scene.film.height, window.c_str(),
                 reached_spp(job, result), resolve_threads(job.options.threads),
                 result.stats.setup_seconds, result.stats.seconds, account.c_str(), dropped.c_str(),
                 output.c_str());
}

}  // namespace svetlo
