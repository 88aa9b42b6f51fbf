#include "layers/models/GltfRig.h"

#include "layers/models/GltfAccessors.h"

#include <tiny_gltf.h>

#include <glm/gtc/type_ptr.hpp>

#include <cmath>

namespace orbis::models {
namespace {

std::string nodeName(const tinygltf::Model& m, int i) {
    const std::string& n = m.nodes[size_t(i)].name;
    return "node " + std::to_string(i) + (n.empty() ? "" : " '" + n + "'");
}

class RigReader {
public:
    RigReader(const tinygltf::Model& m, const GltfAccessors& acc, const std::string& file, const std::vector<uint32_t>& meshTargets,
              ModelData& out, const std::function<void(const std::string&)>& warn)
        : m_(m), acc_(acc), file_(file), meshTargets_(meshTargets), out_(out), warn_(warn) {}

    Result<void> read() {
        if (auto r = readNodes(); !r) return r;
        if (auto r = readSkins(); !r) return r;
        for (size_t a = 0; a < m_.animations.size(); ++a)
            if (auto r = readAnimation(a); !r) return r;
        return {};
    }

private:
    Result<void> readNodes();
    Result<void> readSkins();
    Result<void> readAnimation(size_t index);
    Result<void> readSampler(const tinygltf::AnimationSampler& s, const std::string& what, AnimationPath path,
                             uint32_t components, AnimationSampler& out);
    uint32_t targetsOf(int node) const {
        const int mesh = m_.nodes[size_t(node)].mesh;
        return mesh >= 0 && size_t(mesh) < meshTargets_.size() ? meshTargets_[size_t(mesh)] : 0;
    }

