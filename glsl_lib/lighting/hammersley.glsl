// The Hammersley point set: point i of n is (i / n, radical inverse of i in base 2) (Hammersley 1964;
// Pharr et al., "Physically Based Rendering", sec. 7.4).
vec2 mg_hammersley(int i, int n)
{
    return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(uint(i))) * 2.3283064365386963e-10);
}
