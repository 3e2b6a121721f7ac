// smoothstep (MaterialX Specification 1.39): 0 at or below low, 1 at or above high, the Hermite
// cubic 3t^2 - 2t^3 in between; also defined when low >= high (a step at high).
float mg_smoothstep(float x, float low, float high)
{
    if (x >= high)
        return 1.0;
    if (x <= low)
        return 0.0;
    float t = (x - low) / (high - low);
    return t * t * (3.0 - 2.0 * t);
}
