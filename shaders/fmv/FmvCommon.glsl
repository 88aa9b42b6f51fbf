// The FMV shaders' shared pieces. Needs `fu` (FmvUniforms) in scope.

// Image coordinates (u right, v down, both -1..1 across the video) of a point relative to O,
// and its distance along the boresight (<= 0: behind the sensor).
vec3 sensorImage(vec3 q) {
    vec3 d = q - fu.sensor.xyz;
    float x = dot(d, fu.axisX.xyz);
    return vec3(dot(d, fu.axisY.xyz) / (x * fu.axisX.w), dot(d, fu.axisZ.xyz) / (x * fu.axisY.w), x);
}

// The ray from the sensor through image point (u, v), in world axes (not normalised).
vec3 sensorRay(vec2 uv) { return fu.axisX.xyz + uv.x * fu.axisX.w * fu.axisY.xyz + uv.y * fu.axisY.w * fu.axisZ.xyz; }
