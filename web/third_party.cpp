// The implementations of the header-only readers that Debian builds as libraries for the host
// only: tinygltf and tinyobjloader, compiled here for the browser from the same headers
// (cmake/web_dependencies.cmake). svetlo decodes glTF's images itself (scene/gltf_reader.cpp),
// so tinygltf is built without stb (TINYGLTF_NO_STB_IMAGE and the rest come with its target,
// cmake/web_dependencies.cmake, the same in every file).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>

#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
