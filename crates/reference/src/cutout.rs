//! Cut-out materials (glTF `alphaMode` MASK) for the ray casts: a triangle of an object
//! whose material is a cut-out is hit only where the material's alpha — the base colour
//! factor's alpha × the base colour texture's alpha × the vertex colour's alpha — reaches
//! its cutoff, so primary rays see through the holes and shadow rays pass them.
//!
//! The alpha is the texture's own at the hit point: level 0 filtered by the sampler's
//! magnification filter (a point of the surface, not a pixel's footprint). The renderer
//! tests the alpha it samples at the pixel's level of detail, raised on coarser mip
//! levels so thin cut-outs do not vanish in the distance; where the two disagree is a
//! cut-out's edge, which the end-to-end comparison counts rather than compares.

use std::collections::HashMap;
use std::sync::Arc;

use combustion_scene::{Sampler, Scene, TextureRef};

use crate::texture::{transformed_uv, MipChain};
use crate::WorldTriangle;

/// The cut-out objects of a scene, each with what its alpha test reads.
#[derive(Clone, Debug)]
pub(crate) struct Cutouts {
    by_object: HashMap<usize, ObjectCutout>,
}

#[derive(Clone, Debug)]
struct ObjectCutout {
    alpha: f64,
    cutoff: f64,
    /// The mesh's vertex alphas (COLOR_0's) and indices, where some is below 1.
    vertex_alpha: Option<Arc<(Vec<f64>, Vec<u32>)>>,
    /// The base colour texture's level 0, its sampler and its slot (coordinate set and
    /// transform), with the mesh's coordinates of that set and its indices.
    texture: Option<(Arc<MipChain>, Sampler, TextureRef, Arc<MeshCoordinates>)>,
}

/// One mesh's texture coordinates of one set, and its indices.
#[derive(Debug)]
struct MeshCoordinates {
    uv: Vec<[f64; 2]>,
    indices: Vec<u32>,
}

impl Cutouts {
    /// The cut-outs among the objects `keep` keeps; `None` when there are none, so that
    /// scenes without them pay nothing per hit.
    pub(crate) fn of(
        scene: &Scene,
        keep: impl Fn(&combustion_scene::Object) -> bool,
    ) -> Option<Cutouts> {
        let mut chains: HashMap<*const combustion_scene::Image, Arc<MipChain>> = HashMap::new();
        let mut coordinates: HashMap<(usize, u32), Arc<MeshCoordinates>> = HashMap::new();
        let mut by_object = HashMap::new();
        for (index, object) in scene.objects.iter().enumerate() {
            let Some(material) = scene.materials.get(object.material) else {
                continue;
            };
            let Some(cutoff) = material.alpha_mode.cutoff() else {
                continue;
            };
            if !keep(object) {
                continue;
            }
            let Some(mesh) = scene.meshes.get(object.mesh) else {
                continue;
            };
            let texture = material.base_color_texture.as_ref().map(|slot| {
                let image = &slot.texture.image;
                let chain = chains
                    .entry(Arc::as_ptr(image))
                    .or_insert_with(|| Arc::new(MipChain::level_zero(image)))
                    .clone();
                let set = slot.tex_coord;
                let uv = coordinates
                    .entry((object.mesh, set))
                    .or_insert_with(|| {
                        Arc::new(MeshCoordinates {
                            uv: mesh
                                .vertices
                                .iter()
                                .map(|v| (if set == 1 { v.uv1 } else { v.uv }).map(f64::from))
                                .collect(),
                            indices: mesh.indices.clone(),
                        })
                    })
                    .clone();
                (chain, slot.texture.sampler, slot.clone(), uv)
            });
            let vertex_alpha = mesh.vertices.iter().any(|v| v.color[3] != 1.0).then(|| {
                Arc::new((
                    mesh.vertices
                        .iter()
                        .map(|v| f64::from(v.color[3]))
                        .collect(),
                    mesh.indices.clone(),
                ))
            });
            by_object.insert(
                index,
                ObjectCutout {
                    alpha: f64::from(material.alpha),
                    cutoff: f64::from(cutoff),
                    vertex_alpha,
                    texture,
                },
            );
        }
        (!by_object.is_empty()).then_some(Cutouts { by_object })
    }

    /// Whether `triangle`'s surface is present at barycentrics `b` (true for triangles
    /// of objects that are not cut-outs).
    pub(crate) fn present(&self, triangle: &WorldTriangle, b: [f64; 2]) -> bool {
        let Some(cutout) = self.by_object.get(&triangle.object) else {
            return true;
        };
        cutout.alpha_at(triangle.triangle, b) >= cutout.cutoff
    }
}

impl ObjectCutout {
    fn alpha_at(&self, triangle: usize, [b1, b2]: [f64; 2]) -> f64 {
        let weights = [1.0 - b1 - b2, b1, b2];
        let vertex_alpha = self.vertex_alpha.as_ref().map_or(1.0, |mesh| {
            let (alphas, indices) = &**mesh;
            (0..3)
                .map(|k| {
                    indices
                        .get(3 * triangle + k)
                        .and_then(|&i| alphas.get(i as usize))
                        .map_or(1.0, |a| a * weights[k])
                })
                .sum()
        });
        self.alpha * vertex_alpha * self.texture_alpha(triangle, weights)
    }

    fn texture_alpha(&self, triangle: usize, [b0, b1, b2]: [f64; 3]) -> f64 {
        let Some((chain, sampler, slot, mesh)) = &self.texture else {
            return 1.0;
        };
        let corner = |k: usize| {
            mesh.indices
                .get(3 * triangle + k)
                .and_then(|&i| mesh.uv.get(i as usize))
                .copied()
        };
        let (Some(p0), Some(p1), Some(p2)) = (corner(0), corner(1), corner(2)) else {
            return 1.0;
        };
        let uv = [0, 1].map(|c| b0 * p0[c] + b1 * p1[c] + b2 * p2[c]);
        chain.sample(sampler, transformed_uv(slot, uv), 0.0)[3]
    }
}
