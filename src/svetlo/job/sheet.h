// The comparison sheet of `svetlo compare` (docs/compare.md): each technique's image beside
// its ꟻLIP error against the reference in false colour, its metrics and seconds, and for the
// progressive techniques their error against time. Two forms: one self-contained HTML file
// (images inline as PNG, the plot as inline SVG) and one PNG (a labelled grid).
#pragma once

#include <string>
#include <vector>

#include "svetlo/core/image.h"
#include "svetlo/core/image_io.h"
#include "svetlo/job/compare.h"

namespace svetlo {

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
