//! The assembled BRDF the lighting pass evaluates, and its CPU reference.
//!
//! GLSL mirror: `shaders/include/brdf.glsl` (`struct BrdfInputs`, `brdf_evaluate`, the
//! `DIFFUSE_MODEL_*` defines). The Rust and GLSL versions take the same inputs in the same
//! order and use the same arrangements, so a CPU parity test can compare them per pixel.

use crate::diffuse::{
    diffuse_lambert, diffuse_oren_nayar_full, diffuse_oren_nayar_qualitative,
    OREN_NAYAR_A_CONSTANT_BRDF,
};
use crate::fresnel::{
    fresnel_conductor, fresnel_dielectric, fresnel_dielectric_transmittance, Polarised,
};
use crate::microfacet::{clamp_alpha, d_ggx_anisotropic, smith_ggx_visibility_half};
use crate::real::Real;
use crate::specular::DielectricSpecular;
use crate::thin_film::{thin_film_reflectance, ThinFilm};
use crate::vec3::{ShadingFrame, Vec3};
use core::fmt;

/// Which diffuse model the dielectric part uses. The discriminants are the values the
/// G-buffer/material table stores and GLSL's `DIFFUSE_MODEL_*` defines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[repr(u32)]
pub enum DiffuseModel {
    /// ρ/π ([`diffuse_lambert`]).
    #[default]
    Lambert = 0,
    /// Oren–Nayar qualitative model with the A-constant
    /// [`OREN_NAYAR_A_CONSTANT_BRDF`] ([`diffuse_oren_nayar_qualitative`]).
    OrenNayarQualitative = 1,
    /// Oren–Nayar 1994 full model with interreflection ([`diffuse_oren_nayar_full`]).
    OrenNayarFull = 2,
}

/// A `u32` that names no [`DiffuseModel`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnknownDiffuseModel(pub u32);

impl fmt::Display for UnknownDiffuseModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown diffuse model {} (expected 0, 1 or 2)", self.0)
    }
}

impl std::error::Error for UnknownDiffuseModel {}

impl TryFrom<u32> for DiffuseModel {
    type Error = UnknownDiffuseModel;
    fn try_from(value: u32) -> Result<Self, Self::Error> {
        match value {
            0 => Ok(Self::Lambert),
            1 => Ok(Self::OrenNayarQualitative),
            2 => Ok(Self::OrenNayarFull),
            other => Err(UnknownDiffuseModel(other)),
        }
    }
}

impl From<DiffuseModel> for u32 {
    fn from(m: DiffuseModel) -> u32 {
        m as u32
    }
}

/// Material inputs of [`brdf_evaluate`], as the lighting pass reads them from the G-buffer
/// and material table.
///
/// Out-of-range values are clamped where they are used, never rejected: colours,
/// metalness and polarisation weight to [0, 1], α to [[`ALPHA_MIN`](crate::ALPHA_MIN), 1],
/// IORs to [[`ETA_MIN`](crate::ETA_MIN), [`ETA_MAX`](crate::ETA_MAX)], k to
/// [0, `ETA_MAX`] (|k|), σ to ≥ 0; NaN becomes the lower bound.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BrdfInputs<T> {
    /// Linear RGB albedo of the dielectric (non-metal) part.
    pub base_color: [T; 3],
    /// 0 dielectric … 1 conductor; blends the two lobes linearly.
    pub metalness: T,
    /// GGX α along the tangent (already mapped from roughness/anisotropy, see
    /// [`alpha_from_perceptual_roughness`](crate::microfacet::alpha_from_perceptual_roughness)
    /// and [`anisotropic_alphas`](crate::microfacet::anisotropic_alphas)).
    pub alpha_x: T,
    /// GGX α along the bitangent.
    pub alpha_y: T,
    /// Real part η of the conductor's complex IOR η + ik, per RGB channel.
    pub conductor_eta: [T; 3],
    /// Extinction coefficient k of the conductor, per RGB channel.
    pub conductor_k: [T; 3],
    /// Real IOR of the dielectric part (e.g. 1.5).
    pub dielectric_eta: T,
    /// η_i, IOR of the medium the surface sits in (air 1.0, water 1.33).
    pub outside_eta: T,
    /// 0 = s (perpendicular), 1 = p (parallel), 0.5 unpolarised.
    pub polarisation_weight: T,
    /// Diffuse model of the dielectric part.
    pub diffuse_model: DiffuseModel,
    /// Oren–Nayar σ in radians (see
    /// [`oren_nayar_sigma_from_roughness`](crate::diffuse::oren_nayar_sigma_from_roughness)).
    pub oren_nayar_sigma: T,
}

