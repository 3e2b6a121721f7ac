// Hair lobe roughness: Chiang et al. 2016, "A Practical and Controllable Hair and Fur Model for Production Path Tracing", eqs. 7-8.

// longitudinal variance v = (0.726βm + 0.812βm² + 3.7βm²⁰)²
float mg_chiang_hair_longitudinal_variance(float beta_m)
{
    float b = clamp(beta_m, 0.001, 1.0);
    float v = 0.726 * b + 0.812 * b * b + 3.7 * pow(b, 20.0);
    return v * v;
}

// logistic scale s = 0.265βn + 1.194βn² + 5.372βn²²
float mg_chiang_hair_azimuthal_scale(float beta_n)
{
    float b = clamp(beta_n, 0.001, 1.0);
    return 0.265 * b + 1.194 * b * b + 5.372 * pow(b, 22.0);
}

// (longitudinal variance, azimuthal scale) of a lobe whose longitudinal deviation is scaled by `scale`
// (Marschner et al. 2003: the TT lobe is about half as wide as R, TRT twice)
vec2 mg_chiang_hair_roughness(float longitudinal, float azimuthal, float scale)
{
    return vec2(mg_chiang_hair_longitudinal_variance(longitudinal) * scale * scale, mg_chiang_hair_azimuthal_scale(azimuthal));
}
