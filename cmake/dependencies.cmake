# Every dependency is a Debian package (scripts/setup installs them). Nothing is downloaded.
find_package(glm CONFIG REQUIRED)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
if(SVETLO_TBB)
    find_package(TBB CONFIG REQUIRED)
endif()
find_package(OpenEXR CONFIG REQUIRED)
find_package(tinyobjloader CONFIG REQUIRED)
find_package(TinyGLTF CONFIG REQUIRED)
find_package(Threads REQUIRED)
find_package(ZLIB REQUIRED)      # CRC-32 of the PNG chunk that carries provenance
find_package(OpenSSL REQUIRED)   # SHA-256 of scene files (provenance)

find_path(STB_INCLUDE_DIR stb_image.h PATH_SUFFIXES stb REQUIRED)
add_library(svetlo_stb INTERFACE)
target_include_directories(svetlo_stb SYSTEM INTERFACE ${STB_INCLUDE_DIR})

# OpenMPI is optional: `mpirun -np N build/svetlo render` (docs/distributed.md); without it
# the program runs as one process.
find_package(MPI COMPONENTS CXX QUIET)
if(MPI_CXX_FOUND)
    message(STATUS "svetlo: MPI ${MPI_CXX_VERSION} found")
else()
    message(STATUS "svetlo: MPI not found: one process only")
endif()

# glTF's compressed geometry is optional: Draco (Debian's libdraco-dev) and meshoptimizer
# (libmeshoptimizer-dev); a build without one does not read its extension. libdraco carries a
# tinygltf of its own (its glTF reader's), laid out differently from libtinygltf's: where it
# came first on a link line, its functions took the place of libtinygltf's and the program
# freed a pointer it never allocated. So Draco is linked statically (only the objects the
# decoder needs are taken), after libtinygltf and the libstb it needs: else the linker took
# libdraco's copy of stb for libtinygltf, and its tinygltf with it.
find_package(draco CONFIG QUIET)
find_library(SVETLO_LIBSTB stb)
find_package(meshoptimizer CONFIG QUIET)
if(NOT (draco_FOUND AND TARGET draco::draco_static AND SVETLO_LIBSTB))
    message(STATUS "svetlo: draco not found: KHR_draco_mesh_compression is not read")
endif()
if(NOT (meshoptimizer_FOUND AND TARGET meshoptimizer::meshoptimizer))
    message(STATUS "svetlo: meshoptimizer not found: EXT_meshopt_compression is not read")
endif()
# Links `target` with the codecs found, defining SVETLO_HAS_DRACO and SVETLO_HAS_MESHOPT.
function(svetlo_link_mesh_codecs target)
    if(draco_FOUND AND TARGET draco::draco_static AND SVETLO_LIBSTB)
        target_link_libraries(${target} PRIVATE TinyGLTF::TinyGLTF ${SVETLO_LIBSTB}
                                                draco::draco_static)
        target_compile_definitions(${target} PRIVATE SVETLO_HAS_DRACO)
    endif()
    if(meshoptimizer_FOUND AND TARGET meshoptimizer::meshoptimizer)
        target_link_libraries(${target} PRIVATE meshoptimizer::meshoptimizer)
        target_compile_definitions(${target} PRIVATE SVETLO_HAS_MESHOPT)
    endif()
endfunction()

# Embree is optional: the comparison backend is built only when it is found.
find_package(embree 3 CONFIG QUIET)
if(embree_FOUND)
    message(STATUS "svetlo: Embree ${embree_VERSION} found")
endif()

if(SVETLO_TESTS)
    find_package(GTest CONFIG REQUIRED)
endif()
if(SVETLO_BENCH)
    find_package(benchmark CONFIG REQUIRED)
endif()

# Mesa's OSMesa (llvmpipe) is optional too: the rasterizer benchmark compares against it.
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND AND SVETLO_BENCH)
    pkg_check_modules(OSMESA QUIET IMPORTED_TARGET osmesa)
endif()

# The Python module: pybind11 for Debian's python3 (/usr/bin/python3, where python3-numpy is),
# not whatever python3 comes first on the PATH. Without them the module is left out, and the
# build says so.
if(SVETLO_PYTHON)
    if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
        set(Python_EXECUTABLE /usr/bin/python3)
    endif()
    set(PYBIND11_FINDPYTHON ON)
    find_package(pybind11 CONFIG QUIET)
    if(NOT pybind11_FOUND)
        message(STATUS "svetlo: pybind11 not found: the Python module is not built")
        set(SVETLO_PYTHON OFF)
    endif()
endif()
