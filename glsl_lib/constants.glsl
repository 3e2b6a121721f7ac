// Numeric constants shared by glsl_lib files.
const float MG_PI = 3.14159265358979323846;
const float MG_TWO_PI = 6.28318530717958647692;
const float MG_EPS = 1.0e-8;
