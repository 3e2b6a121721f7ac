// mix of shader values (MaterialX Specification 1.39, "mix"): every member of the closure value is
// blended linearly, bg * (1 - mix) + fg * mix.
surfaceshader mg_mix_surfaceshader(surfaceshader fg, surfaceshader bg, float amount)
{
    return surfaceshader(mix(bg.color, fg.color, amount), mix(bg.transparency, fg.transparency, amount));
}

volumeshader mg_mix_volumeshader(volumeshader fg, volumeshader bg, float amount)
{
    return volumeshader(mix(bg.color, fg.color, amount), mix(bg.transparency, fg.transparency, amount));
}

displacementshader mg_mix_displacementshader(displacementshader fg, displacementshader bg, float amount)
{
    return displacementshader(mix(bg.offset, fg.offset, amount), mix(bg.scale, fg.scale, amount));
}

// BSDF and VDF values (pbrlib's mix of closures): both what they return and what they let through.
// The weight is held to [0, 1] (the spec's range): outside it a "mix" of two closures would subtract one
// from the other and return negative light (pbrt's MixMaterial clamps its weights the same way).
BSDF mg_mix_BSDF(BSDF fg, BSDF bg, float amount)
{
    amount = clamp(amount, 0.0, 1.0);
    return BSDF(mix(bg.response, fg.response, amount), mix(bg.throughput, fg.throughput, amount));
}

VDF mg_mix_VDF(VDF fg, VDF bg, float amount)
{
    amount = clamp(amount, 0.0, 1.0);
    return VDF(mix(bg.response, fg.response, amount), mix(bg.throughput, fg.throughput, amount));
}
