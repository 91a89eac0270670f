#include "svetlo/scene/scene_loader.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "svetlo/core/input_file.h"
#include "svetlo/core/sha256.h"
#include "svetlo/scene/json_node.h"
#include "svetlo/scene/model_scene.h"
#include "svetlo/scene/scene_parts.h"
#include "svetlo/scene/tangents.h"

namespace svetlo {
namespace fs = std::filesystem;

nlohmann::json read_scene_json(const fs::path& path) {
    std::string file = path.string();
    std::string problem = input_file_problem(path, kMaxSceneBytes);
    if (!problem.empty()) throw Error(file, "file", problem);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(file, "file", std::string("cannot open: ") + std::strerror(errno));
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string text = buffer.str();
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        // A number too large for a double (1e999) is an out_of_range error without a
        // position: find it with a SAX pass, whose parse_error receives the position.
        size_t byte = 0;
        if (const auto* pe = dynamic_cast<const nlohmann::json::parse_error*>(&e)) {
            byte = pe->byte;
        } else {
            struct Locator : nlohmann::json_sax<nlohmann::json> {
                size_t byte = 0;
                bool null() override { return true; }
                bool boolean(bool) override { return true; }
                bool number_integer(number_integer_t) override { return true; }
                bool number_unsigned(number_unsigned_t) override { return true; }
                bool number_float(number_float_t, const string_t&) override { return true; }
                bool string(string_t&) override { return true; }
                bool binary(binary_t&) override { return true; }
                bool start_object(std::size_t) override { return true; }
                bool key(string_t&) override { return true; }
                bool end_object() override { return true; }
                bool start_array(std::size_t) override { return true; }
                bool end_array() override { return true; }
                bool parse_error(std::size_t position, const std::string&,
                                 const nlohmann::json::exception&) override {
                    byte = position;
                    return false;
                }
            } locator;
            nlohmann::json::sax_parse(text, &locator);
            byte = locator.byte;
        }
        size_t line = 1, column = 1;
        for (size_t k = 0; k + 1 < byte && k < text.size(); ++k) {
            if (text[k] == '\n') {
                ++line;
                column = 1;
            } else {
                ++column;
            }
        }
        std::string what = e.what();
        // nlohmann's message is "[json.exception.parse_error.101] parse error at line 1,
        // column 2: syntax error while parsing value - ..."; keep the part after "- ".
        size_t dash = what.find(" - ");
        if (dash != std::string::npos) what = what.substr(dash + 3);
        size_t bracket = what.find("] ");  // drop nlohmann's "[json.exception.x.y] " prefix
        if (what.rfind("[json.exception", 0) == 0 && bracket != std::string::npos) {
            what = what.substr(bracket + 2);
        }
        throw Error(file, "line " + std::to_string(line) + ", column " + std::to_string(column),
                    "malformed JSON: " + what);
    }
}

nlohmann::json override_value(const std::string& text) {
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
        return text;  // not JSON (or a number out of range): a plain string
    }
}

