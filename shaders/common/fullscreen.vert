#version 450
// One triangle that covers the screen (no vertex buffer: three vertices from gl_VertexIndex).
void main() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
}
