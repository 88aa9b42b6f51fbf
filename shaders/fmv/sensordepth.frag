#version 450
layout(location = 0) in float distance;
layout(location = 0) out float outDistance;
void main() { outDistance = distance; }
