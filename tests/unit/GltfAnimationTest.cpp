// glTF animation, skins and morph targets (layers/models/GltfAnimation.h): channel sampling
// against analytic values, the real AnimatedMorphCube's weights, a two-joint skin whose answer
// is known, the scene-time rule, and bad rigs that must give clear errors.
#include "layers/models/GltfAnimation.h"
#include "tests/unit/GltfTestFiles.h"
#include "tests/support/ProcessTempDir.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace orbis;
using namespace orbis::models;
using orbis::test::GltfBuilder;

namespace {

const fs::path kMorphCube = fs::path(ORBIS_SHARED_DATA_DIR) / "models" / "AnimatedMorphCube" / "AnimatedMorphCube.gltf";

// Sampled values are computed in double from float keyframes: 1e-6 covers the keyframes'
// float rounding at these magnitudes (<= 20).
constexpr double kTol = 1e-6;

AnimationSampler sampler(AnimationInterpolation i, std::vector<float> times, std::vector<float> values, uint32_t components) {
    AnimationSampler s;
    s.interpolation = i;
    s.times = std::move(times);
    s.values = std::move(values);
    s.components = components;
    return s;
}

fs::path tempFile(const std::string& name, const std::string& text) {
    const fs::path dir = test::processTempDir("orbis-gltf-anim");
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
}

double angleDeg(const glm::dquat& a, const glm::dquat& b) {
    return glm::degrees(2.0 * std::acos(std::min(1.0, std::abs(glm::dot(a, b)))));
}

/// A triangle on node 0, with `extra` merged into the document.
GltfBuilder triangleModel() {
    GltfBuilder b;
    const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
    b.doc["meshes"] = nlohmann::json::parse(R"([{"primitives": [{"attributes": {"POSITION": 0}}]}])");
    b.doc["nodes"] = nlohmann::json::parse(R"([{"mesh": 0}])");
    b.doc["scenes"] = nlohmann::json::parse(R"([{"nodes": [0]}])");
    b.doc["scene"] = 0;
    EXPECT_EQ(pos, 0);
    return b;
}

}  // namespace

TEST(GltfAnimation, LinearTranslationAtMidKeyframe) {
    const auto s = sampler(AnimationInterpolation::Linear, {0, 2, 4}, {0, 0, 0, 10, 4, -2, 10, 4, 18}, 3);
    const glm::dvec3 mid = sampleVec3(s, 1.0);
    EXPECT_NEAR(mid.x, 5.0, kTol);
    EXPECT_NEAR(mid.y, 2.0, kTol);
    EXPECT_NEAR(mid.z, -1.0, kTol);
    EXPECT_NEAR(sampleVec3(s, 3.5).z, -2.0 + 0.75 * 20.0, kTol);
    EXPECT_NEAR(sampleVec3(s, 2.0).x, 10.0, kTol);   // exactly on a keyframe
}

TEST(GltfAnimation, RotationSlerpsAtHalfTime) {
    // 0 -> 170 degrees about Y: slerp turns through exactly 85 at half time (a normalized lerp
    // would not: it is off by degrees this far apart); the same the short way round when the
    // second quaternion is given negated.
    const glm::dquat end = glm::angleAxis(glm::radians(170.0), glm::dvec3(0, 1, 0));
    for (double sign : {1.0, -1.0}) {
        const glm::dquat e = end * sign;
        const auto s = sampler(AnimationInterpolation::Linear, {0, 1},
                               {0, 0, 0, 1, float(e.x), float(e.y), float(e.z), float(e.w)}, 4);
        const glm::dquat q = sampleRotation(s, 0.5);
        EXPECT_NEAR(glm::length(q), 1.0, 1e-12);
        EXPECT_NEAR(angleDeg(q, glm::angleAxis(glm::radians(85.0), glm::dvec3(0, 1, 0))), 0.0, 1e-4) << "sign " << sign;
        EXPECT_NEAR(angleDeg(sampleRotation(s, 0.25), glm::angleAxis(glm::radians(42.5), glm::dvec3(0, 1, 0))), 0.0, 1e-4);
    }
}