    const tinygltf::Model& m_;
    const GltfAccessors& acc_;
    const std::string& file_;
    const std::vector<uint32_t>& meshTargets_;
    ModelData& out_;
    const std::function<void(const std::string&)>& warn_;
    uint64_t keyframes_ = 0;
};

Result<void> RigReader::readNodes() {
    const size_t n = m_.nodes.size();
    ModelRig& rig = out_.rig;
    rig.nodes.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const tinygltf::Node& src = m_.nodes[i];
        RigNode& node = rig.nodes[i];
        node.name = src.name;
        if (src.matrix.size() == 16) {
            node.hasMatrix = true;
            node.matrix = glm::make_mat4(src.matrix.data());
        }
        if (src.translation.size() == 3) node.translation = glm::dvec3(src.translation[0], src.translation[1], src.translation[2]);
        if (src.rotation.size() == 4) node.rotation = glm::normalize(glm::dquat(src.rotation[3], src.rotation[0], src.rotation[1], src.rotation[2]));
        if (src.scale.size() == 3) node.scale = glm::dvec3(src.scale[0], src.scale[1], src.scale[2]);
        const uint32_t targets = targetsOf(int(i));
        if (targets > 0) {
            const std::vector<double>* w = !src.weights.empty() ? &src.weights
                                           : (src.mesh >= 0 && size_t(src.mesh) < m_.meshes.size()) ? &m_.meshes[size_t(src.mesh)].weights
                                                                                                     : nullptr;
            node.weights.assign(targets, 0.0f);
            if (w && !w->empty()) {
                if (w->size() != targets)
                    warn_(nodeName(m_, int(i)) + ": " + std::to_string(w->size()) + " morph weights for " + std::to_string(targets) +
                          " targets: the missing ones are 0");
                for (size_t k = 0; k < std::min<size_t>(targets, w->size()); ++k) node.weights[k] = float((*w)[k]);
            }
        }
        for (int c : src.children) {
            if (c < 0 || size_t(c) >= n)
                return makeError(file_ + ": " + nodeName(m_, int(i)) + " has child " + std::to_string(c) + ", which does not exist");
            if (rig.nodes[size_t(c)].parent >= 0 || size_t(c) == i)
                return makeError(file_ + ": " + nodeName(m_, c) + " has two parents (" + std::to_string(rig.nodes[size_t(c)].parent) +
                                 " and " + std::to_string(i) + "): glTF nodes form trees");
        }
        for (int c : src.children) rig.nodes[size_t(c)].parent = int(i);
    }
    // Parents before children: from each root, depth first (iteratively: a deep chain cannot
    // overflow the stack). Nodes never reached sit on a cycle.
    rig.order.clear();
    rig.order.reserve(n);
    std::vector<uint32_t> stack;
    for (size_t i = 0; i < n; ++i) {
        if (rig.nodes[i].parent >= 0) continue;
        stack.push_back(uint32_t(i));
        while (!stack.empty()) {
            const uint32_t at = stack.back();
            stack.pop_back();
            rig.order.push_back(at);
            for (int c : m_.nodes[at].children) stack.push_back(uint32_t(c));
        }
    }
    if (rig.order.size() != n) return makeError(file_ + ": the node hierarchy has a cycle");
    return {};
}

Result<void> RigReader::readSkins() {
    for (size_t s = 0; s < m_.skins.size(); ++s) {
        const tinygltf::Skin& src = m_.skins[s];
        const std::string where = file_ + ": skin " + std::to_string(s) + (src.name.empty() ? "" : " '" + src.name + "'");
        ModelSkin skin;
        skin.name = src.name;
        if (src.joints.empty()) return makeError(where + ": has no joints");
        if (src.joints.size() > kMaxGltfJoints)
            return makeError(where + ": " + std::to_string(src.joints.size()) + " joints; at most " + std::to_string(kMaxGltfJoints) + " are supported");
        for (int j : src.joints) {
            if (j < 0 || size_t(j) >= m_.nodes.size()) return makeError(where + ": joint node " + std::to_string(j) + " does not exist");
            skin.joints.push_back(uint32_t(j));
        }
        skin.inverseBind.assign(skin.joints.size(), glm::mat4(1.0f));
        if (src.inverseBindMatrices >= 0) {
            auto m = acc_.floats(src.inverseBindMatrices, 16, "inverse bind matrices of skin " + std::to_string(s), kMaxGltfJoints);
            if (!m) return m.error();
            if (m->size() / 16 < skin.joints.size())
                return makeError(where + ": " + std::to_string(m->size() / 16) + " inverse bind matrices for " +
                                 std::to_string(skin.joints.size()) + " joints");
            for (size_t j = 0; j < skin.joints.size(); ++j) skin.inverseBind[j] = glm::make_mat4(m->data() + j * 16);
        }
        out_.rig.skins.push_back(std::move(skin));
    }
    return {};
}

Result<void> RigReader::readSampler(const tinygltf::AnimationSampler& s, const std::string& what, AnimationPath path,
                                    uint32_t components, AnimationSampler& out) {
    const std::string where = file_ + ": " + what;
    if (s.interpolation == "LINEAR") out.interpolation = AnimationInterpolation::Linear;
    else if (s.interpolation == "STEP") out.interpolation = AnimationInterpolation::Step;
    else if (s.interpolation == "CUBICSPLINE") out.interpolation = AnimationInterpolation::CubicSpline;
    else return makeError(where + ": interpolation \"" + s.interpolation + "\" is not LINEAR, STEP or CUBICSPLINE");
    const uint64_t left = kMaxGltfKeyframes - keyframes_;
    auto times = acc_.floats(s.input, 1, "input of " + what, left);
    if (!times) return makeError(times.message());
    if (times->empty()) return makeError(where + ": has no keyframes");
    for (size_t k = 0; k < times->size(); ++k) {
        const float t = (*times)[k];
        if (!std::isfinite(t) || (k > 0 && !(t > (*times)[k - 1])))
            return makeError(where + ": keyframe time " + std::to_string(k) + " (" + std::to_string(t) +
                             " s) does not come after the one before: times must increase strictly");
    }
    const uint32_t perKey = out.interpolation == AnimationInterpolation::CubicSpline ? 3 : 1;
    const int outComponents = path == AnimationPath::Weights ? 1 : int(components);
    const auto expected = uint64_t(times->size()) * perKey * (path == AnimationPath::Weights ? components : 1);
    const auto outCount = acc_.count(s.output);
    if (!outCount) return makeError(where + ": output accessor " + std::to_string(s.output) + " does not exist");
    if (*outCount != expected)
        return makeError(where + ": " + std::to_string(*outCount) + " output values for " + std::to_string(times->size()) +
                         " keyframes; expected " + std::to_string(expected) +
                         (path == AnimationPath::Weights ? " (" + std::to_string(components) + " morph targets each)" : "") +
                         (perKey == 3 ? " (in-tangent, value, out-tangent each)" : ""));
    auto values = acc_.floats(s.output, outComponents, "output of " + what, expected);
    if (!values) return makeError(values.message());
    for (float v : *values)
        if (!std::isfinite(v)) return makeError(where + ": an output value is not a number");
    keyframes_ += times->size();
    out.times = std::move(*times);
    out.values = std::move(*values);
    out.components = components;
    return {};
}

Result<void> RigReader::readAnimation(size_t index) {
    const tinygltf::Animation& src = m_.animations[index];
    ModelAnimation anim;
    anim.name = src.name;
    const std::string what = "animation " + std::to_string(index) + (src.name.empty() ? "" : " '" + src.name + "'");
    const std::string where = file_ + ": " + what;
    // Samplers are read for the channel that uses them (the channel gives their size); -1: not yet.
    std::vector<int> samplerOf(src.samplers.size(), -1);
    std::vector<std::pair<AnimationPath, uint32_t>> samplerUse(src.samplers.size());
    for (size_t c = 0; c < src.channels.size(); ++c) {
        const tinygltf::AnimationChannel& ch = src.channels[c];
        const std::string cw = where + " channel " + std::to_string(c);
        AnimationPath path;
        if (ch.target_path == "translation") path = AnimationPath::Translation;
        else if (ch.target_path == "rotation") path = AnimationPath::Rotation;
        else if (ch.target_path == "scale") path = AnimationPath::Scale;
        else if (ch.target_path == "weights") path = AnimationPath::Weights;
        else {
            warn_(cw + ": target path \"" + ch.target_path + "\" is not animated");
            continue;
        }
        if (ch.target_node < 0) {   // allowed by the spec (an extension may name the target)
            warn_(cw + ": has no target node: not animated");
            continue;
        }
        if (size_t(ch.target_node) >= m_.nodes.size())
            return makeError(cw + ": targets node " + std::to_string(ch.target_node) + ", which does not exist");
        if (ch.sampler < 0 || size_t(ch.sampler) >= src.samplers.size())
            return makeError(cw + ": sampler " + std::to_string(ch.sampler) + " does not exist");
        const RigNode& node = out_.rig.nodes[size_t(ch.target_node)];
        if (node.hasMatrix && path != AnimationPath::Weights)
            return makeError(cw + ": animates the " + ch.target_path + " of " + nodeName(m_, ch.target_node) +
                             ", which is given by a matrix (glTF allows only TRS on animated nodes)");
        uint32_t components = path == AnimationPath::Rotation ? 4 : 3;
        if (path == AnimationPath::Weights) {
            components = targetsOf(ch.target_node);
            if (components == 0)
                return makeError(cw + ": animates the morph weights of " + nodeName(m_, ch.target_node) + ", whose mesh has no morph targets");
        }
        int& s = samplerOf[size_t(ch.sampler)];
        if (s < 0) {
            AnimationSampler sampler;
            if (auto r = readSampler(src.samplers[size_t(ch.sampler)], what + " sampler " + std::to_string(ch.sampler), path,
                                     components, sampler); !r)
                return r;
            anim.duration = std::max(anim.duration, double(sampler.times.back()));
            s = int(anim.samplers.size());
            anim.samplers.push_back(std::move(sampler));
            samplerUse[size_t(ch.sampler)] = {path, components};
        } else if ((samplerUse[size_t(ch.sampler)].first == AnimationPath::Rotation) != (path == AnimationPath::Rotation) ||
                   samplerUse[size_t(ch.sampler)].second != components) {
            return makeError(cw + ": sampler " + std::to_string(ch.sampler) + " is shared by channels of different sizes");
        }
        anim.channels.push_back({uint32_t(ch.target_node), path, uint32_t(s)});
    }
    out_.rig.animations.push_back(std::move(anim));
    return {};
}

}  // namespace

Result<void> readRig(const tinygltf::Model& model, const GltfAccessors& accessors, const std::string& file,
                     const std::vector<uint32_t>& meshTargets, ModelData& out,
                     const std::function<void(const std::string&)>& warn) {
    return RigReader(model, accessors, file, meshTargets, out, warn).read();
}

}  // namespace orbis::models
