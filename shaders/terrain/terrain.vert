#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/TerrainTypes.h"

// A tile's grid vertex: its place on the ellipsoid relative to the tile centre (float, small
// numbers only), raised along the geodetic normal by the height sampled from the elevation
// tile (the tile's own, or an ancestor's through scale/bias while it loads).

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kTerrainSet, binding = kTerrainBindingDraws, std430) readonly buffer DrawBlock { TileDraw draws[]; };
layout(set = kTerrainSet, binding = kTerrainBindingElevation) uniform sampler2DArray elevation;   // a layer per slot
layout(push_constant) uniform PushBlock { TerrainPush pc; };

layout(location = kTerrainInputPosition) in vec3 inPosition;
layout(location = kTerrainInputNormal) in vec4 inNormal;     // xyz: geodetic up; w: 1 on skirt vertices
layout(location = kTerrainInputUv) in vec2 inUv;
layout(location = kTerrainInputCellMetres) in vec2 inCellMetres;

layout(location = 0) out vec3 vNormal;      // terrain normal, world axes
layout(location = 1) out vec2 vUv;
layout(location = 2) out vec3 vFromEye;
layout(location = 3) flat out int vDraw;

// Height (x) and its gradient per sample step east (y) and south (z), bilinear between the four
// samples around `uv`, in float arithmetic: the sampler's linear filter keeps only 8 bits of
// sub-texel position, which at 1 m from the ground of a tile drawn from a coarse ancestor would
// make heights and normals jump as the camera moves by a millimetre. The gradients are stored
// per sample (central differences, computed on the CPU), so the interpolated normal is
// continuous across the data's cells.
vec3 heightAt(TileDraw d, vec2 uv) {
    int slot = d.elevationSlot;
    if (slot < 0) return vec3(0.0);
    int n = d.elevationGridSize;
    // Corner-aligned samples: sample i sits at t = i / (n - 1).
    vec2 t = clamp(uv * d.elevationScaleBias.xy + d.elevationScaleBias.zw, 0.0, 1.0);
    vec2 s = t * float(n - 1);
    vec2 base = min(floor(s), vec2(n - 2));
    vec2 f = s - base;
    ivec2 b = ivec2(base);
    vec3 h00 = texelFetch(elevation, ivec3(b, slot), 0).rgb;
    vec3 h10 = texelFetch(elevation, ivec3(b + ivec2(1, 0), slot), 0).rgb;
    vec3 h01 = texelFetch(elevation, ivec3(b + ivec2(0, 1), slot), 0).rgb;
    vec3 h11 = texelFetch(elevation, ivec3(b + ivec2(1, 1), slot), 0).rgb;
    return mix(mix(h00, h10, f.x), mix(h01, h11, f.x), f.y);
}

void main() {
    TileDraw d = draws[gl_InstanceIndex];
    vDraw = gl_InstanceIndex;
    vec3 up = normalize(inNormal.xyz);
    float exaggeration = pc.verticalExaggeration;
    vec3 hg = heightAt(d, inUv) * exaggeration;
    float h = hg.x;

    // Slope from the data's own grid: one sample step of the elevation tile (possibly an
    // ancestor) spans (1 / scale) cells of this tile's grid.
    float dhdx = hg.y * d.elevationScaleBias.x / max(inCellMetres.x, 1e-3);
    float dhdy = -hg.z * d.elevationScaleBias.y / max(inCellMetres.y, 1e-3);
    vec3 east = vec3(-up.y, up.x, 0.0);
    float el = length(east);
    east = el > 1e-6 ? east / el : vec3(1.0, 0.0, 0.0);   // at a pole any east will do
    vec3 north = cross(up, east);
    vNormal = normalize(up - dhdx * east - dhdy * north);

    float skirt = inNormal.w > 0.5 ? d.skirtDepth : 0.0;
    vec3 p = inPosition + up * (h - skirt);
    vUv = inUv;
    vFromEye = d.originFromEye + p;
    gl_Position = d.modelViewProj * vec4(p, 1.0);
}
