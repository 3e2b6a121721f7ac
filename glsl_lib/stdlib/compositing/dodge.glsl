// dodge (MaterialX Specification 1.39, "Blend Nodes"): B / (1 - F) per channel, mixed over B;
// where F is one the blend is undefined and the result is 0.
float mg_dodge(float fg, float bg, float amount)
{
    if (abs(1.0 - fg) < 1.0e-6)
        return 0.0;
    return mix(bg, bg / (1.0 - fg), amount);
}

vec3 mg_dodge(vec3 fg, vec3 bg, float amount)
{
    return vec3(mg_dodge(fg.x, bg.x, amount), mg_dodge(fg.y, bg.y, amount), mg_dodge(fg.z, bg.z, amount));
}

vec4 mg_dodge(vec4 fg, vec4 bg, float amount)
{
    return vec4(mg_dodge(fg.xyz, bg.xyz, amount), mg_dodge(fg.w, bg.w, amount));
}
