// requires: constants.glsl
// The dielectric's diffuse term coupled to its specular lobe (Kelemen & Szirmay-Kalos 2001, "A Microfacet
// Based Coupled Specular-Matte BRDF Model with Importance Sampling"; DSPBR 2025x, "Energy compensation"):
// B = (1 - E(mu_l)) (1 - E(mu_v)) / (pi (1 - E_avg)), E the albedo of the specular lobe above it.
// Reciprocal, and specular + B reflects all light for a white albedo (the white furnace).
vec3 mg_epbr_diffuse_complement(vec3 e_l, vec3 e_v, vec3 e_avg)
{
    return (1.0 - e_l) * (1.0 - e_v) / (MG_PI * max(1.0 - e_avg, vec3(1.0e-4)));
}
