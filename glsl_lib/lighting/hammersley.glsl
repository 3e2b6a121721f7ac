// requires: pbrlib/microfacet/ggx.glsl
// uniforms: u_envSampleFrame u_envSampleFrames u_envRadianceSamples
// The Hammersley point set: point i of n is (i / n, radical inverse of i in base 2) (Hammersley 1964;
// Pharr et al., "Physically Based Rendering", sec. 7.4).

// The 32 bits of v in reverse order. GLSL ES 3.00 lacks bitfieldReverse (GLSL 4.00 has it): there the
// halves, bytes, nibbles, bit pairs and bits swap in turn (Warren, "Hacker's Delight", sec. 7-1).
uint mg_reverse_bits(uint v)
{
#ifdef GL_ES
    v = (v >> 16u) | (v << 16u);
    v = ((v >> 8u) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8u);
    v = ((v >> 4u) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4u);
    v = ((v >> 2u) & 0x33333333u) | ((v & 0x33333333u) << 2u);
    return ((v >> 1u) & 0x55555555u) | ((v & 0x55555555u) << 1u);
#else
    return bitfieldReverse(v);
#endif
}

vec2 mg_hammersley(int i, int n)
{
    return vec2((float(i) + 0.5) / float(n), float(mg_reverse_bits(uint(i))) * 2.3283064365386963e-10);
}

// Progressive refinement (a viewer accumulating frames while its camera is still): frame u_envSampleFrame of
// u_envSampleFrames draws the points k n .. k n + n - 1 of the first two dimensions of Sobol's sequence
// (Sobol 1967), a (0, 2)-sequence in base 2: for n a power of two each frame's block is a (0, m, 2)-net on its
// own, and the K frames' blocks together are the first n K points, so the mean of the K images is an estimate
// with n K samples. With one frame (the defaults) the points are the Hammersley set, as before. MG_ENV_ONE_FRAME
// (a reduced shader that keeps neither uniform: they are constants) leaves the frames' code out.

// Sobol's second dimension: bit j of t contributes the j-th row of Pascal's triangle mod 2, read from the top bit.
// By Lucas' theorem C(j, k) is odd exactly when the bits of k are among those of j, so bit k of the reversed result
// is the XOR of the bits j of t that contain k: five shift-XOR steps, one per bit of k, then one reversal (no
// loop: the point stays straight-line code wherever a sample loop inlines it).
uint mg_sobol2(uint t)
{
    t ^= (t >> 1u) & 0x55555555u;
    t ^= (t >> 2u) & 0x33333333u;
    t ^= (t >> 4u) & 0x0f0f0f0fu;
    t ^= (t >> 8u) & 0x00ff00ffu;
    t ^= (t >> 16u) & 0x0000ffffu;
    return mg_reverse_bits(t);
}

vec2 mg_env_sample_point(int i, int n)
{
#ifndef MG_ENV_ONE_FRAME
    int frames = max(u_envSampleFrames, 1);
    if (frames > 1)
    {
        uint t = uint(clamp(u_envSampleFrame, 0, frames - 1) * n + i);
        float x = float(mg_reverse_bits(t)) * 2.3283064365386963e-10 + 0.5 / float(n * frames);
        return vec2(x, float(mg_sobol2(t)) * 2.3283064365386963e-10);
    }
#endif
    return mg_hammersley(i, n);
}

// The number of samples the frames together take: what a sample's filtered lookup is sized for.
int mg_env_sample_total(int n)
{
#ifdef MG_ENV_ONE_FRAME
    return n;
#else
    return n * max(u_envSampleFrames, 1);
#endif
}

// How many samples a GGX lobe of alphas `alpha` takes: u_envRadianceSamples, one for a mirror (mg_ggx_is_mirror).
int mg_env_lobe_samples(vec2 alpha)
{
    return mg_ggx_is_mirror(alpha) ? 1 : max(u_envRadianceSamples, 1);
}

// The microfacet normal of a GGX lobe's sample i of n about the view Vt (tangent space): a visible normal (Heitz
// 2018) at the sample's point, or the normal itself for a mirror (mirror: mg_ggx_is_mirror(alpha)). The normal is
// chosen after the visible one is made, from two plain values, so compilers select rather than branch.
vec3 mg_env_lobe_normal(vec3 Vt, vec2 alpha, bool mirror, int i, int n)
{
    vec3 H = mg_ggx_sample_vndf(Vt, alpha, mg_env_sample_point(i, n));
    return mirror ? vec3(0.0, 0.0, 1.0) : H;
}
