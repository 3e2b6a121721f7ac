// hsvtorgb (Smith 1978, "Color Gamut Transform Pairs", the hexcone model): the inverse of
// rgbtohsv; hue wraps modulo 1 and picks one of six sectors of the hexcone; no (or negative)
// saturation is the achromatic axis, grey of the value.
vec3 mg_hsvtorgb(vec3 hsv)
{
    float h = fract(hsv.x) * 6.0;
    float s = hsv.y;
    float v = hsv.z;
    if (s <= 0.0)
        return vec3(v);
    float sector = floor(h);
    float f = h - sector;
    float p = v * (1.0 - s);
    float q = v * (1.0 - s * f);
    float t = v * (1.0 - s * (1.0 - f));
    if (sector < 1.0)
        return vec3(v, t, p);
    if (sector < 2.0)
        return vec3(q, v, p);
    if (sector < 3.0)
        return vec3(p, v, t);
    if (sector < 4.0)
        return vec3(p, q, v);
    if (sector < 5.0)
        return vec3(t, p, v);
    return vec3(v, p, q);
}

vec4 mg_hsvtorgb(vec4 c)
{
    return vec4(mg_hsvtorgb(c.rgb), c.a);
}
