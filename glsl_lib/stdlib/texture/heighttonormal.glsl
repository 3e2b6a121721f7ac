// Height -> [0,1]-encoded tangent-space normal: the height's screen-space gradient taken back to uv by the chain rule (Mikkelsen 2010, "Bump Mapping Unparametrized Surfaces on the GPU").
#define MG_HEIGHT_TO_NORMAL_SCALE (1.0 / 16.0)     // slope units: height per 1/16 of uv
vec3 mg_heighttonormal(float h, float scale, vec2 uv)
{
    vec2 dh = vec2(dFdx(h), dFdy(h));
    mat2 j = mat2(dFdx(uv), dFdy(uv));          // columns: d(uv)/dx, d(uv)/dy; dh/dxy = transpose(j) * dh/duv
    float det = determinant(j);
    vec2 grad = abs(det) > 1e-14 ? inverse(transpose(j)) * dh : vec2(0.0);
    return normalize(vec3(-grad * scale * MG_HEIGHT_TO_NORMAL_SCALE, 1.0)) * 0.5 + 0.5;
}
