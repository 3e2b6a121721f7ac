// Reflectivity and edge tint to complex IOR (Gulbrandsen 2014, "Artist Friendly Metallic Fresnel", JCGT 3(4), eqs. 8-9).

// the reflectivity, kept below 1 so that the inversion stays finite
vec3 mg_artistic_ior_r(vec3 reflectivity)
{
    return clamp(reflectivity, 0.0, 0.99);
}

// n = g·n_min + (1 − g)·n_max, with n_min = (1 − r)/(1 + r) and n_max = (1 + √r)/(1 − √r)
vec3 mg_artistic_ior_n(vec3 reflectivity, vec3 edge_color)
{
    vec3 r = mg_artistic_ior_r(reflectivity);
    vec3 sr = sqrt(r);
    vec3 n_min = (1.0 - r) / (1.0 + r);
    vec3 n_max = (1.0 + sr) / (1.0 - sr);
    return mix(n_max, n_min, edge_color);
}

// k² = ((n + 1)²·r − (n − 1)²) / (1 − r)
vec3 mg_artistic_ior_k(vec3 reflectivity, vec3 edge_color)
{
    vec3 r = mg_artistic_ior_r(reflectivity);
    vec3 n = mg_artistic_ior_n(reflectivity, edge_color);
    vec3 np1 = n + 1.0;
    vec3 nm1 = n - 1.0;
    vec3 k2 = (np1 * np1 * r - nm1 * nm1) / (1.0 - r);
    return sqrt(max(k2, 0.0));
}
