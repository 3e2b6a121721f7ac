// disjointover (Porter & Duff 1984, "Compositing Digital Images", with the disjoint-coverage
// assumption): F + B when f + b <= 1, else F + B (1 - f) / b; alpha min(f + b, 1); mixed over B.
vec4 mg_disjointover(vec4 fg, vec4 bg, float amount)
{
    float coverage = fg.a + bg.a;
    vec3 rgb = fg.rgb + bg.rgb;
    if (coverage > 1.0)
        rgb = abs(bg.a) < 1.0e-6 ? vec3(0.0) : fg.rgb + bg.rgb * ((1.0 - fg.a) / bg.a);
    return mix(bg, vec4(rgb, min(coverage, 1.0)), amount);
}
