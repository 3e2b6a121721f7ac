// Combining closures (MaterialX Specification 1.39, pbrlib "layer", "add", "multiply"): a BSDF (or VDF)
// carries its response and the share of light it lets through to what lies below (albedo scaling).
// One definition serves both closure structs.

#define MG_CLOSURE_COMBINATORS(T)                                                       \
    BSDF mg_layer(T top, BSDF base)                                                     \
    {                                                                                   \
        return BSDF(top.response + top.throughput * base.response,                      \
                    top.throughput * base.throughput);                                  \
    }                                                                                   \
    T mg_add(T a, T b) { return T(a.response + b.response, a.throughput * b.throughput); } \
    T mg_scale(T c, vec3 w) { return T(c.response * w, c.throughput); }                 \
    T mg_scale(T c, float w) { return T(c.response * w, c.throughput); }

MG_CLOSURE_COMBINATORS(BSDF)
MG_CLOSURE_COMBINATORS(VDF)
