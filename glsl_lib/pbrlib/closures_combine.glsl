// Combining closures (MaterialX Specification 1.39, pbrlib "layer", "add", "multiply"): a BSDF carries
// its response and the share of light it lets through to what lies below (albedo scaling).

BSDF mg_layer(BSDF top, BSDF base)
{
    return BSDF(top.response + top.throughput * base.response, top.throughput * base.throughput);
}

BSDF mg_add(BSDF a, BSDF b)
{
    return BSDF(a.response + b.response, a.throughput * b.throughput);
}

BSDF mg_scale(BSDF b, vec3 w)
{
    return BSDF(b.response * w, b.throughput);
}

BSDF mg_scale(BSDF b, float w)
{
    return BSDF(b.response * w, b.throughput);
}

// the same for volumes: a VDF's response and the share of light that passes
BSDF mg_layer(VDF top, BSDF base)
{
    return BSDF(top.response + top.throughput * base.response, top.throughput * base.throughput);
}

VDF mg_add(VDF a, VDF b)
{
    return VDF(a.response + b.response, a.throughput * b.throughput);
}

VDF mg_scale(VDF b, vec3 w)
{
    return VDF(b.response * w, b.throughput);
}

VDF mg_scale(VDF b, float w)
{
    return VDF(b.response * w, b.throughput);
}
