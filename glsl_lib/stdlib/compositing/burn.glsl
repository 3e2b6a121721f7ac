// burn (MaterialX Specification 1.39, "Blend Nodes"): 1 - (1 - B) / F per channel, mixed over B;
// where F is zero the blend is undefined and the result is 0.
float mg_burn(float fg, float bg, float amount)
{
    if (abs(fg) < 1.0e-6)
        return 0.0;
    return mix(bg, 1.0 - (1.0 - bg) / fg, amount);
}

vec3 mg_burn(vec3 fg, vec3 bg, float amount)
{
    return vec3(mg_burn(fg.x, bg.x, amount), mg_burn(fg.y, bg.y, amount), mg_burn(fg.z, bg.z, amount));
}

vec4 mg_burn(vec4 fg, vec4 bg, float amount)
{
    return vec4(mg_burn(fg.xyz, bg.xyz, amount), mg_burn(fg.w, bg.w, amount));
}
