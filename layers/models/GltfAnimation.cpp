#include "layers/models/GltfAnimation.h"

#include "formats/motion/Attitude.h"
#include "formats/motion/Trajectory.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::models {
namespace {

/// The keyframe before `seconds` and the fraction to the next; `clamped` at either end (then
/// the value is keyframe k's alone).
struct Segment {
    size_t k = 0;
    double u = 0.0, dt = 0.0;
    bool clamped = true;
};

Segment segmentAt(const std::vector<float>& times, double seconds) {
    Segment s;
    if (times.size() < 2 || !(seconds > double(times.front()))) return s;   // before the start (or NaN): the first
    if (seconds >= double(times.back())) {
        s.k = times.size() - 1;
        return s;
    }
    s.k = size_t(std::upper_bound(times.begin(), times.end(), seconds, [](double t, float key) { return t < double(key); }) -
                 times.begin()) - 1;
    s.dt = double(times[s.k + 1]) - double(times[s.k]);
    s.u = (seconds - double(times[s.k])) / s.dt;
    s.clamped = false;
    return s;
}

/// Component-wise sampling of any sampler into out[0 .. n) (rotations: before normalization,
/// LINEAR rotations are handled by the caller).
void sampleLinearParts(const AnimationSampler& sp, const Segment& g, size_t n, double* out) {
    const float* v = sp.values.data();
    const bool cubic = sp.interpolation == AnimationInterpolation::CubicSpline;
    // Element e of keyframe k: value (e = 1 for cubic: in-tangent 0, value 1, out-tangent 2).
    auto at = [&](size_t k, size_t e, size_t c) { return double(v[((cubic ? 3 * k + e : k)) * n + c]); };
    if (g.clamped || sp.interpolation == AnimationInterpolation::Step) {
        for (size_t c = 0; c < n; ++c) out[c] = at(g.k, 1, c);
        return;
    }
    const double u = g.u;
    if (!cubic) {
        for (size_t c = 0; c < n; ++c) out[c] = at(g.k, 1, c) + u * (at(g.k + 1, 1, c) - at(g.k, 1, c));
        return;
    }
    // glTF 2.0 Appendix C: p(u) = (2u^3 - 3u^2 + 1) v_k + dt (u^3 - 2u^2 + u) b_k
    //                            + (-2u^3 + 3u^2) v_k+1 + dt (u^3 - u^2) a_k+1
    const double u2 = u * u, u3 = u2 * u;
    const double h00 = 2 * u3 - 3 * u2 + 1, h10 = (u3 - 2 * u2 + u) * g.dt, h01 = -2 * u3 + 3 * u2, h11 = (u3 - u2) * g.dt;
    for (size_t c = 0; c < n; ++c)
        out[c] = h00 * at(g.k, 1, c) + h10 * at(g.k, 2, c) + h01 * at(g.k + 1, 1, c) + h11 * at(g.k + 1, 0, c);
}

glm::dmat4 trs(const glm::dvec3& t, const glm::dquat& r, const glm::dvec3& s) {
    glm::dmat4 m = glm::mat4_cast(r);
    m[0] *= s.x;
    m[1] *= s.y;
    m[2] *= s.z;
    m[3] = glm::dvec4(t, 1.0);
    return m;
}

void store(glm::vec4* out, uint32_t at, const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c) out[at + uint32_t(c)] = glm::vec4(m[c]);
}

glm::mat4 load(const glm::vec4* pose, uint32_t at) { return glm::mat4(pose[at], pose[at + 1], pose[at + 2], pose[at + 3]); }

float poseFloat(const glm::vec4* pose, uint32_t index) { return pose[index / 4][int(index % 4)]; }

}  // namespace

glm::dvec3 sampleVec3(const AnimationSampler& sampler, double seconds) {
    double v[3] = {0, 0, 0};
    if (sampler.components == 3 && !sampler.times.empty()) sampleLinearParts(sampler, segmentAt(sampler.times, seconds), 3, v);
    return {v[0], v[1], v[2]};
}

glm::dquat sampleRotation(const AnimationSampler& sampler, double seconds) {
    if (sampler.components != 4 || sampler.times.empty()) return glm::dquat(1.0, 0.0, 0.0, 0.0);
    const Segment g = segmentAt(sampler.times, seconds);
    if (sampler.interpolation == AnimationInterpolation::Linear && !g.clamped) {
        const float* a = &sampler.values[g.k * 4];
        const float* b = &sampler.values[(g.k + 1) * 4];
        const glm::dquat qa = glm::normalize(glm::dquat(a[3], a[0], a[1], a[2]));
        const glm::dquat qb = glm::normalize(glm::dquat(b[3], b[0], b[1], b[2]));
        return glm::normalize(motion::slerpShortest(qa, qb, g.u));
    }
    double v[4];
    sampleLinearParts(sampler, g, 4, v);
    const glm::dquat q(v[3], v[0], v[1], v[2]);
    const double len = glm::length(q);
    return len > 0.0 && std::isfinite(len) ? q / len : glm::dquat(1.0, 0.0, 0.0, 0.0);
}

