// svetlo compare SCENE.json -T SPEC [-T SPEC]... [--reference SPEC|IMAGE] [-o SHEET.html]
//                [--png SHEET.png] [--json METRICS.json] [-W W] [-H H] [--threads N] [--seed S]
//                [--set KEY=VALUE]... [--curves] [-q]
// One scene under several techniques, each against one reference (docs/compare.md). A SPEC is
// an engine followed by scene overrides, separated by colons: raster:render.shading=gouraud.
#include <cstdio>
#include <optional>

#include "commands.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/progress.h"
#include "svetlo/core/sha256.h"
#include "svetlo/geometry/accel_cache.h"
#include "svetlo/geometry/occluder_cube.h"
#include "svetlo/geometry/triangle_list_cache.h"
#include "svetlo/job/engines.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/render_job.h"
#include "svetlo/job/sheet.h"

namespace svetlo {

int run_compare(const CompareArgs& args) {
    const std::string& file = args.scene;
    // Every output is checked before the renders, which may be long.
    if (!args.png.empty()) check_writable(args.png, "--png");
    if (!args.html.empty()) check_creatable(args.html, "-o");
    if (!args.json.empty()) check_creatable(args.json, "--json");
    if (args.html.empty() && args.png.empty() && args.json.empty())
        throw Error(file, "compare", "nothing to write: give -o SHEET.html, --png or --json");
    const int threads = flag_threads(file, args.threads);
    std::vector<Override> overrides = parse_sets(args.sets, file);
    add_flag_overrides(file, args.width, args.height, overrides, {}, args.seed);
    // The scene is read once; each technique applies its overrides to a copy of its JSON.
    const nlohmann::json base = effective_scene_json(file, overrides);
    const Sheet sheet = compare_techniques(base, file, sha256_file(file), args.techniques,
                                           args.reference, threads, args.curves, args.quiet);
    if (!args.json.empty()) write_text_file(args.json, sheet_json(sheet).dump(2) + "\n", "--json");
    if (!args.html.empty()) write_text_file(args.html, sheet_html(sheet), "-o");
    if (!args.png.empty())
        write_image(args.png, sheet_png(sheet), PixelMeaning::Radiance, 1.0f, "--png");
    return 0;
}

}  // namespace svetlo
