// orbis-shader-contract: fails the build when a shader and its C++ side disagree. Every
// pipeline below lists its compiled shaders (embedded SPIR-V) and the shared headers' tables its
// C++ side is built from; each descriptor, specialisation constant, workgroup size and vertex
// input the SPIR-V declares is checked against them. With --lint FOLDER it also counts the
// numbers written into GLSL layout qualifiers instead of the headers' names.
//
//   orbis-shader-contract [--lint shaders/] [--self-test]
//
// A new pipeline is one more entry in pipelines(): its shaders, its sets' tables, its
// constants' table, its group size or vertex inputs.
#include "shaders/contract/Contract.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "shared/CompositeTypes.h"
#include "shared/EarthTypes.h"
#include "shared/FmvTypes.h"
#include "shared/FrameUniforms.h"
#include "shared/ModelTypes.h"
#include "shared/PointTypes.h"
#include "shared/PolylineTypes.h"
#include "shared/TerrainTypes.h"
#include "shared/VectorTypes.h"
#include "shared/ViewshedTypes.h"
#include "shared/VolumeTypes.h"
#include "spv/analysis/viewshed.comp.h"
#include "spv/analysis/viewshed_cpu.comp.h"

#include "spv/common/composite.frag.h"
#include "spv/common/fullscreen.vert.h"
#include "spv/common/polyline.frag.h"
#include "spv/common/polyline.vert.h"
#include "spv/common/sky.frag.h"
#include "spv/common/sky.vert.h"
#include "spv/earth/ellipsoid.frag.h"
#include "spv/earth/ellipsoid.vert.h"
#include "spv/fmv/drape.comp.h"
#include "spv/fmv/footprint.comp.h"
#include "spv/fmv/lines.frag.h"
#include "spv/fmv/lines.vert.h"
#include "spv/fmv/sensordepth.frag.h"
#include "spv/fmv/sensordepth.vert.h"
#include "spv/models/model.frag.h"
#include "spv/models/model.vert.h"
#include "spv/models/model_animated.vert.h"
#include "spv/points/pointlist.frag.h"
#include "spv/points/pointlist.vert.h"
#include "spv/points/resolve.frag.h"
#include "spv/points/splat.comp.h"
#include "spv/terrain/terrain.frag.h"
#include "spv/terrain/terrain.vert.h"
#include "spv/vector/label.frag.h"
#include "spv/vector/label.vert.h"
#include "spv/vector/marker.frag.h"
#include "spv/vector/marker.vert.h"
#include "spv/vector/mesh.frag.h"
#include "spv/vector/mesh.vert.h"
#include "spv/vector/segment.frag.h"
#include "spv/vector/segment.vert.h"
#include "spv/volume/raycast.comp.h"

