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
