// requires: closures.glsl lighting/environment.glsl pbrlib/irradiance_behind.glsl pbrlib/vdf/absorption.glsl
// anisotropic_vdf (MaterialX Specification 1.39, pbrlib) applied to what is seen through a surface
// (over the path length of absorption.glsl):
// the unscattered light falls by Beer–Lambert over the extinction σt = σa + σs; the share scattered
// back towards the eye, albedo (σs / σt) times (1 - exp(-σt d)), is single-scattered environment light
// whose Henyey–Greenstein (1941) anisotropy g blends the ambient average (g <= 0) towards the light
// from straight behind (g -> 1).
VDF mg_anisotropic_vdf(vec3 absorption, vec3 scattering, float anisotropy, vec3 N, vec3 V)
{
    vec3 sigma_s = max(scattering, vec3(0.0));
    vec3 sigma_t = max(absorption, vec3(0.0)) + sigma_s;
    vec3 T = exp(-sigma_t * mg_vdf_path_length());
    vec3 albedo = sigma_s / max(sigma_t, vec3(1.0e-6));
    vec3 ambient = 0.5 * (mg_env_irradiance(N) + mg_env_irradiance_behind(N));
    vec3 behind = mg_env_radiance(-V, 0.0);
    vec3 inscatter = mix(ambient, behind, clamp(anisotropy, 0.0, 1.0));
    return VDF(albedo * (1.0 - T) * inscatter, T);
}
