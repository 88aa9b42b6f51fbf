#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/EarthTypes.h"

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(push_constant) uniform PushBlock { EarthPush pc; };

layout(location = 0) in vec3 vNormal;
layout(location = 1) in vec2 vLonLat;
layout(location = 2) in vec3 vFromEye;

layout(location = 0) out vec4 outColor;

// Anti-aliased lines every `spacing` degrees, `halfWidth` pixels wide.
// `weight` fades each family (meridians, parallels) separately.
float gridLines(vec2 lonLat, float spacing, float halfWidth, vec2 weight) {
    vec2 cells = lonLat / spacing;
    vec2 dist = abs(fract(cells - 0.5) - 0.5);          // to the nearest line, in cells
    vec2 width = max(fwidth(cells), vec2(1e-6)) * halfWidth;
    vec2 line = (1.0 - clamp(dist / width, 0.0, 1.0)) * weight;
    return max(line.x, line.y);
}

void main() {
    vec3 n = normalize(vNormal);
    vec3 toEye = normalize(-vFromEye);
    bool sun = pc.sunLighting != 0u;
    vec3 toLight = sun ? frame.sunDirection : toEye;

    float ndl = dot(n, toLight);
    float day = smoothstep(-0.10, 0.15, ndl);           // soft terminator (twilight)
    float diffuse = max(ndl, 0.0);
    vec3 base = pc.baseColor;
    vec3 color = base * (0.03 + 0.97 * diffuse);

    // Sun glint on the ocean-coloured surface.
    vec3 h = normalize(toLight + toEye);
    color += vec3(0.25) * pow(max(dot(n, h), 0.0), 80.0) * day;

    // Atmosphere at grazing angles on the lit side.
    float rim = pow(1.0 - max(dot(n, toEye), 0.0), 3.0);
    color = mix(color, vec3(0.30, 0.55, 1.00) * (0.15 + 0.85 * day), rim * 0.45 * day);

    // Lon/lat arrive as interpolated floats whose spacing (ulp) is |value| * 2^-23 degrees:
    // 5e-6 deg (0.5 m) at 45 deg. A line drawn where a pixel spans only a few ulps across it
    // would be quantisation noise that crawls as the camera moves, so each family of lines
    // fades in only once a pixel spans hundreds of ulps across it (a meridian is resolved by
    // longitude, a parallel by latitude).
    vec2 ulp = max(abs(vLonLat), vec2(1.0)) * 1.2e-7;
    vec2 footprint = fwidth(vLonLat);
    vec2 resolvable = smoothstep(100.0 * ulp, 400.0 * ulp, footprint);
    if (pc.drawLines != 0u && max(resolvable.x, resolvable.y) > 0.0) {
        float lines = gridLines(vLonLat, pc.graticuleDeg, pc.lineHalfWidthPx, resolvable);
        // Equator and prime meridian stand out.
        vec2 zero = abs(vLonLat) / max(footprint, vec2(1e-6));
        vec2 axis = (1.0 - clamp(zero / 1.25, 0.0, 1.0)) * resolvable;
        float axes = max(axis.x, axis.y);
        vec3 lineColor = mix(vec3(0.55, 0.65, 0.75), vec3(0.95, 0.80, 0.35), axes);
        float strength = max(lines * 0.55, axes * 0.85) * (0.25 + 0.75 * day);
        color = mix(color, lineColor, strength);
    }
    outColor = vec4(color, 1.0);
}
