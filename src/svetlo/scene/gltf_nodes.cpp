#include "svetlo/scene/gltf_nodes.h"

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "svetlo/scene/gltf_accessors.h"

namespace svetlo {

std::optional<mat4> unit_rotation(double x, double y, double z, double w) {
    const glm::quat q(static_cast<float>(w), static_cast<float>(x), static_cast<float>(y),
                      static_cast<float>(z));
    const float length = glm::length(q);
    if (!(length > 0.0f) || !std::isfinite(length)) return std::nullopt;
    return glm::mat4_cast(q / length);
}

mat4 node_matrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        mat4 m;
        for (int k = 0; k < 16; ++k) glm::value_ptr(m)[k] = static_cast<float>(node.matrix[k]);
        return m;  // glTF stores column-major, as glm does
    }
    mat4 t(1.0f), r(1.0f), s(1.0f);
    if (node.translation.size() == 3) {
        t = glm::translate(mat4(1.0f),
                           vec3(node.translation[0], node.translation[1], node.translation[2]));
    }
    if (node.rotation.size() == 4) {
        r = unit_rotation(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3])
                .value_or(mat4(1.0f));
    }
    if (node.scale.size() == 3) {
        s = glm::scale(mat4(1.0f), vec3(node.scale[0], node.scale[1], node.scale[2]));
    }
    return t * r * s;
}

void pose_first_keys(tinygltf::Model& model) {
    if (model.animations.empty()) return;
    const tinygltf::Animation& animation = model.animations[0];
    for (size_t k = 0; k < animation.channels.size(); ++k) {
        const tinygltf::AnimationChannel& channel = animation.channels[k];
        const std::string name = "animation 0, channel " + std::to_string(k);
        const std::string& path = channel.target_path;
        const bool trs = path == "translation" || path == "rotation" || path == "scale";
        if (!trs && path != "weights") continue;  // KHR_animation_pointer's, and unknown ones
        if (channel.target_node < 0 ||
            static_cast<size_t>(channel.target_node) >= model.nodes.size())
            throw std::runtime_error(name + ": node " + std::to_string(channel.target_node) +
                                     " missing");
        if (channel.sampler < 0 ||
            static_cast<size_t>(channel.sampler) >= animation.samplers.size())
            throw std::runtime_error(name + ": sampler " + std::to_string(channel.sampler) +
                                     " missing");
        const tinygltf::AnimationSampler& sampler =
            animation.samplers[static_cast<size_t>(channel.sampler)];
        tinygltf::Node& node = model.nodes[static_cast<size_t>(channel.target_node)];
        // The earliest key (the inputs increase, but a file may not keep to it).
        const AccessorView input(model, sampler.input, 1);
        if (input.count() == 0) throw std::runtime_error(name + ": no keys");
        size_t first = 0;
        for (size_t i = 1; i < input.count(); ++i)
            if (input.component(i, 0) < input.component(first, 0)) first = i;
        const size_t key = sampler.interpolation == "CUBICSPLINE" ? 3 * first + 1 : first;
        if (trs) {
            if (node.matrix.size() == 16)
                throw std::runtime_error(name + ": node " + std::to_string(channel.target_node) +
                                         " is given by a matrix and cannot be animated");
            const int n = path == "rotation" ? 4 : 3;
            const AccessorView output(model, sampler.output, n);
            if (key >= output.count()) throw std::runtime_error(name + ": fewer outputs than keys");
            std::vector<double> v(static_cast<size_t>(n));
            for (int c = 0; c < n; ++c) {
                v[static_cast<size_t>(c)] = output.component(key, c);
                if (!std::isfinite(v[static_cast<size_t>(c)]))
                    throw std::runtime_error(name + ": an output is not finite");
            }
            (path == "translation" ? node.translation
             : path == "rotation"  ? node.rotation
                                   : node.scale) = v;
        } else {
            // One weight per morph target of the node's mesh, each key's weights in a row.
            if (node.mesh < 0 || static_cast<size_t>(node.mesh) >= model.meshes.size() ||
                model.meshes[static_cast<size_t>(node.mesh)].primitives.empty())
                throw std::runtime_error(name + ": weights of a node without a mesh");
            const size_t targets =
                model.meshes[static_cast<size_t>(node.mesh)].primitives[0].targets.size();
            const AccessorView output(model, sampler.output, 1);
            if ((key + 1) * targets > output.count())
                throw std::runtime_error(name + ": fewer outputs than keys");
            node.weights.resize(targets);
            for (size_t t = 0; t < targets; ++t) {
                node.weights[t] = output.component(key * targets + t, 0);
                if (!std::isfinite(node.weights[t]))
                    throw std::runtime_error(name + ": an output is not finite");
            }
        }
    }
}

