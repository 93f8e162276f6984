// aniso/core/platform.glsl: GLSL twin of platform.h: the numeric constants every kernel uses.
//
// The GLSL library mirrors include/aniso function for function (docs/glsl.md has the naming rule).
// Files carry no #version and no preprocessor lines: a shader prepends its own #version (3.30 core
// and later, or ES 3.00 with `precision highp float;`) and concatenates the files in the order of
// docs/glsl.md. The kernels use float throughout (the C++ Material = MaterialT<float>).

const float kPi = 3.14159265358979323846264338327950288;
const float kInvPi = 0.318309886183790671537767526745028724;
const float kInv2Pi = 0.159154943091895335768883763372514362;
const float kInv4Pi = 0.0795774715459476678844418816862571810;
const float kPiOver2 = 1.57079632679489661923132169163975144;
