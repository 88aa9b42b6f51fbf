#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_ARB_gpu_shader_int64 : require
#include "shared/PointTypes.h"

// The screen buffer of the compute rasterisation (depth and sRGB colour) into colour and depth (depth-tested against
// the opaque scene by the pipeline), with eye-dome lighting: a pixel darkens by how much nearer
// its neighbours are, in log depth (log z - log z_n = log d_n - log d with reversed-Z depth
// d = near / z), so edges and steps in the cloud read as shapes.

// Eye-dome lighting on or off (a specialisation constant, like the colour mode: a CPU device
// would otherwise pay for the neighbours' reads on every pixel even with EDL off).
layout(constant_id = kPointSpecEdl) const bool kEdl = false;

layout(set = kPointSet, binding = kPointBindingUniforms) uniform PointBlock { PointUniforms pu; };
layout(set = kPointSet, binding = kPointBindingScreen, std430) readonly buffer Screen { uint64_t screen[]; };

layout(location = 0) out vec4 outColor;

#include "points/PointColor.glsl"

uint64_t texel(ivec2 p) {
    ivec2 size = ivec2(pu.screenSize);
    p = clamp(p, ivec2(0), size - 1);
    return screen[p.y * size.x + p.x];
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uint64_t v = texel(px);
    if (v == 0ul) discard;
    float depth = uintBitsToFloat(uint(v >> 32));
    vec3 c = unpackColor(uint(v & 0xffffffffUL));
    if (kEdl) {
        const vec2 dirs[8] = vec2[8](vec2(1, 0), vec2(0.7071, 0.7071), vec2(0, 1), vec2(-0.7071, 0.7071),
                                     vec2(-1, 0), vec2(-0.7071, -0.7071), vec2(0, -1), vec2(0.7071, -0.7071));
        float logD = log2(depth), response = 0.0;
        for (int i = 0; i < 8; ++i) {
            uint64_t n = texel(px + ivec2(round(dirs[i] * pu.edlRadiusPx)));
            // Empty neighbours (the background) count as far away: silhouettes get an outline.
            float logN = n == 0ul ? logD - 4.0 : log2(uintBitsToFloat(uint(n >> 32)));
            response += max(0.0, logN - logD);
        }
        c *= exp(-pu.edlStrength * 300.0 * response / 8.0);
    }
    outColor = vec4(c, 1.0) * pu.opacity;   // premultiplied; 1 unless the cloud is translucent
    gl_FragDepth = depth;
}
