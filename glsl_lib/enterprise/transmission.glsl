// requires: constants.glsl
// What a transparent Enterprise PBR surface lets through (DSPBR 2025x, "Transparency" and "Volume"):
// a volumetric object is taken as a solid sphere (the render harness's unit sphere) that the view ray
// refracts into and out of; its medium absorbs by Beer-Lambert with attenuationColor reached at
// attenuationDistance.

// Direction leaving a unit solid sphere of relative IOR eta entered at outward normal N along I, and the
// chord length inside (Snell's law at both interfaces; the exit point is N + chord * R1).
vec3 mg_epbr_refract_sphere(vec3 I, vec3 N, float eta, out float chord)
{
    vec3 R1 = refract(I, N, 1.0 / max(eta, 1.0e-4));
    chord = 0.0;
    if (dot(R1, R1) < 1.0e-8)
        return reflect(I, N);
    chord = 2.0 * max(-dot(R1, N), 0.0);
    vec3 N2 = normalize(N + chord * R1);           // outward normal at the exit point
    vec3 R2 = refract(R1, -N2, eta);
    return dot(R2, R2) < 1.0e-8 ? R1 : R2;
}

// Beer-Lambert transmittance over a path: attenuationColor^(length / attenuationDistance).
vec3 mg_epbr_attenuation(vec3 color, float distance, float len)
{
    if (distance >= 1.0e30 || len <= 0.0)
        return vec3(1.0);
    return exp(log(clamp(color, vec3(1.0e-6), vec3(1.0))) * (len / max(distance, 1.0e-6)));
}
