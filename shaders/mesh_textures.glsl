// The mesh as textures (engine/gpu/gpu_passes.h). Item i of a per-vertex or
// per-ring-entry array lives at texel (i % u_width, i / u_width).
//   u_rings       RG32I: x = first entry of the vertex's ring in u_neighbours, y = ring length
//   u_neighbours  R32I:  (neighbour index << 1) | wedge, wedge = 1 when the triangle
//                        (v, this neighbour, next neighbour) exists; rings are ordered
//                        counter-clockwise and cyclic, as in mesh/vertex_rings.h
uniform int u_width;
uniform int u_count;
uniform highp isampler2D u_rings;
uniform highp isampler2D u_neighbours;

ivec2 texel_of(int i) { return ivec2(i % u_width, i / u_width); }

// The vertex this fragment computes; -1 for the padding texels after the last vertex.
int fragment_vertex() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int v = p.y * u_width + p.x;
    return v < u_count ? v : -1;
}

ivec2 ring_of(int v) { return texelFetch(u_rings, texel_of(v), 0).xy; }
int ring_entry(int i) { return texelFetch(u_neighbours, texel_of(i), 0).x; }
int entry_vertex(int entry) { return entry >> 1; }
bool entry_has_wedge(int entry) { return (entry & 1) == 1; }
vec4 fetch(sampler2D t, int v) { return texelFetch(t, texel_of(v), 0); }

// 0 < s < 1: where b′(s) ≠ 0, the only vertices whose ∇r the field uses.
bool in_blend_region(float s) { return s > 0.0 && s < 1.0; }
