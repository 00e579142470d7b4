// One colour, shaded from screen-space derivatives when u_lit is 1 (spheres).
in vec3 v_view_position;
uniform vec3 u_colour;
uniform int u_lit;
out vec4 o_colour;

void main() {
    vec3 colour = u_colour;
    if (u_lit == 1) {
        vec3 n = normalize(cross(dFdx(v_view_position), dFdy(v_view_position)));
        if (dot(n, -v_view_position) < 0.0) n = -n;
        float diffuse = max(dot(n, normalize(vec3(0.4, 0.6, 1.0))), 0.0);
        colour = u_colour * (0.45 + 0.55 * diffuse);
    }
    o_colour = vec4(colour, 1.0);
}
