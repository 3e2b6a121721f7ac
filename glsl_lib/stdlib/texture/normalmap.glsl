// Tangent-space normal maps: [0,1]-encoded xyz -> world-space normal in the (T, B, N) frame (MaterialX Specification 1.39, "normalmap").
vec3 mg_normalmap(vec3 encoded, vec2 scale, vec3 N, vec3 T, vec3 B)
{
    // an all-zero texel carries no normal (a black or missing map): the surface keeps its own, as in MaterialX
    if (encoded == vec3(0.0))
        return N;
    vec3 v = encoded * 2.0 - 1.0;
    v.xy *= scale;
    return normalize(T * v.x + B * v.y + N * v.z);
}

vec3 mg_normalmap(vec3 encoded, float scale, vec3 N, vec3 T, vec3 B)
{
    return mg_normalmap(encoded, vec2(scale), N, T, B);
}
