// surface_unlit (MaterialX Specification 1.39, "surface_unlit"): emitted light scaled by opacity;
// transmission tints what lies behind, and a cut-out (opacity 0) lets everything through.
surfaceshader mg_surface_unlit(float emission, vec3 emission_color, float transmission,
                               vec3 transmission_color, float opacity)
{
    vec3 through = transmission * transmission_color;
    return surfaceshader(emission_color * (emission * opacity), mix(vec3(1.0), through, opacity));
}
