# The browser's build (make web, docs/web.md): Debian's emscripten cross-compiles the library.
# The header-only libraries are Debian's own headers, linked into a folder of their own (the
# rest of /usr/include is the build machine's C library, not the browser's); tinygltf and
# tinyobjloader are compiled from their headers (web/third_party.cpp). What has no WebAssembly
# build is left out behind its seam: oneTBB (core/parallel_threads.cpp), OpenEXR, zlib and
# OpenSSL (core/), Embree, libjpeg, libwebp, Draco, meshoptimizer.
set(SVETLO_WEB_INCLUDE ${PROJECT_BINARY_DIR}/web-include)
file(MAKE_DIRECTORY ${SVETLO_WEB_INCLUDE})
foreach(entry glm nlohmann stb tiny_gltf.h tiny_obj_loader.h)
    if(NOT EXISTS /usr/include/${entry})
        message(FATAL_ERROR "svetlo web: /usr/include/${entry} is missing (scripts/setup installs it)")
    endif()
    file(CREATE_LINK /usr/include/${entry} ${SVETLO_WEB_INCLUDE}/${entry} SYMBOLIC)
endforeach()

function(svetlo_web_headers target)
    add_library(${target} INTERFACE IMPORTED GLOBAL)
    target_include_directories(${target} SYSTEM INTERFACE ${ARGN})
endfunction()
svetlo_web_headers(glm::glm ${SVETLO_WEB_INCLUDE})
svetlo_web_headers(nlohmann_json::nlohmann_json ${SVETLO_WEB_INCLUDE})
svetlo_web_headers(TinyGLTF::TinyGLTF ${SVETLO_WEB_INCLUDE} ${SVETLO_WEB_INCLUDE}/stb)
svetlo_web_headers(tinyobjloader::tinyobjloader ${SVETLO_WEB_INCLUDE})
# svetlo decodes glTF's images itself: tinygltf without stb, in every file that includes it.
# It still reads image files (no TINYGLTF_NO_EXTERNAL_IMAGE, which Debian's host library does
# not define either): without them a visitor's glTF with its textures beside it was refused,
# every image "does not decode: no data".
target_compile_definitions(TinyGLTF::TinyGLTF INTERFACE TINYGLTF_NO_STB_IMAGE
                           TINYGLTF_NO_STB_IMAGE_WRITE)
add_library(svetlo_stb INTERFACE)
target_include_directories(svetlo_stb SYSTEM INTERFACE ${SVETLO_WEB_INCLUDE}/stb)

set(THREADS_PREFER_PTHREAD_FLAG ON)
find_package(Threads REQUIRED)

function(svetlo_link_mesh_codecs target)
endfunction()
