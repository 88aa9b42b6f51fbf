#version 450
// The ray-cast image (premultiplied linear colour and alpha) over the scene.
layout(set = 1, binding = 6) uniform sampler2D castImage;
layout(location = 0) out vec4 outColor;

void main() { outColor = texelFetch(castImage, ivec2(gl_FragCoord.xy), 0); }
