#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VolumeTypes.h"

// Direct volume rendering of a (lon, lat, height) grid in its curved box: one ray per pixel,
// marched relative to the volume's origin (float, small numbers), each sample turned into
// (lon, lat, height) in a numerically stable form, front-to-back compositing with opacity
// corrected for the step, a jittered start, early termination, and an end at the scene depth.

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform FrameBlock { FrameUniforms frame; };
layout(set = 1, binding = 0) uniform VolumeBlock { VolumeUniforms vol; };
layout(set = 1, binding = 1) uniform sampler3D field;
layout(set = 1, binding = 2, std430) readonly buffer AxisBlock { float axisTable[]; };
layout(set = 1, binding = 3) uniform sampler1D transfer;
layout(set = 1, binding = 4) uniform sampler2D sceneDepth;
layout(set = 1, binding = 5, rgba16f) uniform writeonly image2D outImage;

// Coordinate -> texture coordinate along one axis (texel centres at the samples).
float axisCoord(int axis, float x, float first, float last, float n, bool uniformAxis) {
    float f = clamp((x - first) / (last - first), 0.0, 1.0);
    if (uniformAxis) return (f * (n - 1.0) + 0.5) / n;
    float s = f * float(kVolumeAxisTable - 1);
    int t0 = min(int(s), int(kVolumeAxisTable) - 2);
    int base = axis * int(kVolumeAxisTable);
    return mix(axisTable[base + t0], axisTable[base + t0 + 1], s - float(t0));
}

// Ray parameters where the ray enters and leaves a sphere (centre relative to the ray origin).
vec2 sphereHits(vec3 origin, vec3 dir, vec3 centre, float radius) {
    vec3 oc = origin - centre;
    float b = dot(oc, dir);
    float c = dot(oc, oc) - radius * radius;
    float disc = b * b - c;
    if (disc < 0.0) return vec2(1e30, -1e30);
    float s = sqrt(disc);
    return vec2(-b - s, -b + s);
}

float hash(uvec2 p, uint frameIndex) {
    uint h = p.x * 1973u + p.y * 9277u + frameIndex * 26699u;
    h = (h ^ (h >> 13)) * 1274126177u;
    h ^= h >> 16;
    return float(h & 0xffffu) / 65536.0;
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(outImage);
    if (any(greaterThanEqual(px, size))) return;

    vec2 ndc = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 far = frame.clipToWorldDir * vec4(ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w);
    vec3 eye = vol.eyeFromOrigin.xyz;

    // The segment inside the box's bounds, before the scene's surface.
    vec3 inv = 1.0 / dir;
    vec3 ta = (vol.boxMin.xyz - eye) * inv, tb = (vol.boxMax.xyz - eye) * inv;
    vec3 tlo = min(ta, tb), thi = max(ta, tb);
    float tEnter = max(max(tlo.x, tlo.y), max(tlo.z, 0.0));
    float tExit = min(min(thi.x, thi.y), thi.z);
    float lon0 = vol.originAxis.z;
    float c0 = cos(lon0), s0 = sin(lon0);
    vec3 centre = -vec3(vol.originAxis.x * c0, vol.originAxis.x * s0, vol.originAxis.y);
    vec2 outer = sphereHits(eye, dir, centre, vol.radii.y);
    tEnter = max(tEnter, outer.x);
    tExit = min(tExit, outer.y);
    vec2 inner = sphereHits(eye, dir, centre, vol.radii.x);
    if (inner.x > tEnter) tExit = min(tExit, inner.x);
    float depth = texelFetch(sceneDepth, px, 0).r;
    if (depth > 0.0) tExit = min(tExit, vol.boxMin.w / depth / max(dot(dir, vol.forward.xyz), 1e-6));

    vec4 acc = vec4(0.0);
    float stepLength = vol.eyeFromOrigin.w;
    if (tExit > tEnter) {
        float t = tEnter + hash(uvec2(px), uint(vol.dataRange.w)) * stepLength;
        int maxSteps = int(vol.boxMax.w);
        float exaggeration = vol.lonRange.w;
        float a = vol.forward.w, b = vol.radii.z;
        for (int i = 0; i < maxSteps && t < tExit; ++i, t += stepLength) {
            vec3 d = eye + t * dir;   // relative to the origin, ECEF axes
            // Longitude relative to the origin's meridian: no large number is subtracted.
            float xa = vol.originAxis.x + (d.x * c0 + d.y * s0);
            float yb = d.y * c0 - d.x * s0;
            float rho = length(vec2(xa, yb));
            float z = vol.originAxis.y + d.z;
            float lonDeg = degrees(lon0 + atan(yb, xa));
            lonDeg = vol.lonRange.x + mod(lonDeg - vol.lonRange.x, 360.0);
            float phiC = atan(z, rho);
            float latDeg = degrees(atan(z, rho * vol.samples.w));   // geodetic, near the surface
            float cc = cos(phiC), ss = sin(phiC);
            float rEll = a * b / sqrt(b * b * cc * cc + a * a * ss * ss);
            float h = (length(vec2(rho, z)) - rEll) / exaggeration;
            if (lonDeg > vol.lonRange.y || latDeg < vol.latRange.x || latDeg > vol.latRange.y || h < vol.latRange.z ||
                h > vol.latRange.w)
                continue;
            vec3 tc = vec3(axisCoord(0, lonDeg, vol.lonRange.x, vol.lonRange.y, vol.samples.x, vol.axisUniform.x > 0.5),
                           axisCoord(1, latDeg, vol.latRange.x, vol.latRange.y, vol.samples.y, vol.axisUniform.y > 0.5),
                           axisCoord(2, h, vol.latRange.z, vol.latRange.w, vol.samples.z, vol.axisUniform.z > 0.5));
            float value = texture(field, tc).r;
            if (isnan(value)) continue;   // no data: transparent
            float f = clamp((value - vol.dataRange.x) * vol.dataRange.y, 0.0, 1.0);
            vec4 tf = texture(transfer, (f * 255.0 + 0.5) / 256.0);
            float alpha = clamp(tf.a * vol.dataRange.z, 0.0, 1.0);
            alpha = 1.0 - pow(1.0 - min(alpha, 0.9999), stepLength / vol.originAxis.w);
            acc.rgb += (1.0 - acc.a) * alpha * tf.rgb;
            acc.a += (1.0 - acc.a) * alpha;
            if (acc.a >= 0.99) break;
        }
    }
    imageStore(outImage, px, acc);
}
