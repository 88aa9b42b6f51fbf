// The vector layer's labels (layers/vector/LabelRenderer.cpp, shaders/vector/label.*): one
// instance per glyph (LabelGlyph), a quad in screen pixels cut from the signed-distance-field
// atlas (R8, layers/vector/GlyphAtlas.h) at set kLabelSet. Two pipelines from the same shaders
// (kLabelSpecHalo): every glyph's halo first, then every glyph's text, so that no glyph's halo
// covers its neighbour's stroke where their quads overlap. Alpha blended in the Overlay pass
// without a depth test: which labels are hidden was decided on the CPU.
//
// Extruded buildings and polygons at altitude (layers/vector/MeshRenderer.cpp,
// shaders/vector/mesh.*): indexed triangles of VectorMeshVertex, positions relative to their
// chunk's ECEF origin; the origin minus the eye (taken in double on the CPU) is the push
// constant. Lit by the sun; the picked feature is tinted. Opaque, in the Opaque pass.
// Lines and points at altitude (shaders/vector/segment.*, marker.*): one instance per segment
// (VectorSegment: a quad `widthPx` wide on the screen, antialiased) or per point (VectorMarker:
// a disk of `sizePx` with a dark rim), relative to the same chunk origins, depth-tested,
// blended, after the meshes.
#ifndef ORBIS_SHADERS_SHARED_VECTOR_TYPES_H
#define ORBIS_SHADERS_SHARED_VECTOR_TYPES_H

#include "shared/Common.h"

ORBIS_NAMESPACE_BEGIN

ORBIS_CONST(uint, kLabelSet, 1)
ORBIS_CONST(uint, kLabelBindingAtlas, 0)   // sampler2D: the glyph atlas (R8 distance field)

ORBIS_CONST(uint, kLabelSpecHalo, 0)       // bool: this pipeline draws the halos, else the text

// Vertex inputs, one binding at the instance rate (LabelGlyph).
ORBIS_CONST(uint, kLabelInputOrigin, 0)
ORBIS_CONST(uint, kLabelInputAxisX, 1)
ORBIS_CONST(uint, kLabelInputAxisY, 2)
ORBIS_CONST(uint, kLabelInputUv, 3)
ORBIS_CONST(uint, kLabelInputEdges, 4)
ORBIS_CONST(uint, kLabelInputColor, 5)
ORBIS_CONST(uint, kLabelInputHalo, 6)

// One glyph: a parallelogram in window pixels (x right, y down) so that a line's label turns
// with the line.
struct LabelGlyph {
    vec2 origin;   // pixels: the quad's corner at (uvMin.x, uvMin.y)
    vec2 axisX;    // pixels: from origin to the corner at (uvMax.x, uvMin.y)
    vec2 axisY;    // pixels: from origin to the corner at (uvMin.x, uvMax.y)
    vec4 uv;       // the atlas rectangle: uvMin (xy), uvMax (zw)
    vec2 edges;    // distance-field values: the glyph's outline, the halo's outer edge
    uint color;    // the text: sRGB RGBA8 (R in the low byte), read as UNORM
    uint halo;     // the halo: sRGB RGBA8
};

// Vertex inputs of the meshes, one binding at the vertex rate (VectorMeshVertex).
ORBIS_CONST(uint, kMeshInputPosition, 0)
ORBIS_CONST(uint, kMeshInputNormal, 1)
ORBIS_CONST(uint, kMeshInputColor, 2)
ORBIS_CONST(uint, kMeshInputFeature, 3)

struct VectorMeshVertex {
    vec3 position;   // metres, relative to the chunk's origin (world axes)
    uint normal;     // world axes, SNORM8 x, y, z (x in the low byte)
    uint color;      // sRGB RGBA8 (R in the low byte), read as UNORM
    uint feature;    // the feature's id (FeatureMesh.h: meshFeatureId), 1 and up
};

// Vertex inputs of the segments and markers, one binding at the instance rate.
ORBIS_CONST(uint, kSegmentInputA, 0)
ORBIS_CONST(uint, kSegmentInputColor, 1)
ORBIS_CONST(uint, kSegmentInputB, 2)
ORBIS_CONST(uint, kSegmentInputWidth, 3)
ORBIS_CONST(uint, kSegmentInputFeature, 4)
ORBIS_CONST(uint, kSegmentInputStart, 5)
ORBIS_CONST(uint, kSegmentInputDash, 6)
ORBIS_CONST(uint, kMarkerInputPosition, 0)
ORBIS_CONST(uint, kMarkerInputColor, 1)
ORBIS_CONST(uint, kMarkerInputSize, 2)
ORBIS_CONST(uint, kMarkerInputFeature, 3)
ORBIS_CONST(uint, kMarkerInputIcon, 4)
ORBIS_CONST(uint, kMarkerInputAspect, 5)
ORBIS_CONST(uint, kMarkerInputScale, 6)
ORBIS_CONST(uint, kMarkerInputFrom, 7)
ORBIS_CONST(uint, kMarkerInputGlide, 8)