impl<T: Real> BrdfInputs<T> {
    /// The same inputs in another precision (nearest values).
    pub fn convert<U: Real>(&self) -> BrdfInputs<U> {
        let c = |x: T| U::from_f64(x.to_f64());
        let c3 = |x: [T; 3]| x.map(c);
        BrdfInputs {
            base_color: c3(self.base_color),
            metalness: c(self.metalness),
            alpha_x: c(self.alpha_x),
            alpha_y: c(self.alpha_y),
            conductor_eta: c3(self.conductor_eta),
            conductor_k: c3(self.conductor_k),
            dielectric_eta: c(self.dielectric_eta),
            outside_eta: c(self.outside_eta),
            polarisation_weight: c(self.polarisation_weight),
            diffuse_model: self.diffuse_model,
            oren_nayar_sigma: c(self.oren_nayar_sigma),
        }
    }
}

/// Evaluates the assembled BRDF f(v, l) per RGB channel (**not** multiplied by n·l).
///
/// `n`, `t`, `b` are the world-space normal, tangent and bitangent, `v` the direction
/// to the viewer and `l` the direction to the light; none need be unit length or
/// orthogonal ([`ShadingFrame::new`] orthonormalises; a zero normal gives 0). Returns 0
/// when n·l ≤ 0 or n·v ≤ 0 (which includes v = −l, where the half vector is undefined).
///
/// f = (1 − metalness) f_dielectric + metalness f_conductor, with the shared microfacet
/// lobe S = D_GGX,aniso(h) · V_Smith,height-correlated(v, l) (V = G₂/(4 n·v n·l)) and
/// c_h = v·h = |v + l|/2:
///
/// * f_conductor,c = S · R_w(c_h; η_i, η_c + i k_c) ([`fresnel_conductor`]);
/// * f_dielectric,c = S · R_w(c_h; η_i, η_d) (white specular, [`fresnel_dielectric`], TIR
///   when η_i > η_d) + T_w(n·l) T_w(n·v) · f_diffuse(ρ_c),
///
/// where R_w = (1 − w)R_s + w R_p and T_w = 1 − R_w ([`fresnel_dielectric_transmittance`]).
///
/// **Diffuse weighting**: light reaching the diffuse substrate crosses the interface
/// twice, in along l and out along v, so the diffuse lobe is weighted by the Fresnel
/// transmittance of both crossings at the macro-surface angles, T_w(n·l)·T_w(n·v).
/// It is symmetric in v and l, so f stays reciprocal; it is at most 1 and vanishes at
/// grazing, where the specular lobe takes the energy. ∫f cos ≤ 1 is verified numerically
/// for every diffuse model at ρ = 1 (`tests/identities.rs`). It is not an exact energy
/// balance: the specular lobe's F(v·h) averaged over the lobe differs from the
/// macro-surface F(n·v) at high roughness, and single-scattering GGX loses energy there.
pub fn brdf_evaluate<T: Real>(
    m: &BrdfInputs<T>,
    n: Vec3<T>,
    t: Vec3<T>,
    b: Vec3<T>,
    v: Vec3<T>,
    l: Vec3<T>,
) -> [T; 3] {
    brdf_evaluate_view(m, &brdf_view(m, n, t, b, v), l)
}

