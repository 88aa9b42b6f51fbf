#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FmvTypes.h"

// The footprint: rays from the sensor through the image's border (kFmvEdgeRays an edge, from
// corner 1, upper left, clockwise) and its centre, marched over the heightfield in steps of
// fu.marchStep, then refined by bisection. Heights above the ellipsoid are taken on the sphere
// that osculates it at O (centimetres off over tens of kilometres). A ray that leaves the
// heightfield without meeting it ends on the sphere at the terrain's mean height, and a ray
// that misses that too (the sensor looking above the horizon) ends at the horizon in its
// azimuth: always a finite point.

layout(local_size_x = kFmvFootprintGroup) in;

layout(set = kFmvSet, binding = kFmvBindingUniforms) uniform FmvBlock { FmvUniforms fu; };
layout(set = kFmvSet, binding = kFmvBindingHeightfield) uniform sampler2D heightfield;
layout(set = kFmvSet, binding = kFmvBindingFootprint, std430) writeonly buffer Footprint { vec4 points[]; };

#include "fmv/FmvCommon.glsl"

vec3 sphereCentre() { return -fu.sphereRadius * fu.up; }

// Height above the terrain of a point relative to O (beyond the heightfield: above the
// terrain's mean height).
float aboveTerrain(vec3 q) {
    float halfSize = fu.halfSize;
    vec2 en = vec2(dot(q, fu.east), dot(q, fu.north));
    float ground = 0.5 * (fu.lowestHeight + fu.highestHeight);
    if (all(lessThanEqual(abs(en), vec2(halfSize)))) {
        float n = fu.heightfieldSamples;
        vec2 tc = (en / halfSize * 0.5 + 0.5) * (n - 1.0) / n + 0.5 / n;
        tc.y = 1.0 - tc.y;   // row 0 is north
        ground = textureLod(heightfield, tc, 0.0).r;
    }
    return length(q - sphereCentre()) - fu.sphereRadius - ground;
}

// Where the ray meets the sphere of radius R + h (nearest, ahead), or -1.
float hitSphere(vec3 o, vec3 d, float h) {
    vec3 oc = o - sphereCentre();
    float r = fu.sphereRadius + h;
    float b = dot(oc, d), c = dot(oc, oc) - r * r;
    float disc = b * b - c;
    if (disc < 0.0) return -1.0;
    float t = -b - sqrt(disc);
    return t > 0.0 ? t : -1.0;
}

vec3 horizon(vec3 o, vec3 d, float h) {
    vec3 up = normalize(o - sphereCentre());
    float r = fu.sphereRadius + h;
    float above = max(length(o - sphereCentre()) - r, 0.0);
    vec3 horiz = d - dot(d, up) * up;
    horiz = length(horiz) > 1e-6 ? normalize(horiz) : fu.north;
    float dip = acos(clamp(r / (r + above), -1.0, 1.0));
    float dist = sqrt(above * (2.0 * r + above));
    return o + dist * (cos(dip) * horiz - sin(dip) * up);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= kFmvFootprintRays) return;
    vec2 uv = vec2(0.0);
    if (i < 4u * kFmvEdgeRays) {
        float f = float(i % kFmvEdgeRays) / float(kFmvEdgeRays) * 2.0 - 1.0;
        uint edge = i / kFmvEdgeRays;
        uv = edge == 0u ? vec2(f, -1.0) : edge == 1u ? vec2(1.0, f) : edge == 2u ? vec2(-f, 1.0) : vec2(-1.0, -f);
    }
    vec3 o = fu.sensor;
    vec3 d = normalize(sensorRay(uv));
    // March from where the ray enters the terrain's height range.
    float tStart = hitSphere(o, d, fu.highestHeight);
    bool insideTop = length(o - sphereCentre()) - fu.sphereRadius <= fu.highestHeight;
    if (insideTop) tStart = 0.0;
    float tEnd = hitSphere(o, d, fu.lowestHeight);
    vec4 result = vec4(0.0);
    bool found = false;
    if (tStart >= 0.0) {
        if (tEnd < 0.0) tEnd = tStart + 4.0 * fu.halfSize;
        float step = fu.marchStep;
        int steps = int(min(ceil((tEnd - tStart) / step), 8192.0));
        float t0 = tStart;
        for (int k = 1; k <= steps && !found; ++k) {
            float t1 = min(tStart + float(k) * step, tEnd);
            if (aboveTerrain(o + t1 * d) <= 0.0) {   // crossed: bisection
                float a = t0, b = t1;
                for (int it = 0; it < 24; ++it) {
                    float m = 0.5 * (a + b);
                    if (aboveTerrain(o + m * d) > 0.0) a = m; else b = m;
                }
                result = vec4(o + b * d, 1.0);
                found = true;
            }
            t0 = t1;
        }
        if (!found && aboveTerrain(o + tStart * d) <= 0.0) {   // starts in the ground
            result = vec4(o + tStart * d, 1.0);
            found = true;
        }
    }
    if (!found) {
        float mean = 0.5 * (fu.lowestHeight + fu.highestHeight);
        float t = hitSphere(o, d, mean);
        result = t > 0.0 ? vec4(o + t * d, 1.0) : vec4(horizon(o, d, mean), 0.0);
    }
    points[i] = result;
}
