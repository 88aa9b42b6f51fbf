#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FmvTypes.h"
layout(set = kFmvSet, binding = kFmvBindingUniforms) uniform FmvBlock { FmvUniforms fu; };
layout(location = 0) out vec4 outColor;
void main() { outColor = vec4(fu.outlineColor, 1.0); }