TEST(GltfAnimation, StepHoldsUntilTheNextKeyframe) {
    const auto s = sampler(AnimationInterpolation::Step, {0, 1, 2}, {0, 0, 0, 10, 0, 0, 20, 0, 0}, 3);
    EXPECT_EQ(sampleVec3(s, 0.999).x, 0.0);
    EXPECT_EQ(sampleVec3(s, 1.0).x, 10.0);
    EXPECT_EQ(sampleVec3(s, 1.5).x, 10.0);
    EXPECT_EQ(sampleVec3(s, 2.5).x, 20.0);
    float w[2] = {};
    const auto ws = sampler(AnimationInterpolation::Step, {0, 1}, {0.25f, 0.5f, 1, 0}, 2);
    sampleWeights(ws, 0.7, w);
    EXPECT_EQ(w[0], 0.25f);
    EXPECT_EQ(w[1], 0.5f);
}

TEST(GltfAnimation, CubicSplineWithTangentsIsTheCubic) {
    // p(t) = t^3 - t on [0, 2] from its values and derivatives at the ends: Hermite
    // interpolation reproduces a cubic exactly. Keys: (in-tangent, value, out-tangent).
    auto p = [](double t) { return t * t * t - t; };
    auto dp = [](double t) { return 3 * t * t - 1; };
    const auto s = sampler(AnimationInterpolation::CubicSpline, {0, 2},
                           {9, 9, 9, float(p(0)), 0, 0, float(dp(0)), 0, 0,
                            float(dp(2)), 0, 0, float(p(2)), 0, 0, 9, 9, 9}, 3);
    for (double t : {0.0, 0.3, 0.5, 1.0, 1.3, 1.9, 2.0}) EXPECT_NEAR(sampleVec3(s, t).x, p(t), 1e-5) << t;
    // Weights use the same spline, scalar by scalar.
    const auto ws = sampler(AnimationInterpolation::CubicSpline, {0, 2}, {0, float(p(0)), float(dp(0)), float(dp(2)), float(p(2)), 0}, 1);
    float w = 0.0f;
    sampleWeights(ws, 1.3, &w);
    EXPECT_NEAR(w, p(1.3), 1e-5);
}

TEST(GltfAnimation, ClampsBeforeAndAfterTheKeyframes) {
    const auto lin = sampler(AnimationInterpolation::Linear, {1, 3}, {1, 2, 3, 7, 8, 9}, 3);
    EXPECT_EQ(sampleVec3(lin, -5.0), glm::dvec3(1, 2, 3));
    EXPECT_EQ(sampleVec3(lin, 1.0), glm::dvec3(1, 2, 3));
    EXPECT_EQ(sampleVec3(lin, 3.0), glm::dvec3(7, 8, 9));
    EXPECT_EQ(sampleVec3(lin, 1e9), glm::dvec3(7, 8, 9));
    EXPECT_EQ(sampleVec3(lin, std::nan("")), glm::dvec3(1, 2, 3));
    // CUBICSPLINE clamps to the value, never a tangent.
    const auto cub = sampler(AnimationInterpolation::CubicSpline, {1, 3}, {-9, -9, -9, 1, 2, 3, 5, 5, 5, 6, 6, 6, 7, 8, 9, 99, 99, 99}, 3);
    EXPECT_EQ(sampleVec3(cub, 0.0), glm::dvec3(1, 2, 3));
    EXPECT_EQ(sampleVec3(cub, 4.0), glm::dvec3(7, 8, 9));
    // One keyframe: its value at every time.
    const auto one = sampler(AnimationInterpolation::Linear, {0.5f}, {4, 5, 6}, 3);
    EXPECT_EQ(sampleVec3(one, 0.0), glm::dvec3(4, 5, 6));
    EXPECT_EQ(sampleVec3(one, 9.0), glm::dvec3(4, 5, 6));
}

