// Hair absorption from a colour: Chiang et al. 2016, "A Practical and Controllable Hair and Fur Model for Production Path Tracing", eq. 9.

// σa = (ln(colour) / (5.969 − 0.215βn + 2.532βn² − 10.73βn³ + 5.574βn⁴ + 0.245βn⁵))², βn the azimuthal
// roughness; the colour is kept in [0.001, 1] (white absorbs nothing, black stays finite)
vec3 mg_chiang_hair_absorption_from_color(vec3 color, float azimuthal_roughness)
{
    float b = azimuthal_roughness;
    float d = 5.969 + b * (-0.215 + b * (2.532 + b * (-10.73 + b * (5.574 + b * 0.245))));
    vec3 s = log(clamp(color, 1.0e-3, 1.0)) / d;
    return s * s;
}
