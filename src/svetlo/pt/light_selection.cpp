#include "svetlo/pt/light_selection.h"

#include <algorithm>

namespace svetlo {

namespace {

/// The share of the choice made uniformly, whatever the power estimates say.
constexpr double kUniformShare = 0.1;

}  // namespace

double light_power(const LightSet& lights, const LightSet::Source& s, const Scene& scene,
                   float radius) {
    if (!s.delta) return kPi * luminance(lights.sample_area(s, vec2(0.5f), 0.5f).radiance) * s.area;
    const Light& light = scene.lights[static_cast<size_t>(s.light_index)];
    if (const auto* p = std::get_if<PointLight>(&light)) return 4.0 * kPi * luminance(p->intensity);
    if (const auto* d = std::get_if<DirectionalLight>(&light))
        return kPi * double(radius) * radius * luminance(d->irradiance);
    const auto& spot = std::get<SpotLight>(light);
    return 2.0 * kPi * (1.0 - std::cos(radians(spot.outer_deg))) * luminance(spot.intensity);
}

LightSelection::LightSelection(const LightSet& lights, const Scene& scene, float radius) {
    const auto& sources = lights.sources();
    if (sources.empty()) return;
    std::vector<double> power;
    double total = 0.0;
    for (const LightSet::Source& s : sources) {
        double p = light_power(lights, s, scene, radius);
        power.push_back(std::isfinite(p) && p > 0.0 ? p : 0.0);
        total += power.back();
    }
    const double n = static_cast<double>(sources.size());
    double sum = 0.0;
    for (double p : power) {
        double share =
            total > 0.0 ? (1.0 - kUniformShare) * p / total + kUniformShare / n : 1.0 / n;
        probability_.push_back(static_cast<float>(share));
        sum += share;
        cdf_.push_back(static_cast<float>(sum));
    }
    cdf_.back() = 1.0f;
}

size_t LightSelection::pick(float u, float& probability) const {
    size_t k = static_cast<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
    k = std::min(k, cdf_.size() - 1);
    probability = probability_[k];
    return k;
}

}  // namespace svetlo
