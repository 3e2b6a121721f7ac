// Blackbody colour: Kim et al. 2002, "Design of Advanced Color Temperature Control System for HDTV Applications" (cubic fit of the Planckian locus in CIE xy, 1667-25000 K).

// CIE 1931 xy chromaticity of a blackbody at the given temperature (Kelvin). Above 25000 K the colour
// is held; below 1667 K the fit is extrapolated down to 800 K and held below that, as MaterialX's
// renders do (the extrapolation drifts off the locus: under ~1200 K the colour turns whiter again).
vec2 mg_planckian_xy(float kelvin)
{
    float T = clamp(kelvin, 800.0, 25000.0);
    float t = 1000.0 / T;
    float x = T < 4000.0
        ? ((-0.2661239 * t - 0.2343589) * t + 0.8776956) * t + 0.179910
        : ((-3.0258469 * t + 2.1070379) * t + 0.2226347) * t + 0.240390;
    float y;
    if (T < 2222.0)
        y = ((-1.1063814 * x - 1.34811020) * x + 2.18555832) * x - 0.20219683;
    else if (T < 4000.0)
        y = ((-0.9549476 * x - 1.37418593) * x + 2.09137015) * x - 0.16748867;
    else
        y = ((3.0817580 * x - 5.87338670) * x + 3.75112997) * x - 0.37001483;
    return vec2(x, y);
}

// linear Rec.709 colour of unit luminance (Y = 1), negative channels clipped
vec3 mg_blackbody(float kelvin)
{
    vec2 c = mg_planckian_xy(kelvin);
    if (c.y <= 0.0)
        return vec3(1.0);
    vec3 XYZ = vec3(c.x / c.y, 1.0, (1.0 - c.x - c.y) / c.y);
    // XYZ -> linear Rec.709 (D65), derived from the ITU-R BT.709 primaries and white point
    const mat3 XYZ_TO_REC709 = mat3( 3.2409699, -0.9692436,  0.0556301,
                                    -1.5373832,  1.8759675, -0.2039770,
                                    -0.4986108,  0.0415551,  1.0569715);
    return max(XYZ_TO_REC709 * XYZ, vec3(0.0));
}
