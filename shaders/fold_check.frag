// Fold pass (beyond the paper): 1 for each checked triangle short of the fold
// repair's lift target, N·Ŝ − margin |N| < floor (N its area vector, Ŝ the unit
// sum of its edge neighbours' normals), which every folded one is, as
// FoldRepair::count_folds in engine/deform/fold_repair.cpp (its FoldChecks), for
// sum.frag to count. u_count is the number of checked triangles.
uniform sampler2D u_positions;                // xyz = position, w = s
uniform highp isampler2D u_fold_triangles;    // RGBA32I: the triangle's corners, its entry's margin (float bits)
uniform highp isampler2D u_fold_checks;       // RGBA32I: triangle, first neighbour, neighbours, floor (float bits)
uniform highp isampler2D u_fold_neighbours;   // R32I: triangles
out vec4 o_folded;

vec3 area_vector(int triangle) {
    ivec3 c = texelFetch(u_fold_triangles, texel_of(triangle), 0).xyz;
    vec3 p = fetch(u_positions, c.x).xyz;
    return cross(fetch(u_positions, c.y).xyz - p, fetch(u_positions, c.z).xyz - p);
}

vec3 unit_normal(int triangle) {
    vec3 n = area_vector(triangle);
    float len = length(n);
    return len > 0.0 ? n / len : vec3(0.0);
}

void main() {
    int i = fragment_vertex();
    if (i < 0) { o_folded = vec4(0.0); return; }
    ivec4 check = texelFetch(u_fold_checks, texel_of(i), 0);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < check.z; ++k)
        sum += unit_normal(texelFetch(u_fold_neighbours, texel_of(check.y + k), 0).x);
    float margin = intBitsToFloat(texelFetch(u_fold_triangles, texel_of(check.x), 0).w);
    float floor_ = intBitsToFloat(check.w);
    float len = length(sum);
    vec3 n = area_vector(check.x);
    bool short_of = len > 0.0 && dot(n, sum) / len - margin * length(n) < floor_;
    o_folded = vec4(short_of ? 1.0 : 0.0, 0.0, 0.0, 0.0);
}
