// Gradient pass, eq. (6): the gradient g of the linear function r(y) = s(x) + g·(y − x)
// with g·n = 0 that fits s best on the 1-ring, as estimate_gradients in
// engine/deform/passes.cpp. The normal equations are divided by their trace so
// that the singularity test does not depend on the mesh's scale in float.
// Outside the blend region (s = 0 or 1) b′(s) = 0, ∇r is never used and is 0.
uniform sampler2D u_positions;  // xyz = position, w = s
uniform sampler2D u_normals;
out vec4 o_gradient;

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_gradient = vec4(0.0); return; }
    vec4 xs = fetch(u_positions, v);
    if (!in_blend_region(xs.w)) { o_gradient = vec4(0.0); return; }
    vec3 n = fetch(u_normals, v).xyz;
    ivec2 ring = ring_of(v);
    mat3 normal_matrix = mat3(0.0);
    vec3 rhs = vec3(0.0);
    for (int k = 0; k < ring.y; ++k) {
        vec4 ys = fetch(u_positions, entry_vertex(ring_entry(ring.x + k)));
        vec3 d = ys.xyz - xs.xyz;
        vec3 p = d - dot(d, n) * n;  // (y − x) in the tangent plane
        normal_matrix += outerProduct(p, p);
        rhs += (ys.w - xs.w) * p;
    }
    float scale = normal_matrix[0][0] + normal_matrix[1][1] + normal_matrix[2][2];
    vec3 g = vec3(0.0);
    if (scale > 0.0) {
        // Σ p pᵀ is singular along n; adding n nᵀ keeps g·n = 0.
        mat3 m = normal_matrix / scale + outerProduct(n, n);
        // A ring that spans no plane gives no gradient.
        if (determinant(m) > 1e-6) g = inverse(m) * (rhs / scale);
    }
    o_gradient = vec4(g, 0.0);
}
