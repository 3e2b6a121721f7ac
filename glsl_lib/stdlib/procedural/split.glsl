// Antialiased step after Stefan Gustavson, "Procedural Textures in GLSL" (OpenGL Insights, 2012, ch. 22).

// smoothstep across the value's screen-space footprint (gradient length over sqrt 2) about the threshold
float mg_aastep(float threshold, float value)
{
    float w = 0.70710678 * length(vec2(dFdx(value), dFdy(value)));
    return smoothstep(threshold - w, threshold + w, value);
}