/// [`brdf_evaluate`] under a thin film (`None`: none; see [`brdf_view_with_film`]).
pub fn brdf_evaluate_with_film<T: Real>(
    m: &BrdfInputs<T>,
    film: Option<&ThinFilm<T>>,
    n: Vec3<T>,
    t: Vec3<T>,
    b: Vec3<T>,
    v: Vec3<T>,
    l: Vec3<T>,
) -> [T; 3] {
    brdf_evaluate_layered(m, film, None, n, t, b, v, l)
}

/// [`brdf_evaluate`] with the dielectric's specular strength and colour
/// (KHR_materials_specular; `None` or [`DielectricSpecular::neutral`]: none) and a thin
/// film over it (see [`brdf_view_layered`]).
#[allow(clippy::too_many_arguments)]
pub fn brdf_evaluate_layered<T: Real>(
    m: &BrdfInputs<T>,
    film: Option<&ThinFilm<T>>,
    specular: Option<&DielectricSpecular<T>>,
    n: Vec3<T>,
    t: Vec3<T>,
    b: Vec3<T>,
    v: Vec3<T>,
    l: Vec3<T>,
) -> [T; 3] {
    brdf_evaluate_view(m, &brdf_view_layered(m, film, specular, n, t, b, v), l)
}

/// Everything of f(v, l) that depends on the view alone: the shading frame, v in it,
/// the clamped parameters, the view's half of the Smith visibility and the dielectric
/// transmittance T_w(n·v). A renderer computes it once per pixel and evaluates every
/// light with [`brdf_evaluate_view`]; [`brdf_evaluate`] is exactly the two in sequence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BrdfView<T> {
    frame: ShadingFrame<T>,
    /// v in the shading frame.
    v: Vec3<T>,
    ax: T,
    ay: T,
    metal: T,
    w: T,
    /// (c_v, S_v) of [`smith_ggx_visibility_half`].
    cv: T,
    sv: T,
    /// T_w(n·v) of the dielectric part per channel (1 when there is none).
    transmittance_v: [T; 3],
    /// A thin film over the base, where one is present ([`ThinFilm::is_present`]).
    film: Option<ThinFilm<T>>,
    /// The dielectric's specular strength and colour, where present
    /// ([`DielectricSpecular::is_present`]), with the bare dielectric's F₀.
    specular: Option<(DielectricSpecular<T>, T)>,
}

/// The per-view part of [`brdf_evaluate`] (see [`BrdfView`]).
pub fn brdf_view<T: Real>(
    m: &BrdfInputs<T>,
    n: Vec3<T>,
    t: Vec3<T>,
    b: Vec3<T>,
    v: Vec3<T>,
) -> BrdfView<T> {
    brdf_view_with_film(m, None, n, t, b, v)
}

/// [`brdf_view`] for a surface under a thin film (KHR_materials_iridescence): every
/// Fresnel reflectance R of the BRDF, the dielectric's and the conductor's, becomes
/// mix(R, R_film, weight) per channel, R_film the film's over that base
/// ([`thin_film_reflectance`], polarisation-weighted alike), and the dielectric's
/// transmittances mix(T, 1 − R_film, weight): the film absorbs nothing, so what it does
/// not reflect reaches the diffuse substrate. A film of zero weight or thickness is no
/// film (the view is [`brdf_view`]'s).
pub fn brdf_view_with_film<T: Real>(
    m: &BrdfInputs<T>,
    film: Option<&ThinFilm<T>>,
    n: Vec3<T>,
    t: Vec3<T>,
    b: Vec3<T>,
    v: Vec3<T>,
) -> BrdfView<T> {
    brdf_view_layered(m, film, None, n, t, b, v)
}