TEST(GltfAnimation, SceneTimeLoopsOverTheDuration) {
    AnimationPlayback p;
    p.animation = 0;
    p.origin = fromSeconds(100.0);
    EXPECT_NEAR(animationSeconds(p, 4.0, fromSeconds(101.5)), 1.5, 1e-9);
    EXPECT_NEAR(animationSeconds(p, 4.0, fromSeconds(109.5)), 1.5, 1e-9);   // two loops later
    EXPECT_NEAR(animationSeconds(p, 4.0, fromSeconds(99.0)), 3.0, 1e-9);    // before the origin: looped backwards
    EXPECT_EQ(animationSeconds(p, 4.0, fromSeconds(104.0)), 0.0);
    p.speed = 2.0;
    EXPECT_NEAR(animationSeconds(p, 4.0, fromSeconds(101.5)), 3.0, 1e-9);
    p.loop = false;
    EXPECT_NEAR(animationSeconds(p, 4.0, fromSeconds(109.5)), 19.0, 1e-9);  // the sampler clamps it
    EXPECT_NEAR(animationSeconds(p, 4.0, fromSeconds(99.0)), -2.0, 1e-9);
}

TEST(GltfAnimation, StaticModelsKeepTheFastPath) {
    const fs::path f = tempFile("static.gltf", triangleModel().text());
    auto m = loadGltf(f.string());
    ASSERT_TRUE(m) << m.message();
    EXPECT_FALSE(m->animated());
    EXPECT_TRUE(m->rig.nodes.empty());
    EXPECT_TRUE(m->warnings.empty());
}

TEST(GltfAnimation, TranslationChannelMovesTheNode) {
    GltfBuilder b = triangleModel();
    const int times = b.floats({0, 2}, "SCALAR");
    const int values = b.floats({0, 0, 0, 10, 0, 0}, "VEC3");
    nlohmann::json anim = nlohmann::json::parse(R"({"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]})");
    anim["samplers"] = nlohmann::json::array({{{"input", times}, {"output", values}}});
    b.doc["animations"] = nlohmann::json::array({anim});
    auto m = loadGltf(tempFile("move.gltf", b.text()).string());
    ASSERT_TRUE(m) << m.message();
    ASSERT_TRUE(m->animated());
    ASSERT_EQ(m->rig.animations.size(), 1u);
    EXPECT_EQ(m->rig.animations[0].duration, 2.0);
    PoseEvaluator e(*m, 0);
    std::vector<glm::vec4> pose(e.layout().vec4s);
    e.evaluate(1.0, pose.data());
    const glm::dvec3 p = posedPosition(*m, e.layout(), pose.data(), 0, 1);   // vertex (1, 0, 0)
    EXPECT_NEAR(p.x, 6.0, 1e-5);
    // The bounds hold the whole sweep.
    EXPECT_NEAR(m->boundsMin.x, 0.0, 1e-5);
    EXPECT_NEAR(m->boundsMax.x, 11.0, 1e-5);
}

