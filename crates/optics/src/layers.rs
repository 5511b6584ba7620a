//! The layers over a BRDF, in the order light meets them: a clear coat ([`crate::coat`])
//! on top, a sheen ([`crate::sheen`]) under it on the base. One place says how they
//! combine, for every f64 reference (the G-buffer parity's, the scene's, the
//! environment's integral); GLSL: `light_radiance` in `shaders/include/lighting_terms.glsl`.
//!
//! Per unit irradiance from l: c_coat S_c R (n_c·l)⁺ + A(v) A(l) [f_sheen + s f_base] (n·l)⁺,
//! s the sheen's albedo scaling, A the coat's attenuation.

use crate::coat::{
    coat_evaluate_view, coat_view, coated_radiance, CoatInputs, CoatLayer, CoatView,
};
use crate::sheen::{
    sheen_albedo_lookup, sheen_albedo_scaling, sheen_albedo_table, sheen_lobe, SheenInputs,
};
use crate::specular::DielectricSpecular;
use crate::thin_film::ThinFilm;
use crate::vec3::{ShadingFrame, Vec3};

/// What lies over a surface's BRDF (each `None` where there is none).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Layers {
    /// A clear coat, with its own normal.
    pub coat: Option<CoatLayer<f64>>,
    /// A sheen, on the base's shading normal.
    pub sheen: Option<SheenInputs<f64>>,
    /// A thin film on the base (KHR_materials_iridescence). Not a layer of its own: it
    /// changes the base BRDF's Fresnel terms, so the references evaluate the base with
    /// [`crate::brdf::brdf_evaluate_layered`]; it travels here with what else lies on
    /// the surface.
    pub film: Option<ThinFilm<f64>>,
    /// The dielectric's specular strength and colour (KHR_materials_specular), where
    /// they are not the neutral 1 and 1. Like the film, it changes the base's Fresnel
    /// terms ([`crate::brdf::brdf_evaluate_layered`]).
    pub specular: Option<DielectricSpecular<f64>>,
}

/// The layers prepared for one view ([`layers_view`]).
#[derive(Debug, Clone, Copy)]
pub struct LayersView {
    coat: Option<(CoatInputs<f64>, CoatView<f64>)>,
    sheen: Option<SheenView>,
}

/// The sheen, its frame about the base's normal, v in it, its perceptual roughness and
/// E(n·v).
#[derive(Debug, Clone, Copy)]
struct SheenView {
    inputs: SheenInputs<f64>,
    frame: ShadingFrame<f64>,
    v: Vec3<f64>,
    roughness: f64,
    albedo_v: f64,
}

impl LayersView {
    /// What of the light passing through the surface towards the viewer (glass's) the
    /// layers let out: a coat's A(v) times a sheen's 1 − max(c) E(n·v) (1 without
    /// either).
    pub fn through_layers_v(&self) -> f64 {
        let coat = self.coat.map_or(1.0, |(_, view)| view.attenuation_v());
        let sheen = self.sheen.map_or(1.0, |s| {
            let c = s.inputs.color[0]
                .max(s.inputs.color[1])
                .max(s.inputs.color[2]);
            1.0 - c.clamp(0.0, 1.0) * s.albedo_v
        });
        coat * sheen
    }
}

/// The layers' view-dependent half for a surface of shading normal `n` seen from `v`
/// (world space). A sheen's E is read from [`sheen_albedo_table`] (made on first use).
pub fn layers_view(layers: &Layers, n: Vec3<f64>, v: Vec3<f64>) -> LayersView {
    LayersView {
        coat: layers
            .coat
            .map(|c| (c.inputs, coat_view(&c.inputs, c.normal, v))),
        sheen: layers.sheen.map(|inputs| {
            let frame = ShadingFrame::from_normal(n);
            let v = frame.to_local(v.normalize());
            let roughness = inputs.alpha.max(0.0).sqrt();
            SheenView {
                inputs,
                frame,
                v,
                roughness,
                albedo_v: sheen_albedo_lookup(sheen_albedo_table(), v.z, roughness),
            }
        }),
    }
}

/// Whether light from `l` (world space) may reach any layer: the base's cosine `cos_base`
/// is positive, or a coat's normal faces it.
pub fn layers_face(view: &LayersView, cos_base: f64, l: Vec3<f64>) -> bool {
    cos_base > 0.0
        || view
            .coat
            .is_some_and(|(_, coat)| coat.normal().dot(l.normalize()) > 0.0)
}

/// The radiance reflected per unit irradiance from `l` (world space): the base's f(v, l)
/// `base` and its n·l `cos_base`, under the layers (module documentation).
pub fn layered_radiance(
    view: &LayersView,
    base: [f64; 3],
    cos_base: f64,
    l: Vec3<f64>,
) -> [f64; 3] {
    let mut f = base;
    if let Some(sheen) = &view.sheen {
        let l_local = sheen.frame.to_local(l.normalize());
        let albedo_l = sheen_albedo_lookup(sheen_albedo_table(), l_local.z, sheen.roughness);
        let color = sheen.inputs.color;
        let scaling = sheen_albedo_scaling(color, sheen.albedo_v, albedo_l);
        let lobe = sheen_lobe(sheen.v, l_local, sheen.inputs.alpha);
        f = std::array::from_fn(|c| color[c].clamp(0.0, 1.0) * lobe + scaling * base[c]);
    }
    match &view.coat {
        Some((inputs, coat)) => {
            coated_radiance(f, cos_base, coat, &coat_evaluate_view(inputs, coat, l))
        }
        None => f.map(|f| f * cos_base.max(0.0)),
    }
}
