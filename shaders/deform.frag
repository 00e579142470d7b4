// Deformation pass (sec. 5): one classical RK4 step of v + ṽ from t to t + h with
// r = s and ∇b = b'(s) ∇r held fixed over the step, as deformation_step in
// engine/deform/passes.cpp. Writes the next vertex texture (ping-pong). With
// u_midpoint_rule, one step of the explicit midpoint rule instead: the midpoint
// predictor over half a step (predict_midpoints), into the midpoint texture.
// With u_keep_volume, the volume keeper's velocity −(x / y) w a is added to the
// field at every stage (KeeperVelocity, deform/passes.h; keeper_rate.frag's sums x, y
// and a the ring's area vector where the normals were last estimated).
uniform sampler2D u_positions;  // xyz = position, w = s
uniform sampler2D u_gradients;
uniform sampler2D u_normals;    // xyz = normal, w = |area vector|
uniform sampler2D u_keeper;     // 1 x 1: keeper_rate.frag's sums
uniform bool u_keep_volume;
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
    vec3 keep = vec3(0.0);
    if (u_keep_volume && in_blend_region(xs.w)) {
        vec2 sums = texelFetch(u_keeper, ivec2(0), 0).xy;
        vec4 n = fetch(u_normals, v);
        if (sums.y > 0.0) keep = -(sums.x / sums.y) * stream_weight(xs.w) * n.w * n.xyz;
    }
    vec3 k1 = deformation_velocity(u_start, x, b, grad_b) + keep;
    vec3 k2 = deformation_velocity(u_middle, x + 0.5 * u_h * k1, b, grad_b) + keep;
    if (u_midpoint_rule) { o_position = vec4(x + u_h * k2, xs.w); return; }
    vec3 k3 = deformation_velocity(u_middle, x + 0.5 * u_h * k2, b, grad_b) + keep;
    vec3 k4 = deformation_velocity(u_end, x + u_h * k3, b, grad_b) + keep;
    o_position = vec4(x + (u_h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4), xs.w);
}
