// requires: closures.glsl
// layer (MaterialX Specification 1.39, pbrlib) of a BSDF over a VDF: the medium below the interface
// attenuates what the BSDF lets through (its throughput, in the "transmission" context where a VDF is
// not empty) and adds what it scatters itself; other contexts see the empty VDF (response 0, throughput 1).
BSDF mg_layer(BSDF top, VDF base)
{
    return BSDF(top.response * base.throughput + base.response, top.throughput * base.throughput);
}
