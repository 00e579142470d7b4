// Sum pass (beyond the paper): each texel the sum of a block of kBlock x kBlock
// texels of the source, so that a few passes add a whole texture up into one
// texel (the volume keeper's sums, the fold count) with no read-back.
const int kBlock = 8;
uniform sampler2D u_source;
uniform ivec2 u_source_size;
out vec4 o_sum;

void main() {
    ivec2 first = ivec2(gl_FragCoord.xy) * kBlock;
    vec4 sum = vec4(0.0);
    for (int j = 0; j < kBlock; ++j)
        for (int i = 0; i < kBlock; ++i) {
            ivec2 p = first + ivec2(i, j);
            if (p.x < u_source_size.x && p.y < u_source_size.y) sum += texelFetch(u_source, p, 0);
        }
    o_sum = sum;
}
