#include "fuzz_targets.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "svetlo/core/error.h"
#include "svetlo/core/image_io.h"
#include "svetlo/scene/mesh_file.h"
#include "svetlo/scene/scene_loader.h"
#include "svetlo/shading/environment.h"

namespace svetlo::fuzz {

namespace {

/// The contract broken: abort, so that the fuzzer keeps the input and the replay test fails.
void require(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz: accepted input broke docs/robustness.md's rule: %s\n", what);
        std::abort();
    }
}

/// The bytes as a file of this process (the readers take paths), removed afterwards.
class TempFile {
public:
    TempFile(const uint8_t* data, size_t size, const std::string& extension)
        : path_(std::filesystem::temp_directory_path() /
                ("svetlo_fuzz_" + std::to_string(getpid()) + extension)) {
        std::ofstream(path_, std::ios::binary)
            .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    ~TempFile() {
        std::error_code ec;
        std::filesystem::remove(path_, ec);
    }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

void check_mesh(const Mesh& m) {
    for (vec3 p : m.positions) require(is_finite(p), "a position that is not finite");
    for (uint32_t i : m.indices) require(i < m.positions.size(), "an index out of range");
    require(m.indices.size() % 3 == 0, "indices not in threes");
}

}  // namespace

void scene(const uint8_t* data, size_t size) {
    TempFile file(data, size, ".json");
    Scene s;
    try {
        s = load_scene(file.path());
    } catch (const Error&) {
        return;  // refused, with its one line
    }
    require(is_finite(s.camera.position) && is_finite(s.camera.look_at),
            "a camera that is not finite");
    require(s.film.width >= 1 && s.film.height >= 1, "an empty film");
    for (const Object& o : s.objects) {
        if (const auto* m = std::get_if<Mesh>(&o.shape)) check_mesh(*m);
    }
    for (const Prototype& p : s.prototypes)
        for (const Object& o : p.objects)
            if (const auto* m = std::get_if<Mesh>(&o.shape)) check_mesh(*m);
    for (const Instance& i : s.instances)
        require(i.prototype < s.prototypes.size(), "an instance of no prototype");
}

void mesh(const uint8_t* data, size_t size, const std::string& extension) {
    TempFile file(data, size, "." + extension);
    MeshFile m;
    try {
        m = read_mesh_file(file.path());
    } catch (const std::exception&) {
        return;
    }
    check_mesh(m.mesh);
    for (const MeshFile::Shared& shared : m.shared) check_mesh(shared.mesh);
}

/// The file extension that the bytes' magic number says, `fallback` for none.
const char* image_extension(const uint8_t* data, size_t size, const char* fallback) {
    return size >= 2 && data[0] == 'P' && (data[1] == 'F' || data[1] == 'f') ? ".pfm"
           : size >= 4 && data[0] == 0x76 && data[1] == 0x2f                 ? ".exr"
                                                                             : fallback;
}

void environment(const uint8_t* data, size_t size) {
    TempFile file(data, size, image_extension(data, size, ".hdr"));
    Scene scene;
    try {
        scene.textures.push_back(read_texture(file.path(), false, kMaxTextureBytes, "fuzz",
                                              NegativeTexels::ClampToZero));
    } catch (const Error&) {
        return;
    }
    scene.environment = EnvironmentSettings{0, Color(1.0f), 30.0f};
    const Environment env(scene);
    for (int k = 0; k < 64; ++k) {
        const vec2 u((k % 8 + 0.5f) / 8.0f, (k / 8 + 0.5f) / 8.0f);
        const EnvironmentSample s = env.sample(u);
        if (env.is_black()) break;
        require(is_finite(s.radiance) && s.radiance.r >= 0.0f && std::isfinite(s.pdf),
                "an environment sample that is not finite");
        require(s.pdf > 0.0f || s.wi == vec3(0.0f), "an environment draw of density 0");
    }
}

void image(const uint8_t* data, size_t size) {
    TempFile file(data, size, image_extension(data, size, ".png"));
    TextureImage img;
    try {
        img = read_texture(file.path(), true, kMaxTextureBytes, "fuzz");
    } catch (const Error&) {
        return;
    }
    for (int j = 0; j < img.height(); ++j) {
        for (int i = 0; i < img.width(); ++i) {
            Color c = img.texel(i, j);
            require(is_finite(c) && c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f,
                    "a texel that is not finite and >= 0");
        }
    }
}

void run(const std::string& name, const uint8_t* data, size_t size) {
    if (name == "scene") {
        scene(data, size);
    } else if (name == "image") {
        image(data, size);
    } else if (name == "environment") {
        environment(data, size);
    } else {
        mesh(data, size, name);
    }
}

}  // namespace svetlo::fuzz
