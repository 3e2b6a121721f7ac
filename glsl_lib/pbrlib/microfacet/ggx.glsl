// requires: constants.glsl
// Anisotropic GGX microfacet distribution and its Smith masking, in a tangent frame where x follows the
// tangent input, y the bitangent and z the normal. alpha is the roughness input (x along the tangent).

// Orthonormal shading frame (columns: tangent, bitangent, normal) from a normal and a tangent hint.
mat3 mg_tangent_frame(vec3 N, vec3 T)
{
    vec3 t = T - N * dot(N, T);
    float len2 = dot(t, t);
    if (len2 < 1.0e-12)
    {
        // No usable hint: N x (0, 1, 0), or N x (1, 0, 0) for a normal near the y axis, written out.
        t = abs(N.y) < 0.99 ? vec3(-N.z, 0.0, N.x) : vec3(0.0, N.z, -N.y);
        len2 = dot(t, t);
    }
    t *= inversesqrt(len2);
    return mat3(t, cross(N, t), N);
}

// Roughness input to GGX alpha, kept away from the singular mirror limit.
const float MG_GGX_ALPHA_MIN = 1.0e-4;
vec2 mg_ggx_alpha(vec2 roughness)
{
    return clamp(roughness, vec2(MG_GGX_ALPHA_MIN), vec2(1.0));
}

// A lobe at the floor in both directions is a mirror to the environment's samplers: its visible normals lie within
// about 1e-4 rad of the normal, its reflected directions within 2e-4 rad of the mirror direction (a 1024-texel
// lat-long map's texel spans 6e-3 rad), read at level 0, each with F(v.h) G2 / G1 within 1e-4 of F(n.v): one sample
// along the normal itself is their mean. With a literal roughness of 0 (the reduced interface) the sample loop is
// then one straight pass, and a mirror drawn with the complete interface takes one texture read, not n.
bool mg_ggx_is_mirror(vec2 alpha)
{
    return max(alpha.x, alpha.y) <= MG_GGX_ALPHA_MIN;
}

// Anisotropic GGX normal distribution (Walter et al. 2007 eq. 33; anisotropic form of Burley 2012 eq. 13).
float mg_ggx_D(vec3 H, vec2 alpha)
{
    vec3 s = vec3(H.x / alpha.x, H.y / alpha.y, H.z);
    float d = dot(s, s);
    return 1.0 / (MG_PI * alpha.x * alpha.y * d * d);
}

// Smith Lambda of anisotropic GGX (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 86).
float mg_ggx_lambda(vec3 w, vec2 alpha)
{
    float z2 = max(w.z * w.z, 1.0e-12);
    float t2 = (alpha.x * alpha.x * w.x * w.x + alpha.y * alpha.y * w.y * w.y) / z2;
    return 0.5 * (sqrt(1.0 + t2) - 1.0);
}

// Smith masking G1 (Heitz 2014 eq. 43).
float mg_ggx_G1(vec3 w, vec2 alpha)
{
    return 1.0 / (1.0 + mg_ggx_lambda(w, alpha));
}

// Height-correlated masking-shadowing G2 (Heitz 2014 eq. 99).
float mg_ggx_G2(vec3 L, vec3 V, vec2 alpha)
{
    return 1.0 / (1.0 + mg_ggx_lambda(L, alpha) + mg_ggx_lambda(V, alpha));
}

// Sample a visible normal for the view V, u in [0,1)^2 (Heitz 2018, "Sampling the GGX Distribution of
// Visible Normals"); returns the microfacet normal in the tangent frame.
vec3 mg_ggx_sample_vndf(vec3 V, vec2 alpha, vec2 u)
{
    vec3 Vh = normalize(vec3(alpha.x * V.x, alpha.y * V.y, V.z));
    float lensq = Vh.x * Vh.x + Vh.y * Vh.y;
    vec3 T1 = lensq > 0.0 ? vec3(-Vh.y, Vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 T2 = cross(Vh, T1);
    float r = sqrt(u.x);
    float phi = MG_TWO_PI * u.y;
    float t1 = r * cos(phi);
    float t2 = r * sin(phi);
    float s = 0.5 * (1.0 + Vh.z);
    t2 = (1.0 - s) * sqrt(max(0.0, 1.0 - t1 * t1)) + s * t2;
    vec3 Nh = t1 * T1 + t2 * T2 + sqrt(max(0.0, 1.0 - t1 * t1 - t2 * t2)) * Vh;
    return normalize(vec3(alpha.x * Nh.x, alpha.y * Nh.y, max(0.0, Nh.z)));
}
