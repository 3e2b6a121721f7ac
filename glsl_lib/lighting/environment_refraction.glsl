// requires: constants.glsl lighting/environment.glsl lighting/environment_specular.glsl
// Environment seen through a transmitting surface. What is behind it is the environment: the view ray
// refracts in at a microfacet, crosses a solid sphere of the BSDF's IOR along a chord and refracts out, or,
// for a thin-walled surface (MaterialX Specification 1.39, surface; OpenPBR 1.1 §geometry: "no refraction"),
// leaves through a back face parallel to the surface, which bends it back.

// Exit direction of the ray I entering a solid sphere at a point whose outward normal is N: Snell's law in,
// along the chord to the exit point (the unit sphere's chord from N along R1 ends at N - 2 (R1.N) R1, which is
// also the exit's outward normal), Snell's law out; a ray held inside by total internal reflection leaves
// mirrored.
vec3 mg_refraction_solid_sphere(vec3 I, vec3 N, float ior)
{
    float eta = max(ior, 1.0e-4);
    vec3 R1 = refract(I, N, 1.0 / eta);
    if (dot(R1, R1) < 1.0e-8)
        return reflect(I, N);
    vec3 N2 = normalize(N + 2.0 * dot(R1, -N) * R1);
    vec3 R2 = refract(R1, -N2, eta);
    return dot(R2, R2) < 1.0e-8 ? reflect(R1, -N2) : R2;
}

// The sample loop's exit direction for the microfacet M of a surface whose normal is z: through the solid sphere
// above, or through a thin shell: in at M, out through the back face, parallel to the surface (M = z gives I
// itself). Both enter alike and leave through one face, the sphere's exit normal -N2 or the shell's back face, so
// one refraction in and one out serve either (a loop holding both paths compiled to about 40 more GPU
// instructions).
vec3 mg_refraction_exit(vec3 I, vec3 M, float ior, bool thin_walled)
{
    float eta = max(ior, 1.0e-4);
    vec3 R1 = refract(I, M, 1.0 / eta);
    if (dot(R1, R1) < 1.0e-8)
        return reflect(I, M);
    vec3 out_n = thin_walled ? vec3(0.0, 0.0, 1.0) : -normalize(M + 2.0 * dot(R1, -M) * R1);
    vec3 R2 = refract(R1, out_n, eta);
    return dot(R2, R2) < 1.0e-8 ? reflect(R1, out_n) : R2;
}

// The sample loop of mg_env_refraction over the Fresnel curve FRESNEL(fr, cosine), as MG_ENV_SPECULAR_SAMPLES: NAME
// returns the sum of the radiance transmitted through each sample's facet times its share w = 1 - F, and sets share
// to the sum of the shares and reflected to the same samples' reflection as the node's reflection lobe weighs it
// (F G2 / G1(v), as mg_env_specular), for the cap. A mirror (mg_ggx_is_mirror) takes one sample, along the normal.
#define MG_ENV_REFRACTION_SAMPLES(NAME, FRESNEL) \
vec3 NAME(vec3 Vt, mat3 frame, float ior, vec2 alpha, MgFresnel fr, bool thin_walled, int n, float G1V, \
          out vec3 share, out vec3 reflected) \
{ \
    vec3 sum = vec3(0.0); \
    share = vec3(0.0); \
    reflected = vec3(0.0); \
    bool mirror = mg_ggx_is_mirror(alpha); \
    int texels = mg_env_texels(); \
    for (int i = 0; i < n; ++i) \
    { \
        vec3 H = mg_env_lobe_normal(Vt, alpha, mirror, i, n); \
        vec3 Lt = mg_refraction_exit(-Vt, H, ior, thin_walled); \
        float pdf = G1V * mg_ggx_D(H, alpha) / (4.0 * Vt.z); \
        vec3 L = frame * Lt; \
        vec3 F = FRESNEL(fr, clamp(dot(Vt, H), 0.0, 1.0)); \
        vec3 w = max(1.0 - F, 0.0); \
        float lod = mg_env_lod(L, pdf, texels, mg_env_sample_total(n)); \
        sum += mg_env_radiance(L, lod) * w; \
        share += w; \
        vec3 Lr = reflect(-Vt, H); \
        if (mirror || Lr.z > 0.0) \
            reflected += F * (mg_ggx_G2(Lr, Vt, alpha) / G1V); \
    } \
    return sum; \
}

MG_ENV_REFRACTION_SAMPLES(mg_env_refraction_samples, mg_fresnel_eval)

// Transmitted environment radiance, times what the interface lets through. The rough transmission lobe
// (Walter et al. 2007) is sampled by its microfacets: n visible normals m of the view (Heitz 2018), each
// sending the view ray through the sphere (or shell) as if m were the surface there, weighted by the
// share 1 - F(v.m) that facet transmits and read at the mip level of its reflection density (Krivanek &
// Colbert 2008), as MaterialX's sampler does. MaterialX then divides by the masking G1(v) (its reflection
// estimator's normalisation), which lifts the transmitted light above what the interface does not reflect
// towards the silhouette: with the reflection lobe, more than arrives in a white furnace. We keep that
// estimate where it stays within 1 - R, R what the node's reflection lobe returns of a white environment
// (the same samples' F G2 / G1, times its energy compensation `comp`), and scale the lobe down to 1 - R
// elsewhere: the lobe's shape is MaterialX's, its energy capped, and reflection plus transmission never
// exceed 1 (docs/differences/README.md, rough transmission). The cap's factor depends on the view and the
// surface only, never on the environment. Define MG_REFRACTION_UNBOUNDED for the estimate without the cap
// (a comparison switch: tests/test_rough_transmission.py shows it at parity with MaterialX on the whole
// sphere). MG_REFRACTION_PREFILTERED (the split-sum method): one lookup in the GGX-prefiltered map along the
// refracted direction at the level of the lobe's roughness, times `through` (1 - the tabulated reflected albedo).
vec3 mg_env_refraction(vec3 V, vec3 N, vec3 Tg, float ior, vec2 alpha, MgFresnel fr, vec3 comp, vec3 through,
                       bool thin_walled)
{
#ifdef MG_REFRACTION_PREFILTERED
    vec3 T = thin_walled ? -V : mg_refraction_solid_sphere(-V, N, ior);
    return mg_env_radiance(T, mg_env_lod_prefiltered(alpha)) * through;
#else
    mat3 frame = mg_tangent_frame(N, Tg);
    vec3 Vt = V * frame;
    Vt.z = max(Vt.z, 1.0e-4);
    Vt = normalize(Vt);
    int n = mg_env_lobe_samples(alpha);
    float G1V = mg_ggx_G1(Vt, alpha);
    vec3 share, reflected;
    vec3 sum = mg_env_refraction_samples(Vt, frame, ior, alpha, fr, thin_walled, n, G1V, share, reflected);
#ifdef MG_REFRACTION_UNBOUNDED
    return sum / (float(n) * G1V);
#else
    vec3 bound = max(1.0 - reflected / float(n) * comp, 0.0);
    return sum / float(n) * min(vec3(1.0 / G1V), bound / max(share / float(n), vec3(1.0e-6)));
#endif
#endif
}