/// [`brdf_view_with_film`] with the dielectric's specular strength and colour
/// (KHR_materials_specular, [`crate::specular`]): the dielectric's every reflectance R
/// becomes F′ = factor (F₀′ + (1 − F₀′) (R − F₀)/(1 − F₀)) per channel and its
/// transmittances 1 − max_c F′_c, before a film is mixed in (the film lies over the
/// specular interface). Neutral or absent values leave the view as [`brdf_view_with_film`]'s.
pub fn brdf_view_layered<T: Real>(
    m: &BrdfInputs<T>,
    film: Option<&ThinFilm<T>>,
    specular: Option<&DielectricSpecular<T>>,
    n: Vec3<T>,
    t: Vec3<T>,
    b: Vec3<T>,
    v: Vec3<T>,
) -> BrdfView<T> {
    let specular = specular.filter(|s| s.is_present()).map(|s| {
        (
            *s,
            fresnel_dielectric(T::ONE, m.outside_eta, m.dielectric_eta).weighted(T::HALF),
        )
    });
    let film = film.filter(|f| f.is_present()).map(|f| ThinFilm {
        weight: f.weight.saturate(),
        ..*f
    });
    let frame = ShadingFrame::new(n, t, b);
    let v = frame.to_local(v.normalize());
    let ax = clamp_alpha(m.alpha_x);
    let ay = clamp_alpha(m.alpha_y);
    let metal = m.metalness.saturate();
    let w = m.polarisation_weight.saturate();
    let (cv, sv) = smith_ggx_visibility_half(v, ax, ay);
    let transmittance_v = if metal < T::ONE {
        dielectric_transmittance(m, film.as_ref(), specular.as_ref(), w, v.z)
    } else {
        [T::ONE; 3]
    };
    BrdfView {
        frame,
        v,
        ax,
        ay,
        metal,
        w,
        cv,
        sv,
        transmittance_v,
        film,
        specular,
    }
}

/// The film's R_w(c) per channel over a base η + ik per channel.
fn film_reflectance<T: Real>(
    m: &BrdfInputs<T>,
    f: &ThinFilm<T>,
    w: T,
    c: T,
    (eta, k): ([T; 3], [T; 3]),
) -> [T; 3] {
    let r = thin_film_reflectance(c, m.outside_eta, f, eta, k);
    std::array::from_fn(|ch| weighted_channel(&r, ch, w))
}

/// base + weight (film − base) per channel: the film's share of a Fresnel term.
fn film_mixed<T: Real>(base: [T; 3], f: &ThinFilm<T>, film: [T; 3]) -> [T; 3] {
    std::array::from_fn(|ch| base[ch] + f.weight * (film[ch] - base[ch]))
}

/// R_w(c; η_i, η_d) of the dielectric part per channel, its specular strength and colour
/// applied, then a film mixed in.
fn dielectric_reflectance<T: Real>(
    m: &BrdfInputs<T>,
    film: Option<&ThinFilm<T>>,
    specular: Option<&(DielectricSpecular<T>, T)>,
    w: T,
    c: T,
) -> [T; 3] {
    let bare = fresnel_dielectric(c, m.outside_eta, m.dielectric_eta).weighted(w);
    let base = specular.map_or([bare; 3], |(s, f0)| s.reflectance(bare, *f0));
    film.map_or(base, |f| {
        let dielectric = ([m.dielectric_eta; 3], [T::ZERO; 3]);
        film_mixed(base, f, film_reflectance(m, f, w, c, dielectric))
    })
}

/// T_w(c; η_i, η_d) of the dielectric part per channel (1 − max_c F′_c with a specular
/// strength or colour), a film mixed in (1 − its reflectance: it absorbs nothing).
fn dielectric_transmittance<T: Real>(
    m: &BrdfInputs<T>,
    film: Option<&ThinFilm<T>>,
    specular: Option<&(DielectricSpecular<T>, T)>,
    w: T,
    c: T,
) -> [T; 3] {
    let base = [specular.map_or_else(
        || fresnel_dielectric_transmittance(c, m.outside_eta, m.dielectric_eta).weighted(w),
        |(s, f0)| {
            s.transmittance(
                fresnel_dielectric(c, m.outside_eta, m.dielectric_eta).weighted(w),
                *f0,
            )
        },
    ); 3];
    film.map_or(base, |f| {
        let dielectric = ([m.dielectric_eta; 3], [T::ZERO; 3]);
        let r = film_reflectance(m, f, w, c, dielectric);
        film_mixed(base, f, r.map(|r| T::ONE - r))
    })
}

