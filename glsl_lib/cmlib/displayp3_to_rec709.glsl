// Linear Display P3 (SMPTE EG 432-1 DCI-P3 primaries, D65 white) -> linear Rec.709 (ITU-R BT.709-6); derived from the published chromaticities.
vec3 mg_displayp3_to_rec709(vec3 c)
{
    const mat3 m = mat3( 1.224940176, -0.042056955, -0.019637555,
                        -0.224940176,  1.042056955, -0.078636046,
                         0.0,          0.0,          1.098273600);
    return m * c;
}
