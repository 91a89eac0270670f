// One render as the commands run it (render, reproduce, compare): the effective scene, the
// engine's options, the AOVs asked for, and the images written with their provenance.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "svetlo/job/provenance.h"
#include "svetlo/job/renderer_pool.h"
#include "svetlo/scene/file_cache.h"
#include "svetlo/scene/renderer.h"
#include "svetlo/scene/scene_loader.h"

namespace svetlo {

struct RenderJob {
    RunRecord run;
    Scene scene;
    RenderOptions options;
    std::vector<std::pair<std::string, std::string>> aov_files;  // NAME, FILE
};

/// The job of `json` (an effective scene, every override applied) read as the file `path`:
/// the scene built and validated, the record filled but for the command and the threads.
/// Mesh files come through `meshes` when given (the jobs of one command share them).
/// Every file the scene names must lie in `files`.
RenderJob make_job(nlohmann::json json, const std::filesystem::path& path, std::string sha256,
                   FileCache* meshes = nullptr, const FileScope& files = {});

/// Gives the job a time budget of `seconds` (> 0, at most a week): the command line's --time
/// and Python's `time`, named `key` in the errors. Throws Error for a number out of range or
/// an engine that is not progressive (engines.h).
void set_time_budget(RenderJob& job, double seconds, const std::string& file,
                     const std::string& key);

/// Parses --crop X0,X1,Y0,Y1 for a film of width x height; throws Error naming --crop for a
/// window outside the film or empty.
Crop parse_crop(const std::string& text, const std::string& file, int width, int height);

/// Asks the job's engine for AOV `name` (a plain or a debug one); throws Error(file, where)
/// for an unknown name or one the job's engine and technique do not make.
void request_aov(RenderJob& job, const std::string& name, const std::string& file,
                 const std::string& where);

/// request_aov for each of the NAME=FILE specs; their files are checked writable.
void request_aovs(RenderJob& job, const std::vector<std::string>& specs, const std::string& output);

/// An AOV made visible in 8 bits, as PNG writes it: values in [0, 1] to be written linearly
/// (normals mapped from [-1, 1], depths and counts scaled, costs as a heat map).
Image aov_for_display(const std::string& name, Image image);

/// Renders the job with its renderer.
RenderResult run_job(const RenderJob& job);
/// The same with a renderer of its engine taken from `pool` (the viewer's, kept from one
/// request to the next) and given back after.
RenderResult run_job(const RenderJob& job, RendererPool& pool);

/// Writes the colour image to `output` (none when empty) and each AOV to its file, every one
/// with its provenance.
void write_job_outputs(const RenderJob& job, const RenderResult& result, const std::string& output);

/// The memory a render of the job takes beyond its scene, bytes: its film (or crop) times
/// the engine's Capabilities::film_bytes_per_pixel and kAovBytesPerPixel per AOV asked for.
/// A caller with a hard limit (the web page's WebAssembly memory) refuses a job above it.
uint64_t estimated_render_bytes(const RenderJob& job);
/// What each AOV asked for adds per pixel (its image and its sums), bytes.
inline constexpr uint64_t kAovBytesPerPixel = 40;

/// Writes `text` to `path` atomically (a temporary file, then a rename); throws Error naming
/// `where`.
void write_text_file(const std::string& path, const std::string& text, const std::string& where);

/// The samples per pixel a result reached: the passes of a progressive engine, else the
/// scene's spp.
int reached_spp(const RenderJob& job, const RenderResult& result);

/// The provenance an image of the job carries (docs/provenance.md), as the text written into
/// the file: of its colour image, or of the AOV `image` names.
std::string job_provenance(const RenderJob& job, const RenderResult& result,
                           const std::string& image = "color");

}  // namespace svetlo
