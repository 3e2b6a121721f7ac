// Hex-tiling: each point blends three randomly transformed copies of the texture over a triangle grid (Mikkelsen 2022, "Practical Real-Time Hex-Tiling", JCGT 11(2); grid from Heitz & Neyret 2018).
// requires: stdlib/texture/normalmap.glsl
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

// per-tile transform of uv: rotation (radians), scale and offset drawn from the ranges, blended in by strength
mat2 mg_hextile_rotation(vec2 id, float strength, vec2 range_deg)
{
    float a = radians(mix(range_deg.x, range_deg.y, mg_hextile_hash(id).x)) * strength;
    return mat2(cos(a), sin(a), -sin(a), cos(a));
}

vec2 mg_hextile_uv(vec2 uv, vec2 id, float rotation, vec2 rotationrange, float scale, vec2 scalerange,
                   float offset, vec2 offsetrange, out mat2 rot)
{
    vec2 h = mg_hextile_hash(id + vec2(0.5));
    rot = mg_hextile_rotation(id, rotation, rotationrange);
    float s = mix(1.0, mix(scalerange.x, scalerange.y, h.x), scale);
    vec2 o = mix(vec2(0.0), mix(vec2(offsetrange.x), vec2(offsetrange.y), h), offset);
    vec2 centre = id * vec2(0.5, 0.86602540) / sqrt(3.0);          // the vertex in uv units
    return rot * (uv - centre) / s + centre + o;
}

vec3 mg_hextile_weights(vec3 w, float falloff)
{
    w = pow(max(w, vec3(1e-6)), vec3(1.0 + 6.0 * falloff));
    return w / (w.x + w.y + w.z);
}

vec4 mg_hextiledimage(sampler2D tex, vec2 texcoord, vec2 tiling, float rotation, vec2 rotationrange, float scale,
                      vec2 scalerange, float offset, vec2 offsetrange, float falloff, float falloffcontrast,
                      vec3 lumacoeffs)
{
    vec2 uv = texcoord * tiling;
    vec3 w; vec2 v1, v2, v3;
    mg_hextile_grid(uv, w, v1, v2, v3);
    mat2 r1, r2, r3;
    vec2 uv1 = mg_hextile_uv(uv, v1, rotation, rotationrange, scale, scalerange, offset, offsetrange, r1);
    vec2 uv2 = mg_hextile_uv(uv, v2, rotation, rotationrange, scale, scalerange, offset, offsetrange, r2);
    vec2 uv3 = mg_hextile_uv(uv, v3, rotation, rotationrange, scale, scalerange, offset, offsetrange, r3);
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    vec4 c1 = textureGrad(tex, uv1, r1 * dx, r1 * dy);
    vec4 c2 = textureGrad(tex, uv2, r2 * dx, r2 * dy);
    vec4 c3 = textureGrad(tex, uv3, r3 * dx, r3 * dy);
    // luminance-weighted blend: brighter features win at the seams (the paper's section 3.2)
    vec3 luma = vec3(dot(c1.rgb, lumacoeffs), dot(c2.rgb, lumacoeffs), dot(c3.rgb, lumacoeffs));
    vec3 wl = w * pow(max(luma, vec3(1e-4)), vec3(4.0 * falloffcontrast));
    vec3 ww = mg_hextile_weights(wl / max(wl.x + wl.y + wl.z, 1e-6), falloff);
    return ww.x * c1 + ww.y * c2 + ww.z * c3;
}

vec3 mg_hextilednormalmap(sampler2D tex, vec2 texcoord, vec2 tiling, float rotation, vec2 rotationrange, float scale,
                          vec2 scalerange, float offset, vec2 offsetrange, float falloff, float strength, bool flip_g,
                          vec3 N, vec3 T, vec3 B)
{
    vec2 uv = texcoord * tiling;
    vec3 w; vec2 v1, v2, v3;
    mg_hextile_grid(uv, w, v1, v2, v3);
    mat2 r1, r2, r3;
    vec2 uv1 = mg_hextile_uv(uv, v1, rotation, rotationrange, scale, scalerange, offset, offsetrange, r1);
    vec2 uv2 = mg_hextile_uv(uv, v2, rotation, rotationrange, scale, scalerange, offset, offsetrange, r2);
    vec2 uv3 = mg_hextile_uv(uv, v3, rotation, rotationrange, scale, scalerange, offset, offsetrange, r3);
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    float g = flip_g ? -1.0 : 1.0;
    // tangent-space xy rotate back with their tile so the bumps stay consistent
    vec3 n1 = textureGrad(tex, uv1, r1 * dx, r1 * dy).xyz * 2.0 - 1.0;
    vec3 n2 = textureGrad(tex, uv2, r2 * dx, r2 * dy).xyz * 2.0 - 1.0;
    vec3 n3 = textureGrad(tex, uv3, r3 * dx, r3 * dy).xyz * 2.0 - 1.0;
    n1.xy = transpose(r1) * (n1.xy * vec2(1.0, g));
    n2.xy = transpose(r2) * (n2.xy * vec2(1.0, g));
    n3.xy = transpose(r3) * (n3.xy * vec2(1.0, g));
    vec3 ww = mg_hextile_weights(w, falloff);
    vec3 n = ww.x * n1 + ww.y * n2 + ww.z * n3;
    n.xy *= strength;
    return mg_normalmap(n * 0.5 + 0.5, 1.0, N, T, B);
}
