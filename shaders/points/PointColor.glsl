// A point's colour from its packed attributes (uvec2): x = sRGB r | g << 8 | b << 16 |
// classification << 24; y = intensity (16 bits) | height << 16 (0..65535 over the cloud's
// height range). Needs `pu` (PointUniforms) in scope. Every mode yields sRGB: the compute
// rasteriser stores it in 24 bits of the screen buffer (pointColorPacked) and the resolve
// linearises it (unpackColor); the point list calls pointColor. The mode is a specialisation
// constant: a CPU device runs every side of a branch, so the modes not drawn must not be in the
// shader at all.

layout(constant_id = kPointSpecColorMode) const uint kColorMode = kPointColorRgb;

vec3 srgbToLinear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

// ASPRS standard classes (LAS 1.4 R15, table 17), in sRGB.
vec3 classColor(uint c) {
    switch (c) {
        case 2u: return vec3(0.63, 0.47, 0.30);   // ground
        case 3u: return vec3(0.65, 0.85, 0.40);   // low vegetation
        case 4u: return vec3(0.35, 0.70, 0.25);   // medium vegetation
        case 5u: return vec3(0.13, 0.47, 0.15);   // high vegetation
        case 6u: return vec3(0.85, 0.30, 0.22);   // building
        case 7u: return vec3(0.90, 0.20, 0.90);   // low point (noise)
        case 9u: return vec3(0.20, 0.45, 0.90);   // water
        case 10u: return vec3(0.55, 0.40, 0.55);  // rail
        case 11u: return vec3(0.45, 0.45, 0.50);  // road surface
        case 13u: case 14u: case 16u: return vec3(1.00, 0.85, 0.20);   // wires
        case 15u: return vec3(0.95, 0.60, 0.10);  // transmission tower
        case 17u: return vec3(0.60, 0.60, 0.65);  // bridge deck
        case 18u: return vec3(1.00, 0.00, 0.50);  // high noise
        default: return vec3(0.70, 0.70, 0.70);   // created, unclassified and the rest
    }
}

// Blue - cyan - green - yellow - red over 0..1, in sRGB.
vec3 heightRamp(float f) {
    const vec3 stops[5] = vec3[5](vec3(0.15, 0.25, 0.85), vec3(0.10, 0.75, 0.90), vec3(0.25, 0.80, 0.30),
                                  vec3(0.95, 0.85, 0.20), vec3(0.85, 0.20, 0.15));
    float s = clamp(f, 0.0, 1.0) * 4.0;
    int i = min(int(s), 3);
    return mix(stops[i], stops[i + 1], s - float(i));
}

vec3 pointColorSrgb(uvec2 a) {
    if (kColorMode == kPointColorRgb) return vec3(a.x & 255u, (a.x >> 8) & 255u, (a.x >> 16) & 255u) / 255.0;
    if (kColorMode == kPointColorIntensity) return vec3(clamp(float(a.y & 65535u) * pu.intensityGain, 0.0, 1.0));
    if (kColorMode == kPointColorClassification) return classColor(a.x >> 24);
    if (kColorMode == kPointColorHeight) return heightRamp((float(a.y >> 16) / 65535.0 - pu.heightLow) * pu.heightScale);
    return pu.constantColor.rgb;
}

// Linear RGB.
vec3 pointColor(uvec2 a) { return srgbToLinear(pointColorSrgb(a)); }

// sRGB, 8 bits a channel: r | g << 8 | b << 16.
uint pointColorPacked(uvec2 a) {
    if (kColorMode == kPointColorRgb) return a.x & 0xFFFFFFu;
    uvec3 c = uvec3(round(clamp(pointColorSrgb(a), 0.0, 1.0) * 255.0));
    return c.r | (c.g << 8) | (c.b << 16);
}

// Linear RGB from pointColorPacked's value.
vec3 unpackColor(uint c) { return srgbToLinear(vec3(c & 255u, (c >> 8) & 255u, (c >> 16) & 255u) / 255.0); }
