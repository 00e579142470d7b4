// The deformed mesh drawn straight from the vertex texture (no read-back): the
// index buffer holds vertex indices, and gl_VertexID picks the texel.
uniform sampler2D u_positions;  // xyz = position, w = s
uniform int u_width;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_view_position;
out float v_s;

void main() {
    vec4 xs = texelFetch(u_positions, ivec2(gl_VertexID % u_width, gl_VertexID / u_width), 0);
    vec4 view = u_view * vec4(xs.xyz, 1.0);
    v_view_position = view.xyz;
    v_s = xs.w;
    gl_Position = u_projection * view;
}
