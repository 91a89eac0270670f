// svetlo trace SCENE.json --pixel X,Y [--sample K] [--json FILE] [--obj FILE] [--set ...]
//              [-e ENGINE] [-W W] [-H H] [--spp N] [--seed S] [-t N]
// One camera sample of one pixel, followed through the scene's engine and printed as a tree
// (docs/trace.md): the engine renders that pixel alone (a crop of one pixel) and records
// every ray or path vertex of the sample. Its total is the pixel of `render --spp 1 --crop
// X,X+1,Y,Y+1` for sample 0.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "commands.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/sha256.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/pixel_trace_job.h"
#include "svetlo/job/render_job.h"

namespace svetlo {

namespace {

/// --pixel X,Y inside a width x height film.
std::pair<int, int> parse_pixel(const std::string& text, const std::string& file, int width,
                                int height) {
    const size_t comma = text.find(',');
    if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos)
        throw Error(file, "--pixel", "expected X,Y (is '" + text + "')");
    const long long x = flag_integer(file, "--pixel", text.substr(0, comma), 0, kMaxFilmSide);
    const long long y = flag_integer(file, "--pixel", text.substr(comma + 1), 0, kMaxFilmSide);
    if (x >= width || y >= height) {
        char why[160];
        std::snprintf(why, sizeof why, "(%lld, %lld) lies outside the %d x %d film", x, y, width,
                      height);
        throw Error(file, "--pixel", why);
    }
    return {static_cast<int>(x), static_cast<int>(y)};
}

std::string number(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", static_cast<double>(v));
    return text;
}

std::string color_text(Color c) { return number(c.r) + " " + number(c.g) + " " + number(c.b); }

/// The tree as text, each ray under the one it branches from.
std::string trace_text(const PixelTrace& log, const std::string& engine) {
    std::ostringstream out;
    out << "pixel (" << log.x << ", " << log.y << "), sample " << log.sample << ", " << engine
        << "\n";
    std::vector<std::vector<int>> children(log.rays.size());
    std::vector<int> roots;
    for (size_t k = 0; k < log.rays.size(); ++k) {
        const int parent = log.rays[k].parent;
        (parent < 0 ? roots : children[static_cast<size_t>(parent)]).push_back(static_cast<int>(k));
    }
    auto print = [&](auto&& self, int k, int indent) -> void {
        const TraceRay& r = log.rays[static_cast<size_t>(k)];
        out << std::string(static_cast<size_t>(2 * indent), ' ') << r.kind << " #" << k << ": t "
            << (std::isfinite(r.t) ? number(r.t) : "inf") << ", adds "
            << color_text(r.contribution);
        if (!r.note.empty()) out << " (" << r.note << ")";
        for (const TraceValue& v : r.values) {
            out << ", " << v.name;
            for (float x : v.value) out << " " << number(x);
        }
        out << "\n";
        for (int child : children[static_cast<size_t>(k)]) self(self, child, indent + 1);
    };
    for (int root : roots) print(print, root, 1);
    for (const std::string& note : log.notes) out << "note: " << note << "\n";
    out << "total " << color_text(log.total) << "\n";
    return out.str();
}

/// The rays as OBJ line segments, one object per ray named by its index and kind; a ray that
/// meets nothing is drawn twice as long as the longest that does.
std::string trace_obj(const PixelTrace& log) {
    float longest = 0.0f;
    for (const TraceRay& r : log.rays)
        if (std::isfinite(r.t)) longest = std::max(longest, r.t);
    const float open = longest > 0.0f ? 2.0f * longest : 1.0f;
    std::ostringstream out;
    out << "# svetlo trace: pixel " << log.x << " " << log.y << ", sample " << log.sample << "\n";
    int vertex = 0;
    for (size_t k = 0; k < log.rays.size(); ++k) {
        const TraceRay& r = log.rays[k];
        const vec3 end = r.origin + r.direction * (std::isfinite(r.t) ? r.t : open);
        out << "o ray" << k << "_" << r.kind << "\n";
        out << "v " << number(r.origin.x) << " " << number(r.origin.y) << " " << number(r.origin.z)
            << "\n";
        out << "v " << number(end.x) << " " << number(end.y) << " " << number(end.z) << "\n";
        out << "l " << vertex + 1 << " " << vertex + 2 << "\n";
        vertex += 2;
    }
    return out.str();
}

}  // namespace

PixelTrace trace_pixel(const TraceArgs& args, std::string& engine) {
    std::vector<Override> overrides = parse_sets(args.sets, args.scene);
    add_flag_overrides(args.scene, args.width, args.height, overrides, args.engine, args.seed);
    const long long sample =
        args.sample.empty() ? 0 : flag_integer(args.scene, "--sample", args.sample, 0, kMaxSpp - 1);
    const long long spp =
        args.spp.empty() ? 1 : flag_integer(args.scene, "--spp", args.spp, 1, kMaxSpp);
    RenderJob job =
        make_job(effective_scene_json(args.scene, overrides), args.scene, sha256_file(args.scene));
    engine = job.scene.render.engine;
    const auto [x, y] =
        parse_pixel(args.pixel, args.scene, job.scene.film.width, job.scene.film.height);
    if (!args.json.empty()) check_creatable(args.json, "--json");
    if (!args.obj.empty()) check_creatable(args.obj, "--obj");
    job.options.threads = flag_threads(args.scene, args.threads);
    return trace_job(job, x, y, sample, spp);
}

int run_trace(const TraceArgs& args) {
    std::string engine;
    const PixelTrace log = trace_pixel(args, engine);
    if (!args.json.empty())
        write_text_file(args.json, trace_json(log, engine).dump(2) + "\n", "--json");
    if (!args.obj.empty()) write_text_file(args.obj, trace_obj(log), "--obj");
    std::fputs(trace_text(log, engine).c_str(), stdout);
    return 0;
}

}  // namespace svetlo
