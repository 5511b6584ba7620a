//! `combustion eval`: evaluates one term of the optics reference (f64), or the whole
//! BRDF, for inputs given on the command line, and returns JSON — so users and tools
//! can check values without writing Rust.
//!
//! Directions are in the local shading frame (z = normal, x = tangent, y = bitangent),
//! given either as angles (`--theta-v`, `--phi-v`, `--theta-l`, `--phi-l`, degrees) or as
//! vectors (`--v x,y,z`, `--l x,y,z`, normalised here). The microfacet normal is the half
//! vector of v and l unless `--m x,y,z` is given.

use std::collections::BTreeMap;

use serde_json::{Map, Value};

use combustion_optics::brdf::{brdf_evaluate, BrdfInputs, DiffuseModel};
use combustion_optics::diffuse::{
    diffuse_lambert, diffuse_oren_nayar_full, diffuse_oren_nayar_qualitative,
    oren_nayar_sigma_from_roughness, OREN_NAYAR_A_CONSTANT_NOTES,
};
use combustion_optics::fresnel::{
    fresnel_conductor, fresnel_cook_torrance_1981, fresnel_dielectric, fresnel_schlick,
};
use combustion_optics::microfacet::{
    alpha_from_perceptual_roughness, clamp_alpha, d_beckmann, d_ggx, d_ggx_anisotropic,
    g1_smith_ggx, g1_smith_ggx_anisotropic, g2_smith_ggx_height_correlated,
    g2_smith_ggx_height_correlated_anisotropic, g2_smith_ggx_separable, g_cook_torrance_1981,
    lambda_ggx, lambda_ggx_anisotropic,
};
use combustion_optics::readable;
use combustion_optics::vec3::Vec3;

use crate::Error;

/// The terms `combustion eval` knows, with a one-line description each.
pub const TERMS: &[(&str, &str)] = &[
    (
        "d-ggx",
        "GGX normal distribution D(m), isotropic (Walter et al. 2007)",
    ),
    ("d-ggx-anisotropic", "GGX D(m) with αx, αy (Burley 2012)"),
    ("d-beckmann", "Beckmann D(m), normalised"),
    (
        "lambda-ggx",
        "Smith Λ(v) for GGX (isotropic, or anisotropic with --alpha-x/--alpha-y)",
    ),
    ("g1-smith-ggx", "Smith G1(v, m) for GGX"),
    ("g2-separable", "Smith G2 = G1(v)·G1(l), separable"),
    (
        "g2-height-correlated",
        "Smith G2 = 1/(1 + Λ(v) + Λ(l)), height-correlated (Heitz 2014)",
    ),
    (
        "g-cook-torrance",
        "Cook–Torrance 1981 geometric attenuation",
    ),
    (
        "fresnel-conductor",
        "full dielectric–conductor Fresnel Rs, Rp, R with outside IOR ηi at cosθ = v·m",
    ),
    (
        "fresnel-dielectric",
        "dielectric Fresnel with total internal reflection (ηi > η) at cosθ = v·m",
    ),
    (
        "fresnel-cook-torrance",
        "Cook–Torrance 1981 dielectric Fresnel (g, c form) at cosθ = v·m",
    ),
    (
        "fresnel-schlick",
        "Schlick's approximation with --f0 (or F0 from η, ηi) at cosθ = v·m",
    ),
    ("lambert", "Lambert ρ/π"),
    (
        "oren-nayar-qualitative",
        "Oren–Nayar 1994 qualitative model (A constant --oren-nayar-a, default 0.57)",
    ),
    (
        "oren-nayar-full",
        "Oren–Nayar 1994 full model with interreflection",
    ),
    (
        "brdf",
        "the assembled BRDF f(v, l) per RGB channel, as the lighting pass evaluates it",
    ),
];

/// The inputs of one evaluation: each flag's list of numbers (checked by
/// [`parse_value`]) and the diffuse model.
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    values: BTreeMap<&'static str, Vec<f64>>,
    diffuse: Option<DiffuseModel>,
}

impl Inputs {
    /// Sets `flag`'s values (as [`parse_value`] returned them for it).
    pub fn set(&mut self, flag: &'static EvalFlag, values: Vec<f64>) {
        self.values.insert(flag.name, values);
    }
    /// Sets the diffuse model of the `brdf` term.
    pub fn set_diffuse(&mut self, model: DiffuseModel) {
        self.diffuse = Some(model);
    }
    fn get(&self, name: &str) -> Option<&[f64]> {
        self.values.get(name).map(Vec::as_slice)
    }
    fn scalar(&self, name: &str, default: f64) -> f64 {
        self.get(name).map_or(default, |v| v[0])
    }
    fn rgb(&self, name: &str, default: f64) -> [f64; 3] {
        match self.get(name) {
            Some([x]) => [*x; 3],
            Some([r, g, b]) => [*r, *g, *b],
            _ => [default; 3],
        }
    }
}

