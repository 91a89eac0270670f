// The fuzz targets: each takes arbitrary bytes as one kind of input file and checks the
// contract's promise, not only "no crash": the input is refused with svetlo::Error (or the
// readers' std::runtime_error), or it is accepted and everything read from it is finite.
// Built two ways: into libFuzzer programs (make fuzz, clang), and into replay_test, which runs
// every file of tests/fuzz/corpus/ through them in the ordinary test suite.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace svetlo::fuzz {

/// A scene file (JSON, with its overrides' syntax as well).
void scene(const uint8_t* data, size_t size);
/// A mesh file of one format: "obj", "ply" or "gltf" (also GLB: the reader decides).
void mesh(const uint8_t* data, size_t size, const std::string& extension);
/// An image file: PNG, JPEG, HDR, PFM or EXR, told apart by their first bytes.
void image(const uint8_t* data, size_t size);
/// An environment map (PFM, EXR or HDR): read as `environment` reads it (negative texels made
/// 0, others refused), then its importance sampling built and drawn from: every texel,
/// radiance and density finite, every density > 0.
void environment(const uint8_t* data, size_t size);

/// Runs target `name` ("scene", "obj", "ply", "gltf", "image", "environment") on the bytes.
void run(const std::string& name, const uint8_t* data, size_t size);

}  // namespace svetlo::fuzz
