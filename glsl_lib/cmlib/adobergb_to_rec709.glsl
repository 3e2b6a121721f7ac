// Linear Adobe RGB (1998) -> linear Rec.709, both D65 (Adobe RGB (1998) Color Image Encoding section 4.3.1; ITU-R BT.709-6); derived from the published chromaticities.
vec3 mg_adobergb_to_rec709(vec3 c)
{
    const mat3 m = mat3( 1.398355744,  0.0,          0.0,
                        -0.398355744,  1.0,         -0.042928989,
                         0.0,          0.0,          1.042928989);
    return m * c;
}