/// R_w(c; η_i, η_c + i k_c) of the conductor part per channel, a film mixed in.
fn conductor_reflectance<T: Real>(
    m: &BrdfInputs<T>,
    film: Option<&ThinFilm<T>>,
    w: T,
    c: T,
) -> [T; 3] {
    let base: [T; 3] = std::array::from_fn(|ch| {
        fresnel_conductor(c, m.outside_eta, m.conductor_eta[ch], m.conductor_k[ch]).weighted(w)
    });
    film.map_or(base, |f| {
        film_mixed(
            base,
            f,
            film_reflectance(m, f, w, c, (m.conductor_eta, m.conductor_k)),
        )
    })
}

/// (1 − w) R_s + w R_p of one channel.
fn weighted_channel<T: Real>(r: &Polarised<[T; 3]>, ch: usize, w: T) -> T {
    Polarised {
        s: r.s[ch],
        p: r.p[ch],
    }
    .weighted(w)
}

/// f(v, l) per channel for a view prepared by [`brdf_view`] (see [`brdf_evaluate`]).
pub fn brdf_evaluate_view<T: Real>(m: &BrdfInputs<T>, view: &BrdfView<T>, l: Vec3<T>) -> [T; 3] {
    let zero = [T::ZERO; 3];
    let v = view.v;
    let l = view.frame.to_local(l.normalize());
    if !(v.z.is_positive() && l.z.is_positive()) {
        return zero;
    }
    let (ax, ay, metal, w) = (view.ax, view.ay, view.metal, view.w);

    // Shared microfacet lobe. |v + l| > 0 here since v.z + l.z > 0.
    let sum = v + l;
    let len = sum.length();
    let h = sum * (T::ONE / len);
    let cos_h = (T::HALF * len).min(T::ONE); // v·h = l·h, symmetric in v and l
    let (cl, sl) = smith_ggx_visibility_half(l, ax, ay);
    let visibility = T::HALF / (cl * view.sv + view.cv * sl);
    let lobe = d_ggx_anisotropic(h, ax, ay) * visibility;

    let film = view.film.as_ref();
    let specular = view.specular.as_ref();
    let mut out = zero;
    if metal < T::ONE {
        let spec = dielectric_reflectance(m, film, specular, w, cos_h);
        let transmittance_l = dielectric_transmittance(m, film, specular, w, l.z);
        let sigma = m.oren_nayar_sigma;
        for (c, (o, &rho)) in out.iter_mut().zip(&m.base_color).enumerate() {
            let rho = rho.saturate();
            let diffuse = match m.diffuse_model {
                DiffuseModel::Lambert => diffuse_lambert(rho),
                DiffuseModel::OrenNayarQualitative => diffuse_oren_nayar_qualitative(
                    rho,
                    sigma,
                    T::from_f64(OREN_NAYAR_A_CONSTANT_BRDF),
                    v,
                    l,
                ),
                DiffuseModel::OrenNayarFull => diffuse_oren_nayar_full(rho, sigma, v, l),
            };
            let diffuse_weight = transmittance_l[c] * view.transmittance_v[c];
            *o = (T::ONE - metal) * (lobe * spec[c] + diffuse_weight * diffuse);
        }
    }
    if metal > T::ZERO {
        let r = conductor_reflectance(m, film, w, cos_h);
        for (o, r) in out.iter_mut().zip(r) {
            *o += metal * lobe * r;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diffuse_model_round_trips_through_u32() {
        for m in [
            DiffuseModel::Lambert,
            DiffuseModel::OrenNayarQualitative,
            DiffuseModel::OrenNayarFull,
        ] {
            assert_eq!(DiffuseModel::try_from(u32::from(m)), Ok(m));
        }
        assert_eq!(DiffuseModel::Lambert as u32, 0);
        assert_eq!(DiffuseModel::OrenNayarQualitative as u32, 1);
        assert_eq!(DiffuseModel::OrenNayarFull as u32, 2);
        assert_eq!(DiffuseModel::try_from(3), Err(UnknownDiffuseModel(3)));
    }
}
