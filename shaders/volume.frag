// Volume pass (beyond the paper), the sums of VolumeKeeper (engine/deform/
// volume_keeper.cpp) per vertex, for sum.frag to add up:
//   x: six times the signed volume of the tetrahedra (u_centre, triangle) of the
//      triangles that have a moving corner (s < 1) and this vertex as their lowest;
//   y: w |a|² on the blend region, w = (1 − b) b′(s) and a the ring's area vector
//      where the normals were last estimated (normal.frag: normal · w).
uniform sampler2D u_positions;  // xyz = position, w = s
uniform sampler2D u_normals;    // xyz = normal, w = |area vector|
uniform vec3 u_centre;
out vec4 o_volume;

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_volume = vec4(0.0); return; }
    vec4 xs = fetch(u_positions, v);
    ivec2 ring = ring_of(v);
    float six_volume = 0.0;
    for (int k = 0; k < ring.y; ++k) {
        int entry = ring_entry(ring.x + k);
        if (!entry_has_wedge(entry)) continue;
        int a = entry_vertex(entry);
        int b = entry_vertex(ring_entry(ring.x + (k + 1 == ring.y ? 0 : k + 1)));
        if (v > a || v > b) continue;  // each triangle once, from its lowest corner
        vec4 xa = fetch(u_positions, a), xb = fetch(u_positions, b);
        if (xs.w < 1.0 || xa.w < 1.0 || xb.w < 1.0)
            six_volume += dot(xs.xyz - u_centre, cross(xa.xyz - u_centre, xb.xyz - u_centre));
    }
    float weighted = 0.0;
    if (in_blend_region(xs.w)) {
        float area = fetch(u_normals, v).w;
        weighted = stream_weight(xs.w) * area * area;
    }
    o_volume = vec4(six_volume, weighted, 0.0, 0.0);
}
