// Linear ACES AP1 (ACEScg, SMPTE ST 2065-1 / Academy S-2014-004 primaries, ACES white) -> linear Rec.709 (ITU-R BT.709-6, D65), Bradford-adapted; derived from the published chromaticities.
vec3 mg_ap1_to_rec709(vec3 c)
{
    const mat3 m = mat3( 1.705050993, -0.130256418, -0.024003357,    // columns: the contribution of R, G, B
                        -0.621792121,  1.140804737, -0.128968976,
                        -0.083258872, -0.010548319,  1.152972333);
    return m * c;
}
