#version 460
// One triangle that covers the target; no inputs, no outputs but the position.
void main() {
    const int corner = gl_VertexIndex % 3;
    gl_Position = vec4(vec2((corner << 1) & 2, corner & 2) * 2.0 - 1.0, 0.0, 1.0);
}
