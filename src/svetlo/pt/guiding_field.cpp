#include "svetlo/pt/guiding_field.h"

#include <atomic>
#include <bit>
#include <cmath>

#include "svetlo/core/atomic_add.h"
#include "svetlo/core/bit_cast.h"
#include "svetlo/core/rng.h"

namespace svetlo {

namespace {

/// The regions' depth at most: a cube split 48 times has cells 2^-16 of its edge.
constexpr int kMaxSpaceDepth = 48;
/// Fixed point: a step is 2^-30 (W/(m^2 sr) per unit of pdf), one record at most 2^50 steps,
/// so that 2^14 records at that cap still fit in 64 bits.
constexpr double kStep = 0x1p-30;
constexpr double kMaxStepsPerRecord = 0x1p50;
/// The training passes of a render to a time budget: five iterations.
constexpr int kBudgetTrainingPasses = 31;

uint64_t combine(uint64_t hash, uint64_t value) {
    return mix64(hash ^ (value + 0x9e3779b97f4a7c15ULL));
}

/// The bits of v (16 of them) spread to every third place: bit i to bit 3 i.
uint64_t spread3(uint64_t v) {
    v &= 0xffff;
    v = (v | (v << 16)) & 0x0000ff0000ffULL;
    v = (v | (v << 8)) & 0x00f00f00f00fULL;
    v = (v | (v << 4)) & 0x0c30c30c30c3ULL;
    v = (v | (v << 2)) & 0x249249249249ULL;
    return v;
}

}  // namespace

GuidingField::GuidingField(const Bounds3& bounds) : nodes_(1), regions_(1) {
    const vec3 extent = bounds.empty() ? vec3(1.0f) : bounds.extent();
    const float size = std::max(1.02f * std::max({extent.x, extent.y, extent.z}), 1e-6f);
    origin_ = (bounds.empty() ? vec3(0.0f) : bounds.center()) - vec3(0.5f * size);
    inv_size_ = 1.0f / size;
}

uint32_t GuidingField::region_at(vec3 p) const {
    // The tree halves x, y and z in turn, so the side taken at depth d is bit 15 - d / 3 of
    // coordinate d % 3 in 16-bit fixed point: bit 47 - d of their Morton code.
    const vec3 x = glm::clamp((p - origin_) * inv_size_, vec3(0.0f), vec3(1.0f));
    auto fixed = [](float c) {  // NaN to 0, as the comparisons of halving took it
        return c > 0.0f ? std::min(static_cast<uint64_t>(c * 65536.0f), uint64_t{0xffff}) : 0;
    };
    const uint64_t code =
        (spread3(fixed(x.x)) << 2) | (spread3(fixed(x.y)) << 1) | spread3(fixed(x.z));
    uint32_t index = 0;
    for (int depth = 0; nodes_[index].child; ++depth)
        index = nodes_[index].child + static_cast<uint32_t>((code >> (47 - depth)) & 1);
    return nodes_[index].region;
}

int facing_of(vec3 n) {
    const vec3 a = glm::abs(n);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    return 2 * axis + (n[axis] < 0.0f);
}

vec3 to_facing(vec3 d, int f) {
    const int a = f / 2;
    const float s = f & 1 ? -1.0f : 1.0f;
    return vec3(d[(a + 1) % 3], s * d[(a + 2) % 3], s * d[a]);
}

vec3 from_facing(vec3 d, int f) {
    const int a = f / 2;
    const float s = f & 1 ? -1.0f : 1.0f;
    vec3 w;
    w[a] = s * d.z;
    w[(a + 1) % 3] = d.x;
    w[(a + 2) % 3] = s * d.y;
    return w;
}

vec3 Guide::sample(vec2 u, float& pdf) const {
    const vec2 x = tree->sample(u, pdf);
    pdf /= kSquareToSolidAngle;
    return from_facing(square_to_direction(x), facing);
}

float Guide::pdf(vec3 wi) const {
    return tree->pdf(direction_to_square(to_facing(wi, facing))) / kSquareToSolidAngle;
}

Guide GuidingField::at(vec3 p, vec3 n) const {
    const int f = facing_of(n);
    const uint32_t region = region_at(p);
    const Directions& d = regions_[region].facing[static_cast<size_t>(f)];
    return Guide{d.drawable ? &d.sampling : nullptr, f, region};
}

void GuidingField::record(const Guide& where, vec3 wi, float value) {
    // Many threads record at once: the recorders and counts are added to atomically.
    Region& r = regions_[where.region];
    atomic_add_relaxed(r.records, 1);
    if (!(value > 0.0f) || !std::isfinite(value)) return;
    const double steps =
        std::min(std::round(static_cast<double>(value) / kStep), kMaxStepsPerRecord);
    const auto fixed = static_cast<uint64_t>(steps);
    if (fixed) {
        r.facing[static_cast<size_t>(where.facing)].recording.add(
            direction_to_square(to_facing(wi, where.facing)), fixed);
    }
}

void GuidingField::refine(int passes) {
    // What was recorded becomes what is drawn from (a region that received nothing keeps
    // its distribution).
    for (Region& r : regions_) {
        for (Directions& d : r.facing) {
            if (d.recording.total() == 0) continue;
            d.sampling = d.recording.to_tree(kStep);
            d.drawable = d.sampling.irradiance() > 0.0f;
        }
    }
    // Regions that saw many records split in two, and again, each half taking half the
    // records (Müller et al., section 5.2); the loop reaches the children, appended, later.
    const double threshold = kSplitRecords * std::sqrt(static_cast<double>(passes));
    for (size_t k = 0; k < nodes_.size(); ++k) {
        if (nodes_[k].child) continue;
        const uint32_t region = nodes_[k].region;
        if (static_cast<double>(regions_[region].records) <= threshold ||
            nodes_[k].depth >= kMaxSpaceDepth)
            continue;
        regions_[region].records /= 2;
        const auto second = static_cast<uint32_t>(regions_.size());
        regions_.push_back(regions_[region]);
        const auto child = static_cast<uint32_t>(nodes_.size());
        const int depth = nodes_[k].depth + 1;
        nodes_.push_back(SpaceNode{0, region, depth});
        nodes_.push_back(SpaceNode{0, second, depth});
        nodes_[k].child = child;
    }
    for (Region& r : regions_) {
        for (Directions& d : r.facing)
            d.recording = DirectionRecorder::refined(d.sampling, kSplitEnergy, kMaxDirectionDepth);
        r.records = 0;
    }
}

size_t GuidingField::direction_nodes() const {
    size_t n = 0;
    for (const Region& r : regions_)
        for (const Directions& d : r.facing) n += d.sampling.nodes().size();
    return n;
}

uint64_t GuidingField::fingerprint() const {
    uint64_t h = 0;
    for (const SpaceNode& n : nodes_) h = combine(combine(h, n.child), n.region);
    for (const Region& r : regions_) {
        for (const Directions& d : r.facing) {
            h = combine(h, d.drawable);
            for (const DirectionTree::Node& n : d.sampling.nodes()) {
                for (size_t q = 0; q < 4; ++q)
                    h = combine(combine(h, svetlo::bit_cast<uint32_t>(n.energy[q])), n.child[q]);
            }
        }
    }
    return h;
}

int guiding_training_passes(int spp, bool time_budget) {
    if (time_budget) return kBudgetTrainingPasses;
    int passes = 0;
    while (2 * (2 * passes + 1) <= spp) passes = 2 * passes + 1;  // 1, 3, 7, 15 ...
    return passes;
}

bool ends_guiding_iteration(int pass, int& passes) {
    // Iteration k covers passes 2^k - 1 ... 2^(k+1) - 2.
    const unsigned done = static_cast<unsigned>(pass) + 1;
    if (!std::has_single_bit(done + 1)) return false;
    passes = static_cast<int>((done + 1) / 2);
    return true;
}

}  // namespace svetlo
