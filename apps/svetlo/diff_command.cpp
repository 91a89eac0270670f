// svetlo diff A B [--metric mae|rmse|relmse|flip] [--tolerance X] [-o ERROR_IMAGE]
// The metrics of docs/metrics.md, B the reference; exit 0 when the metric is at most the
// tolerance, 1 above it, 2 on trouble, as Unix diff.
#include <cstdio>
#include <limits>

#include "commands.h"
#include "svetlo/core/error.h"
#include "svetlo/core/flip.h"
#include "svetlo/core/image_io.h"
#include "svetlo/core/image_metrics.h"
#include "svetlo/job/compare.h"

namespace svetlo {

namespace {

const std::vector<std::string>& metric_names() {
    static const std::vector<std::string> names = {"mae", "rmse", "relmse", "flip"};
    return names;
}

}  // namespace

int run_diff(const DiffArgs& args) {
    try {
        if (!args.metric.empty() && std::find(metric_names().begin(), metric_names().end(),
                                              args.metric) == metric_names().end()) {
            throw Error(
                "svetlo", "--metric",
                "unknown metric '" + args.metric + "' (expected mae, rmse, relmse or flip)");
        }
        double tolerance = 0.0;
        if (!args.tolerance.empty()) {
            char* end = nullptr;
            tolerance = std::strtod(args.tolerance.c_str(), &end);
            if (end != args.tolerance.c_str() + args.tolerance.size() || !(tolerance >= 0.0) ||
                !std::isfinite(tolerance))
                throw Error("svetlo", "--tolerance",
                            "must be a number >= 0 (is '" + args.tolerance + "')");
        }
        if (!args.output.empty()) check_writable(args.output, "-o");
        LoadedImage a = read_image(args.a, "diff"), b = read_image(args.b, "diff");
        if (a.image.width != b.image.width || a.image.height != b.image.height) {
            char why[160];
            std::snprintf(why, sizeof why, "is %d x %d but %s is %d x %d", a.image.width,
                          a.image.height, args.b.c_str(), b.image.width, b.image.height);
            throw Error(args.a, "diff", why);
        }
        // LDR-ꟻLIP when both are 8-bit sRGB files, HDR-ꟻLIP otherwise.
        const bool ldr = a.ldr && b.ldr;
        ImageComparison c = compare_images(a.image, b.image, ldr, 0);
        const std::string decisive = args.metric.empty() ? "rmse" : args.metric;
        if (args.metric.empty()) {
            for (const std::string& m : metric_names())
                std::printf("%s %.9g\n", m.c_str(), c.value(m));
        } else {
            std::printf("%s %.9g\n", args.metric.c_str(), c.value(args.metric));
        }
        if (!args.output.empty()) {
            std::vector<float> errors =
                decisive == "flip" ? c.flip.error : pixel_errors(a.image, b.image, decisive);
            Image out;
            if (image_format_for(args.output, "-o") == ImageFormat::Png) {
                // ꟻLIP's errors are in [0, 1]; the others are scaled by their largest value.
                float top = 1.0f;
                if (decisive != "flip") {
                    top = 0.0f;
                    for (float e : errors) top = std::max(top, e);
                }
                out = false_color(errors, a.image.width, a.image.height, top);
            } else {
                out = Image(a.image.width, a.image.height);
                for (size_t k = 0; k < errors.size(); ++k) out.pixels[k] = Color(errors[k]);
            }
            write_image(args.output, out, PixelMeaning::Data, 1.0f, "-o");
        }
        return c.value(decisive) <= tolerance ? 0 : 1;
    } catch (const Error& e) {
        std::fprintf(stderr, "svetlo: error: %s: %s: %s\n", e.file().c_str(), e.where().c_str(),
                     e.message().c_str());
        return 2;
    }
}

}  // namespace svetlo
