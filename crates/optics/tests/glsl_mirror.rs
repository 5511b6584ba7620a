//! The GLSL mirrors in `shaders/include/` must not drift from this crate: constants,
//! enum values, struct fields and function names are checked here against the Rust
//! definitions (the numerical parity of the compiled shader is the renderer's parity
//! test, which runs on a Vulkan device).

use combustion_optics::brdf::DiffuseModel;
use combustion_optics::diffuse::{
    OREN_NAYAR_A_CONSTANT_BRDF, OREN_NAYAR_A_CONSTANT_NOTES, OREN_NAYAR_A_CONSTANT_PAPER,
};
use combustion_optics::vec3::TANGENT_DEGENERATE_FRACTION_SQ;
use combustion_optics::{ALPHA_MIN, COS_MIN, ETA_MAX, ETA_MIN, FACING_COS_MIN};
use std::path::PathBuf;

fn include(name: &str) -> String {
    let path: PathBuf = [
        env!("CARGO_MANIFEST_DIR"),
        "..",
        "..",
        "shaders",
        "include",
        name,
    ]
    .iter()
    .collect();
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The right-hand side of `const float NAME = …;` in the source.
fn glsl_const(src: &str, name: &str) -> String {
    let key = format!("const float {name} = ");
    let start = src
        .find(&key)
        .unwrap_or_else(|| panic!("constants.glsl has no {name}"))
        + key.len();
    let end = start + src[start..].find(';').unwrap();
    src[start..end].trim().to_string()
}

#[test]
fn constants_match() {
    let src = include("constants.glsl");
    // A GLSL float literal compiles to the nearest f32 of its decimal value, which is what
    // the Rust f32 path's `T::from_f64` gives for the same constant.
    let expect: [(&str, f64); 13] = [
        ("PI", std::f64::consts::PI),
        ("INV_PI", std::f64::consts::FRAC_1_PI),
        ("INV_SQRT_2", std::f64::consts::FRAC_1_SQRT_2),
        ("FLT_MAX", f32::MAX as f64),
        ("FLT_EPSILON", f32::EPSILON as f64),
        ("ALPHA_MIN", ALPHA_MIN),
        ("COS_MIN", COS_MIN),
        ("FACING_COS_MIN", FACING_COS_MIN),
        ("ETA_MIN", ETA_MIN),
        ("ETA_MAX", ETA_MAX),
        (
            "TANGENT_DEGENERATE_FRACTION_SQ",
            TANGENT_DEGENERATE_FRACTION_SQ,
        ),
        ("OREN_NAYAR_A_CONSTANT_NOTES", OREN_NAYAR_A_CONSTANT_NOTES),
        ("OREN_NAYAR_A_CONSTANT_PAPER", OREN_NAYAR_A_CONSTANT_PAPER),
    ];
    for (name, value) in expect {
        let literal = glsl_const(&src, name);
        let parsed: f64 = literal
            .parse()
            .unwrap_or_else(|e| panic!("{name} = {literal}: {e}"));
        assert_eq!(
            parsed as f32, value as f32,
            "{name}: GLSL {literal} vs Rust {value}"
        );
        // "exact digits": the literal carries at least f64 precision where it matters
        if ["PI", "INV_PI", "INV_SQRT_2"].contains(&name) {
            assert_eq!(parsed, value, "{name} should be written with full digits");
        }
    }
    let brdf_choice = glsl_const(&src, "OREN_NAYAR_A_CONSTANT_BRDF");
    let rust_choice = if OREN_NAYAR_A_CONSTANT_BRDF == OREN_NAYAR_A_CONSTANT_PAPER {
        "OREN_NAYAR_A_CONSTANT_PAPER"
    } else {
        "OREN_NAYAR_A_CONSTANT_NOTES"
    };
    assert_eq!(brdf_choice, rust_choice);
}

#[test]
fn diffuse_model_defines_match_the_enum() {
    let src = include("brdf.glsl");
    for (name, model) in [
        ("DIFFUSE_MODEL_LAMBERT", DiffuseModel::Lambert),
        (
            "DIFFUSE_MODEL_OREN_NAYAR_QUALITATIVE",
            DiffuseModel::OrenNayarQualitative,
        ),
        ("DIFFUSE_MODEL_OREN_NAYAR_FULL", DiffuseModel::OrenNayarFull),
    ] {
        let line = format!("#define {name} {}u", model as u32);
        assert!(src.contains(&line), "brdf.glsl lacks `{line}`");
    }
}

/// The (type, name) fields of GLSL `struct NAME { ... };` in `src`, in order.
fn glsl_struct_fields(src: &str, name: &str) -> Vec<(String, String)> {
    let start = src
        .find(&format!("struct {name} {{"))
        .unwrap_or_else(|| panic!("no struct {name}"));
    let body = &src[start..start + src[start..].find("};").unwrap()];
    body.lines()
        .skip(1)
        .filter_map(|line| {
            let code = line.split("//").next().unwrap().trim();
            let code = code.strip_suffix(';')?;
            let mut parts = code.split_whitespace();
            Some((parts.next()?.to_string(), parts.next()?.to_string()))
        })
        .collect()
}

#[test]
fn coat_inputs_fields_match_the_struct() {
    let fields = glsl_struct_fields(&include("brdf.glsl"), "CoatInputs");
    let got: Vec<(&str, &str)> = fields
        .iter()
        .map(|(t, n)| (t.as_str(), n.as_str()))
        .collect();
    assert_eq!(
        got,
        [
            ("float", "factor"),
            ("float", "alpha"),
            ("float", "eta"),
            ("float", "outside_eta"),
            ("float", "polarisation_weight"),
        ]
    );
    // the Rust struct has exactly these fields (a compile-time check by construction)
    let _ = combustion_optics::coat::CoatInputs::<f32> {
        factor: 0.0,
        alpha: 0.0,
        eta: 0.0,
        outside_eta: 0.0,
        polarisation_weight: 0.0,
    };
}

#[test]
fn brdf_inputs_fields_match_the_struct() {
    let fields = glsl_struct_fields(&include("brdf.glsl"), "BrdfInputs");
    // the Rust struct, in declaration order, with the GLSL type each field maps to
    let expected = [
        ("vec3", "base_color"),
        ("float", "metalness"),
        ("float", "alpha_x"),
        ("float", "alpha_y"),
        ("vec3", "conductor_eta"),
        ("vec3", "conductor_k"),
        ("float", "dielectric_eta"),
        ("float", "outside_eta"),
        ("float", "polarisation_weight"),
        ("uint", "diffuse_model"),
        ("float", "oren_nayar_sigma"),
    ];
    let got: Vec<(&str, &str)> = fields
        .iter()
        .map(|(t, n)| (t.as_str(), n.as_str()))
        .collect();
    assert_eq!(got, expected);
    // and the Rust struct has exactly these fields (a compile-time check by construction)
    let m = combustion_optics::BrdfInputs::<f32> {
        base_color: [0.0; 3],
        metalness: 0.0,
        alpha_x: 0.0,
        alpha_y: 0.0,
        conductor_eta: [0.0; 3],
        conductor_k: [0.0; 3],
        dielectric_eta: 0.0,
        outside_eta: 0.0,
        polarisation_weight: 0.0,
        diffuse_model: DiffuseModel::Lambert,
        oren_nayar_sigma: 0.0,
    };
    let _ = m;
}

#[test]
fn every_term_has_a_glsl_mirror() {
    let files: [(&str, &[&str]); 5] = [
        (
            "microfacet.glsl",
            &[
                "float alpha_from_perceptual_roughness(float r)",
                "vec2 anisotropic_alphas(float alpha, float strength)",
                "float d_ggx(vec3 m, float alpha)",
                "float d_ggx_anisotropic(vec3 m, float alpha_x, float alpha_y)",
                "float d_beckmann(vec3 m, float alpha)",
                "float d_beckmann_anisotropic(vec3 m, float alpha_x, float alpha_y)",
                "float lambda_beckmann_anisotropic(vec3 v, float alpha_x, float alpha_y)",
                "float lambda_ggx(vec3 v, float alpha)",
                "float lambda_ggx_anisotropic(vec3 v, float alpha_x, float alpha_y)",
                "float g1_smith_ggx(vec3 v, vec3 m, float alpha)",
                "float g1_smith_ggx_anisotropic(vec3 v, vec3 m, float alpha_x, float alpha_y)",
                "float g2_smith_ggx_separable(vec3 v, vec3 l, vec3 m, float alpha)",
                "float g2_smith_ggx_separable_anisotropic(",
                "float g2_smith_ggx_height_correlated(vec3 v, vec3 l, vec3 m, float alpha)",
                "float g2_smith_ggx_height_correlated_anisotropic(",
                "float visibility_smith_ggx_height_correlated_anisotropic(",
                "float g_cook_torrance_1981(vec3 v, vec3 l, vec3 h)",
                "float specular_microfacet(float d, float f, float g, float cos_v, float cos_l)",
            ],
        ),
        (
            "fresnel.glsl",
            &[
                "float polarised_weighted(vec2 r, float polarisation_weight)",
                "vec2 fresnel_conductor(float cos_theta_i, float eta_i, float eta_t, float k_t)",
                "vec2 fresnel_dielectric(float cos_theta_i, float eta_i, float eta_t)",
                "vec2 fresnel_dielectric_transmittance(float cos_theta_i, float eta_i, float eta_t)",
                "float fresnel_cook_torrance_1981(float cos_theta, float eta)",
                "float fresnel_schlick(float cos_theta, float f0)",
                "float fresnel_f82_coefficient(float f0, float f_at_f82_cos)",
                "float fresnel_f82(float cos_theta, float f0, float b)",
                "float f0_dielectric(float eta_i, float eta_t)",
                "float eta_from_f0(float f0)",
            ],
        ),
        (
            "diffuse.glsl",
            &[
                "float oren_nayar_sigma_from_roughness(float r)",
                "vec3 diffuse_lambert(vec3 rho)",
                "vec3 diffuse_oren_nayar_qualitative(vec3 rho, float sigma, float a_constant, vec3 v, vec3 l)",
                "vec3 diffuse_oren_nayar_full(vec3 rho, float sigma, vec3 v, vec3 l)",
            ],
        ),
        (
            "brdf.glsl",
            &[
                "vec3 safe_normalize(vec3 v)",
                "mat3 shading_frame(vec3 n_in, vec3 t_in, vec3 b_in)",
                "vec3 facing_view(vec3 n, vec3 v)",
                "vec3 brdf_evaluate(BrdfInputs m, vec3 n, vec3 t, vec3 b, vec3 v, vec3 l)",
                "float coat_attenuation(CoatInputs c, float cos_theta)",
                "CoatView coat_view(CoatInputs c, vec3 n, vec3 v)",
                "vec3 coat_evaluate_view(CoatInputs c, CoatView view, vec3 l)",
                "vec3 coated(vec3 base, CoatView view, vec3 terms)",
                "vec3 coated_radiance(vec3 base, float cos_base, CoatView view, vec3 terms)",
                "float d_charlie(vec3 m, float alpha)",
                "float lambda_sheen(float cos_theta, float alpha)",
                "float visibility_sheen(vec3 v, vec3 l, float alpha)",
                "float sheen_lobe(vec3 v, vec3 l, float alpha)",
                "float sheen_albedo_scaling(vec3 color, float albedo_v, float albedo_l)",
                "BrdfView brdf_view_with_film(BrdfInputs m, ThinFilm film, vec3 n, vec3 t, vec3 b, vec3 v)",
            ],
        ),
        (
            "thin_film.glsl",
            &[
                "void thin_film_sensitivity(float opd_nm, out vec3 cos_part, out vec3 sin_part)",
                "void thin_film_reflectance(float cos_theta, float outside_eta, ThinFilm film, vec3 base_eta,",
                "vec3 thin_film_reflectance_weighted(float cos_theta, float outside_eta, ThinFilm film,",
                "void film_crossing_transmittance(float cos_theta, float eta_from, float eta_to, ThinFilm film,",
            ],
        ),
    ];
    for (file, signatures) in files {
        let src = include(file);
        for sig in signatures {
            assert!(src.contains(sig), "{file} lacks `{sig}`");
        }
    }
}

#[test]
fn include_guards() {
    for (file, guard) in [
        ("constants.glsl", "COMBUSTION_CONSTANTS_GLSL"),
        ("microfacet.glsl", "COMBUSTION_MICROFACET_GLSL"),
        ("fresnel.glsl", "COMBUSTION_FRESNEL_GLSL"),
        ("diffuse.glsl", "COMBUSTION_DIFFUSE_GLSL"),
        ("brdf.glsl", "COMBUSTION_BRDF_GLSL"),
        ("thin_film.glsl", "COMBUSTION_THIN_FILM_GLSL"),
    ] {
        let src = include(file);
        assert!(
            src.contains(&format!("#ifndef {guard}\n#define {guard}\n")),
            "{file}: guard"
        );
        assert!(
            src.trim_end().ends_with(&format!("#endif // {guard}")),
            "{file}: #endif"
        );
        // no magic π: the only π literal is the one in constants.glsl
        if file != "constants.glsl" {
            assert!(!src.contains("3.14"), "{file} spells out π");
        }
    }
}

/// The film's sensitivity constants in thin_film.glsl are the Rust derivation's
/// (`sensitivity_weights`, from Belcour & Barla's Gaussians and the sRGB matrix), to the
/// f32 they compile to (9 significant digits written), and the harmonics and thickness
/// bound agree.
#[test]
fn thin_film_constants_match() {
    use combustion_optics::thin_film::{
        sensitivity_weights, FILM_HARMONICS, FILM_THICKNESS_MAX_NM,
    };
    let src = include("thin_film.glsl");
    let vec4_of = |name: &str| -> [f64; 4] {
        let key = format!("const vec4 {name} = vec4(");
        let start = src.find(&key).unwrap_or_else(|| panic!("no {name}")) + key.len();
        let end = start + src[start..].find(')').unwrap();
        let values: Vec<f64> = src[start..end]
            .split(',')
            .map(|x| x.trim().parse().unwrap())
            .collect();
        values.try_into().unwrap()
    };
    let (w, k, a) = sensitivity_weights();
    let close = |glsl: [f64; 4], rust: [f64; 4], what: &str| {
        for (g, r) in glsl.iter().zip(rust) {
            assert!(
                (g - r).abs() <= 1e-8 * r.abs(),
                "{what}: GLSL {g} vs Rust {r}"
            );
        }
    };
    for (c, channel) in ["R", "G", "B"].iter().enumerate() {
        close(
            vec4_of(&format!("FILM_SENSITIVITY_WEIGHTS_{channel}")),
            w[c],
            channel,
        );
    }
    close(vec4_of("FILM_SENSITIVITY_FREQUENCIES"), k, "frequencies");
    close(vec4_of("FILM_SENSITIVITY_DECAYS"), a, "decays");
    assert!(src.contains(&format!("#define FILM_HARMONICS {FILM_HARMONICS}\n")));
    let max = glsl_const(&src, "FILM_THICKNESS_MAX_NM");
    assert_eq!(max.parse::<f64>().unwrap(), FILM_THICKNESS_MAX_NM);
}
