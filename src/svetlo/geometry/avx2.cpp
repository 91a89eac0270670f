#include "svetlo/geometry/avx2.h"

namespace svetlo {

bool avx2_available() {
#ifdef SVETLO_HAS_AVX2_BVH  // the library's AVX2 files are compiled (CMakeLists.txt)
    static const bool has = __builtin_cpu_supports("avx2") != 0;
    return has;
#else
    return false;
#endif
}

bool avx512_available() {
#ifdef SVETLO_HAS_AVX512_BVH  // wide_bvh_avx512.cpp is compiled (CMakeLists.txt)
    static const bool has = __builtin_cpu_supports("avx512f") != 0;
    return has;
#else
    return false;
#endif
}

}  // namespace svetlo
