// requires: constants.glsl
// Metallic flakes of the Enterprise PBR material (DSPBR 2025x, "Flakes"): a layer of small mirrors in the
// coating, on a grid of flakeSize (mm; scene units are metres). Each cell holds a flake with probability
// flakeCoverage, turned away from the normal by a GGX-distributed slope of alpha = flakeRoughness^2.
// flakeSize 0 (or below a pixel) is the statistical limit: coverage flakeCoverage everywhere and the
// flakes' orientations become the lobe's normal distribution about N.

// pcg3d integer hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering").
uvec3 mg_epbr_pcg3d(uvec3 v)
{
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v;
}

// Flake normal Nf, flake coverage c in [0, 1] and the flakes' lobe alpha at position P (metres).
void mg_epbr_flakes(vec3 P, mat3 frame, float size_mm, float coverage, float roughness, float footprint,
                    out vec3 Nf, out float c, out float alpha)
{
    float a = max(roughness * roughness, 1.0e-4);
    Nf = frame[2];
    c = clamp(coverage, 0.0, 1.0);
    alpha = a;
    float size = size_mm * 1.0e-3;
    if (size <= footprint || c <= 0.0)
        return;
    uvec3 h = mg_epbr_pcg3d(uvec3(ivec3(floor(P / size))));
    vec3 u = vec3(h) * (1.0 / 4294967296.0);
    c = u.x < coverage ? 1.0 : 0.0;
    // slope of the flake: GGX's tan(theta) = alpha sqrt(xi / (1 - xi)), uniform azimuth (Walter et al. 2007 eq. 35)
    float t = a * sqrt(u.y / max(1.0 - u.y, 1.0e-6));
    float phi = MG_TWO_PI * u.z;
    Nf = normalize(frame * vec3(t * cos(phi), t * sin(phi), 1.0));
    alpha = 0.01;       // each flake is a near mirror
}

// Flake colour, turning from flakeColor towards flipFlopColor as the half-vector cosine falls (v.h = l.h:
// reciprocal).
vec3 mg_epbr_flake_color(vec3 color, vec3 flip_flop_color, float flip_flop, float VdotH)
{
    return mix(color, flip_flop_color, clamp(flip_flop, 0.0, 1.0) * (1.0 - clamp(VdotH, 0.0, 1.0)));
}
