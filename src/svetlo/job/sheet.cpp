#include "svetlo/job/sheet.h"

#include <stb_easy_font.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "svetlo/core/image_io.h"
#include "svetlo/core/image_metrics.h"

namespace svetlo {

namespace {

std::string base64(const std::vector<unsigned char>& bytes) {
    static constexpr char table[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t k = 0; k < bytes.size(); k += 3) {
        uint32_t v = uint32_t{bytes[k]} << 16;
        if (k + 1 < bytes.size()) v |= uint32_t{bytes[k + 1]} << 8;
        if (k + 2 < bytes.size()) v |= bytes[k + 2];
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += k + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        out += k + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

std::string escape_html(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '&':
                out += "&amp;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

Image error_image(const SheetEntry& e) {
    return false_color(e.metrics.flip.error, e.image.width, e.image.height, 1.0f);
}

/// The numbers under a technique's error image, in two lines that fit the narrowest column.
std::array<std::string, 2> numbers(const SheetEntry& e) {
    char first[120], second[120];
    std::snprintf(first, sizeof first, "mae %.4g  rmse %.4g  relmse %.4g", e.metrics.pixels.mae,
                  e.metrics.pixels.rmse, e.metrics.pixels.relmse);
    std::snprintf(second, sizeof second, "flip %.4f  %.2f s", e.metrics.flip.mean, e.seconds);
    return {first, second};
}

const char* kCurveColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};

}  // namespace

std::string png_data_url(const Image& image, PixelMeaning meaning, float exposure) {
    return "data:image/png;base64," + base64(encode_png(image, meaning, exposure));
}

std::string curves_svg(const Sheet& sheet) {
    double t0 = 1e300, t1 = 0.0, e0 = 1e300, e1 = 0.0;
    for (const SheetEntry& e : sheet.entries) {
        for (const CurvePoint& p : e.curve) {
            if (p.seconds <= 0.0 || p.relmse <= 0.0) continue;
            t0 = std::min(t0, p.seconds), t1 = std::max(t1, p.seconds);
            e0 = std::min(e0, p.relmse), e1 = std::max(e1, p.relmse);
        }
    }
    if (t1 <= 0.0) return {};
    // Log-log axes padded to whole decades.
    const double lt0 = std::floor(std::log10(t0)), lt1 = std::ceil(std::log10(t1) + 1e-9);
    const double le0 = std::floor(std::log10(e0)), le1 = std::ceil(std::log10(e1) + 1e-9);
    const double W = 640, H = 400, L = 70, R = 20, T = 20, B = 50;
    auto x = [&](double t) { return L + (std::log10(t) - lt0) / (lt1 - lt0) * (W - L - R); };
    auto y = [&](double e) { return H - B - (std::log10(e) - le0) / (le1 - le0) * (H - T - B); };
    std::string svg =
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"400\" "
        "font-family=\"sans-serif\" font-size=\"12\">\n";
    char line[400];
    for (double d = lt0; d <= lt1; d += 1.0) {
        std::snprintf(line, sizeof line,
                      "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                      "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">1e%g s</text>\n",
                      x(std::pow(10, d)), T, x(std::pow(10, d)), H - B, x(std::pow(10, d)),
                      H - B + 18, d);
        svg += line;
    }
    for (double d = le0; d <= le1; d += 1.0) {
        std::snprintf(line, sizeof line,
                      "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                      "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">1e%g</text>\n",
                      L, y(std::pow(10, d)), W - R, y(std::pow(10, d)), L - 6,
                      y(std::pow(10, d)) + 4, d);
        svg += line;
    }
    std::snprintf(line, sizeof line,
                  "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">seconds</text>"
                  "<text x=\"14\" y=\"%.1f\" transform=\"rotate(-90 14 %.1f)\" "
                  "text-anchor=\"middle\">relMSE</text>\n",
                  (L + W - R) / 2, H - 8, (T + H - B) / 2, (T + H - B) / 2);
    svg += line;
    int k = 0;
    for (const SheetEntry& e : sheet.entries) {
        if (e.curve.empty()) continue;
        const char* color = kCurveColors[k % 6];
        // The line through the passes, and the last pass marked: an engine of one pass is
        // that mark alone.
        std::string points, mark;
        for (const CurvePoint& p : e.curve) {
            if (p.seconds <= 0.0 || p.relmse <= 0.0) continue;
            std::snprintf(line, sizeof line, "%.1f,%.1f ", x(p.seconds), y(p.relmse));
            points += line;
            std::snprintf(line, sizeof line,
                          "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n", x(p.seconds),
                          y(p.relmse), color);
            mark = line;
        }
        svg += "<polyline fill=\"none\" stroke-width=\"2\" stroke=\"" + std::string(color) +
               "\" points=\"" + points + "\"/>\n" + mark;
        std::snprintf(line, sizeof line, "<text x=\"%.1f\" y=\"%.1f\" fill=\"%s\">", W - R - 240,
                      T + 16.0 * (k + 1), color);
        svg += line + escape_html(e.name) + "</text>\n";
        ++k;
    }
    return svg + "</svg>";
}

std::string sheet_html(const Sheet& sheet) {
    std::string h =
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        "<title>svetlo compare: " +
        escape_html(sheet.scene) +
        "</title>\n<style>body{font-family:sans-serif;margin:1em;background:#fafafa}"
        "table{border-collapse:collapse}td,th{padding:6px;vertical-align:top;text-align:left}"
        "img{image-rendering:pixelated;display:block;max-width:480px}"
        "code{font-size:90%}.legend{width:256px;height:14px;background:linear-gradient(to right";
    for (int k = 0; k <= 10; ++k) {
        Color c = magma(static_cast<float>(k) / 10.0f);
        char stop[48];
        std::snprintf(stop, sizeof stop, ",rgb(%d,%d,%d)", static_cast<int>(c.r * 255 + 0.5f),
                      static_cast<int>(c.g * 255 + 0.5f), static_cast<int>(c.b * 255 + 0.5f));
        h += stop;
    }
    h += ")}</style></head>\n<body>\n<h1>svetlo compare</h1>\n<p>Scene <code>" +
         escape_html(sheet.scene) + "</code>, reference <code>" + escape_html(sheet.reference) +
         "</code>. Errors are ꟻLIP against the reference (0: no visible difference).</p>\n"
         "<div>ꟻLIP 0 <span class=\"legend\" style=\"display:inline-block\"></span> 1</div>\n"
         "<table>\n<tr><th>technique</th><th>image</th><th>ꟻLIP error</th><th>numbers</th>"
         "<th>buffers</th></tr>\n";
    h += "<tr class=\"reference\"><td><code>" + escape_html(sheet.reference) +
         "</code><br>reference</td><td><img alt=\"reference\" src=\"" +
         png_data_url(sheet.reference_image, PixelMeaning::Radiance, sheet.reference_exposure) +
         "\"></td><td></td><td></td><td></td></tr>\n";
    for (const SheetEntry& e : sheet.entries) {
        char seconds[64];
        std::snprintf(seconds, sizeof seconds, "%.3f", e.seconds);
        h += "<tr class=\"technique\"><td title=\"" + escape_html(e.spec) + "\">" +
             escape_html(e.name) + "<br><code>" + escape_html(e.spec) +
             "</code></td><td><img alt=\"" + escape_html(e.name) + "\" src=\"" +
             png_data_url(e.image, PixelMeaning::Radiance, e.exposure) +
             "\"></td><td><img alt=\"error of " + escape_html(e.spec) + "\" src=\"" +
             png_data_url(error_image(e), PixelMeaning::Data, 1.0f) + "\"></td><td>";
        char cell[400];
        std::snprintf(cell, sizeof cell,
                      "mae %.5g<br>rmse %.5g<br>relmse %.5g<br>flip %.5f<br>%s s",
                      e.metrics.pixels.mae, e.metrics.pixels.rmse, e.metrics.pixels.relmse,
                      e.metrics.flip.mean, seconds);
        h += cell;
        h += "</td><td>";
        for (const auto& [name, image] : e.buffers) {
            h += "<figure><img alt=\"" + escape_html(name) + " of " + escape_html(e.spec) +
                 "\" src=\"" + png_data_url(image, PixelMeaning::Data, 1.0f) +
                 "\"><figcaption><code>" + escape_html(name) + "</code></figcaption></figure>";
        }
        h += "</td></tr>\n";
    }
    h += "</table>\n";
    std::string svg = curves_svg(sheet);
    if (!svg.empty()) h += "<h2>Error against time</h2>\n" + svg + "\n";
    h += "</body></html>\n";
    return h;
}

namespace {

/// Draws `text` with stb_easy_font's quads (a 6 x 7 pixel font at scale 1) in `color`.
void draw_text(Image& image, int x, int y, const std::string& text, Color color, int scale = 2) {
    std::vector<char> buffer(text.size() * 300 + 64);
    std::string copy = text;

    int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(),
                                    static_cast<int>(buffer.size()));
    // Each vertex: x, y, z (floats) and a 4-byte colour; four vertices a quad.
    const float* v = reinterpret_cast<const float*>(buffer.data());
    for (int q = 0; q < quads; ++q) {
        const float* a = v + q * 16;  // 4 vertices x 4 floats
        int x0 = static_cast<int>(a[0]), y0 = static_cast<int>(a[1]);
        int x1 = static_cast<int>(a[8]), y1 = static_cast<int>(a[9]);
        for (int j = y0 * scale; j < y1 * scale; ++j) {
            for (int i = x0 * scale; i < x1 * scale; ++i) {
                int px = x + i, py = y + j;
                if (px >= 0 && py >= 0 && px < image.width && py < image.height)
                    image.at(px, py) = color;
            }
        }
    }
}

void paste(Image& sheet, const Image& image, int x, int y) {
    for (int j = 0; j < image.height && y + j < sheet.height; ++j)
        for (int i = 0; i < image.width && x + i < sheet.width; ++i)
            sheet.at(x + i, y + j) = image.at(i, j);
}

/// `image` shrunk (nearest texel) to fit max_w x max_h, or as it is when it fits.
Image fit(const Image& image, int max_w, int max_h) {
    const double scale = std::min(
        {1.0, static_cast<double>(max_w) / image.width, static_cast<double>(max_h) / image.height});
    if (scale >= 1.0) return image;
    Image out(std::max(1, static_cast<int>(image.width * scale)),
              std::max(1, static_cast<int>(image.height * scale)));
    for (int j = 0; j < out.height; ++j)
        for (int i = 0; i < out.width; ++i)
            out.at(i, j) = image.at(static_cast<int>(i / scale), static_cast<int>(j / scale));
    return out;
}

}  // namespace

Image sheet_png(const Sheet& sheet) {
    const int w = sheet.reference_image.width, h = sheet.reference_image.height;
    const int label = 24, gap = 12, text = 22;
    const int columns = static_cast<int>(sheet.entries.size()) + 1;
    const int col_w = std::max(w, 360) + gap;
    const int legend = 60;
    // Rows of buffers below the numbers, as many as the entry with most, each labelled above;
    // a buffer larger than the column (a shadow map's cross) is shrunk to fit it.
    std::vector<std::vector<Image>> shown(sheet.entries.size());
    std::vector<int> row_height;
    for (size_t n = 0; n < sheet.entries.size(); ++n) {
        const SheetEntry& e = sheet.entries[n];
        for (size_t k = 0; k < e.buffers.size(); ++k) {
            shown[n].push_back(fit(e.buffers[k].second, col_w - gap, 2 * h));
            if (row_height.size() <= k) row_height.push_back(0);
            row_height[k] = std::max(row_height[k], shown[n].back().height);
        }
    }
    int buffers_height = 0;
    for (int rh : row_height) buffers_height += label + rh + gap;
    Image out(columns * col_w + gap, label + h + gap + h + text * 2 + buffers_height + legend,
              Color(1.0f));
    const Color ink(0.0f);
    auto srgb = [](Color display) {  // a display colour as the linear value PNG encodes back
        return Color(srgb_to_linear(display.r), srgb_to_linear(display.g),
                     srgb_to_linear(display.b));
    };
    int x = gap;
    std::string title = "reference: " + sheet.reference;
    draw_text(out, x, 4, title, ink, 2 * stb_easy_font_width(title.data()) < col_w - gap ? 2 : 1);
    paste(out, as_8bit_srgb(sheet.reference_image, sheet.reference_exposure), x, label);
    for (size_t n = 0; n < sheet.entries.size(); ++n) {
        const SheetEntry& e = sheet.entries[n];
        x += col_w;
        // The technique's name (its SPEC is in the HTML sheet and the JSON), twice the font's
        // size where it fits the column, else its own size.
        std::string name = e.name;
        draw_text(out, x, 4, name, ink, 2 * stb_easy_font_width(name.data()) < col_w - gap ? 2 : 1);
        paste(out, as_8bit_srgb(e.image, e.exposure), x, label);
        Image err = error_image(e);
        for (Color& c : err.pixels) c = srgb(c);
        paste(out, err, x, label + h + gap);
        const std::array<std::string, 2> lines = numbers(e);
        draw_text(out, x, label + 2 * h + gap + 4, lines[0], ink, 1);
        draw_text(out, x, label + 2 * h + gap + 16, lines[1], ink, 1);
        int y = label + 2 * h + gap + text * 2;
        for (size_t k = 0; k < e.buffers.size(); ++k) {
            draw_text(out, x, y + 4, e.buffers[k].first, ink);
            Image buffer = shown[n][k];  // written linearly: undo PNG's sRGB encoding
            for (Color& c : buffer.pixels) c = srgb(c);
            paste(out, buffer, x, y + label);
            y += label + row_height[k] + gap;
        }
    }
    // The legend: the false colour from 0 to 1.
    const int ly = out.height - legend + 10;
    draw_text(out, gap, ly, "FLIP error against the reference: 0", ink);
    for (int i = 0; i < 256; ++i) {
        Color c = srgb(magma(static_cast<float>(i) / 255.0f));
        for (int j = 0; j < 16; ++j) {
            if (gap + 450 + i < out.width) out.at(gap + 450 + i, ly + j) = c;
        }
    }
    draw_text(out, gap + 450 + 262, ly, "1", ink);
    return out;
}

nlohmann::ordered_json sheet_json(const Sheet& sheet) {
    // The keys of docs/compare.md, in their order.
    nlohmann::ordered_json j = {{"scene", sheet.scene}, {"reference", sheet.reference}};
    j["techniques"] = nlohmann::ordered_json::array();
    for (const SheetEntry& e : sheet.entries) {
        nlohmann::ordered_json t = {{"spec", e.spec},
                                    {"name", e.name},
                                    {"engine", e.engine},
                                    {"seconds", e.seconds},
                                    {"mae", e.metrics.pixels.mae},
                                    {"rmse", e.metrics.pixels.rmse},
                                    {"relmse", e.metrics.pixels.relmse},
                                    {"flip", e.metrics.flip.mean}};
        for (const auto& [name, image] : e.buffers) t["aovs"].push_back(name);
        if (!e.curve.empty()) {
            t["curve"] = nlohmann::ordered_json::array();
            for (const CurvePoint& p : e.curve)
                t["curve"].push_back({{"spp", p.spp},
                                      {"seconds", p.seconds},
                                      {"rmse", p.rmse},
                                      {"relmse", p.relmse}});
        }
        j["techniques"].push_back(t);
    }
    return j;
}

}  // namespace svetlo
