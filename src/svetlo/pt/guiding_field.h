// Path guiding's SD-tree (Müller, Gross and Novák 2017, "Practical Path Guiding for
// Efficient Light-Transport Simulation", EGSR; docs/path.md, "Path guiding"): a binary tree
// over the scene's bounding cube, split at the middle along x, y and z in turn, whose leaves
// (regions) each hold the directional quadtrees of direction_tree.h. The path tracer draws
// part of its bounces from the region's DirectionTree (path_integrator.cpp) and, while it
// trains, records what each bounce brought back.
//
// Training runs in iterations of 1, 2, 4, 8 ... passes (guiding_training_passes). At the end
// of each, refine() makes the recorded sums the distributions to draw from, splits the
// regions that received more than kSplitRecords sqrt(passes) records, and lays out new,
// finer recorders. The sums are integers (fixed point: 2^-30 W/(m^2 sr) per steradian a
// step, a record capped at 2^20), added atomically: their value does not depend on the
// order the threads add them in, so the field, and the image, are the same for any thread
// count.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "svetlo/core/math.h"
#include "svetlo/pt/direction_tree.h"

namespace svetlo {

/// Müller et al.'s constants: a region splits past kSplitRecords sqrt(passes) records; a
/// quadrant holding more than kSplitEnergy of its tree's energy splits, to kMaxDirectionDepth.
inline constexpr double kSplitRecords = 12000.0;
inline constexpr float kSplitEnergy = 0.01f;
inline constexpr int kMaxDirectionDepth = 20;
/// The probability of drawing a guided bounce from the BSDF rather than from the field.
inline constexpr float kGuidingBsdfFraction = 0.5f;

/// A region's distribution for surfaces of one facing (facing_of). Its square maps the
/// directions of the facing's own frame, whose polar axis is the facing's axis, so that
/// the cosine of a surface of that facing is the square's x: the guide draws in proportion
/// to the learned incident radiance times that cosine (DirectionTree::sample).
struct Guide {
    const DirectionTree* tree = nullptr;  // null: nothing to draw from here
    int facing = 0;
    uint32_t region = 0;  // the field's region, where record() adds

    explicit operator bool() const { return tree != nullptr; }
    /// A world-space unit direction drawn from u in [0,1)^2, and its density per steradian
    /// (the same as pdf's).
    vec3 sample(vec2 u, float& pdf) const;
    float pdf(vec3 wi) const;
};

/// World direction d in the frame of facing f (its axis the frame's z), and back.
vec3 to_facing(vec3 d, int f);
vec3 from_facing(vec3 d, int f);

class GuidingField {
public:
    /// A field over `bounds` (points outside are clamped into it).
    explicit GuidingField(const Bounds3& bounds);

    /// The distribution to draw from at p on a surface of normal n, its tree null where
    /// nothing has been learned yet (or nothing above the facing's horizon).
    Guide at(vec3 p, vec3 n) const;
    /// A path's estimate of the radiance arriving from unit direction wi where `at` found
    /// `where`, divided by the pdf with which wi was drawn. Safe from many threads at once.
    void record(const Guide& where, vec3 wi, float value);
    /// Ends a training iteration of `passes` passes (above).
    void refine(int passes);

    int regions() const { return static_cast<int>(regions_.size()); }
    /// Directional nodes in all the regions' distributions.
    size_t direction_nodes() const;
    /// A hash of the whole field (layout and energies, bit for bit): equal fields, equal hash.
    uint64_t fingerprint() const;

private:
    struct SpaceNode {
        uint32_t child = 0;   // the first of two children; 0: a leaf
        uint32_t region = 0;  // a leaf's region
        int depth = 0;        // the axis split is depth % 3
    };
    struct Directions {
        DirectionTree sampling;
        bool drawable = false;  // sampling holds energy above the facing's horizon
        DirectionRecorder recording;
    };
    struct Region {
        std::array<Directions, 6> facing;  // by facing_of the surface's normal
        uint64_t records = 0;
    };
    /// The index of the region that holds p.
    uint32_t region_at(vec3 p) const;

    vec3 origin_;     // the cube's lowest corner
    float inv_size_;  // 1 / its edge
    std::vector<SpaceNode> nodes_;
    std::vector<Region> regions_;
};

/// Which of the six distributions of a region serves a surface of normal n: the axis n is
/// nearest, and its sign (0: +x, 1: -x, 2: +y ... 5: -z). Surfaces that face apart see
/// different light: a door's two sides, a floor and a ceiling.
int facing_of(vec3 n);

/// The passes a render of `spp` samples per pixel trains the field in: whole iterations of
/// 1, 2, 4 ... passes, 2^k - 1 in all, at most half the spp, so that the finished field
/// draws at least half of them. A render to a time budget trains for 31 passes.
int guiding_training_passes(int spp, bool time_budget);
/// Whether pass `pass` (from 0) ends a training iteration, and that iteration's passes.
bool ends_guiding_iteration(int pass, int& passes);

}  // namespace svetlo
