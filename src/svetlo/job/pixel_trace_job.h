// svetlo trace's record of one camera sample (docs/trace.md), made by the job's engine for
// the command line, the viewer and Python alike.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "svetlo/job/render_job.h"
#include "svetlo/scene/pixel_trace.h"

namespace svetlo {

/// Sample `sample` of pixel (x, y) of the job's scene, recorded by its engine, with `spp`
/// samples per pixel (a path renders sample + 1 passes at least); throws Error naming
/// --pixel or --sample for a pixel or sample that does not exist.
PixelTrace trace_job(RenderJob& job, int x, int y, long long sample, long long spp);
/// The trace as the JSON object of docs/trace.md.
nlohmann::json trace_json(const PixelTrace& trace, const std::string& engine);

}  // namespace svetlo
