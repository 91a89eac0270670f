// svetlo compare's renders (docs/compare.md): one scene under several techniques, each
// measured against one reference with the metrics of docs/metrics.md. The command line, the
// viewer's A/B and Python make their sheets here; sheet.h draws them.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "svetlo/core/flip.h"
#include "svetlo/core/image.h"
#include "svetlo/core/image_metrics.h"

namespace svetlo {

/// The metrics of `test` against `reference` (docs/metrics.md): LDR-ꟻLIP when `ldr` (both
/// images came from 8-bit sRGB files), HDR-ꟻLIP otherwise.
struct ImageComparison {
    PixelMetrics pixels;
    FlipMap flip;
    double value(const std::string& metric) const;  // mae, rmse, relmse or flip
};
ImageComparison compare_images(const Image& test, const Image& reference, bool ldr, int threads);

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

}  // namespace svetlo
