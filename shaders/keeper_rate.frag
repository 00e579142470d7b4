// Keeper rate pass (beyond the paper), VolumeKeeper::rate of engine/deform/
// volume_keeper.cpp per vertex, for sum.frag to add up:
//   x: u · a, u the field (v + ṽ, rigid on the inner region) at the vertex and a
//      its ring's area vector (6 ∂V/∂x): summed, six times dV/dt;
//   y: w |a|² on the blend region, w = (1 − b) b′(s), as volume.frag's y.
// The deformation pass adds the keeper's velocity −(x / y) w a to the field
// (deform.frag), so that dV/dt vanishes where ∇r was taken.
uniform sampler2D u_positions;  // xyz = position (or midpoint), w = s
uniform sampler2D u_normals;    // xyz = normal, w = |area vector|
uniform sampler2D u_gradients;
uniform Motion u_sample;
out vec4 o_rate;

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_rate = vec4(0.0); return; }
    vec4 xs = fetch(u_positions, v);
    if (xs.w >= 1.0) { o_rate = vec4(0.0); return; }  // outer region: u = 0
    vec4 n = fetch(u_normals, v);
    vec3 a = n.w * n.xyz;
    vec3 grad_b = bernstein_blend_derivative(xs.w) * fetch(u_gradients, v).xyz;
    vec3 u = deformation_velocity(u_sample, xs.xyz, bernstein_blend(xs.w), grad_b);
    float weighted = in_blend_region(xs.w) ? stream_weight(xs.w) * n.w * n.w : 0.0;
    o_rate = vec4(dot(u, a), weighted, 0.0, 0.0);
}
