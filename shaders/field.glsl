// The deformation field v + ṽ in closed form, as engine/field/vector_field.cpp.
// MotionSample of engine/curve/inner_motion.h at one time t.
struct Motion {
    vec3 position;          // c(t)
    vec3 velocity;          // ċ(t)
    vec3 angular_velocity;  // ω(t), zero in translation mode
    vec3 twist;             // τ(t) = α̇(t) ĉ(t)
    vec3 twist_origin;      // where the twist's plane ẽ = 0 crosses its axis: c(t) + ζ0 ĉ(t)
    vec3 stream_origin;     // o: where e and f are built about (c(t) by default)
    // The stream's gauge ∇φ (field/stream_gauge.h): three quadratic polynomials in
    // d = (x − gauge_centre) · gauge_inverse_scale, gauge[k] the coefficients of
    // (1, dx, dy, dz, dx², dy², dz², dx dy, dx dz, dy dz); all zero is the paper's.
    vec3 gauge_centre;
    float gauge_inverse_scale;
    vec3 gauge[10];
};

// b(u) of eq. (4): 4u³ − 3u⁴ on [0,1], 0 below, 1 above.
float bernstein_blend(float u) {
    if (u <= 0.0) return 0.0;
    if (u >= 1.0) return 1.0;
    return u * u * u * (4.0 - 3.0 * u);
}

// db/du = 12u²(1 − u) on (0,1), 0 elsewhere.
float bernstein_blend_derivative(float u) {
    if (u <= 0.0 || u >= 1.0) return 0.0;
    return 12.0 * u * u * (1.0 - u);
}

// (1 − b) b′(s): where the stream meets ∇r in v, the gauge fit's and the volume
// keeper's weight (field/stream_gauge.h, deform/volume_keeper.h).
float stream_weight(float s) { return (1.0 - bernstein_blend(s)) * bernstein_blend_derivative(s); }

// f ∇e − e ∇f of a rotation with angular velocity omega about an axis through
// the origin of y, its plane e = 0 through that origin: ½ |y⊥|² Ω − (Ω·y) y⊥.
vec3 rotation_stream(vec3 omega, vec3 y) {
    float omega2 = dot(omega, omega);
    if (omega2 == 0.0) return vec3(0.0);
    float along = dot(omega, y);
    vec3 y_perp = y - (along / omega2) * omega;
    return 0.5 * dot(y_perp, y_perp) * omega - along * y_perp;
}

// ∇φ(x), gauge_gradient of engine/field/stream_gauge.cpp.
vec3 gauge_gradient(Motion m, vec3 x) {
    vec3 d = (x - m.gauge_centre) * m.gauge_inverse_scale;
    return m.gauge[0] + d.x * m.gauge[1] + d.y * m.gauge[2] + d.z * m.gauge[3] + d.x * d.x * m.gauge[4] +
           d.y * d.y * m.gauge[5] + d.z * d.z * m.gauge[6] + d.x * d.y * m.gauge[7] + d.x * d.z * m.gauge[8] +
           d.y * d.z * m.gauge[9];
}

// Rigid velocity of the inner region: ∇e × ∇f (+ ∇ẽ × ∇f̃).
vec3 inner_velocity(Motion m, vec3 x) {
    return m.velocity + cross(m.angular_velocity + m.twist, x - m.position);
}

// f ∇e − e ∇f (+ f̃ ∇ẽ − ẽ ∇f̃): translation (eqs. 9–10) with U = ċ + ω × (o − c),
// the velocity at the stream's origin o, and rotation (eqs. 11–13) about o; twist
// (eq. 14) about the axis through c, its plane through m.twist_origin; then the gauge.
vec3 stream_vector(Motion m, vec3 x) {
    vec3 z = x - m.stream_origin;
    vec3 u = m.velocity + cross(m.angular_velocity, m.stream_origin - m.position);
    return cross(z, u) + rotation_stream(m.angular_velocity, z) + rotation_stream(m.twist, x - m.twist_origin) +
           gauge_gradient(m, x);
}

// v + ṽ = (1 − b)² ∇e × ∇f − (1 − b) (f ∇e − e ∇f) × ∇b   (eqs. 1–3)
vec3 deformation_velocity(Motion m, vec3 x, float b, vec3 grad_b) {
    float a = 1.0 - b;
    return a * a * inner_velocity(m, x) - a * cross(stream_vector(m, x), grad_b);
}
