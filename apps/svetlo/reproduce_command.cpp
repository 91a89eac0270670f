// svetlo reproduce IMAGE -o OUT: the image rendered again from its provenance (the embedded
// effective scene, engine, seed, spp reached, crop), bit for bit, whatever the scene file
// holds now. svetlo info IMAGE: that provenance.
#include <cstdio>

#include "commands.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/progress.h"
#include "svetlo/job/limits.h"
#include "svetlo/job/render_job.h"

namespace svetlo {

int run_reproduce(const ReproduceArgs& args) {
    nlohmann::json p = read_provenance(args.image, "reproduce");
    auto scene = p.find("scene");
    auto file = p.find("scene_file");
    auto spp = p.find("spp");
    if (scene == p.end() || !scene->is_object() || file == p.end() || !file->is_string() ||
        spp == p.end() || !spp->is_number_integer()) {
        throw Error(args.image, "reproduce",
                    "its provenance lacks the scene, scene_file or spp to render it from");
    }
    check_writable(args.output, "-o");
    nlohmann::json json = *scene;
    // The passes a --time render reached, now as a count: no clock decides this time.
    json["render"]["spp"] = spp->get<int>();
    RenderJob job = make_job(json, file->get<std::string>(), p.value("scene_sha256", ""));
    job.run.command = p.value("command", std::vector<std::string>{});
    job.options.threads =
        args.threads.empty() ? p.value("threads", 0) : flag_threads(args.image, args.threads);
    const auto [w, h] = provenance_resolution(p, args.image);
    if (w != job.scene.film.width || h != job.scene.film.height)
        throw Error(args.image, "provenance.full_resolution", "differs from the scene's film");
    const Crop crop = provenance_crop(p, args.image);
    if (!crop.inside(w, h)) throw Error(args.image, "provenance.crop", "leaves the film");
    job.options.crop = crop;
    const std::string image = p.value("image", "color");
    if (image != "color") request_aovs(job, {image + "=" + args.output}, "");
    job.options.progress = !args.quiet && stderr_is_terminal();
    RenderResult result = run_job(job);
    // An AOV's image is reproduced as that AOV alone (request_aovs made OUT its file).
    write_job_outputs(job, result, image == "color" ? args.output : std::string());
    if (!args.quiet) print_summary(job, result, args.output);
    return 0;
}

int run_image_info(const std::string& image, bool json) {
    nlohmann::json p = read_provenance(image, "info");
    if (json) {
        std::printf("%s\n", p.dump(2).c_str());
        return 0;
    }
    // The scene is long: its size here, the whole of it with --json.
    for (const auto& [key, value] : p.items()) {
        if (key == "scene") {
            std::printf("%-16s (%zu keys; svetlo info IMAGE --json prints it)\n", key.c_str(),
                        value.size());
        } else if (key == "command" && value.is_array()) {
            std::string line;
            for (const auto& arg : value) {
                if (!line.empty()) line += ' ';
                line += arg.is_string() ? arg.get<std::string>() : arg.dump();
            }
            std::printf("%-16s %s\n", key.c_str(), line.c_str());
        } else {
            std::printf(
                "%-16s %s\n", key.c_str(),
                value.is_string() ? value.get<std::string>().c_str() : value.dump().c_str());
        }
    }
    return 0;
}

}  // namespace svetlo
