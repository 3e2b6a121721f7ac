// The scatter_mode enum of the microfacet BSDF nodes (MaterialX Specification 1.39, pbrlib): reflection,
// transmission, or both; templates spell it mg_scatter_{{=scatter_mode}}.
const int mg_scatter_R = 0;
const int mg_scatter_T = 1;
const int mg_scatter_RT = 2;