TEST(GltfAnimation, TwoJointSkinBendsAtTheElbow) {
    auto m = loadGltf(tempFile("arm.gltf", orbis::test::twoJointArmGltf()).string());
    ASSERT_TRUE(m) << m.message();
    ASSERT_TRUE(m->animated());
    EXPECT_TRUE(m->warnings.empty()) << m->warnings.front();
    ASSERT_EQ(m->draws.size(), 1u);
    EXPECT_EQ(m->draws[0].skin, 0);
    PoseEvaluator e(*m, 0);
    EXPECT_EQ(e.layout().drawMatrix[0], kPoseNone) << "a skinned draw ignores its node's transform";
    std::vector<glm::vec4> pose(e.layout().vec4s);
    // Float pose data: positions of a metre-sized arm to 1e-6 m.
    const double tol = 1e-6;
    for (double t : {0.0, 0.5, 1.0, 2.0}) {
        e.evaluate(t, pose.data());
        const double a = glm::radians(90.0 * std::min(t, 1.0));
        // The tip (0, 2, 0) turns about the elbow (0, 1, 0) by a about +Z: (-sin a, 1 + cos a).
        const glm::dvec3 tip = posedPosition(*m, e.layout(), pose.data(), 0, 1);
        EXPECT_NEAR(tip.x, -std::sin(a), tol) << t;
        EXPECT_NEAR(tip.y, 1.0 + std::cos(a), tol) << t;
        EXPECT_NEAR(tip.z, 0.0, tol);
        // Vertices on the root joint stay; the node's own translation (100, 0, 0) is ignored.
        const glm::dvec3 side = posedPosition(*m, e.layout(), pose.data(), 0, 2);
        EXPECT_NEAR(glm::length(side - glm::dvec3(1, 0, 0)), 0.0, tol) << t;
        // Half and half: the mean of the still and the turned tip (linear blend skinning).
        const glm::dvec3 half = posedPosition(*m, e.layout(), pose.data(), 0, 3);
        EXPECT_NEAR(half.x, 0.5 * -std::sin(a), tol) << t;
        EXPECT_NEAR(half.y, 0.5 * (2.0 + 1.0 + std::cos(a)), tol) << t;
    }
}

