// svetlo assemble PART... -o OUT: crops of one render (render --crop) back into the full
// image, placed by their provenance. Parts of different renders, gaps and overlaps are
// refused with one line.
#include <cstdio>

#include "commands.h"
#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/job/provenance.h"

namespace svetlo {

namespace {

/// What makes two crops parts of one render: everything but the window and the timings.
nlohmann::json render_identity(const nlohmann::json& p) {
    nlohmann::json id;
    for (const char* key :
         {"scene", "engine", "spp", "seed", "full_resolution", "image", "version"})
        id[key] = p.value(key, nlohmann::json());
    return id;
}

}  // namespace

int run_assemble(const AssembleArgs& args) {
    check_writable(args.output, "-o");
    nlohmann::json first;
    int width = 0, height = 0;
    Image full;
    std::vector<int> owner;  // per pixel, the part that filled it (-1: none yet)
    bool all_ldr = true;
    double seconds = 0.0;
    for (size_t k = 0; k < args.parts.size(); ++k) {
        const std::string& part = args.parts[k];
        nlohmann::json p = read_provenance(part, "assemble");
        if (k == 0) {
            first = p;
            std::tie(width, height) = provenance_resolution(p, part);
            if (width <= 0 || height <= 0)
                throw Error(part, "provenance.full_resolution", "is not a film size");
            full = Image(width, height);
            owner.assign(static_cast<size_t>(width) * height, -1);
        } else if (render_identity(p) != render_identity(first)) {
            throw Error(part, "assemble",
                        "is a crop of another render than " + args.parts[0] +
                            " (its scene, engine, spp, seed or resolution differ)");
        }
        Crop c = provenance_crop(p, part);
        LoadedImage image = read_image(part, "assemble");
        all_ldr = all_ldr && image.ldr;
        if (!c.inside(width, height) || image.image.width != c.width() ||
            image.image.height != c.height()) {
            throw Error(part, "provenance.crop", "does not match the image or leaves the film");
        }
        for (int j = c.y0; j < c.y1; ++j) {
            for (int i = c.x0; i < c.x1; ++i) {
                int& o = owner[static_cast<size_t>(j) * width + i];
                if (o >= 0) {
                    char why[200];
                    std::snprintf(why, sizeof why, "overlaps %s at pixel (%d, %d)",
                                  args.parts[o].c_str(), i, j);
                    throw Error(part, "assemble", why);
                }
                o = static_cast<int>(k);
                full.at(i, j) = image.image.at(i - c.x0, j - c.y0);
            }
        }
        seconds += p.value("seconds", 0.0);
    }
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            if (owner[static_cast<size_t>(j) * width + i] >= 0) continue;
            char why[160];
            std::snprintf(why, sizeof why,
                          "the parts leave a gap: pixel (%d, %d) of the %d x %d film is in none", i,
                          j, width, height);
            throw Error(args.parts[0], "assemble", why);
        }
    }
    nlohmann::json p = first;
    p["crop"] = {0, width, 0, height};
    p["seconds"] = seconds;
    p["assembled_from"] = args.parts.size();
    // 8-bit parts hold the exposed, encoded values already: written again without exposure.
    float exposure = 1.0f;
    if (!all_ldr && first["scene"].contains("render"))
        exposure = first["scene"]["render"].value("exposure", 1.0f);
    const bool radiance = p.value("image", "color") == "color" || p.value("image", "") == "albedo";
    write_image(args.output, full, radiance ? PixelMeaning::Radiance : PixelMeaning::Data, exposure,
                "-o", p.dump());
    return 0;
}

}  // namespace svetlo
