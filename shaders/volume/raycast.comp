#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/VolumeTypes.h"

// Ray casting of a (lon, lat, height) grid in its curved box: one ray per pixel, marched
// relative to the volume's origin (float, small numbers), each sample turned into (lon, lat,
// height) in a numerically stable form. Direct volume rendering composites front to back with
// opacity corrected for the step; isosurfaces are found by a sign change between samples, then
// refined by secant/bisection steps, lit with Phong shading and a normal from central
// differences. A jittered start, early termination, and an end at the scene depth.

layout(local_size_x = 8, local_size_y = 8) in;

// What the scene's modes use is compiled in; the rest is left out.
layout(constant_id = 0) const bool kDvr = true;
layout(constant_id = 1) const int kIsoCount = 0;   // isosurfaces (0 .. kVolumeMaxIso)

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

// Shared per ray.
vec3 gEye, gDir;
float gC0, gS0;

// The field at ray parameter t; false outside the box or where there is no data.
bool sampleAt(float t, out float value) {
    vec3 d = gEye + t * gDir;   // relative to the origin, ECEF axes
    // Longitude relative to the origin's meridian: no large number is subtracted.
    float xa = vol.originAxis.x + (d.x * gC0 + d.y * gS0);
    float yb = d.y * gC0 - d.x * gS0;
    float rho = length(vec2(xa, yb));
    float z = vol.originAxis.y + d.z;
    float lonDeg = degrees(vol.originAxis.z + atan(yb, xa));
    lonDeg = vol.lonRange.x + mod(lonDeg - vol.lonRange.x, 360.0);
    float latDeg = degrees(atan(z, rho * vol.samples.w));   // geodetic, near the surface
    // Radius of the ellipsoid along the point's direction, without trigonometry:
    // r = a b |p| / sqrt(b^2 rho^2 + a^2 z^2).
    float a = vol.forward.w, b = vol.radii.z;
    float r = length(vec2(rho, z));
    float rEll = a * b * r / length(vec2(b * rho, a * z));
    float h = (r - rEll) / vol.lonRange.w;
    value = 0.0;
    if (lonDeg > vol.lonRange.y || latDeg < vol.latRange.x || latDeg > vol.latRange.y || h < vol.latRange.z ||
        h > vol.latRange.w)
        return false;
    vec3 tc = vec3(axisCoord(0, lonDeg, vol.lonRange.x, vol.lonRange.y, vol.samples.x, vol.axisUniform.x > 0.5),
                   axisCoord(1, latDeg, vol.latRange.x, vol.latRange.y, vol.samples.y, vol.axisUniform.y > 0.5),
                   axisCoord(2, h, vol.latRange.z, vol.latRange.w, vol.samples.z, vol.axisUniform.z > 0.5));
    value = texture(field, tc).r;
    return !isnan(value);
}

vec4 transferAt(float value) {
    float f = clamp((value - vol.dataRange.x) * vol.dataRange.y, 0.0, 1.0);
    return texture(transfer, (f * 255.0 + 0.5) / 256.0);
}

float isovalue(int i) { return vol.isovalues[i / 4][i % 4]; }

// Where the field crosses `c` between ta (value va) and tb (value vb): regula falsi, with a
// bisection step whenever the secant lands badly or a sample has no data.
float refineCrossing(float ta, float va, float tb, float vb, float c) {
    for (int k = 0; k < 8; ++k) {
        float denom = vb - va;
        float tm = abs(denom) > 1e-20 ? ta + (c - va) * (tb - ta) / denom : 0.5 * (ta + tb);
        if (!(tm > ta && tm < tb) || k % 3 == 2) tm = 0.5 * (ta + tb);   // keep the bracket shrinking
        float vm;
        if (!sampleAt(tm, vm)) return tm;
        if ((va - c) * (vm - c) <= 0.0) { tb = tm; vb = vm; }
        else { ta = tm; va = vm; }
    }
    float denom = vb - va;
    return abs(denom) > 1e-20 ? ta + (c - va) * (tb - ta) / denom : 0.5 * (ta + tb);
}

