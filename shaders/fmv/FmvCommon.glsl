// The FMV shaders' shared pieces. Needs `fu` (FmvUniforms) in scope.

// Image coordinates (u right, v down, both -1..1 across the video) of a point relative to O,
// and its distance along the boresight (<= 0: behind the sensor).
vec3 sensorImage(vec3 q) {
    vec3 d = q - fu.sensor;
    float x = dot(d, fu.boresight);
    return vec3(dot(d, fu.imageRight) / (x * fu.tanHalfFovX), dot(d, fu.imageDown) / (x * fu.tanHalfFovY), x);
}

// The ray from the sensor through image point (u, v), in world axes (not normalised).
vec3 sensorRay(vec2 uv) { return fu.boresight + uv.x * fu.tanHalfFovX * fu.imageRight + uv.y * fu.tanHalfFovY * fu.imageDown; }
