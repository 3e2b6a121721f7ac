// requires: constants.glsl
// measured_edf (MaterialX Specification 1.39, pbrlib): emission `color` shaped by an IES LM-63
// photometric profile (IES LM-63-2002, type C), read from the 2-D texture mtlxgen/ies.py makes of it:
// intensity / peak intensity, u = horizontal angle / 360° (columns at multiples of 360° / width),
// v = vertical angle / 180° (rows at multiples of 180° / (height - 1)), vertical angle 0 along the normal.

// An orthonormal basis about n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void mg_ies_basis(vec3 n, out vec3 t, out vec3 b)
{
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

vec3 mg_measured_edf(sampler2D profile, vec3 V, vec3 color, vec3 N)
{
    vec3 n = normalize(N);
    vec3 t, b;
    mg_ies_basis(n, t, b);
    float theta = acos(clamp(dot(n, V), -1.0, 1.0));
    float phi = atan(dot(V, b), dot(V, t));
    if (phi < 0.0)
        phi += MG_TWO_PI;
    vec2 size = vec2(textureSize(profile, 0));
    // texel centres: columns wrap around in phi, rows span theta from 0 to pi inclusive
    vec2 uv = vec2(phi / MG_TWO_PI + 0.5 / size.x, (theta / MG_PI * (size.y - 1.0) + 0.5) / size.y);
    return color * textureLod(profile, uv, 0.0).r;
}
