#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FrameUniforms.h"
#include "shared/ModelTypes.h"

// Base colour (factor x texture x vertex colour), alpha test for MASK materials, and a simple
// lighting: the sun (or a headlight) as a diffuse light with a sky ambient term; both faces are
// lit (double-sided materials and mirrored nodes show their back faces).

layout(set = kFrameSet, binding = kFrameBinding) uniform FrameBlock { FrameUniforms frame; };
layout(set = kModelMaterialSet, binding = kModelBindingBaseColor) uniform sampler2D baseColorTexture;
layout(push_constant) uniform PushBlock { ModelPush pc; };

layout(location = 0) in vec3 vNormal;
layout(location = 1) in vec2 vUv;
layout(location = 2) in vec4 vColor;
layout(location = 3) in vec3 vFromEye;

layout(location = 0) out vec4 outColor;

void main() {
    vec4 base = pc.baseColor * vColor;
    if (pc.textured != 0u) base *= texture(baseColorTexture, vUv);
    if (pc.alphaCutoff >= 0.0 && base.a < pc.alphaCutoff) discard;

    vec3 color = base.rgb;
    if (pc.unlit == 0u) {
        vec3 n = normalize(vNormal);
        vec3 toEye = normalize(-vFromEye);
        if (dot(n, toEye) < 0.0) n = -n;   // the back face of a double-sided surface
        bool sun = pc.sunLighting != 0u;
        vec3 toLight = sun ? frame.sunDirection : toEye;
        float diffuse = max(dot(n, toLight), 0.0);
        // A constant sky ambient keeps the faces turned away from the light readable.
        float ambient = sun ? 0.22 : 0.3;
        color *= ambient + (1.0 - ambient) * diffuse;
    }
    // Premultiplied for the BLEND pipeline; opaque materials write alpha 1.
    outColor = vec4(color * base.a, base.a);
}
