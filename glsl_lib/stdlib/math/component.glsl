// Smallest and largest channel of a vector (MaterialX Specification, Standard Nodes: "mincomponent", "maxcomponent").
float mg_mincomponent(vec2 v) { return min(v.x, v.y); }
float mg_mincomponent(vec3 v) { return min(min(v.x, v.y), v.z); }
float mg_mincomponent(vec4 v) { return min(min(v.x, v.y), min(v.z, v.w)); }
float mg_maxcomponent(vec2 v) { return max(v.x, v.y); }
float mg_maxcomponent(vec3 v) { return max(max(v.x, v.y), v.z); }
float mg_maxcomponent(vec4 v) { return max(max(v.x, v.y), max(v.z, v.w)); }
