// Hex-tiling: each point blends three randomly transformed copies of the texture over a triangle grid (Mikkelsen 2022, "Practical Real-Time Hex-Tiling", JCGT 11(2); grid from Heitz & Neyret 2018).

// per-vertex random pair in [0,1)^2 (the sine hash the paper uses); .x drives rotation and offset.x, .y scale and offset.y
vec2 mg_hextile_hash(vec2 p)
{
    return fract(sin(vec2(dot(p, vec2(127.1, 311.7)), dot(p, vec2(269.5, 183.3)))) * 43758.5453);
}

// barycentric weights and the three vertex ids of the triangle holding st
void mg_hextile_grid(vec2 st, out vec3 w, out vec2 v1, out vec2 v2, out vec2 v3)
{
    st *= 2.0 * sqrt(3.0);
    vec2 skewed = vec2(st.x - 0.57735027 * st.y, 1.15470054 * st.y);
    vec2 base = floor(skewed);
    vec3 f = vec3(fract(skewed), 0.0);
    f.z = 1.0 - f.x - f.y;
    float s = step(0.0, -f.z);
    float s2 = 2.0 * s - 1.0;
    w = vec3(-f.z * s2, s - f.y * s2, s - f.x * s2);
    v1 = base + vec2(s, s);
    v2 = base + vec2(s, 1.0 - s);
    v3 = base + vec2(1.0 - s, s);
}

// a grid vertex in uv units (the skew undone, then the 2*sqrt(3) scaling)
vec2 mg_hextile_centre(vec2 id)
{
    return vec2(id.x + 0.5 * id.y, 0.86602540 * id.y) / (2.0 * sqrt(3.0));
}

// One tile's copy of the texture: rotated about its vertex, scaled and offset by amounts drawn from the ranges.
// rotation, scale and offset are the nodedef's randomness weights: each scales how far the draw reaches into its range.
struct mg_hextile_tile { vec2 uv; mat2 rot; float scale; };

mg_hextile_tile mg_hextile_transform(vec2 uv, vec2 id, float rotation, vec2 rotationrange, float scale,
                                     vec2 scalerange, float offset, vec2 offsetrange)
{
    vec2 h = mg_hextile_hash(id);
    float a = radians(mix(rotationrange.x, rotationrange.y, rotation * h.x));
    float s = mix(1.0, mix(scalerange.x, scalerange.y, h.y), scale);
    vec2 o = mix(vec2(offsetrange.x), vec2(offsetrange.y), offset * h);
    mat2 rot = mat2(cos(a), sin(a), -sin(a), cos(a));
    vec2 centre = mg_hextile_centre(id);
    return mg_hextile_tile(rot * (uv - centre) / s + centre + o, rot, s);
}

// Schlick's gain (Graphics Gems IV, 1994: "Fast alternatives to Perlin's bias and gain functions"): r < 0.5 steepens, r > 0.5 flattens
float mg_schlick_bias(float t, float r)
{
    return t / ((1.0 / r - 2.0) * (1.0 - t) + 1.0);
}

vec3 mg_schlick_gain(vec3 t, float r)
{
    r = clamp(r, 0.001, 0.999);
    vec3 g;
    for (int i = 0; i < 3; ++i)
        g[i] = t[i] < 0.5 ? 0.5 * mg_schlick_bias(2.0 * t[i], r) : 1.0 - 0.5 * mg_schlick_bias(2.0 - 2.0 * t[i], r);
    return g;
}

// Blend weights: barycentrics to the 7th power (the paper's exponent), optionally favouring the brighter copy
// (its section 3.2, contrast in [0,1]), then the falloff shapes the transition with Schlick's gain.
vec3 mg_hextile_weights(vec3 w, vec3 luma, float contrast, float falloff)
{
    vec3 W = mix(vec3(1.0), luma, contrast) * pow(w, vec3(7.0));
    W /= W.x + W.y + W.z;
    W = mg_schlick_gain(W, falloff);
    return W / (W.x + W.y + W.z);
}