namespace orbis::contract {
namespace {

using namespace orbis::shader;

#define ORBIS_SHADER(folder, name, stage) ShaderModule{#folder "/" #name "." #stage, kSpv_##folder##_##name##_##stage}
#define ORBIS_SET(set, table) SetTable{set, "shader::" #table, table}
#define ORBIS_SPECS(table) "shader::" #table, table

std::vector<PipelineContract> pipelines() {
    const SetTable frame = ORBIS_SET(kFrameSet, kFrameBindings);
    const std::vector<uint32_t> polylineInputs = {kPolylineInputPosition, kPolylineInputColor};
    const std::vector<uint32_t> modelInputs = {kModelInputPosition, kModelInputNormal, kModelInputUv, kModelInputColor};
    std::vector<uint32_t> animatedInputs = modelInputs;
    animatedInputs.insert(animatedInputs.end(), {kModelInputJoints, kModelInputWeights});
    return {
        // Shared pieces: the sky (terrain and earth layers) and polylines (models, annotations).
        {"sky", {ORBIS_SHADER(common, sky, vert), ORBIS_SHADER(common, sky, frag)}, {frame}},
        {"polylines", {ORBIS_SHADER(common, polyline, vert), ORBIS_SHADER(common, polyline, frag)}, {frame},
         ORBIS_SPECS(kPolylineSpecConstants), {}, polylineInputs},
        {"earth", {ORBIS_SHADER(earth, ellipsoid, vert), ORBIS_SHADER(earth, ellipsoid, frag)}, {frame}, nullptr, {}, {},
         {kEarthInputPosition, kEarthInputNormal, kEarthInputLonLat}},
        {"terrain", {ORBIS_SHADER(terrain, terrain, vert), ORBIS_SHADER(terrain, terrain, frag)},
         {frame, ORBIS_SET(kTerrainSet, kTerrainBindings)}, ORBIS_SPECS(kTerrainSpecConstants), {},
         {kTerrainInputPosition, kTerrainInputNormal, kTerrainInputUv, kTerrainInputCellMetres}},
        // Points (layers/points/PointsLayer.cpp).
        {"points splat", {ORBIS_SHADER(points, splat, comp)}, {frame, ORBIS_SET(kPointSet, kPointBindings)},
         ORBIS_SPECS(kPointSpecConstants), {kPointGroupSize, 1, 1}},
        {"points resolve", {ORBIS_SHADER(common, fullscreen, vert), ORBIS_SHADER(points, resolve, frag)},
         {frame, ORBIS_SET(kPointSet, kPointBindings)}, ORBIS_SPECS(kPointSpecConstants)},
        {"points list", {ORBIS_SHADER(points, pointlist, vert), ORBIS_SHADER(points, pointlist, frag)},
         {frame, ORBIS_SET(kPointSet, kPointBindings)}, ORBIS_SPECS(kPointSpecConstants)},
        // Analysis (layers/analysis/ViewshedGpu.cpp).
        {"viewshed", {ORBIS_SHADER(analysis, viewshed, comp)}, {ORBIS_SET(kViewshedSet, kViewshedBindings)}, nullptr, {},
         {kViewshedGroupSize, 1, 1}},
        {"viewshed (CPU device)", {ORBIS_SHADER(analysis, viewshed_cpu, comp)}, {ORBIS_SET(kViewshedSet, kViewshedBindings)}, nullptr, {},
         {kViewshedCpuGroupSize, 1, 1}},
        // Full-motion video (layers/fmv/FmvLayer.cpp).
        {"fmv drape", {ORBIS_SHADER(fmv, drape, comp)}, {frame, ORBIS_SET(kFmvSet, kFmvBindings)}, nullptr, {},
         {kFmvGroupSize, kFmvGroupSize, 1}},
        {"fmv footprint", {ORBIS_SHADER(fmv, footprint, comp)}, {frame, ORBIS_SET(kFmvSet, kFmvBindings)}, nullptr, {},
         {kFmvFootprintGroup, 1, 1}},
        {"fmv distance map", {ORBIS_SHADER(fmv, sensordepth, vert), ORBIS_SHADER(fmv, sensordepth, frag)},
         {frame, ORBIS_SET(kFmvSet, kFmvBindings)}, nullptr, {}, {}, {kFmvInputPosition}},
        {"fmv composite", {ORBIS_SHADER(common, fullscreen, vert), ORBIS_SHADER(common, composite, frag)},
         {frame, ORBIS_SET(kFmvSet, kFmvBindings)}},
        {"fmv lines", {ORBIS_SHADER(fmv, lines, vert), ORBIS_SHADER(fmv, lines, frag)}, {frame, ORBIS_SET(kFmvSet, kFmvBindings)},
         ORBIS_SPECS(kFmvSpecConstants)},
        // Models (layers/models/ModelLayer.cpp): static and animated vertex shaders, one fragment shader.
        {"model static", {ORBIS_SHADER(models, model, vert), ORBIS_SHADER(models, model, frag)},
         {frame, ORBIS_SET(kModelSet, kModelStaticBindings), ORBIS_SET(kModelMaterialSet, kModelMaterialBindings)}, nullptr, {}, {},
         modelInputs},
        {"model animated", {ORBIS_SHADER(models, model_animated, vert), ORBIS_SHADER(models, model, frag)},
         {frame, ORBIS_SET(kModelSet, kModelAnimatedBindings), ORBIS_SET(kModelMaterialSet, kModelMaterialBindings)}, nullptr, {},
         {}, animatedInputs},
        // Volumes (layers/volume/VolumeLayer.cpp).
        {"volume ray cast", {ORBIS_SHADER(volume, raycast, comp)}, {frame, ORBIS_SET(kVolumeSet, kVolumeBindings)},
         ORBIS_SPECS(kVolumeSpecConstants), {kVolumeGroupSize, kVolumeGroupSize, 1}},
        {"volume composite", {ORBIS_SHADER(common, fullscreen, vert), ORBIS_SHADER(common, composite, frag)},
         {frame, ORBIS_SET(kVolumeSet, kVolumeBindings)}},
        // Vector meshes (layers/vector/MeshRenderer.cpp): one layout, the icon atlas for the markers.
        {"vector meshes", {ORBIS_SHADER(vector, mesh, vert), ORBIS_SHADER(vector, mesh, frag)}, {frame}, nullptr, {}, {},
         {kMeshInputPosition, kMeshInputNormal, kMeshInputColor, kMeshInputFeature}},
        {"vector segments", {ORBIS_SHADER(vector, segment, vert), ORBIS_SHADER(vector, segment, frag)}, {frame}, nullptr, {}, {},
         {kSegmentInputA, kSegmentInputColor, kSegmentInputB, kSegmentInputWidth, kSegmentInputFeature, kSegmentInputStart,
          kSegmentInputDash}},
        {"vector markers", {ORBIS_SHADER(vector, marker, vert), ORBIS_SHADER(vector, marker, frag)},
         {frame, ORBIS_SET(kMeshSet, kMeshBindings)}, nullptr, {}, {},
         {kMarkerInputPosition, kMarkerInputColor, kMarkerInputSize, kMarkerInputFeature, kMarkerInputIcon, kMarkerInputAspect,
          kMarkerInputScale, kMarkerInputFrom, kMarkerInputGlide}},
        // Vector labels (layers/vector/LabelRenderer.cpp): halos and text, one pipeline each.
        {"vector labels", {ORBIS_SHADER(vector, label, vert), ORBIS_SHADER(vector, label, frag)},
         {frame, ORBIS_SET(kLabelSet, kLabelBindings)}, ORBIS_SPECS(kLabelSpecConstants), {},
         {kLabelInputOrigin, kLabelInputAxisX, kLabelInputAxisY, kLabelInputUv, kLabelInputEdges, kLabelInputColor,
          kLabelInputHalo}},
    };
}

/// The terrain's set as it was when heights lay in four pages (an array of samplers): no table
/// declares an array now, and the checker must still see an array's size.
constexpr shader::DescriptorBinding kTerrainBindingsPaged[] = {
    {shader::kTerrainBindingDraws, shader::DescriptorKind::StorageBuffer, 1, shader::kStageVertex | shader::kStageFragment},
    {shader::kTerrainBindingElevation, shader::DescriptorKind::CombinedImageSampler, 4, shader::kStageVertex},
};

/// The checker must see a mismatch of each kind: the points' splat shader against the FMV's and
/// the static models' tables (kinds, stages, constants, group size, a missing binding), the
/// terrain's vertex shader against the points' table, the earth's vertex inputs and a paged
/// table (a set without a table, a location, an array size).
bool selfTest() {
    const PipelineContract wrong[] = {
        {"self-test splat", {ORBIS_SHADER(points, splat, comp)}, {ORBIS_SET(kPointSet, kFmvBindings)},
         ORBIS_SPECS(kFmvSpecConstants), {kFmvGroupSize, kFmvGroupSize, 1}},
        {"self-test splat", {ORBIS_SHADER(points, splat, comp)}, {ORBIS_SET(kPointSet, kModelStaticBindings)},
         ORBIS_SPECS(kPointSpecConstants), {kPointGroupSize, 1, 1}},
        {"self-test terrain", {ORBIS_SHADER(terrain, terrain, vert)}, {ORBIS_SET(kTerrainSet, kPointBindings)}, nullptr, {}, {},
         {kEarthInputPosition, kEarthInputNormal, kEarthInputLonLat}},
        {"self-test terrain", {ORBIS_SHADER(terrain, terrain, vert)}, {ORBIS_SET(kTerrainSet, kTerrainBindingsPaged)}, nullptr,
         {}, {}, {kTerrainInputPosition, kTerrainInputNormal, kTerrainInputUv, kTerrainInputCellMetres}},
    };
    const char* expected[] = {"is a storage buffer in the shader but a combined image sampler in shader::kFmvBindings",
                              "is read by the compute stage, which shader::kFmvBindings (set 1) does not give it",
                              "is int in the shader but bool in shader::kFmvSpecConstants",
                              "is not one of shader::kFmvSpecConstants",
                              "the workgroup size is (256, 1, 1) in the shader but (8, 8, 1)",
                              "has no binding 2",
                              "has no table for set 0",
                              "is an array of 1 in the shader but 4 in shader::kTerrainBindingsPaged",
                              "vertex input location 3 ('inCellMetres') is not one the C++ attributes name"};
    std::string all;
    for (const PipelineContract& p : wrong)
        for (const std::string& e : checkPipeline(p)) all += e + "\n";
    bool ok = true;
    for (const char* e : expected)
        if (all.find(e) == std::string::npos) {
            std::fprintf(stderr, "shader contract self-test: no error saying \"%s\" in:\n%s", e, all.c_str());
            ok = false;
        }
    if (ok) std::printf("shader contract: the self-test's mismatches were all found\n");
    return ok;
}

int lint(const char* folder) {
    int failing = 0;
    for (const LayoutLiteral& l : findLayoutLiterals(folder)) {
        ++failing;
        std::fprintf(stderr, "%s:%d: %s: a number in a layout qualifier; name it in shaders/shared/*Types.h\n", l.file.c_str(),
                     l.line, l.text.c_str());
    }
    std::printf("shader contract: %d numeric literals in GLSL layout qualifiers\n", failing);
    return failing;
}

}  // namespace
}  // namespace orbis::contract

int main(int argc, char** argv) {
    using namespace orbis::contract;
    int errors = 0;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--lint") == 0 && i + 1 < argc) {
            errors += lint(argv[++i]) > 0 ? 1 : 0;
        } else if (std::strcmp(argv[i], "--self-test") == 0) {
            errors += selfTest() ? 0 : 1;
        } else {
            std::fprintf(stderr, "usage: %s [--lint SHADER_FOLDER] [--self-test]\n", argv[0]);
            return 2;
        }
    }
    const std::vector<PipelineContract> all = pipelines();
    for (const PipelineContract& p : all)
        for (const std::string& e : checkPipeline(p)) {
            std::fprintf(stderr, "shader contract: %s\n", e.c_str());
            ++errors;
        }
    if (errors == 0) std::printf("shader contract: %zu pipelines agree with their shared headers\n", all.size());
    return errors == 0 ? 0 : 1;
}
