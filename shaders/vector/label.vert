#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VectorTypes.h"

// One glyph's quad (six vertices, two triangles) from its instance: window pixels to clip space
// through the frame's viewport. No depth: the Overlay pass draws labels without a depth test.

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };

layout(location = kLabelInputOrigin) in vec2 inOrigin;
layout(location = kLabelInputAxisX) in vec2 inAxisX;
layout(location = kLabelInputAxisY) in vec2 inAxisY;
layout(location = kLabelInputUv) in vec4 inUv;
layout(location = kLabelInputEdges) in vec2 inEdges;
layout(location = kLabelInputColor) in vec4 inColor;
layout(location = kLabelInputHalo) in vec4 inHalo;

layout(location = 0) out vec2 vUv;
layout(location = 1) flat out vec2 vEdges;
layout(location = 2) flat out vec4 vColor;
layout(location = 3) flat out vec4 vHalo;

const vec2 kCorners[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
    vec2 c = kCorners[gl_VertexIndex];
    vec2 pixel = inOrigin + c.x * inAxisX + c.y * inAxisY;
    vUv = mix(inUv.xy, inUv.zw, c);
    vEdges = inEdges;
    vColor = inColor;
    vHalo = inHalo;
    gl_Position = vec4(pixel * 2.0 * frame.invViewportSize - 1.0, 0.0, 1.0);
}
