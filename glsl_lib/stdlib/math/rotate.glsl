// requires: constants.glsl
// rotate2d / rotate3d (MaterialX Specification 1.39): angles in degrees. As MaterialX's own renders do
// (and so every material authored against them), a positive amount turns clockwise about the axis.

vec2 mg_rotate2d(vec2 p, float degrees)
{
    float a = -radians(degrees);
    float c = cos(a);
    float s = sin(a);
    return vec2(c * p.x - s * p.y, s * p.x + c * p.y);
}

// Rodrigues' rotation formula about a (normalised) axis.
vec3 mg_rotate3d(vec3 p, float degrees, vec3 axis)
{
    vec3 k = normalize(axis);
    float a = -radians(degrees);
    float c = cos(a);
    return p * c + cross(k, p) * sin(a) + k * (dot(k, p) * (1.0 - c));
}
