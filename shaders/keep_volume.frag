// Volume keeper pass (beyond the paper), VolumeKeeper::restore of engine/deform/
// volume_keeper.cpp: one Newton step on the enclosed volume, moving each blend
// vertex by −(6V − 6V_rest) w a / Σ w |a|² (a its ring's area vector, 6 ∂V/∂x).
// Writes the next vertex texture (ping-pong).
uniform sampler2D u_positions;    // xyz = position, w = s
uniform sampler2D u_normals;      // xyz = normal, w = |area vector|
uniform sampler2D u_volume;       // 1 x 1: the volume pass's sums now (x: 6V of the moving triangles, y: Σ w |a|²)
uniform sampler2D u_rest_volume;  // 1 x 1: the same sums at rest
out vec4 o_position;

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_position = vec4(0.0); return; }
    vec4 xs = fetch(u_positions, v);
    vec2 sums = texelFetch(u_volume, ivec2(0), 0).xy;
    if (!in_blend_region(xs.w) || !(sums.y > 0.0)) { o_position = xs; return; }
    float drift = sums.x - texelFetch(u_rest_volume, ivec2(0), 0).x;  // six times the volume's drift
    vec4 n = fetch(u_normals, v);
    o_position = vec4(xs.xyz - (drift / sums.y) * stream_weight(xs.w) * n.w * n.xyz, xs.w);
}
