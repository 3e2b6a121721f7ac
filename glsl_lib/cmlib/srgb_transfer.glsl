// sRGB electro-optical transfer function, encoded -> linear (IEC 61966-2-1:1999, section 4.7).
float mg_srgb_to_linear(float c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

vec3 mg_srgb_to_linear(vec3 c)
{
    return vec3(mg_srgb_to_linear(c.r), mg_srgb_to_linear(c.g), mg_srgb_to_linear(c.b));
}