fn usage(message: String) -> Error {
    Error::Usage(message)
}

/// A numeric input of `combustion eval`: its flag, how many comma-separated values it
/// takes, the range each must lie in, and what it means.
#[derive(Debug)]
pub struct EvalFlag {
    /// The flag with its dashes, e.g. `--theta-v`.
    pub name: &'static str,
    /// The accepted numbers of values (1 for a scalar, 3 for a vector or RGB).
    pub lengths: &'static [usize],
    /// The smallest value accepted (inclusive).
    pub low: f64,
    /// The largest value accepted (inclusive).
    pub high: f64,
    /// What the value means, for `--help`.
    pub help: &'static str,
}

impl EvalFlag {
    /// The flag without its dashes (`theta-v`).
    pub fn long(&self) -> &'static str {
        self.name.trim_start_matches('-')
    }
}

/// The diffuse models `--diffuse` names.
pub const DIFFUSE_MODELS: [(&str, DiffuseModel); 3] = [
    ("lambert", DiffuseModel::Lambert),
    ("oren-nayar-qualitative", DiffuseModel::OrenNayarQualitative),
    ("oren-nayar-full", DiffuseModel::OrenNayarFull),
];

const fn flag(
    name: &'static str,
    lengths: &'static [usize],
    low: f64,
    high: f64,
    help: &'static str,
) -> EvalFlag {
    EvalFlag {
        name,
        lengths,
        low,
        high,
        help,
    }
}

/// Every numeric input `combustion eval` takes.
pub const FLAGS: &[EvalFlag] = &[
    flag(
        "--theta-v",
        &[1],
        0.0,
        180.0,
        "polar angle of v from the normal, degrees",
    ),
    flag(
        "--phi-v",
        &[1],
        -360.0,
        360.0,
        "azimuth of v from the tangent, degrees (default 0)",
    ),
    flag(
        "--theta-l",
        &[1],
        0.0,
        180.0,
        "polar angle of l from the normal, degrees",
    ),
    flag(
        "--phi-l",
        &[1],
        -360.0,
        360.0,
        "azimuth of l from the tangent, degrees (default 0)",
    ),
    flag(
        "--v",
        &[3],
        f64::MIN,
        f64::MAX,
        "view direction x,y,z (normalised here; not with --theta-v/--phi-v)",
    ),
    flag(
        "--l",
        &[3],
        f64::MIN,
        f64::MAX,
        "light direction x,y,z (normalised here; not with --theta-l/--phi-l)",
    ),
    flag(
        "--m",
        &[3],
        f64::MIN,
        f64::MAX,
        "microfacet normal x,y,z (default: the half vector of v and l)",
    ),
    flag(
        "--alpha",
        &[1],
        0.0,
        1.0,
        "GGX/Beckmann width α (clamped as the renderer clamps it)",
    ),
    flag(
        "--roughness",
        &[1],
        0.0,
        1.0,
        "perceptual roughness r (α = r²; not with --alpha)",
    ),
    flag(
        "--alpha-x",
        &[1],
        0.0,
        1.0,
        "anisotropic α along the tangent",
    ),
    flag(
        "--alpha-y",
        &[1],
        0.0,
        1.0,
        "anisotropic α along the bitangent",
    ),
    flag(
        "--eta",
        &[1, 3],
        1e-4,
        1e4,
        "the surface's η, one value or one per RGB channel (default 1.5)",
    ),
    flag(
        "--k",
        &[1, 3],
        0.0,
        1e4,
        "the conductor's extinction k, one value or per channel (default 0)",
    ),
    flag(
        "--eta-i",
        &[1],
        1e-4,
        1e4,
        "the outside medium's index ηi (default 1)",
    ),
    flag(
        "--dielectric-eta",
        &[1],
        1e-4,
        1e4,
        "`brdf`: the dielectric layer's η (default 1.5)",
    ),
    flag(
        "--f0",
        &[1],
        0.0,
        1.0,
        "`fresnel-schlick`: F0 (default: from η and ηi)",
    ),
    flag(
        "--sigma",
        &[1],
        0.0,
        10.0,
        "Oren–Nayar σ, radians (default: from the roughness)",
    ),
    flag(
        "--polarisation",
        &[1],
        0.0,
        1.0,
        "weight w of R = (1 − w)Rs + wRp (default 0.5)",
    ),
    flag(
        "--rho",
        &[1, 3],
        0.0,
        1.0,
        "diffuse albedo ρ, one value or per channel",
    ),
    flag(
        "--metalness",
        &[1],
        0.0,
        1.0,
        "`brdf`: metalness (default 0)",
    ),
    flag(
        "--oren-nayar-a",
        &[1],
        0.0,
        10.0,
        "the qualitative model's A constant (default 0.57)",
    ),
];

