// Fold pass (beyond the paper): 1 for each checked triangle that faces against
// the sum of its edge neighbours' normals and did not at rest, as
// FoldRepair::folded in engine/deform/fold_repair.cpp (its FoldChecks), for
// sum.frag to count. u_count is the number of checked triangles.
uniform sampler2D u_positions;                // xyz = position, w = s
uniform highp isampler2D u_fold_triangles;    // RGBA32I: the triangle's corners
uniform highp isampler2D u_fold_checks;       // RGBA32I: triangle, first neighbour, neighbours, against at rest
uniform highp isampler2D u_fold_neighbours;   // R32I: triangles
out vec4 o_folded;

vec3 unit_normal(int triangle) {
    ivec3 c = texelFetch(u_fold_triangles, texel_of(triangle), 0).xyz;
    vec3 p = fetch(u_positions, c.x).xyz;
    vec3 n = cross(fetch(u_positions, c.y).xyz - p, fetch(u_positions, c.z).xyz - p);
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0);
}

void main() {
    int i = fragment_vertex();
    if (i < 0) { o_folded = vec4(0.0); return; }
    ivec4 check = texelFetch(u_fold_checks, texel_of(i), 0);
    vec3 mean = vec3(0.0);
    for (int k = 0; k < check.z; ++k)
        mean += unit_normal(texelFetch(u_fold_neighbours, texel_of(check.y + k), 0).x);
    bool folded = check.w == 0 && check.z > 0 && dot(unit_normal(check.x), mean) < 0.0;
    o_folded = vec4(folded ? 1.0 : 0.0, 0.0, 0.0, 0.0);
}
