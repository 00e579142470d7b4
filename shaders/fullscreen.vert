// One triangle that covers the viewport: every GPGPU pass draws it once, so the
// fragment shader runs once per texel, i.e. once per vertex (sec. 5).
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
