// The curve (a line strip) and the time spheres: plain geometry from a buffer.
layout(location = 0) in vec3 a_position;
uniform mat4 u_model;
uniform mat4 u_view;
uniform mat4 u_projection;
out vec3 v_view_position;

void main() {
    vec4 view = u_view * u_model * vec4(a_position, 1.0);
    v_view_position = view.xyz;
    gl_Position = u_projection * view;
}