std::vector<mat4> node_world_matrices(const tinygltf::Model& model) {
    const size_t n = model.nodes.size();
    std::vector<int> parent(n, -1);
    for (size_t k = 0; k < n; ++k) {
        for (int child : model.nodes[k].children) {
            if (child < 0 || static_cast<size_t>(child) >= n)
                throw std::runtime_error("node " + std::to_string(child) + " missing");
            if (parent[static_cast<size_t>(child)] >= 0 || static_cast<size_t>(child) == k)
                throw std::runtime_error("node " + std::to_string(child) +
                                         " is the child of two nodes (the nodes must form trees)");
            parent[static_cast<size_t>(child)] = static_cast<int>(k);
        }
    }
    // Each node after its parent: climb to the first node done, then come back down.
    std::vector<mat4> world(n, mat4(1.0f));
    std::vector<char> done(n, 0);
    std::vector<int> chain;
    for (size_t k = 0; k < n; ++k) {
        chain.clear();
        for (int at = static_cast<int>(k); at >= 0 && !done[static_cast<size_t>(at)];
             at = parent[static_cast<size_t>(at)]) {
            chain.push_back(at);
            if (chain.size() > n) throw std::runtime_error("the nodes' hierarchy has a cycle");
        }
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
            const auto at = static_cast<size_t>(*it);
            const int up = parent[at];
            world[at] = (up >= 0 ? world[static_cast<size_t>(up)] : mat4(1.0f)) *
                        node_matrix(model.nodes[at]);
            done[at] = 1;
        }
    }
    return world;
}

std::vector<mat4> skinning_matrices(const tinygltf::Model& model, int skin,
                                    const tinygltf::Primitive& prim, size_t count,
                                    const std::vector<mat4>& world) {
    if (skin < 0 || static_cast<size_t>(skin) >= model.skins.size())
        throw std::runtime_error("skin " + std::to_string(skin) + " missing");
    const tinygltf::Skin& s = model.skins[static_cast<size_t>(skin)];
    const std::string name = "skin " + std::to_string(skin);
    if (prim.attributes.find("JOINTS_0") == prim.attributes.end()) return {};
    // Each joint's world transform times its inverse bind matrix (identity where none).
    std::vector<mat4> joint(s.joints.size(), mat4(1.0f));
    std::optional<AccessorView> inverse_bind;
    if (s.inverseBindMatrices >= 0) {
        inverse_bind.emplace(model, s.inverseBindMatrices, 16);
        if (inverse_bind->count() < s.joints.size())
            throw std::runtime_error(name + ": fewer inverse bind matrices than joints");
    }
    for (size_t j = 0; j < s.joints.size(); ++j) {
        const int node = s.joints[j];
        if (node < 0 || static_cast<size_t>(node) >= world.size())
            throw std::runtime_error(name + ": joint node " + std::to_string(node) + " missing");
        mat4 ibm(1.0f);
        if (inverse_bind)
            for (int c = 0; c < 16; ++c)
                glm::value_ptr(ibm)[c] = static_cast<float>(inverse_bind->component(j, c));
        joint[j] = world[static_cast<size_t>(node)] * ibm;
    }
    std::vector<mat4> out(count, mat4(0.0f));
    std::vector<float> total(count, 0.0f);
    for (const char* set : {"0", "1"}) {
        const auto joints = prim.attributes.find(std::string("JOINTS_") + set);
        const auto weights = prim.attributes.find(std::string("WEIGHTS_") + set);
        if (joints == prim.attributes.end()) continue;
        if (weights == prim.attributes.end())
            throw std::runtime_error(name + ": JOINTS_" + set + " without WEIGHTS_" + set);
        const AccessorView j(model, joints->second, 4), w(model, weights->second, 4);
        if (j.count() != count || w.count() != count)
            throw std::runtime_error(name + ": JOINTS_" + set + " or WEIGHTS_" + set + " count");
        for (size_t v = 0; v < count; ++v) {
            for (int c = 0; c < 4; ++c) {
                const double weight = w.component(v, c);
                if (!(weight >= 0.0) || !std::isfinite(weight))
                    throw std::runtime_error(name + ": a weight is negative or not finite");
                if (weight == 0.0) continue;
                const double index = j.component(v, c);
                if (!(index >= 0.0 && index < static_cast<double>(joint.size())))
                    throw std::runtime_error(name + ": joint index out of range");
                out[v] += static_cast<float>(weight) * joint[static_cast<size_t>(index)];
                total[v] += static_cast<float>(weight);
            }
        }
    }
    for (size_t v = 0; v < count; ++v)
        out[v] = total[v] > 0.0f ? out[v] * (1.0f / total[v]) : mat4(1.0f);
    return out;
}

}  // namespace svetlo