void sampleWeights(const AnimationSampler& sampler, double seconds, float* out) {
    const size_t n = sampler.components;
    if (n == 0 || n > kMaxGltfMorphTargets || sampler.times.empty()) return;
    double v[kMaxGltfMorphTargets];
    sampleLinearParts(sampler, segmentAt(sampler.times, seconds), n, v);
    for (size_t c = 0; c < n; ++c) out[c] = float(v[c]);
}

PoseEvaluator::PoseEvaluator(const ModelData& model, int animation)
    : nodes_(model.rig.nodes), order_(model.rig.order), skins_(model.rig.skins) {
    if (animation >= 0 && size_t(animation) < model.rig.animations.size()) {
        const ModelAnimation& a = model.rig.animations[size_t(animation)];
        samplers_ = a.samplers;
        channels_ = a.channels;
        duration_ = a.duration;
        animation_ = animation;
        start_ = duration_;
        for (const AnimationSampler& sp : samplers_) start_ = std::min(start_, double(sp.times.front()));
    }
    const size_t nodes = nodes_.size();
    t_.resize(nodes);
    s_.resize(nodes);
    r_.resize(nodes);
    global_.assign(nodes, glm::dmat4(1.0));

    // The layout: draw matrices, then joint matrices of the skins in use, then weights.
    PoseLayout& l = layout_;
    const size_t draws = model.draws.size();
    l.drawMatrix.assign(draws, kPoseNone);
    l.drawJoints.assign(draws, kPoseNone);
    l.drawWeights.assign(draws, kPoseNone);
    l.skinJoints.assign(skins_.size(), kPoseNone);
    l.nodeWeights.assign(nodes, kPoseNone);
    drawNode_.resize(draws);
    uint32_t at = 0;
    for (size_t d = 0; d < draws; ++d) {
        drawNode_[d] = model.draws[d].node;
        if (model.draws[d].skin < 0) {
            l.drawMatrix[d] = at;
            at += 4;
        }
    }
    for (size_t d = 0; d < draws; ++d) {
        const int skin = model.draws[d].skin;
        if (skin < 0) continue;
        if (l.skinJoints[size_t(skin)] == kPoseNone) {
            l.skinJoints[size_t(skin)] = at;
            at += 4 * uint32_t(skins_[size_t(skin)].joints.size());
        }
        l.drawJoints[d] = l.skinJoints[size_t(skin)];
    }
    weightsStart_ = at;
    uint32_t floats = at * 4;
    for (size_t d = 0; d < draws; ++d) {
        const int node = model.draws[d].node;
        if (node < 0 || model.primitives[model.draws[d].primitive].morphTargets == 0) continue;
        if (l.nodeWeights[size_t(node)] == kPoseNone) {
            l.nodeWeights[size_t(node)] = floats;
            floats += uint32_t(nodes_[size_t(node)].weights.size());
        }
        l.drawWeights[d] = l.nodeWeights[size_t(node)];
    }
    l.vec4s = std::max(1u, (floats + 3) / 4);
    weights_.assign(size_t(l.vec4s) * 4, 0.0f);
}

float PoseEvaluator::weight(uint32_t node, uint32_t target) const {
    if (node >= layout_.nodeWeights.size() || layout_.nodeWeights[node] == kPoseNone) return 0.0f;
    return weights_[layout_.nodeWeights[node] + target];
}