/// `flag`'s value: comma-separated finite numbers, as many as the flag takes, each in its
/// range. The error says why, without the value (the command line shows it).
pub fn parse_value(flag: &EvalFlag, text: &str) -> Result<Vec<f64>, String> {
    let list = crate::number_list(text, flag.lengths)?;
    if let Some(bad) = list.iter().find(|&&x| x < flag.low || x > flag.high) {
        return Err(format!(
            "{} is outside [{}, {}]",
            readable(*bad),
            readable(flag.low),
            readable(flag.high)
        ));
    }
    Ok(list)
}

fn direction(
    inputs: &Inputs,
    vector: &str,
    theta: &str,
    phi: &str,
) -> Result<Option<Vec3<f64>>, Error> {
    if let Some(v) = inputs.get(vector) {
        for angle in [theta, phi].into_iter().filter(|a| !a.is_empty()) {
            if inputs.get(angle).is_some() {
                return Err(usage(format!(
                    "give {vector} or {angle}, not both (they say the same direction)"
                )));
            }
        }
        // Scaled by its largest component first, so that neither 1e200 (whose square
        // overflows) nor 1e-200 (whose square underflows) is lost.
        let largest = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        if largest == 0.0 {
            return Err(usage(format!("{vector} must not be the zero vector")));
        }
        let v = Vec3::new(v[0] / largest, v[1] / largest, v[2] / largest);
        return Ok(Some(v.normalize()));
    }
    match inputs.get(theta) {
        None => Ok(None),
        Some(t) => {
            // cos θ as sin(90° − θ): exactly 0 at θ = 90°, as the vector (1, 0, 0) gives,
            // where cos(π/2) would leave 6e-17 and a grazing direction would count as lit
            // (and sin θ exactly 0 at θ = 0).
            let sin_t = t[0].to_radians().sin();
            let cos_t = (90.0 - t[0]).to_radians().sin();
            let p = inputs.scalar(phi, 0.0).to_radians();
            Ok(Some(Vec3::new(sin_t * p.cos(), sin_t * p.sin(), cos_t)))
        }
    }
}

fn need<T>(value: Option<T>, what: &str) -> Result<T, Error> {
    value.ok_or_else(|| usage(format!("this term needs {what}")))
}

/// A JSON number (serde_json writes the shortest form that reads back as the same
/// f64), or null for NaN/Inf.
fn json_number(x: f64) -> Value {
    serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number)
}

fn json_vec(v: Vec3<f64>) -> Value {
    Value::Array(vec![json_number(v.x), json_number(v.y), json_number(v.z)])
}

/// A JSON array of numbers.
fn json_list(values: impl IntoIterator<Item = f64>) -> Value {
    Value::Array(values.into_iter().map(json_number).collect())
}

