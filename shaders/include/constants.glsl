// Numeric constants of the optics includes, defined once (exact digits; the compiler
// rounds each literal to the nearest float, as the Rust f32 path's T::from_f64 does).
// Mirrors crates/optics: the values are checked against the Rust constants by
// crates/optics/tests/glsl_mirror.rs.
#ifndef COMBUSTION_CONSTANTS_GLSL
#define COMBUSTION_CONSTANTS_GLSL

const float PI = 3.14159265358979323846264338328;
// 1/π
const float INV_PI = 0.318309886183790671537767526745;
// 1/√2
const float INV_SQRT_2 = 0.707106781186547524400844362105;
// largest finite float (Rust f32::MAX)
const float FLT_MAX = 3.40282346638528859811704183485e+38;
// machine epsilon of float, 2⁻²³ (Rust f32::EPSILON)
const float FLT_EPSILON = 1.1920928955078125e-7;

// Smallest GGX/Beckmann α; every α is clamped to [ALPHA_MIN, 1] (lib.rs, "Conventions").
const float ALPHA_MIN = 1.0e-3;
// Cosines in (0, COS_MIN) are raised to COS_MIN before anything is divided by them.
const float COS_MIN = 1.0e-6;
// A shading normal facing the eye by a cosine below this is bent towards it until it
// does (brdf.glsl: facing_view; Rust: combustion_optics::FACING_COS_MIN, 1/64).
const float FACING_COS_MIN = 0.015625;
// IORs are clamped to [ETA_MIN, ETA_MAX], extinction coefficients to [0, ETA_MAX].
const float ETA_MIN = 1.0e-4;
const float ETA_MAX = 1.0e4;
// |t⊥|² ≤ this × |t|²: the tangent is within 0.057° of the normal and unusable.
const float TANGENT_DEGENERATE_FRACTION_SQ = 1.0e-6;

// Oren–Nayar A = 1 − 0.5 σ²/(σ² + a): the notes' a, the paper's a, and the BRDF's choice.
const float OREN_NAYAR_A_CONSTANT_NOTES = 0.57;
const float OREN_NAYAR_A_CONSTANT_PAPER = 0.33;
const float OREN_NAYAR_A_CONSTANT_BRDF = OREN_NAYAR_A_CONSTANT_PAPER;

#endif // COMBUSTION_CONSTANTS_GLSL
