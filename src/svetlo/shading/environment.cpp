#include "svetlo/shading/environment.h"

#include <algorithm>
#include <cmath>

namespace svetlo {

namespace {

/// Index k with cdf[k] <= u < cdf[k + 1] among n cells (cdf has n + 1 entries, 0 to 1).
int find_cell(const float* cdf, int n, float u) {
    const float* at = std::upper_bound(cdf, cdf + n + 1, u);
    return std::clamp(static_cast<int>(at - cdf) - 1, 0, n - 1);
}

}  // namespace

Environment::Environment(const Scene& scene, bool importance) {
    if (!scene.environment) {
        uniform_ = scene.render.background;
        black_ = svetlo::is_black(uniform_);
        return;
    }
    const EnvironmentSettings& e = *scene.environment;
    map_ = &scene.textures[static_cast<size_t>(e.texture)];
    scale_ = e.scale;
    cos_rot_ = std::cos(radians(e.rotate_deg));
    sin_rot_ = std::sin(radians(e.rotate_deg));
    width_ = map_->width();
    height_ = map_->height();
    black_ = false;
    if (!importance) return;
    // Texel weights: the mean luminance over the cell that sample() maps texel (i, j) to,
    // times sin(theta). The cell spans from half a texel before the texel's centre to half a
    // texel after it, where radiance() interpolates bilinearly with the neighbours: the mean
    // of that interpolation is the texel's luminance filtered by (1/8, 3/4, 1/8) along each
    // axis. It is positive wherever the radiance in the cell is.
    std::vector<float> lum(static_cast<size_t>(width_) * height_);
    for (int j = 0; j < height_; ++j)
        for (int i = 0; i < width_; ++i)
            lum[static_cast<size_t>(j) * width_ + i] = luminance(map_->texel(i, j) * scale_);
    constexpr float kTent[3] = {0.125f, 0.75f, 0.125f};
    // Each cell's mean luminance, and each row's sin(theta).
    std::vector<double> cell(lum.size()), sines(static_cast<size_t>(height_));
    double total = 0.0, solid = 0.0;
    for (int j = 0; j < height_; ++j) {
        const double sin_theta = std::sin(kPi * (j + 0.5) / height_);
        sines[static_cast<size_t>(j)] = sin_theta;
        for (int i = 0; i < width_; ++i) {
            float m = 0.0f;
            for (int dj = -1; dj <= 1; ++dj) {
                const int jj = std::clamp(j + dj, 0, height_ - 1);
                for (int di = -1; di <= 1; ++di) {
                    const int ii = (i + di + width_) % width_;
                    m += kTent[dj + 1] * kTent[di + 1] * lum[static_cast<size_t>(jj) * width_ + ii];
                }
            }
            cell[static_cast<size_t>(j) * width_ + i] = m;
            total += m * sin_theta;
            solid += sin_theta;
        }
    }
    black_ = !(total > 0.0);
    // The importance: each cell's mean luminance times sin(theta), plus a floor of 1e-3 of
    // the mean weight.
    const double floor = total > 0.0 ? 1e-3 * total / static_cast<double>(cell.size()) : 1.0;
    std::vector<double> weight(cell.size());
    for (size_t k = 0; k < cell.size(); ++k)
        weight[k] = cell[k] * sines[k / static_cast<size_t>(width_)] + floor;
    importance_ = Tables(weight, width_, height_);
    // Compensated: the same less the luminance's mean over the sphere, clamped at zero.
    const double average = total / solid;
    double above = 0.0;
    for (size_t k = 0; k < cell.size(); ++k) {
        weight[k] = std::max(0.0, cell[k] - average) * sines[k / static_cast<size_t>(width_)];
        above += weight[k];
    }
    compensated_ = above > 0.0 ? Tables(weight, width_, height_) : importance_;
}

Environment::Tables::Tables(const std::vector<double>& weight, int width, int height) {
    double total = 0.0;
    for (double w : weight) total += w;
    // p over [0,1]^2: a texel's probability times the texel count; the CDFs. A row of no
    // weight keeps an even CDF (never drawn: the row CDF gives it no width).
    density.assign(weight.size(), 0.0f);
    row_cdf.assign(static_cast<size_t>(height) + 1, 0.0f);
    texel_cdf.assign(static_cast<size_t>(height) * (width + 1), 0.0f);
    double rows = 0.0;
    for (int j = 0; j < height; ++j) {
        double row = 0.0;
        float* cdf = &texel_cdf[static_cast<size_t>(j) * (width + 1)];
        for (int i = 0; i < width; ++i) {
            const double w = weight[static_cast<size_t>(j) * width + i];
            density[static_cast<size_t>(j) * width + i] =
                static_cast<float>(w / total * static_cast<double>(weight.size()));
            row += w;
            cdf[i + 1] = static_cast<float>(row);
        }
        for (int i = 1; i <= width; ++i)
            cdf[i] = row > 0.0 ? static_cast<float>(cdf[i] / row)
                               : static_cast<float>(i) / static_cast<float>(width);
        cdf[width] = 1.0f;
        rows += row;
        row_cdf[static_cast<size_t>(j) + 1] = static_cast<float>(rows / total);
    }
    row_cdf[static_cast<size_t>(height)] = 1.0f;
}

namespace {

/// Environment::uv_of with the map's turn (cos, sin): inlined into radiance_many's loop.
[[gnu::always_inline]] inline vec2 map_uv(vec3 d, float cos_rot, float sin_rot) {
    // Into the map's frame: turned by -rotate about +y.
    const float x = cos_rot * d.x - sin_rot * d.z;
    const float z = sin_rot * d.x + cos_rot * d.z;
    // The latitude as atan2 of the height over the horizontal length: asin(y) for a unit d,
    // and as exact for one a rounding off unit length.
    const float u = 0.5f + atan2_approx(x, -z) * (0.5f * kInvPi);
    const float v = 0.5f + atan2_approx(d.y, std::sqrt(x * x + z * z)) * kInvPi;
    // u - floor(u) for u in [-1, 2), as selects (floor does not vectorize without SSE4.1).
    return vec2(u >= 1.0f ? u - 1.0f : (u < 0.0f ? u + 1.0f : u), v);
}

/// floor(x) as an int, for |x| < 2^31, without SSE4.1's rounding (so that it vectorizes).
[[gnu::always_inline]] inline int floor_int(float x) {
    const int t = static_cast<int>(x);  // toward zero
    return t - (x < static_cast<float>(t) ? 1 : 0);
}

}  // namespace

vec2 Environment::uv_of(vec3 d) const { return map_uv(d, cos_rot_, sin_rot_); }

vec3 Environment::direction_of(vec2 uv) const {
    const float phi = 2.0f * kPi * (uv.x - 0.5f), lat = kPi * (uv.y - 0.5f);
    const float x = std::sin(phi) * std::cos(lat), z = -std::cos(phi) * std::cos(lat);
    // Back to the world: turned by +rotate.
    return vec3(cos_rot_ * x + sin_rot_ * z, std::sin(lat), -sin_rot_ * x + cos_rot_ * z);
}

Color Environment::radiance(vec3 d) const { return map_ ? radiance_at(uv_of(d)) : uniform_; }

void Environment::radiance_many(const vec3* d, size_t count, Color* out) const {
    if (!map_) {
        std::fill(out, out + count, uniform_);
        return;
    }
    constexpr size_t kChunk = 64;
    const float w = static_cast<float>(width_), h = static_cast<float>(height_);
    for (size_t first = 0; first < count; first += kChunk) {
        const size_t n = std::min(kChunk, count - first);
        alignas(32) float x[kChunk], y[kChunk], z[kChunk], ax[kChunk], ay[kChunk];
        alignas(32) int i0[kChunk], j0[kChunk];
        for (size_t k = 0; k < n; ++k) {
            x[k] = d[first + k].x;
            y[k] = d[first + k].y;
            z[k] = d[first + k].z;
        }
        // uv_of and the texel places lane by lane without a branch: the compiler runs them
        // four at a time; then the texels, one direction at a time.
        for (size_t k = 0; k < n; ++k) {
            const vec2 uv = map_uv(vec3(x[k], y[k], z[k]), cos_rot_, sin_rot_);
            const float fx = uv.x * w - 0.5f, fy = (1.0f - uv.y) * h - 0.5f;
            i0[k] = floor_int(fx);
            j0[k] = floor_int(fy);
            ax[k] = fx - static_cast<float>(i0[k]);
            ay[k] = fy - static_cast<float>(j0[k]);
        }
        for (size_t k = 0; k < n; ++k) out[first + k] = bilinear(i0[k], j0[k], ax[k], ay[k]);
    }
}

Color Environment::radiance_at(vec2 uv) const {
    if (!map_) return uniform_;
    // Between texel centres; rows from the top (v = 0 the bottom row).
    const float fx = uv.x * static_cast<float>(width_) - 0.5f,
                fy = (1.0f - uv.y) * static_cast<float>(height_) - 0.5f;
    const int i0 = floor_int(fx), j0 = floor_int(fy);
    return bilinear(i0, j0, fx - static_cast<float>(i0), fy - static_cast<float>(j0));
}

Color Environment::bilinear(int i0, int j0, float ax, float ay) const {
    // The columns wrap around, the rows stop at the poles; each index found once, not once
    // per texel read (the background of every raster frame reads the map here).
    const int a = static_cast<unsigned>(i0) < static_cast<unsigned>(width_)
                      ? i0  // one compare; the division only left of the first texel's centre (-1)
                      : (i0 % width_ + width_) % width_;
    const int b = a + 1 == width_ ? 0 : a + 1;
    const int r0 = std::clamp(j0, 0, height_ - 1), r1 = std::clamp(j0 + 1, 0, height_ - 1);
    const Color c = (1.0f - ay) * ((1.0f - ax) * map_->texel(a, r0) + ax * map_->texel(b, r0)) +
                    ay * ((1.0f - ax) * map_->texel(a, r1) + ax * map_->texel(b, r1));
    return c * scale_;
}

EnvironmentSample Environment::sample(vec2 u, EnvironmentDensity which) const {
    EnvironmentSample s;
    if (!map_) return s;
    const Tables& t = tables(which);
    const int j = find_cell(t.row_cdf.data(), height_, u.y);
    const float r0 = t.row_cdf[static_cast<size_t>(j)], r1 = t.row_cdf[static_cast<size_t>(j) + 1];
    const float fy = r1 > r0 ? std::clamp((u.y - r0) / (r1 - r0), 0.0f, 0.99999994f) : 0.5f;
    const float* cdf = &t.texel_cdf[static_cast<size_t>(j) * (width_ + 1)];
    const int i = find_cell(cdf, width_, u.x);
    const float fx = cdf[i + 1] > cdf[i]
                         ? std::clamp((u.x - cdf[i]) / (cdf[i + 1] - cdf[i]), 0.0f, 0.99999994f)
                         : 0.5f;
    const vec2 uv((i + fx) / width_, 1.0f - (j + fy) / height_);
    const float cos_lat = std::cos(kPi * (uv.y - 0.5f));
    if (!(cos_lat > 0.0f)) return s;
    s.wi = direction_of(uv);
    s.pdf = t.density[static_cast<size_t>(j) * width_ + i] / (2.0f * kPi * kPi * cos_lat);
    s.radiance = radiance(s.wi);
    return s;
}

float Environment::pdf(vec3 d, EnvironmentDensity which) const {
    if (!map_) return 0.0f;
    const vec2 uv = uv_of(d);
    const float cos_lat = std::cos(kPi * (uv.y - 0.5f));
    if (!(cos_lat > 0.0f)) return 0.0f;
    const int i = std::clamp(static_cast<int>(uv.x * width_), 0, width_ - 1);
    const int j = std::clamp(static_cast<int>((1.0f - uv.y) * height_), 0, height_ - 1);
    return tables(which).density[static_cast<size_t>(j) * width_ + i] /
           (2.0f * kPi * kPi * cos_lat);
}

}  // namespace svetlo
