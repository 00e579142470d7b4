// Deformation pass (sec. 5): one classical RK4 step of v + ṽ from t to t + h with
// r = s and ∇b = b'(s) ∇r held fixed over the step, as deformation_step in
// engine/deform/passes.cpp. Writes the next vertex texture (ping-pong). With
// u_midpoint_rule, one step of the explicit midpoint rule instead: the midpoint
// predictor over half a step (predict_midpoints), into the midpoint texture.
uniform sampler2D u_positions;  // xyz = position, w = s
uniform sampler2D u_gradients;
uniform Motion u_start;   // at t
uniform Motion u_middle;  // at t + h/2
uniform Motion u_end;     // at t + h
uniform float u_h;
uniform bool u_midpoint_rule;
out vec4 o_position;

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_position = vec4(0.0); return; }
    vec4 xs = fetch(u_positions, v);
    if (xs.w >= 1.0) { o_position = xs; return; }  // outer region: v = 0 exactly
    float b = bernstein_blend(xs.w);
    vec3 grad_b = bernstein_blend_derivative(xs.w) * fetch(u_gradients, v).xyz;
    vec3 x = xs.xyz;
    vec3 k1 = deformation_velocity(u_start, x, b, grad_b);
    vec3 k2 = deformation_velocity(u_middle, x + 0.5 * u_h * k1, b, grad_b);
    if (u_midpoint_rule) { o_position = vec4(x + u_h * k2, xs.w); return; }
    vec3 k3 = deformation_velocity(u_middle, x + 0.5 * u_h * k2, b, grad_b);
    vec3 k4 = deformation_velocity(u_end, x + u_h * k3, b, grad_b);
    o_position = vec4(x + (u_h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4), xs.w);
}
