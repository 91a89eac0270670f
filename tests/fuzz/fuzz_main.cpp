// A libFuzzer program for one target (SVETLO_FUZZ_TARGET, a string): built by `make fuzz`
// with clang, -fsanitize=fuzzer,address,undefined.
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    svetlo::fuzz::run(SVETLO_FUZZ_TARGET, data, size);
    return 0;
}
