// The comparison sheet of `svetlo compare` (docs/compare.md): each technique's image beside
// its ꟻLIP error against the reference in false colour, its metrics and seconds, and for the
// progressive techniques their error against time. Two forms: one self-contained HTML file
// (images inline as PNG, the plot as inline SVG) and one PNG (a labelled grid).
#pragma once

#include <string>
#include <vector>

#include "commands.h"
#include "svetlo/core/image.h"
#include "svetlo/core/image_io.h"

namespace svetlo {

/// One point of a convergence curve: after `spp` passes, `seconds` in, the error.
struct CurvePoint {
    int spp = 0;
    double seconds = 0.0;
    double rmse = 0.0, relmse = 0.0;
};

struct SheetEntry {
    std::string spec;  // the technique SPEC
    std::string name;  // the technique as the lecture names it (technique_name)
    std::string engine;
    Image image;  // linear radiance
    float exposure = 1.0f;
    ImageComparison metrics;
    double seconds = 0.0;
    std::vector<CurvePoint> curve;  // progressive engines, with --curves
    /// The buffers asked for by `aov=NAME` in the SPEC, as aov_for_display makes them.
    std::vector<std::pair<std::string, Image>> buffers;
};

struct Sheet {
    std::string scene;      // the scene file
    std::string reference;  // SPEC or image file
    Image reference_image;
    float reference_exposure = 1.0f;
    std::vector<SheetEntry> entries;
};

/// compare's renders: each technique SPEC over `base` (the scene's JSON with the command's
/// overrides, read as `file`) against the reference (a SPEC or an image; empty:
/// path:render.spp=1024), with its metrics, and with `curves` its error after each pass.
/// Every film is checked against the reference's before any render; errors name the SPEC.
Sheet compare_techniques(const nlohmann::json& base, const std::string& file,
                         const std::string& sha256, const std::vector<std::string>& techniques,
                         const std::string& reference, int threads, bool curves, bool quiet);

/// The sheet's metrics as compare --json writes them: the keys of docs/compare.md in their order.
nlohmann::ordered_json sheet_json(const Sheet& sheet);

/// The HTML page: one file, nothing fetched.
std::string sheet_html(const Sheet& sheet);

/// The PNG grid: a column per image (the reference first), the images above their error
/// images, each labelled with its SPEC and numbers, then the buffers of each, labelled; a
/// legend of the false colour below.
Image sheet_png(const Sheet& sheet);

/// The error-against-time plot of the entries that have curves, as an SVG element (log-log
/// axes, relMSE against seconds); empty when none has a curve.
std::string curves_svg(const Sheet& sheet);

/// An image as a PNG inside a data: URL, for pages that inline their images (the sheet, the
/// viewer's A/B comparison).
std::string png_data_url(const Image& image, PixelMeaning meaning, float exposure);

}  // namespace svetlo