// Unit gradient direction of the field at t (world axes), by central differences over `e`
// metres (one-sided at the box's faces); zero gradients (constant fields) fall back to facing
// the eye.
vec3 normalAt(float t, float e) {
    vec3 g = vec3(0.0);
    float v0;
    bool ok0 = sampleAt(t, v0);
    for (int axis = 0; axis < 3; ++axis) {
        vec3 off = vec3(0.0);
        off[axis] = e;
        // Sample along the ray's frame by moving the eye: the same position function is used.
        vec3 saveEye = gEye;
        float vp, vm;
        gEye = saveEye + off;
        bool okP = sampleAt(t, vp);
        gEye = saveEye - off;
        bool okM = sampleAt(t, vm);
        gEye = saveEye;
        // Central where both neighbours have data; one-sided at the box's faces and next to
        // no-data cells.
        if (okP && okM) g[axis] = (vp - vm) / (2.0 * e);
        else if (okP && ok0) g[axis] = (vp - v0) / e;
        else if (okM && ok0) g[axis] = (v0 - vm) / e;
    }
    float len = length(g);
    return len > 1e-30 ? -g / len : -gDir;   // pointing toward lower values
}

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(outImage);
    if (any(greaterThanEqual(px, size))) return;

    vec2 ndc = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 far = frame.clipToWorldDir * vec4(ndc, 1.0, 1.0);
    gDir = normalize(far.xyz / far.w);
    gEye = vol.eyeFromOrigin.xyz;
    gC0 = cos(vol.originAxis.z);
    gS0 = sin(vol.originAxis.z);

    // The segment inside the box's bounds, before the scene's surface.
    vec3 inv = 1.0 / gDir;
    vec3 ta = (vol.boxMin.xyz - gEye) * inv, tb = (vol.boxMax.xyz - gEye) * inv;
    vec3 tlo = min(ta, tb), thi = max(ta, tb);
    float tEnter = max(max(tlo.x, tlo.y), max(tlo.z, 0.0));
    float tExit = min(min(thi.x, thi.y), thi.z);
    vec3 centre = -vec3(vol.originAxis.x * gC0, vol.originAxis.x * gS0, vol.originAxis.y);
    vec2 outer = sphereHits(gEye, gDir, centre, vol.radii.y);
    tEnter = max(tEnter, outer.x);
    tExit = min(tExit, outer.y);
    vec2 inner = sphereHits(gEye, gDir, centre, vol.radii.x);
    if (inner.x > tEnter) tExit = min(tExit, inner.x);
    float depth = texelFetch(sceneDepth, px, 0).r;
    if (depth > 0.0) tExit = min(tExit, vol.boxMin.w / depth / max(dot(gDir, vol.forward.xyz), 1e-6));

    vec4 acc = vec4(0.0);
    float stepLength = vol.eyeFromOrigin.w;
    if (tExit > tEnter) {
        float t = tEnter + hash(uvec2(px), uint(vol.dataRange.w)) * stepLength;
        int maxSteps = int(vol.boxMax.w);
        bool sunLight = frame.sunDirection.w > 0.5;
        float prevT = t, prevV = 0.0;
        bool prevOk = false;
        for (int i = 0; i < maxSteps && t < tExit; ++i, t += stepLength) {
            float value;
            bool ok = sampleAt(t, value);
            if (kIsoCount > 0 && ok && prevOk) {
                // The nearest crossing in this step over all isovalues.
                float tHit = 1e30;
                int hit = -1;
                for (int k = 0; k < kIsoCount; ++k) {
                    float c = isovalue(k);
                    if ((prevV - c) * (value - c) < 0.0 || (value == c && prevV != c)) {
                        float th = refineCrossing(prevT, prevV, t, value, c);
                        if (th < tHit) { tHit = th; hit = k; }
                    }
                }
                if (hit >= 0) {
                    vec3 n = normalAt(tHit, max(0.25 * stepLength, 1.0));
                    if (dot(n, gDir) > 0.0) n = -n;   // the side facing the eye
                    vec3 l = sunLight ? frame.sunDirection.xyz : -gDir;
                    vec3 hv = normalize(l - gDir);
                    vec3 base = transferAt(isovalue(hit)).rgb;
                    vec3 lit = base * (0.25 + 0.75 * max(dot(n, l), 0.0)) + 0.25 * pow(max(dot(n, hv), 0.0), 32.0);
                    float alpha = vol.radii.w;
                    acc.rgb += (1.0 - acc.a) * alpha * lit;
                    acc.a += (1.0 - acc.a) * alpha;
                    if (acc.a >= 0.99) break;
                }
            }
            if (kDvr && ok) {
                vec4 tf = transferAt(value);
                float alpha = clamp(tf.a * vol.dataRange.z, 0.0, 1.0);
                alpha = 1.0 - pow(1.0 - min(alpha, 0.9999), stepLength / vol.originAxis.w);
                acc.rgb += (1.0 - acc.a) * alpha * tf.rgb;
                acc.a += (1.0 - acc.a) * alpha;
                if (acc.a >= 0.99) break;
            }
            prevT = t;
            prevV = value;
            prevOk = ok;
        }
    }
    imageStore(outImage, px, acc);
}
