// requires: cmlib/srgb_transfer.glsl
// UsdUVTexture under the seed's rules (UsdPreviewSurface Specification 2.5, "Texture Reader"):
// wrap modes black / clamp / repeat / mirror applied to st here (independent of the sampler state),
// the 1-, 2- and 3-channel rules, the sRGB transfer curve on rgb when the source is sRGB, then
// output = texel * scale + bias. st (0, 0) is the image's lower-left corner.

#define MG_USD_WRAP_BLACK 0
#define MG_USD_WRAP_CLAMP 1
#define MG_USD_WRAP_REPEAT 2
#define MG_USD_WRAP_MIRROR 3

float mg_usd_wrap(float x, int mode)
{
    if (mode == MG_USD_WRAP_CLAMP)
        return clamp(x, 0.0, 1.0);
    if (mode == MG_USD_WRAP_REPEAT)
        return fract(x);
    if (mode == MG_USD_WRAP_MIRROR)
    {
        float m = mod(x, 2.0);
        return m > 1.0 ? 2.0 - m : m;
    }
    return x;
}

bool mg_usd_outside(float x, int mode)
{
    return mode == MG_USD_WRAP_BLACK && (x < 0.0 || x > 1.0);
}

vec4 mg_usd_uvtexture(sampler2D tex, vec2 st, int wrap_s, int wrap_t, int channels, bool srgb, vec4 scale,
                      vec4 bias)
{
    // black: the reader returns transparent black outside the unit square (scale and bias still apply)
    if (mg_usd_outside(st.x, wrap_s) || mg_usd_outside(st.y, wrap_t))
        return bias;
    vec2 uv = vec2(mg_usd_wrap(st.x, wrap_s), mg_usd_wrap(st.y, wrap_t));
    // gradients of the unwrapped st: no mip seam where repeat or mirror folds the coordinate
    vec4 t = textureGrad(tex, uv, dFdx(st), dFdy(st));
    if (channels == 1)
        t = vec4(t.rrr, 1.0);
    else if (channels == 2)
        t = vec4(t.rrr, t.g);
    else if (channels == 3)
        t.a = 1.0;
    if (srgb)
        t.rgb = mg_srgb_to_linear(t.rgb);
    return t * scale + bias;
}
