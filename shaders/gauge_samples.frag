// Gauge samples (beyond the paper): texel 2j holds sample j's position, texel
// 2j + 1 its ∇r, for the stream gauge's fit on the CPU (field/stream_gauge.h,
// CpuSteps::fit_stream_gauge), which reads these few texels back. u_count is the
// number of texels, 2 per sample.
uniform sampler2D u_positions;         // xyz = position (or midpoint), w = s
uniform sampler2D u_gradients;         // xyz = ∇r
uniform highp isampler2D u_samples;    // R32I: the sample's vertex, one texel per sample
out vec4 o_sample;

void main() {
    int texel = fragment_vertex();
    if (texel < 0) { o_sample = vec4(0.0); return; }
    int v = texelFetch(u_samples, texel_of(texel / 2), 0).x;
    o_sample = (texel % 2 == 0) ? fetch(u_positions, v) : fetch(u_gradients, v);
}
