#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/FmvTypes.h"

// The heightfield seen from the sensor: its distance map (metres along the boresight).
layout(location = kFmvInputPosition) in vec3 position;   // relative to O

layout(push_constant) uniform PushBlock { FmvDistancePush push; };

layout(location = 0) out float distance;

void main() {
    gl_Position = push.sensorClip * vec4(position, 1.0);
    distance = dot(position - push.sensor, push.boresight);
}