void PoseEvaluator::evaluate(double seconds, glm::vec4* out) {
    const size_t n = nodes_.size();
    for (size_t i = 0; i < n; ++i) {
        t_[i] = nodes_[i].translation;
        r_[i] = nodes_[i].rotation;
        s_[i] = nodes_[i].scale;
        if (layout_.nodeWeights[i] != kPoseNone)
            std::copy(nodes_[i].weights.begin(), nodes_[i].weights.end(), weights_.begin() + layout_.nodeWeights[i]);
    }
    for (const AnimationChannel& c : channels_) {
        const AnimationSampler& sp = samplers_[c.sampler];
        switch (c.path) {
            case AnimationPath::Translation: t_[c.node] = sampleVec3(sp, seconds); break;
            case AnimationPath::Rotation: r_[c.node] = sampleRotation(sp, seconds); break;
            case AnimationPath::Scale: s_[c.node] = sampleVec3(sp, seconds); break;
            case AnimationPath::Weights:
                if (layout_.nodeWeights[c.node] != kPoseNone) sampleWeights(sp, seconds, &weights_[layout_.nodeWeights[c.node]]);
                break;
        }
    }
    for (uint32_t i : order_) {
        const RigNode& node = nodes_[i];
        const glm::dmat4 local = node.hasMatrix ? node.matrix : trs(t_[i], r_[i], s_[i]);
        global_[i] = node.parent >= 0 ? global_[size_t(node.parent)] * local : local;
    }
    for (size_t d = 0; d < drawNode_.size(); ++d)
        if (layout_.drawMatrix[d] != kPoseNone) store(out, layout_.drawMatrix[d], global_[size_t(drawNode_[d])]);
    for (size_t s = 0; s < skins_.size(); ++s) {
        if (layout_.skinJoints[s] == kPoseNone) continue;
        const ModelSkin& skin = skins_[s];
        for (size_t j = 0; j < skin.joints.size(); ++j)
            store(out, layout_.skinJoints[s] + 4 * uint32_t(j), global_[skin.joints[j]] * glm::dmat4(skin.inverseBind[j]));
    }
    for (uint32_t v = weightsStart_; v < layout_.vec4s; ++v)
        out[v] = glm::vec4(weights_[v * 4], weights_[v * 4 + 1], weights_[v * 4 + 2], weights_[v * 4 + 3]);
}

glm::dvec3 posedPosition(const ModelData& model, const PoseLayout& l, const glm::vec4* pose, uint32_t draw, uint32_t vertex) {
    const ModelDraw& d = model.draws[draw];
    const ModelPrimitive& p = model.primitives[d.primitive];
    const size_t vi = size_t(p.vertexOffset) + vertex;
    const ModelVertex& v = model.vertices[vi];
    glm::vec3 pos(v.position[0], v.position[1], v.position[2]);
    if (l.drawWeights[draw] != kPoseNone) {
        for (uint32_t k = 0; k < p.morphTargets; ++k) {
            const float w = poseFloat(pose, l.drawWeights[draw] + k);
            const float* delta = &model.rig.morphDeltas[(size_t(p.morphBase) + size_t(vertex) * p.morphTargets + k) * 6];
            pos += w * glm::vec3(delta[0], delta[1], delta[2]);
        }
    }
    glm::mat4 m(0.0f);
    if (l.drawJoints[draw] != kPoseNone) {
        const ModelSkinVertex& s = model.rig.skinVertices[vi];
        for (int i = 0; i < 4; ++i)
            if (s.weights[i] != 0.0f) m += s.weights[i] * load(pose, l.drawJoints[draw] + 4 * uint32_t(s.joints[i]));
    } else {
        m = load(pose, l.drawMatrix[draw]);
    }
    return glm::dvec3(m * glm::vec4(pos, 1.0f));
}

void posedBounds(ModelData& model) {
    uint64_t vertices = 0;
    for (const ModelDraw& d : model.draws) vertices += model.primitives[d.primitive].vertexCount;
    constexpr uint64_t kBudget = 8'000'000;
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    std::vector<glm::vec4> pose;
    for (int a = -1; a < int(model.rig.animations.size()); ++a) {
        PoseEvaluator e(model, a);
        pose.assign(e.layout().vec4s, glm::vec4(0.0f));
        const uint64_t perAnimation = kBudget / (model.rig.animations.size() + 1);
        const uint64_t times = !e.moves() ? 1 : std::clamp<uint64_t>(perAnimation / std::max<uint64_t>(vertices, 1), 2, 33);
        for (uint64_t k = 0; k < times; ++k) {
            e.evaluate(times == 1 ? 0.0 : e.duration() * double(k) / double(times - 1), pose.data());
            for (uint32_t d = 0; d < model.draws.size(); ++d) {
                const uint32_t count = model.primitives[model.draws[d].primitive].vertexCount;
                for (uint32_t v = 0; v < count; ++v) {
                    const glm::dvec3 q = posedPosition(model, e.layout(), pose.data(), d, v);
                    lo = glm::min(lo, q);
                    hi = glm::max(hi, q);
                }
            }
        }
    }
    if (lo.x <= hi.x) {
        model.boundsMin = lo;
        model.boundsMax = hi;
    }
}

double animationSeconds(const AnimationPlayback& p, double duration, TimeNs t) {
    const double s = motion::secondsBetween(t, p.origin) * p.speed;
    if (!p.loop || !(duration > 0.0)) return s;
    double w = std::fmod(s, duration);
    if (w < 0.0) w += duration;
    if (w >= duration) w = 0.0;   // -1e-17 + duration rounds to duration
    return w;
}

}  // namespace orbis::models
