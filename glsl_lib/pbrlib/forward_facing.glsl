// Shading normals for BSDFs: made unit length (an authored or connected normal need not be) and turned towards the viewer: n when n.v >= 0, else -n (the face-forward rule of Pharr, Jakob & Humphreys, "Physically Based Rendering" 3rd ed., sec. 2.4, FaceForward).
vec3 mg_forward_facing(vec3 n, vec3 v)
{
    n = normalize(n);
    return dot(n, v) < 0.0 ? -n : n;
}
