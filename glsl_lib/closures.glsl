// Closure value types of MaterialX's GLSL semantics (MaterialX Specification 1.39, "Shader Types").
// A BSDF carries what it reflects toward the viewer and the share of light it lets through below it.
struct BSDF { vec3 response; vec3 throughput; };
struct VDF { vec3 response; vec3 throughput; };
#define EDF vec3
struct surfaceshader { vec3 color; vec3 transparency; };
struct volumeshader { vec3 color; vec3 transparency; };
struct displacementshader { vec3 offset; float scale; };
struct lightshader { vec3 intensity; vec3 direction; };
