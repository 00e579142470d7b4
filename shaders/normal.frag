// Normal pass (sec. 5): the normalised sum of the (area-weighted) normals of the
// triangles around each vertex, as estimate_normals in engine/deform/passes.cpp.
// w is that sum's length, so normal · w is the ring's area vector (6 ∂V/∂x), the
// volume keeper's direction (volume.frag, keep_volume.frag).
uniform sampler2D u_positions;  // xyz = position, w = s
out vec4 o_normal;

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_normal = vec4(0.0); return; }
    vec3 x = fetch(u_positions, v).xyz;
    ivec2 ring = ring_of(v);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < ring.y; ++k) {
        int entry = ring_entry(ring.x + k);
        if (!entry_has_wedge(entry)) continue;
        int next = ring_entry(ring.x + (k + 1 == ring.y ? 0 : k + 1));
        vec3 a = fetch(u_positions, entry_vertex(entry)).xyz - x;
        vec3 b = fetch(u_positions, entry_vertex(next)).xyz - x;
        sum += cross(a, b);  // twice the triangle's area times its normal
    }
    float len = length(sum);
    o_normal = vec4(len > 0.0 ? sum / len : vec3(0.0), len);
}
