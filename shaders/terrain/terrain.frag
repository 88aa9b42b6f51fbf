#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/TerrainTypes.h"

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kTerrainSet, binding = kTerrainBindingDraws, std430) readonly buffer DrawBlock { TileDraw draws[]; };
layout(set = kTerrainSet, binding = kTerrainBindingImagery) uniform sampler2DArray imagery;   // a layer per slot
layout(push_constant) uniform PushBlock { TerrainPush pc; };

// Imagery layers this pipeline blends (the scene's count): unused layers cost nothing.
layout(constant_id = kTerrainSpecImageryLayers) const int kImageryLayers = int(kTerrainMaxImagery);
// Layers from this one on are drapes (vector features painted into tiles): thin lines that an
// isotropic mip level (from the footprint's long axis) would blur away at grazing angles. They
// are sampled one level finer than that where the footprint is elongated (up to 2:1 anisotropy
// taken by aliasing along the long axis). Several taps along that axis (filtering by hand, the
// level being explicit) cost 3-4x the whole frame on lavapipe: measured, not kept.
layout(constant_id = kTerrainSpecFirstDrape) const int kFirstDrape = int(kTerrainMaxImagery);

layout(location = 0) in vec3 vNormal;
layout(location = 1) in vec2 vUv;
layout(location = 2) in vec3 vFromEye;
layout(location = 3) flat in int vDraw;

layout(location = 0) out vec4 outColor;

void main() {
    TileDraw d = draws[vDraw];
    vec3 color = pc.baseColor;
    // The level of detail is computed here, in uniform control flow, and passed in: implicit
    // derivatives inside the loop's branches are not reliable, and textureLod is much cheaper
    // than textureGrad on CPU rasterisers.
    // Texels of an own-level imagery tile per pixel, squared; an ancestor's scale shrinks it.
    vec2 uvDx = dFdx(vUv) * pc.imageSizePx, uvDy = dFdy(vUv) * pc.imageSizePx;
    float fx2 = dot(uvDx, uvDx), fy2 = dot(uvDy, uvDy);
    float footprint2 = max(fx2, fy2);
    // Drapes: the footprint with its long axis shortened up to twice.
    float drapeFootprint2 = max(footprint2 * 0.25, min(fx2, fy2));
    // Imagery layers in scene order, each over the ones before it; night lights apart.
    vec3 lights = vec3(0.0);
    for (int i = 0; i < kImageryLayers; ++i) {
        int slot = d.imagerySlot[i];
        if (slot < 0) continue;
        vec2 t = vUv * d.imageryScaleBias[i].xy + d.imageryScaleBias[i].zw;
        float scale = d.imageryScaleBias[i].x;
        float lod = 0.5 * log2(max((i < kFirstDrape ? footprint2 : drapeFootprint2) * scale * scale, 1e-12));
        // Drapes read one mip level, not a blend of two: on lavapipe a trilinear drape made the
        // default scene's frame 4-9 % longer (1920x1080: 134-138 against 126-132 ms).
        if (i >= kFirstDrape) lod = floor(lod + 0.5);
        vec4 c = textureLod(imagery, vec3(t, float(slot)), lod);
        if ((pc.nightLayers & (1u << uint(i))) != 0u) {
            lights += c.rgb * (c.a * pc.imageryOpacity[i]);
            continue;
        }
        color = mix(color, c.rgb, c.a * pc.imageryOpacity[i]);
    }

    vec3 n = normalize(vNormal);
    vec3 toEye = normalize(-vFromEye);
    bool sun = pc.sunLighting != 0u;
    vec3 toLight = sun ? frame.sunDirection : toEye;
    float ndl = dot(n, toLight);
    float lit = sun ? 0.06 + 0.94 * max(ndl, 0.0) : 0.25 + 0.75 * max(ndl, 0.0);
    color *= lit;
    // The night side's lights, fading in through twilight (the sun 6 degrees above the
    // horizon to 6 below, at the ground's own horizon).
    if (sun) color += lights * (1.0 - smoothstep(-0.1, 0.1, dot(normalize(vFromEye + frame.eyeEcef), frame.sunDirection)));

    // Aerial perspective: the optical depth grows with the length of the path through the air
    // (short near the ground, up to one air mass times the slant when seen from space).
    float dist = length(vFromEye);
    float cosZenith = max(dot(n, toEye), 0.03);
    float opticalDepth = 0.12 * min(dist / 8000.0, 1.0 / cosZenith);
    float haze = 1.0 - exp(-opticalDepth);
    float day = sun ? smoothstep(-0.1, 0.2, dot(normalize(vFromEye + frame.eyeEcef), frame.sunDirection)) : 1.0;
    color = mix(color, vec3(0.32, 0.52, 0.85) * 0.55 * day, haze);

    if (pc.tileBorders != 0u) {   // debug: tile borders
        vec2 e = min(vUv, 1.0 - vUv) / max(fwidth(vUv), vec2(1e-6));
        if (min(e.x, e.y) < 1.0) color = vec3(1.0, 0.9, 0.1);
    }
    outColor = vec4(color, 1.0);
}
