// Gradient pass, eq. (6): the gradient g of the linear function r(y) = s(x) + g·(y − x)
// with g·n = 0 that fits s best on the 1-ring, as ring_gradient in
// engine/deform/passes.cpp: 2×2 normal equations in tangent coordinates. The
// singularity test divides by the trace, so it does not depend on the mesh's scale.
// Outside the blend region (s = 0 or 1) b′(s) = 0, ∇r is never used and is 0.
uniform sampler2D u_positions;  // xyz = position, w = s
uniform sampler2D u_normals;
out vec4 o_gradient;

// Unit tangents t1, t2 with (t1, t2, n) orthonormal (Duff et al. 2017).
void tangent_basis(vec3 n, out vec3 t1, out vec3 t2) {
    float side = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (side + n.z);
    float b = n.x * n.y * a;
    t1 = vec3(1.0 + side * n.x * n.x * a, side * b, -side * n.x);
    t2 = vec3(b, side + n.y * n.y * a, -n.y);
}

void main() {
    int v = fragment_vertex();
    if (v < 0) { o_gradient = vec4(0.0); return; }
    vec4 xs = fetch(u_positions, v);
    vec3 n = fetch(u_normals, v).xyz;
    if (!in_blend_region(xs.w) || n == vec3(0.0)) { o_gradient = vec4(0.0); return; }
    vec3 t1, t2;
    tangent_basis(n, t1, t2);
    ivec2 ring = ring_of(v);
    vec3 a = vec3(0.0);  // Σ p1², Σ p1 p2, Σ p2²
    vec2 rhs = vec2(0.0);
    for (int k = 0; k < ring.y; ++k) {
        vec4 ys = fetch(u_positions, entry_vertex(ring_entry(ring.x + k)));
        vec3 d = ys.xyz - xs.xyz;
        vec2 p = vec2(dot(d, t1), dot(d, t2));  // (y − x) in tangent coordinates
        a += vec3(p.x * p.x, p.x * p.y, p.y * p.y);
        rhs += (ys.w - xs.w) * p;
    }
    float scale = a.x + a.z;
    vec3 g = vec3(0.0);
    if (scale > 0.0) {
        vec3 m = a / scale;
        float det = m.x * m.z - m.y * m.y;
        // A ring that spans no plane gives no gradient: the same test as the CPU's
        // ring_gradient (engine/deform/passes.cpp, kFlatRing), det / trace² > 1e-6.
        if (det > 1e-6) {
            vec2 r = rhs / scale;
            g = ((m.z * r.x - m.y * r.y) * t1 + (m.x * r.y - m.y * r.x) * t2) / det;
        }
    }
    o_gradient = vec4(g, 0.0);
}