// The 3-D markers' icons (MeshRenderer): one atlas of kMeshIconCells x kMeshIconCells square
// cells of kMeshIconCellPx, icon i (IconCache's index) in cell i, fitted and centred.
ORBIS_CONST(uint, kMeshSet, 1)
ORBIS_CONST(uint, kMeshBindingIcons, 0)   // sampler2D: the icon atlas (sRGB RGBA8)
ORBIS_CONST(uint, kMeshIconCells, 8)
ORBIS_CONST(uint, kMeshIconCellPx, 64)

struct VectorSegment {
    vec3 a;          // metres, relative to the chunk's origin
    uint color;      // sRGB RGBA8, alpha the opacity
    vec3 b;
    float widthPx;
    uint feature;
    float startM;    // the distance along its line at a (m): where its dashes fall
    vec2 dashPx;     // on, off (px); 0: solid
};

struct VectorMarker {
    vec3 position;   // metres, relative to the chunk's origin
    uint color;      // sRGB RGBA8
    float sizePx;    // the disk's diameter, or the icon's height
    uint feature;
    uint icon;       // 0: a disk; else 1 + the icon's cell in the atlas
    float aspect;    // the icon's width over its height
    vec3 scale;      // near, far (m), farScale: the size x 1 nearer than near, x farScale past
                     // far, linear between (far <= near: a constant size); FeatureStyle::iconSizeAt
    vec3 from;       // a moving point (MarkerMotion.h): where it glides from, relative to the origin
    vec2 glide;      // when its glide starts and ends (s on the chunk's clock, glideNow); end <=
                     // start: at `position`
};

// Push constants, per chunk (meshes, segments and markers).
struct VectorMeshPush {
    vec3 originFromEye;   // the chunk's origin minus the eye (m, world axes)
    uint highlight;       // the picked feature's id, 0: none
    float glideNow;       // seconds since the chunk's glideEpoch: where its moving markers are
    float pad0, pad1, pad2;
};

ORBIS_NAMESPACE_END

#ifdef __cplusplus
namespace orbis::shader {
/// Set kLabelSet (layers/vector/LabelRenderer.cpp): one, the atlas.
inline constexpr DescriptorBinding kLabelBindings[] = {
    {kLabelBindingAtlas, DescriptorKind::CombinedImageSampler, 1, kStageFragment},
};
inline constexpr SpecConstant kLabelSpecConstants[] = {{kLabelSpecHalo, SpecType::Bool}};
/// Set kMeshSet (layers/vector/MeshRenderer.cpp): one, the 3-D markers' icon atlas.
inline constexpr DescriptorBinding kMeshBindings[] = {
    {kMeshBindingIcons, DescriptorKind::CombinedImageSampler, 1, kStageFragment},
};
}  // namespace orbis::shader
static_assert(sizeof(orbis::shader::LabelGlyph) == 56, "LabelGlyph layout changed");
static_assert(offsetof(orbis::shader::LabelGlyph, uv) == 24 && offsetof(orbis::shader::LabelGlyph, edges) == 40 &&
                  offsetof(orbis::shader::LabelGlyph, color) == 48 && offsetof(orbis::shader::LabelGlyph, halo) == 52,
              "LabelGlyph offsets changed");
static_assert(sizeof(orbis::shader::VectorMeshVertex) == 24 && offsetof(orbis::shader::VectorMeshVertex, normal) == 12,
              "VectorMeshVertex layout changed");
static_assert(sizeof(orbis::shader::VectorSegment) == 48 && offsetof(orbis::shader::VectorSegment, b) == 16 &&
                  offsetof(orbis::shader::VectorSegment, feature) == 32 && offsetof(orbis::shader::VectorSegment, dashPx) == 40,
              "VectorSegment layout changed");
static_assert(sizeof(orbis::shader::VectorMarker) == 64 && offsetof(orbis::shader::VectorMarker, sizePx) == 16 &&
                  offsetof(orbis::shader::VectorMarker, icon) == 24 && offsetof(orbis::shader::VectorMarker, scale) == 32 &&
                  offsetof(orbis::shader::VectorMarker, from) == 44 && offsetof(orbis::shader::VectorMarker, glide) == 56,
              "VectorMarker layout changed");
static_assert(sizeof(orbis::shader::VectorMeshPush) == 32 && offsetof(orbis::shader::VectorMeshPush, highlight) == 12 &&
                  offsetof(orbis::shader::VectorMeshPush, glideNow) == 16,
              "VectorMeshPush must match std430");
#endif

#endif
