#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/CompositeTypes.h"

// A layer's image (premultiplied linear colour and alpha) over the scene, a texel a pixel.
layout(set = kCompositeSet, binding = kCompositeBindingImage) uniform sampler2D image;
layout(location = 0) out vec4 outColor;

void main() { outColor = texelFetch(image, ivec2(gl_FragCoord.xy), 0); }
