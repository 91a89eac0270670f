#include "svetlo/pt/sobol_sampler.h"

namespace svetlo {

#ifndef SVETLO_HAS_AVX2_SAMPLER
// Without the AVX2 file (another compiler or processor), avx2_available() is false and this
// is never called; it draws the same numbers as SobolSampler's scalar code all the same.
void sobol_draw8_avx2(uint32_t key, uint32_t reversed_index, uint32_t d, float* out) {
    for (uint32_t k = 0; k < 8; ++k) {
        out[k] = sobol_dimension(key, sobol_shuffled(key, reversed_index, (d + k) >> 1), d + k);
    }
}
#endif

}  // namespace svetlo
