// The binned-SAH build of the binary BVH (Wald, "On fast Construction of SAH-based Bounding
// Volume Hierarchies", IEEE RT 2007), kept apart from its traversal (bvh.cpp): 16 bins on the
// axis of largest centroid extent (spans of at most 16 primitives sorted along it and swept
// exactly), leaves of at most 8 primitives, subtrees built in parallel. The references move
// between two buffers, level after level, without being copied back.
#pragma once

#include <cstdint>

#include "svetlo/core/large_array.h"
#include "svetlo/geometry/bvh.h"

namespace svetlo {

struct BvhBuild {
    LargeArray<BvhNode> nodes;   // depth first; the two children of an inner node adjacent
    LargeArray<uint32_t> prims;  // primitive ids in leaf order
    int depth = 0;
};

/// Builds the BVH over every triangle and bounded shape of `geometry` (infinite planes are
/// left to the caller) on `threads` threads (0: all): the same boxes and leaves on any number of
/// threads, though not always at the same places in the arrays.
BvhBuild build_bvh(const Geometry& geometry, int threads);

}  // namespace svetlo
