// rgbtohsv (Smith 1978, "Color Gamut Transform Pairs", the hexcone model): hue in [0, 1) turns
// through red, yellow, green, cyan, blue, magenta; saturation (max - min) / max; value max.
vec3 mg_rgbtohsv(vec3 c)
{
    float hi = max(c.r, max(c.g, c.b));
    float lo = min(c.r, min(c.g, c.b));
    float delta = hi - lo;
    float s = hi > 0.0 ? delta / hi : 0.0;
    float h = 0.0;
    if (s > 0.0)
    {
        if (c.r >= hi)
            h = (c.g - c.b) / delta;
        else if (c.g >= hi)
            h = 2.0 + (c.b - c.r) / delta;
        else
            h = 4.0 + (c.r - c.g) / delta;
        h /= 6.0;
        if (h < 0.0)
            h += 1.0;
    }
    return vec3(h, s, hi);
}

vec4 mg_rgbtohsv(vec4 c)
{
    return vec4(mg_rgbtohsv(c.rgb), c.a);
}