TEST(GltfAnimation, MorphCubeWeightsAtItsKeyframes) {
    if (!fs::exists(kMorphCube)) GTEST_SKIP() << "shared data absent: " << kMorphCube;
    auto m = loadGltf(kMorphCube.string());
    ASSERT_TRUE(m) << m.message();
    ASSERT_TRUE(m->animated());
    for (const std::string& w : m->warnings) {
        EXPECT_EQ(w.find("morph"), std::string::npos) << w;
        EXPECT_EQ(w.find("animation"), std::string::npos) << w;
    }
    ASSERT_EQ(m->rig.animations.size(), 1u);
    EXPECT_EQ(m->rig.animations[0].name, "Square");
    ASSERT_EQ(m->primitives.size(), 1u);
    EXPECT_EQ(m->primitives[0].morphTargets, 2u);
    // The keyframes straight from the .bin (accessor 10: 127 times at byte 2760; accessor 11:
    // 254 weights at byte 3268, two per keyframe).
    std::ifstream in(kMorphCube.parent_path() / "AnimatedMorphCube.bin", std::ios::binary);
    std::string bin((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GE(bin.size(), 3268u + 254u * 4u);
    std::vector<float> times(127), weights(254);
    std::memcpy(times.data(), bin.data() + 2760, 127 * 4);
    std::memcpy(weights.data(), bin.data() + 3268, 254 * 4);
    EXPECT_NEAR(m->rig.animations[0].duration, times.back(), 1e-6);
    PoseEvaluator e(*m, 0);
    std::vector<glm::vec4> pose(e.layout().vec4s);
    for (size_t k = 0; k < times.size(); k += 9) {
        e.evaluate(times[k], pose.data());
        EXPECT_NEAR(e.weight(0, 0), weights[k * 2], 1e-6) << "keyframe " << k;
        EXPECT_NEAR(e.weight(0, 1), weights[k * 2 + 1], 1e-6) << "keyframe " << k;
    }
    // Halfway between keyframes 40 and 41: the mean (LINEAR).
    e.evaluate(0.5 * (double(times[40]) + double(times[41])), pose.data());
    EXPECT_NEAR(e.weight(0, 0), 0.5 * (weights[80] + weights[82]), 1e-6);
    // The "thin" target at full weight moves the top vertices (those with a POSITION delta).
    const float maxThin = *std::max_element(weights.begin(), weights.end());
    EXPECT_GT(maxThin, 0.99f);
}

TEST(GltfAnimation, BadRigsGiveClearErrors) {
    auto expectError = [](const std::string& name, GltfBuilder& b, const std::string& needle) {
        auto m = loadGltf(tempFile(name, b.text()).string());
        ASSERT_FALSE(m) << name;
        EXPECT_NE(m.message().find(name), std::string::npos) << m.message();
        EXPECT_NE(m.message().find(needle), std::string::npos) << name << ": " << m.message();
    };
    auto animated = [](const std::vector<float>& times, const std::vector<float>& values, int node, const char* path,
                       const char* interpolation = "LINEAR") {
        GltfBuilder b = triangleModel();
        const int t = b.floats(times, "SCALAR");
        const int v = b.floats(values, std::string(path) == "rotation" ? "VEC4" : std::string(path) == "weights" ? "SCALAR" : "VEC3");
        nlohmann::json anim = {{"name", "Run"}};
        anim["samplers"] = nlohmann::json::array({{{"input", t}, {"output", v}, {"interpolation", interpolation}}});
        anim["channels"] = nlohmann::json::array({{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}});
        b.doc["animations"] = nlohmann::json::array({anim});
        return b;
    };
    auto missingNode = animated({0, 1}, {0, 0, 0, 1, 1, 1}, 7, "translation");
    expectError("missing-node.gltf", missingNode, "targets node 7, which does not exist");
    auto counts = animated({0, 1, 2}, {0, 0, 0, 1, 1, 1}, 0, "translation");
    expectError("counts.gltf", counts, "2 output values for 3 keyframes");
    auto cubicCounts = animated({0, 1}, {0, 0, 0, 1, 1, 1}, 0, "translation", "CUBICSPLINE");
    expectError("cubic-counts.gltf", cubicCounts, "in-tangent, value, out-tangent");
    auto unsorted = animated({0, 2, 1}, {0, 0, 0, 1, 1, 1, 2, 2, 2}, 0, "scale");
    expectError("unsorted.gltf", unsorted, "times must increase strictly");
    auto noTargets = animated({0, 1}, {0, 1}, 0, "weights");
    expectError("no-targets.gltf", noTargets, "has no morph targets");
    auto interp = animated({0, 1}, {0, 0, 0, 1, 1, 1}, 0, "translation", "SMOOTH");
    expectError("interp.gltf", interp, "\"SMOOTH\"");

    GltfBuilder noJoints = triangleModel();
    noJoints.doc["skins"] = nlohmann::json::parse(R"([{"joints": []}])");
    expectError("no-joints.gltf", noJoints, "skin 0: has no joints");
    GltfBuilder badJoint = triangleModel();
    badJoint.doc["skins"] = nlohmann::json::parse(R"([{"joints": [0, 5]}])");
    expectError("bad-joint.gltf", badJoint, "joint node 5 does not exist");
    GltfBuilder cycle = triangleModel();
    cycle.doc["nodes"] = nlohmann::json::parse(R"([{"mesh": 0, "children": [1]}, {"children": [0]}])");
    cycle.doc["skins"] = nlohmann::json::parse(R"([{"joints": [0]}])");
    expectError("cycle.gltf", cycle, "cycle");
    GltfBuilder twoParents = triangleModel();
    twoParents.doc["nodes"] = nlohmann::json::parse(R"([{"mesh": 0, "children": [2]}, {"children": [2]}, {}])");
    twoParents.doc["skins"] = nlohmann::json::parse(R"([{"joints": [0]}])");
    expectError("two-parents.gltf", twoParents, "two parents");
    // A vertex on a joint the skin does not have.
    const std::string arm = orbis::test::twoJointArmGltf({0});
    auto m = loadGltf(tempFile("few-joints.gltf", arm).string());
    ASSERT_FALSE(m);
    EXPECT_NE(m.message().find("few-joints.gltf"), std::string::npos) << m.message();
    EXPECT_NE(m.message().find("has vertices on joint 1"), std::string::npos) << m.message();
}
