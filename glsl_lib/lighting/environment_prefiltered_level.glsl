// requires: constants.glsl
// Which GGX roughness each level of a prefiltered lat-long radiance map holds, and its inverse: the one mapping the
// prefilter pass (lighting/environment_prefilter.glsl) writes with and the split-sum lookup reads with.
// Level 0 is the map itself (a mirror, alpha 0). Level l >= 1 holds the lobe of alpha_l = 2^l K 2 pi / w, w the width
// of level 0 and K = MG_ENV_PREFILTER_TEXELS = 2: K times the azimuth one of the level's texels spans, in radians (a
// lobe of alpha reaches half its peak about 1.3 alpha from its centre, so a lobe spans some 5 texels of its level:
// bilinear reads between them stay close to the lobe's own; K = 1 measured 1.5% more error, K = 4 blurs the low
// roughnesses, which blend the mirror and alpha_1). alpha doubles from level to level; levels past alpha 1 are never
// read (they hold broader lobes still).
#ifndef MG_ENV_PREFILTER_TEXELS
#define MG_ENV_PREFILTER_TEXELS 2.0
#endif

// alpha_l of level `level` of a map `width` texels wide at level 0 (0 for level 0).
float mg_env_prefiltered_alpha(int level, float width)
{
    return level <= 0 ? 0.0 : exp2(float(level)) * MG_ENV_PREFILTER_TEXELS * MG_TWO_PI / width;
}

// The (fractional) level holding a lobe of roughness alpha: log2 of alpha over alpha_1, plus 1, for alpha at least
// alpha_1; below it a straight blend from the mirror at level 0 to alpha_1 at level 1. Clamped to the chain.
float mg_env_prefiltered_lod(float alpha, float width, int mips)
{
    float alpha1 = 2.0 * MG_ENV_PREFILTER_TEXELS * MG_TWO_PI / width;
    float lod = alpha < alpha1 ? alpha / alpha1 : 1.0 + log2(alpha / alpha1);
    return clamp(lod, 0.0, float(max(mips - 1, 0)));
}

// One roughness for an anisotropic lobe: the geometric mean sqrt(ax ay), the isotropic lobe of the same solid angle
// (GGX's peak density 1 / (pi ax ay) is the same).
float mg_env_prefiltered_isotropic(vec2 alpha)
{
    return sqrt(max(alpha.x * alpha.y, 0.0));
}
