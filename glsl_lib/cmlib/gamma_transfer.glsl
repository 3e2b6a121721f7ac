// Pure power-law decoding, encoded -> linear: 2.2 and 1.8 gammas, BT.1886's 2.4 and Adobe RGB (1998)'s 563/256 (Adobe RGB (1998) Color Image Encoding, section 4.3.4.2).
vec3 mg_gamma_to_linear(vec3 c, float gamma)
{
    return pow(max(c, vec3(0.0)), vec3(gamma));
}
