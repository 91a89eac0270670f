// Where a progressive solve stands (progressive.cpp): what its parts (the rows, the ranks'
// shares, the checkpoints) read and write. Internal to radiosity/.
#pragma once

#include <vector>

#include "svetlo/radiosity/solver.h"

namespace svetlo {

/// A shooter of the progressive solve: a node at the patch level, and its light not yet shot
/// from each side, W/m^2.
struct Patch {
    uint32_t node;
    float area;
    Sides unshot;
};

/// Per leaf what it has received (whole, and straight from lights and emitters) and what a
/// watt per square metre of it adds to its patch's unshot radiosity (its reflectance times its
/// share of the patch's area); the patches; the shots done; and the power in the scene (W,
/// summed over the channels: emitted, and reflected from the lights), against which the
/// unshot power is measured.
struct ShootingState {
    std::vector<uint32_t> leaves;
    std::vector<uint32_t> patch_of;  // per leaf: the index of its patch
    std::vector<Patch> patches;
    std::vector<Sides> received, direct;
    std::vector<Color> to_unshot;
    double power = 0.0;
    int shots = 0;
};

}  // namespace svetlo