// the three tiles whose copies meet at uv, and their barycentric weights
void mg_hextile_tiles(vec2 uv, float rotation, vec2 rotationrange, float scale, vec2 scalerange, float offset,
                      vec2 offsetrange, out vec3 w, out mg_hextile_tile t1, out mg_hextile_tile t2, out mg_hextile_tile t3)
{
    vec2 v1, v2, v3;
    mg_hextile_grid(uv, w, v1, v2, v3);
    t1 = mg_hextile_transform(uv, v1, rotation, rotationrange, scale, scalerange, offset, offsetrange);
    t2 = mg_hextile_transform(uv, v2, rotation, rotationrange, scale, scalerange, offset, offsetrange);
    t3 = mg_hextile_transform(uv, v3, rotation, rotationrange, scale, scalerange, offset, offsetrange);
}

vec4 mg_hextile_sample(sampler2D tex, mg_hextile_tile t, vec2 dx, vec2 dy)
{
    return textureGrad(tex, t.uv, t.rot * dx / t.scale, t.rot * dy / t.scale);
}

vec4 mg_hextiledimage(sampler2D tex, vec2 texcoord, vec2 tiling, float rotation, vec2 rotationrange, float scale,
                      vec2 scalerange, float offset, vec2 offsetrange, float falloff, float falloffcontrast,
                      vec3 lumacoeffs)
{
    vec2 uv = texcoord * tiling;
    vec3 w; mg_hextile_tile t1, t2, t3;
    mg_hextile_tiles(uv, rotation, rotationrange, scale, scalerange, offset, offsetrange, w, t1, t2, t3);
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    vec4 c1 = mg_hextile_sample(tex, t1, dx, dy), c2 = mg_hextile_sample(tex, t2, dx, dy), c3 = mg_hextile_sample(tex, t3, dx, dy);
    vec3 luma = vec3(dot(c1.rgb, lumacoeffs), dot(c2.rgb, lumacoeffs), dot(c3.rgb, lumacoeffs));
    vec3 W = mg_hextile_weights(w, luma, falloffcontrast, falloff);
    return W.x * c1 + W.y * c2 + W.z * c3;
}

// One tile's normal as height derivatives (the paper blends normal maps as derivatives of a height map): the
// slopes xy/|z| of its tangent-space normal, turned back by the tile's rotation: texture coordinates t = R uv
// give height gradients d/duv = R^T d/dt, so the bumps keep facing the light they face in the texture.
vec2 mg_hextile_slopes(sampler2D tex, mg_hextile_tile t, vec2 dx, vec2 dy, float g)
{
    vec3 n = mg_hextile_sample(tex, t, dx, dy).xyz * 2.0 - 1.0;
    n.y *= g;
    return transpose(t.rot) * (n.xy / max(abs(n.z), 1.0e-4));
}

vec3 mg_hextilednormalmap(sampler2D tex, vec2 texcoord, vec2 tiling, float rotation, vec2 rotationrange, float scale,
                          vec2 scalerange, float offset, vec2 offsetrange, float falloff, float strength, bool flip_g,
                          vec3 N, vec3 T, vec3 B)
{
    vec2 uv = texcoord * tiling;
    vec3 w; mg_hextile_tile t1, t2, t3;
    mg_hextile_tiles(uv, rotation, rotationrange, scale, scalerange, offset, offsetrange, w, t1, t2, t3);
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    float g = flip_g ? -1.0 : 1.0;
    vec2 d1 = mg_hextile_slopes(tex, t1, dx, dy, g), d2 = mg_hextile_slopes(tex, t2, dx, dy, g),
         d3 = mg_hextile_slopes(tex, t3, dx, dy, g);
    vec3 W = mg_hextile_weights(w, vec3(1.0), 0.0, falloff);
    vec2 slopes = (W.x * d1 + W.y * d2 + W.z * d3) * strength;
    return normalize(T * slopes.x + B * slopes.y + N);
}
