// luminance (MaterialX Specification 1.39): the weighted sum of rgb with lumacoeffs, as a grey colour.
vec3 mg_luminance(vec3 c, vec3 coeffs)
{
    return vec3(dot(c, coeffs));
}

vec4 mg_luminance(vec4 c, vec3 coeffs)
{
    return vec4(vec3(dot(c.rgb, coeffs)), c.a);
}
