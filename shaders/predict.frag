// Midpoint predictor: each vertex half a step along the field with the previous
// step's gradients, as predict_midpoints in engine/deform/passes.cpp.
uniform sampler2D u_positions;  // xyz = position, w = s
uniform sampler2D u_gradients;
uniform Motion u_start;         // the motion at the step's start time t
uniform float u_h;
out vec4 o_midpoint;

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_midpoint = vec4(0.0); return; }
    vec4 xs = fetch(u_positions, v);
    vec3 grad_b = bernstein_blend_derivative(xs.w) * fetch(u_gradients, v).xyz;
    vec3 mid = xs.xyz + 0.5 * u_h * deformation_velocity(u_start, xs.xyz, bernstein_blend(xs.w), grad_b);
    o_midpoint = vec4(mid, xs.w);
}
