#pragma once
// glTF poses: sampling animation channels (glTF 2.0, 3.11 and Appendix C), the node hierarchy at
// a time, skin joint matrices and morph weights, written as one block of floats per pose that
// the model vertex shader reads (shaders/models/model_animated.vert). No Vulkan.
//
// Sampling. Keyframe times are clamped at both ends: before the first the first value, after
// the last the last value (for CUBICSPLINE the value, not a tangent). STEP holds a keyframe's
// value until the next; LINEAR interpolates component-wise, rotations by slerp the short way
// round (q and -q are one rotation); CUBICSPLINE is the spec's cubic Hermite spline with the
// tangents scaled by the keyframe interval, rotations normalized after.
//
// A pose block, in vec4 units (PoseLayout): per draw one matrix (its node to model space; for a
// skinned draw the identity is not stored: the skin matrices are in model space already, glTF
// 2.0 3.7.3.3 ignores the mesh node's transform), per skin that a draw uses its joint matrices
// (joint's global transform x inverse bind matrix), per morphing node its weights (packed,
// four to a vec4). One block serves every copy drawn at the same animation time.
//
// Time (AnimationPlayback). The animation time of a scene time t is
//   s = (t - origin) x speed seconds,   looped: s mod duration (in [0, duration)),
//                                       not looped: s (clamped by the keyframes: the first
//                                       pose before the start, the last after the end).
// `duration` is the animation's last keyframe time; a looped animation restarts at 0 (glTF
// times start at 0 in practice; a first keyframe later than 0 holds its value until then).

#include "base/TimeFormat.h"
#include "layers/models/GltfModel.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <vector>

namespace orbis::models {

inline constexpr uint32_t kPoseNone = 0xffffffffu;

/// Values of a translation or scale sampler at `seconds`.
glm::dvec3 sampleVec3(const AnimationSampler& sampler, double seconds);
/// A rotation sampler's unit quaternion at `seconds`.
glm::dquat sampleRotation(const AnimationSampler& sampler, double seconds);
/// A weights sampler's `sampler.components` values at `seconds`.
void sampleWeights(const AnimationSampler& sampler, double seconds, float* out);

/// Where each part of a pose lies in its block (offsets in vec4s unless said otherwise).
struct PoseLayout {
    uint32_t vec4s = 0;                  ///< the block's size
    std::vector<uint32_t> drawMatrix;    ///< per draw: its node's matrix, or kPoseNone (skinned)
    std::vector<uint32_t> drawJoints;    ///< per draw: its skin's first joint matrix, or kPoseNone
    std::vector<uint32_t> drawWeights;   ///< per draw: its node's first weight in floats, or kPoseNone
    std::vector<uint32_t> skinJoints;    ///< per skin: first joint matrix, or kPoseNone when no draw uses it
    std::vector<uint32_t> nodeWeights;   ///< per node: first weight in floats, or kPoseNone
};

/// Evaluates one animation of a model (or its rest pose) at any time. Keeps copies of what it
/// needs (the rig's nodes, skins and the one animation), so the model's vertices may go.
/// Not thread-safe (its scratch arrays are reused): one evaluator per thread.
class PoseEvaluator {
public:
    /// `animation`: an index into model.rig.animations, or -1 for the rest pose.
    PoseEvaluator(const ModelData& model, int animation);

    const PoseLayout& layout() const { return layout_; }
    int animation() const { return animation_; }
    double duration() const { return duration_; }
    /// The first keyframe time of all the animation's samplers: before it (and after
    /// duration()) every pose is the same.
    double start() const { return start_; }
    /// True when poses depend on the time (an animation with channels is played).
    bool moves() const { return !channels_.empty(); }

    /// Writes the pose at `seconds` (animation time) into out[0 .. layout().vec4s). No allocation.
    void evaluate(double seconds, glm::vec4* out);
    /// The nodes' global matrices (model space) and morph weights of the last evaluate().
    const std::vector<glm::dmat4>& globals() const { return global_; }
    float weight(uint32_t node, uint32_t target) const;

private:
    std::vector<RigNode> nodes_;
    std::vector<uint32_t> order_;
    std::vector<ModelSkin> skins_;
    std::vector<AnimationSampler> samplers_;
    std::vector<AnimationChannel> channels_;
    std::vector<int> drawNode_;
    int animation_ = -1;
    double duration_ = 0.0, start_ = 0.0;
    PoseLayout layout_;
    uint32_t weightsStart_ = 0;   ///< the first vec4 of weights in a block
    // Scratch, per node.
    std::vector<glm::dvec3> t_, s_;
    std::vector<glm::dquat> r_;
    std::vector<glm::dmat4> global_;
    std::vector<float> weights_;   ///< at layout_.nodeWeights offsets
};

/// A vertex of a draw in a pose as the vertex shader places it: morphed, then skinned or moved
/// by its node (model space). `vertex` counts from the primitive's first vertex. Needs the
/// model's vertices (before a layer hands them to the GPU).
glm::dvec3 posedPosition(const ModelData& model, const PoseLayout& layout, const glm::vec4* pose, uint32_t draw, uint32_t vertex);

/// Sets model.boundsMin/Max to hold every draw in its rest pose and in every animation at up to
/// 33 times over its duration (fewer for large meshes: at most ~8 million vertex evaluations).
/// Between those times a pose may reach a little further: a bound for culling, not a guarantee.
void posedBounds(ModelData& model);

/// Which animation a layer plays, and how its time follows the scene's.
struct AnimationPlayback {
    int animation = -1;   ///< index into rig.animations; -1: none (rest pose)
    bool loop = true;
    double speed = 1.0;   ///< animation seconds per scene second
    TimeNs origin = 0;    ///< the scene time of the animation's time 0
};

/// The animation time (seconds) at scene time `t`: see the header.
double animationSeconds(const AnimationPlayback& playback, double duration, TimeNs t);

}  // namespace orbis::models
