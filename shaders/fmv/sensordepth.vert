#version 450
#extension GL_GOOGLE_include_directive : require

// The heightfield seen from the sensor: its distance map (metres along the boresight).
layout(location = 0) in vec3 position;   // relative to O

layout(push_constant) uniform Push {
    mat4 sensorClip;   // relative to O -> clip (reversed-Z, infinite far)
    vec4 sensor;       // xyz: relative to O
    vec4 axisX;        // the boresight
} push;

layout(location = 0) out float distance;

void main() {
    gl_Position = push.sensorClip * vec4(position, 1.0);
    distance = dot(position - push.sensor.xyz, push.axisX.xyz);
}
