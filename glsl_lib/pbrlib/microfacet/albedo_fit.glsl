// Directional albedo of GGX reflection with height-correlated Smith G2 (Heitz 2014), split over
// Schlick weights: the mirror limit plus a least-squares polynomial in x = 1 - sqrt(mu), y = sqrt(alpha)
// (total degree 6, every term with y) fitted to the table of tools/ggx_albedo.py; max error 0.0414. Generated.
vec2 mg_ggx_albedo_fit(float mu, float alpha)
{
    float x = 1.0 - sqrt(clamp(mu, 0.0, 1.0)), y = sqrt(clamp(alpha, 0.0, 1.0));
    float s = pow(1.0 - clamp(mu, 0.0, 1.0), 5.0);
    float A = 1.0 - s + ((((((-4.631333) * y) * x
        + ((9.046821) * y - 5.485576) * y) * x
        + (((24.41119) * y - 54.68778) * y + 33.26733) * y) * x
        + ((((24.22812) * y - 79.56849) * y + 84.62872) * y - 30.10825) * y) * x
        + (((((-4.128512) * y - 7.446166) * y + 34.69147) * y - 30.45244) * y + 7.852942) * y) * x
        + ((((((-0.5922903) * y + 2.313107) * y + 0.05669814) * y - 4.547024) * y + 2.513082) * y - 0.4364915) * y;
    float B = s + ((((((3.597971) * y) * x
        + ((-9.149964) * y + 7.021188) * y) * x
        + (((-13.2369) * y + 36.45546) * y - 26.56199) * y) * x
        + ((((-3.538016) * y + 21.21062) * y - 32.47758) * y + 15.91657) * y) * x
        + (((((8.928504) * y - 24.46766) * y + 21.09585) * y - 4.700481) * y - 0.9790764) * y) * x
        + ((((((-0.08705463) * y - 1.593784) * y + 4.788008) * y - 4.711131) * y + 1.808107) * y - 0.2018923) * y;
    return clamp(vec2(A, B), 0.0, 1.0);
}
