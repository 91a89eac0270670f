#include "svetlo/pt/sobol_sampler.h"

namespace svetlo {

#ifndef SVETLO_HAS_AVX2_SAMPLER
// Without the AVX2 file (another compiler or processor), avx2_available() is false and this
// is never called; it draws the same numbers as SobolSampler's scalar code all the same.
void sobol_draw8_avx2(uint32_t key, uint32_t reversed_index, uint32_t d, float* out) {
    for (uint32_t k = 0; k < 8; ++k) {
        const uint32_t dim = d + k;
        const uint32_t i = owen_of_reversed(reversed_index, sobol_hash(key, dim | 1u));
        const uint32_t point = k & 1u ? sobol1_reversed(i) : i;
        out[k] = sobol_to_unit(owen_of_reversed(point, sobol_hash(key, 2 * dim)));
    }
}
#endif

}  // namespace svetlo
