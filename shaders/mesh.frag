// s colour-coded from blue (0, inner region) to red (1, outer region), the two
// separation lines (s leaving 0 and reaching 1) highlighted, flat-shaded from
// screen-space derivatives. u_wire = 1 draws the edges in one dark colour
// instead, u_wire = 2 folded triangles in magenta.
in vec3 v_view_position;
in float v_s;
uniform int u_wire;
out vec4 o_colour;

// 1 on the level line s = level, fading out over about 1.5 pixels.
float level_line(float s, float level) {
    float w = max(fwidth(s), 1e-6);
    return 1.0 - smoothstep(0.5 * w, 1.5 * w, abs(s - level));
}

void main() {
    if (u_wire == 1) { o_colour = vec4(0.08, 0.08, 0.1, 1.0); return; }
    if (u_wire == 2) { o_colour = vec4(0.95, 0.15, 0.9, 1.0); return; }
    vec3 n = normalize(cross(dFdx(v_view_position), dFdy(v_view_position)));
    vec3 to_eye = normalize(-v_view_position);
    if (dot(n, to_eye) < 0.0) n = -n;  // two-sided
    vec3 base = mix(vec3(0.16, 0.36, 0.92), vec3(0.90, 0.18, 0.14), clamp(v_s, 0.0, 1.0));
    vec3 light = normalize(vec3(0.4, 0.6, 1.0));
    float diffuse = max(dot(n, light), 0.0);
    float specular = pow(max(dot(n, normalize(light + to_eye)), 0.0), 40.0);
    vec3 colour = base * (0.30 + 0.70 * diffuse) + 0.25 * specular;
    float line = max(level_line(v_s, 0.01), level_line(v_s, 0.99));
    o_colour = vec4(mix(colour, vec3(1.0, 0.92, 0.25), line), 1.0);
}