void apply_override(nlohmann::json& root, const Override& o, const std::string& file) {
    std::string where = "--set " + o.key;
    if (o.key.empty()) throw Error(file, where, "empty key");
    const nlohmann::json value = override_value(o.value);
    nlohmann::json* node = &root;
    std::stringstream parts(o.key);
    std::string part;
    while (std::getline(parts, part, '.')) {
        if (part.empty()) throw Error(file, where, "empty path component");
        if (node->is_array()) {
            size_t used = 0;
            unsigned long index = 0;
            try {
                index = std::stoul(part, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != part.size()) throw Error(file, where, "'" + part + "' is not an index");
            if (index >= node->size()) {
                throw Error(file, where, "index " + part + " is past the end of the array");
            }
            node = &(*node)[index];
        } else if (node->is_object() || node->is_null()) {
            node = &(*node)[part];
        } else {
            throw Error(file, where, "'" + part + "' goes inside a value that is not an object");
        }
    }
    *node = value;
}

nlohmann::json effective_scene_json(const fs::path& path, const std::vector<Override>& overrides,
                                    FileCache* meshes, const FileScope& files) {
    FileCache own;
    nlohmann::json root = is_model_file(path)
                              ? model_scene_json(path, meshes ? *meshes : own, files)
                              : read_scene_json(path);
    for (const Override& o : overrides) apply_override(root, o, path.string());
    return root;
}

Scene load_scene(const fs::path& path, const std::vector<Override>& overrides) {
    // One cache for both steps: a model file is read once, for its framing and its triangles.
    FileCache meshes;
    return scene_from_json(effective_scene_json(path, overrides, &meshes), path, &meshes);
}

namespace {

/// Scene::geometry_key of the scene read from `root` (objects, area lights and the order of
/// its materials, whose indices the primitives hold), a SHA-256 in hex.
std::string geometry_key(const nlohmann::json& root, const Scene& scene) {
    std::string text = scene.path.parent_path().string() + "\n";
    // A mesh file edited while `svetlo serve` runs makes another geometry.
    auto add_objects = [&](const nlohmann::json& objects) {
        if (!objects.is_array()) return;
        text += objects.dump() + "\n";
        for (const nlohmann::json& object : objects) {
            auto file = object.find("file");
            if (file == object.end() || !file->is_string()) continue;
            text += file_stamp(scene.path.parent_path() / file->get<std::string>()) + "\n";
        }
    };
    if (auto it = root.find("objects"); it != root.end()) add_objects(*it);
    if (auto it = root.find("prototypes"); it != root.end() && it->is_object()) {
        for (const auto& [name, prototype] : it->items()) {
            text += name + "\n";
            if (auto objects = prototype.find("objects"); objects != prototype.end())
                add_objects(*objects);
        }
    }
    if (auto it = root.find("lights"); it != root.end()) {
        for (const nlohmann::json& light : *it)
            if (light.value("type", "") == "area") text += light.dump() + "\n";
    }
    for (const std::string& name : scene.material_names) text += name + "\n";
    // The meshes a normal map gave tangents (a material's edit can add them).
    const auto tangents = [&](const Object& object) {
        const auto* mesh = std::get_if<Mesh>(&object.shape);
        text += mesh && !mesh->tangents.empty() ? "t" : "-";
    };
    for (const Object& object : scene.objects) tangents(object);
    for (const Prototype& prototype : scene.prototypes)
        for (const Object& object : prototype.objects) tangents(object);
    return sha256_hex(text);
}

}  // namespace

Scene scene_from_json(const nlohmann::json& root, const fs::path& path, FileCache* meshes,
                      const FileScope& files) {
    FileCache own;
    Scene scene;
    scene.path = path;
    scene.files = files;
    JsonNode top(root, path.string(), "");
    top.expect_object({"camera", "film", "render", "materials", "lights", "objects", "environment",
                       "prototypes"});
    FileCache& cache = meshes ? *meshes : own;
    scene.camera = parse_camera(top.at("camera"));
    if (auto film = top.find("film")) scene.film = parse_film(*film);
    if (auto render = top.find("render")) scene.render = parse_render(*render);
    if (auto materials = top.find("materials")) parse_materials(*materials, scene, cache);
    if (auto lights = top.find("lights")) {
        for (size_t k = 0; k < lights->size(); ++k)
            scene.lights.push_back(parse_light(lights->at(k)));
    }
    if (auto environment = top.find("environment")) parse_environment(*environment, scene, cache);
    Prototypes prototypes(top.find("prototypes"));
    std::vector<Instance> placed;
    if (auto objects = top.find("objects")) {
        for (size_t k = 0; k < objects->size(); ++k)
            parse_object(objects->at(k), scene, cache, prototypes, scene.objects, placed);
    }
    settle_instances(std::move(placed), scene);
    add_missing_tangents(scene);
    scene.geometry_key = geometry_key(root, scene);
    return scene;
}

}  // namespace svetlo