/// Evaluates `term` with `inputs` and returns a JSON object.
pub fn evaluate(term: &str, inputs: &Inputs) -> Result<String, Error> {
    if !TERMS.iter().any(|(name, _)| *name == term) {
        return Err(usage(format!(
            "unknown term `{term}`; terms: {}",
            TERMS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
        )));
    }
    let v = direction(inputs, "--v", "--theta-v", "--phi-v")?;
    let l = direction(inputs, "--l", "--theta-l", "--phi-l")?;
    let m = match inputs.get("--m") {
        Some(_) => direction(inputs, "--m", "", "")?,
        None => match (v, l) {
            (Some(v), Some(l)) => {
                let sum = v + l;
                if sum.length_squared() < 1e-24 {
                    return Err(usage(
                        "v and l are opposite: the half vector is undefined; give --m".into(),
                    ));
                }
                Some(sum.normalize())
            }
            _ => None,
        },
    };
    let alpha = match (inputs.get("--alpha"), inputs.get("--roughness")) {
        (Some(_), Some(_)) => {
            return Err(usage(
                "give --alpha or --roughness, not both (α = r²; --sigma sets Oren–Nayar's σ)"
                    .into(),
            ))
        }
        (Some(a), _) => Some(a[0]),
        (None, Some(r)) => Some(alpha_from_perceptual_roughness(r[0])),
        (None, None) => None,
    };
    let anisotropic = inputs.get("--alpha-x").is_some() || inputs.get("--alpha-y").is_some();
    if alpha.is_some() && anisotropic {
        // One took the other's place without a word (which, by the term).
        return Err(usage(
            "give --alpha (or --roughness), or --alpha-x and --alpha-y, not both".into(),
        ));
    }
    let alphas = match (inputs.get("--alpha-x"), inputs.get("--alpha-y")) {
        (Some(x), Some(y)) => Some((x[0], y[0])),
        (None, None) => alpha.map(|a| (a, a)),
        _ => return Err(usage("give both --alpha-x and --alpha-y".into())),
    };
    let eta_i = inputs.scalar("--eta-i", 1.0);
    let w = inputs.scalar("--polarisation", 0.5);
    let cos_vm = || -> Result<f64, Error> {
        Ok(need(v, "--v or --theta-v")?.dot(need(m, "--m, or both v and l")?))
    };
    let mut out = Map::new();
    match term {
        "d-ggx" => {
            out.insert(
                "value".into(),
                json_number(d_ggx(
                    need(m, "m (--m, or v and l)")?,
                    need(alpha, "--alpha or --roughness")?,
                )),
            );
        }
        "d-ggx-anisotropic" => {
            let (ax, ay) = need(alphas, "--alpha-x and --alpha-y")?;
            out.insert(
                "value".into(),
                json_number(d_ggx_anisotropic(need(m, "m (--m, or v and l)")?, ax, ay)),
            );
        }
        "d-beckmann" => {
            out.insert(
                "value".into(),
                json_number(d_beckmann(
                    need(m, "m (--m, or v and l)")?,
                    need(alpha, "--alpha or --roughness")?,
                )),
            );
        }
        "lambda-ggx" => {
            let (ax, ay) = need(alphas, "--alpha (or --alpha-x and --alpha-y)")?;
            let v = need(v, "--v or --theta-v")?;
            let value = if ax == ay {
                lambda_ggx(v, ax)
            } else {
                lambda_ggx_anisotropic(v, ax, ay)
            };
            out.insert("value".into(), json_number(value));
        }
        "g1-smith-ggx" => {
            let (ax, ay) = need(alphas, "--alpha (or --alpha-x and --alpha-y)")?;
            let (v, m) = (
                need(v, "--v or --theta-v")?,
                need(m, "m (--m, or v and l)")?,
            );
            let value = if ax == ay {
                g1_smith_ggx(v, m, ax)
            } else {
                g1_smith_ggx_anisotropic(v, m, ax, ay)
            };
            out.insert("value".into(), json_number(value));
        }
        "g2-separable" => {
            let a = need(alpha, "--alpha or --roughness")?;
            out.insert(
                "value".into(),
                json_number(g2_smith_ggx_separable(
                    need(v, "v")?,
                    need(l, "l")?,
                    need(m, "m")?,
                    a,
                )),
            );
        }
        "g2-height-correlated" => {
            let (ax, ay) = need(alphas, "--alpha (or --alpha-x and --alpha-y)")?;
            let (v, l, m) = (need(v, "v")?, need(l, "l")?, need(m, "m")?);
            let value = if ax == ay {
                g2_smith_ggx_height_correlated(v, l, m, ax)
            } else {
                g2_smith_ggx_height_correlated_anisotropic(v, l, m, ax, ay)
            };
            out.insert("value".into(), json_number(value));
        }
        "g-cook-torrance" => {
            out.insert(
                "value".into(),
                json_number(g_cook_torrance_1981(
                    need(v, "v")?,
                    need(l, "l")?,
                    need(m, "m")?,
                )),
            );
        }
        "fresnel-conductor" => {
            let c = cos_vm()?;
            let (eta, k) = (inputs.rgb("--eta", 1.5), inputs.rgb("--k", 0.0));
            let r: Vec<_> = (0..3)
                .map(|i| fresnel_conductor(c, eta_i, eta[i], k[i]))
                .collect();
            out.insert("cos_theta".into(), json_number(c));
            out.insert("rs".into(), json_list(r.iter().map(|p| p.s)));
            out.insert("rp".into(), json_list(r.iter().map(|p| p.p)));
            out.insert("r".into(), json_list(r.iter().map(|p| p.weighted(w))));
        }
        "fresnel-dielectric" => {
            let c = cos_vm()?;
            let r = fresnel_dielectric(c, eta_i, inputs.scalar("--eta", 1.5));
            out.insert("cos_theta".into(), json_number(c));
            out.insert("rs".into(), json_number(r.s));
            out.insert("rp".into(), json_number(r.p));
            out.insert("r".into(), json_number(r.weighted(w)));
        }
        "fresnel-cook-torrance" => {
            let c = cos_vm()?;
            out.insert("cos_theta".into(), json_number(c));
            out.insert(
                "value".into(),
                json_number(fresnel_cook_torrance_1981(
                    c,
                    inputs.scalar("--eta", 1.5) / eta_i,
                )),
            );
        }
        "fresnel-schlick" => {
            let c = cos_vm()?;
            if inputs.get("--f0").is_some() && inputs.get("--eta").is_some() {
                return Err(usage(
                    "give --f0 or --eta (F0 from η and ηi), not both".into(),
                ));
            }
            let f0 = match inputs.get("--f0") {
                Some(f) => f[0],
                None => {
                    let eta = inputs.scalar("--eta", 1.5);
                    ((eta - eta_i) / (eta + eta_i)).powi(2)
                }
            };
            out.insert("cos_theta".into(), json_number(c));
            out.insert("f0".into(), json_number(f0));
            out.insert("value".into(), json_number(fresnel_schlick(c, f0)));
        }
        "lambert" => {
            let rho = inputs.rgb("--rho", 1.0);
            out.insert("value".into(), json_list(rho.map(diffuse_lambert)));
        }
        "oren-nayar-qualitative" | "oren-nayar-full" => {
            let rho = inputs.rgb("--rho", 1.0);
            let sigma = match (inputs.get("--sigma"), inputs.get("--roughness")) {
                (Some(s), _) => s[0],
                (None, Some(r)) => oren_nayar_sigma_from_roughness(r[0]),
                _ => return Err(usage("this term needs --sigma or --roughness".into())),
            };
            let (v, l) = (need(v, "v")?, need(l, "l")?);
            let a = inputs.scalar("--oren-nayar-a", OREN_NAYAR_A_CONSTANT_NOTES);
            let values = rho.map(|r| {
                if term == "oren-nayar-full" {
                    diffuse_oren_nayar_full(r, sigma, v, l)
                } else {
                    diffuse_oren_nayar_qualitative(r, sigma, a, v, l)
                }
            });
            out.insert("sigma".into(), json_number(sigma));
            out.insert("value".into(), json_list(values));
        }
        "brdf" => {
            let (ax, ay) = need(alphas, "--alpha, --roughness or --alpha-x and --alpha-y")?;
            let roughness = inputs.scalar("--roughness", alpha.unwrap_or(ax).sqrt());
            let inputs_brdf = BrdfInputs {
                base_color: inputs.rgb("--rho", 0.8),
                metalness: inputs.scalar("--metalness", 0.0),
                alpha_x: ax,
                alpha_y: ay,
                conductor_eta: inputs.rgb("--eta", 1.5),
                conductor_k: inputs.rgb("--k", 0.0),
                dielectric_eta: inputs.scalar("--dielectric-eta", 1.5),
                outside_eta: eta_i,
                polarisation_weight: w,
                diffuse_model: inputs.diffuse.unwrap_or_default(),
                oren_nayar_sigma: inputs
                    .get("--sigma")
                    .map_or_else(|| oren_nayar_sigma_from_roughness(roughness), |s| s[0]),
            };
            let z = Vec3::new(0.0, 0.0, 1.0);
            let (x, y) = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
            let f = brdf_evaluate(&inputs_brdf, z, x, y, need(v, "v")?, need(l, "l")?);
            out.insert("value".into(), json_list(f));
        }
        _ => unreachable!("checked against TERMS above"),
    }
    // One key each: the term, the input as given, what was evaluated from it (directions
    // normalised or made from angles, the half vector, α after its clamp), the result.
    let mut input = Map::new();
    for (flag, values) in &inputs.values {
        let name = flag.trim_start_matches("--").replace('-', "_");
        let value = match values.as_slice() {
            [x] => json_number(*x),
            _ => json_list(values.iter().copied()),
        };
        input.insert(name, value);
    }
    if let Some(model) = inputs.diffuse {
        input.insert("diffuse".into(), Value::from(format!("{model:?}")));
    }
    let mut used = Map::new();
    for (name, value) in [("v", v), ("l", l), ("m", m)] {
        if let Some(d) = value {
            used.insert(name.into(), json_vec(d));
        }
    }
    if let Some((ax, ay)) = alphas {
        used.insert("alpha_x".into(), json_number(clamp_alpha(ax)));
        used.insert("alpha_y".into(), json_number(clamp_alpha(ay)));
    }
    let json = serde_json::json!({
        "term": term,
        "input": input,
        "used": used,
        "result": out,
    });
    serde_json::to_string_pretty(&json).map_err(|e| usage(format!("cannot write JSON: {e}")))
}
