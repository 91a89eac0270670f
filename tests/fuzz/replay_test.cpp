// Every file of the fuzz corpus (tests/fuzz/corpus/TARGET/) through its target, in the
// ordinary test suite: the seeds, and every input the fuzzers found that once broke svetlo.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz_targets.h"

namespace svetlo {
namespace {

TEST(FuzzCorpus, EveryInputIsRefusedOrReadAsFiniteValues) {
    const std::filesystem::path corpus = SVETLO_FUZZ_CORPUS;
    int files = 0;
    for (const char* target : {"scene", "obj", "ply", "gltf", "image", "environment"}) {
        int in_target = 0;
        for (const auto& entry : std::filesystem::directory_iterator(corpus / target)) {
            std::ifstream in(entry.path(), std::ios::binary);
            std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                       std::istreambuf_iterator<char>());
            fuzz::run(target, bytes.data(),
                      bytes.size());  // aborts if docs/robustness.md's rule breaks
            ++in_target;
        }
        EXPECT_GT(in_target, 0) << target;
        files += in_target;
    }
    std::printf("%d corpus files replayed\n", files);
}

}  // namespace
}  // namespace svetlo
