// Stride's diffuse models (Stride manual, "Shading attributes" > Diffuse model; formulas in
// docs/material-models.md sec. 5). Lambert reflects diffuse / pi * light * NL; cel shading replaces NL
// by a ramp of it.

// Default cel-shading ramp: NL > 0.8 -> 1, > 0.5 -> 0.8, > 0.2 -> 0.3, else 0 (Stride docs, cel shading "Default").
vec3 mg_stride_cel_default(float x)
{
    return vec3(x > 0.8 ? 1.0 : (x > 0.5 ? 0.8 : (x > 0.2 ? 0.3 : 0.0)));
}

// Black-and-white cel-shading ramp: NL > 0.2 -> 1, else 0 (Stride docs, cel shading "Black and white").
vec3 mg_stride_cel_black_white(float x)
{
    return vec3(x > 0.2 ? 1.0 : 0.0);
}

// Cel-shading ramp texture: a 1-D ramp read at (sat(NL), 0.5) (Stride docs, cel shading "Ramp"); u is
// kept within the end texels' centres, which reads as clamp-to-edge whatever the sampler's wrap mode.
vec3 mg_stride_cel_texture(sampler2D ramp, float x)
{
    float half_texel = 0.5 / float(textureSize(ramp, 0).x);
    return texture(ramp, vec2(clamp(x, half_texel, 1.0 - half_texel), 0.5)).rgb;
}
