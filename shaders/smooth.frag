// Smoothing pass (sec. 5), one Laplacian step: move ∇r by u_weight toward the mean
// of the neighbours inside the blend region (0 < s < 1), then, with u_tangent,
// remove its normal part, as smooth_gradients in engine/deform/passes.cpp. Run N
// times, ping-pong. Outside the blend region ∇r stays 0.
uniform sampler2D u_positions;  // w = s
uniform sampler2D u_normals;
uniform sampler2D u_gradients;
uniform float u_weight;
uniform bool u_tangent;  // keep ∇r tangent (sec. 5 as printed) or smooth it in space
out vec4 o_gradient;

void main() {
    int v = fragment_vertex();
    if (v < 0 || !in_blend_region(fetch(u_positions, v).w)) { o_gradient = vec4(0.0); return; }
    ivec2 ring = ring_of(v);
    vec3 sum = vec3(0.0);
    int count = 0;
    for (int k = 0; k < ring.y; ++k) {
        int y = entry_vertex(ring_entry(ring.x + k));
        if (in_blend_region(fetch(u_positions, y).w)) {
            sum += fetch(u_gradients, y).xyz;
            ++count;
        }
    }
    vec3 g = fetch(u_gradients, v).xyz;
    if (count > 0) g += u_weight * (sum / float(count) - g);
    vec3 n = fetch(u_normals, v).xyz;
    o_gradient = vec4(u_tangent ? g - dot(g, n) * n : g, 0.0);
}
