// smoothstep (MaterialX Specification 1.39): 0 at or below low, 1 at or above high, the Hermite
// cubic 3t^2 - 2t^3 in between; also defined when low >= high (a step at high). The value stays in
// [0, 1] whatever arrives: an undefined input (NaN, e.g. from pow of a negative base upstream) reads
// as below low, 0, as the clamped cubic MaterialX's GLSL calls gives there, not an undefined pixel.
float mg_smoothstep(float x, float low, float high)
{
    if (x >= high)
        return 1.0;
    if (!(x > low))
        return 0.0;
    float t = (x - low) / (high - low);
    return t * t * (3.0 - 2.0 * t);
}
