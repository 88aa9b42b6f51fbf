#version 450
// The draped video (premultiplied linear colour and alpha) over the scene.
layout(set = 1, binding = 6) uniform sampler2D decal;
layout(location = 0) out vec4 outColor;

void main() { outColor = texelFetch(decal, ivec2(gl_FragCoord.xy), 0); }
