//! A rendered frame against the scene itself: the f64 reference of
//! `combustion_reference::shading` (primary rays cast through the scene's triangles,
//! each hit shaded from the scene's own materials, textures and lights) computed once
//! per scene and size, then compared with any number of frames of it — the report's
//! end-to-end error columns and `tests/end_to_end.rs`.
//!
//! Each pixel the reference shades twice: exactly, and from the inputs as the frame's
//! G-buffer stores them ([`precision_of`] its [`GBufferStorage`]), so a frame's error splits
//! into the storage's share and the rest. Pixels at an edge (within one pixel of a
//! pixel whose ray sees another object, another material or nothing, or a triangle
//! sharing no vertex with its own whose shading normal is more than [`CREASE_ANGLE`]
//! away: a crease; which side of an edge a pixel whose centre lies within rounding of
//! it shows is the rasteriser's call) are counted, not compared.

use combustion_reference::primary::{camera_ray, per_pixel};
use combustion_reference::shading::{GBufferPrecision, SceneShading, StoredValue, SurfacePoint};
use combustion_reference::SceneBvh;
use combustion_renderer::reference::RADIANCE_FLOOR;
use combustion_renderer::{BaseColorStorage, Frame, GBufferStorage};
use combustion_scene::{Light, Scene};

/// Relative error of `a` against `b`: the largest over the channels of
/// |a − b| / max(|b|, [`RADIANCE_FLOOR`]).
pub fn relative(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3)
        .map(|c| (a[c] - b[c]).abs() / b[c].abs().max(RADIANCE_FLOOR))
        .fold(0.0, f64::max)
}

/// Neighbouring pixels whose triangles share no vertex and whose shading normals differ
/// by more than this (radians, 29°) lie on either side of a crease (a hard edge, where a
/// mesh's vertices are split to give each face its own normal). A smooth surface turns
/// its normal by far less from one pixel to the next, except at its rim (a silhouette
/// anyway) or when it spans a few pixels.
pub const CREASE_ANGLE: f64 = 0.5;

/// What the reference models of the G-buffer `storage` keeps: its formats as
/// docs/gbuffer.md describes them.
pub fn precision_of(storage: GBufferStorage) -> GBufferPrecision {
    let (base_color, metalness) = match storage.base_color {
        BaseColorStorage::Srgb8 => (StoredValue::Unorm(8), StoredValue::Unorm(8)),
        BaseColorStorage::Srgb16 => (StoredValue::Unorm(16), StoredValue::Unorm(16)),
        BaseColorStorage::LinearHalf => (StoredValue::Half, StoredValue::Half),
    };
    GBufferPrecision {
        base_color,
        metalness,
        roughness_bits: storage.surface.bits(),
        normal_octahedral_bits: storage.surface.bits(),
    }
}

/// How [`SceneReference::with_environment`] samples a frame lit by an environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnvironmentReference {
    /// Samples of each strategy of the environment's integral per shaded pixel.
    pub samples: u32,
    /// One pixel in `stride`² is shaded (and compared).
    pub stride: u32,
}

/// One pixel of the reference.
#[derive(Clone, Copy, Debug)]
pub struct ReferencePixel {
    /// The surface the pixel's ray hits, exactly as the scene describes it.
    pub surface: SurfacePoint,
    /// The same surface as the G-buffer stores it.
    pub stored: SurfacePoint,
    /// The material the ray sees.
    pub material: usize,
    /// The radiance of `surface` (NaN where the reference samples the frame and this
    /// pixel is not shaded: [`SceneReference::with_environment`]).
    pub exact: [f64; 3],
    /// The radiance of `stored` (NaN likewise).
    pub as_stored: [f64; 3],
}

impl ReferencePixel {
    /// Whether the reference shaded this pixel.
    pub fn is_shaded(&self) -> bool {
        !self.exact[0].is_nan()
    }
}

/// The scene's f64 reference for one camera, size and set of lights.
pub struct SceneReference<'a> {
    scene: &'a Scene,
    bvh: &'a SceneBvh,
    /// How it shades (for re-shading perturbed surfaces).
    pub shading: SceneShading<'a>,
    width: u32,
    height: u32,
    /// Per pixel, row-major from the top-left; `None` where the ray hits nothing.
    pub pixels: Vec<Option<ReferencePixel>>,
    /// The material each pixel's ray sees (`None`: nothing).
    seen: Vec<Option<usize>>,
    /// Per pixel: the blended surfaces (alphaMode BLEND) its ray passes through before
    /// its opaque surface, nearest first, each with its radiance (NaN where the pixel
    /// is not shaded); empty in a scene without blended materials.
    blended: Vec<Vec<(SurfacePoint, [f64; 3])>>,
}

/// One pixel of a frame compared with the reference.
#[derive(Clone, Copy, Debug)]
pub struct ComparedPixel {
    /// Column, from the left.
    pub x: u32,
    /// Row, from the top.
    pub y: u32,
    /// The GPU's HDR radiance.
    pub gpu: [f64; 3],
    /// The GPU against the exact reference.
    pub total: f64,
    /// The storage's share: the stored reference against the exact one.
    pub storage: f64,
    /// The GPU against the stored reference.
    pub rest: f64,
}

/// A frame compared with a [`SceneReference`].
#[derive(Clone, Debug, Default)]
pub struct FrameComparison {
    /// Every compared pixel (both see the same material, away from silhouettes).
    pub pixels: Vec<ComparedPixel>,
    /// Pixels at edges (silhouettes and creases), not compared.
    pub silhouette: usize,
    /// Pixels whose material differs from the reference's away from any silhouette,
    /// with no ray within the rasteriser's snapping of the pixel's centre seeing it
    /// either: what the frame shows there is wrong.
    pub away: Vec<(u32, u32)>,
    /// Compared pixels whose GPU radiance is not finite.
    pub non_finite: usize,
    /// Pixels showing points or lines (a material only they use): they have no surface
    /// for a ray to hit, so they are counted, not compared.
    pub strokes: usize,
    /// Pixels seen through a transmissive surface (glass), compared apart: the
    /// renderer's transmission is a screen-space estimate whose error is measured here,
    /// not bounded (docs/gltf.md, "Transmission").
    pub transmissive: Vec<ComparedPixel>,
}

/// Mean and maximum of some per-pixel errors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeanMax {
    /// The mean.
    pub mean: f64,
    /// The largest.
    pub max: f64,
}

impl MeanMax {
    /// Of `values` (0 and 0 when empty).
    pub fn of(values: impl Iterator<Item = f64>) -> MeanMax {
        let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0usize);
        for v in values {
            sum += v;
            max = max.max(v);
            n += 1;
        }
        MeanMax {
            mean: sum / n.max(1) as f64,
            max,
        }
    }
}

/// Per material of `scene`: whether only points and lines use it (some object of
/// theirs does, and no object of triangles).
fn materials_of_strokes_only(scene: &Scene) -> Vec<bool> {
    let mut strokes = vec![false; scene.materials.len()];
    let mut surfaces = vec![false; scene.materials.len()];
    for object in &scene.objects {
        let Some(mesh) = scene.meshes.get(object.mesh) else {
            continue;
        };
        let used = if mesh.topology == combustion_scene::Topology::Triangles {
            &mut surfaces
        } else {
            &mut strokes
        };
        if let Some(flag) = used.get_mut(object.material) {
            *flag = true;
        }
    }
    strokes
        .iter()
        .zip(&surfaces)
        .map(|(&l, &s)| l && !s)
        .collect()
}

/// A frame's end-to-end errors in summary.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EndToEndErrors {
    /// Pixels compared.
    pub compared: usize,
    /// Pixels at silhouettes.
    pub silhouette: usize,
    /// Pixels showing the wrong material away from silhouettes.
    pub away: usize,
    /// Pixels showing points or lines, not compared.
    pub strokes: usize,
    /// The GPU against the exact reference.
    pub total: MeanMax,
    /// The G-buffer storage's share.
    pub storage: MeanMax,
    /// The GPU against the stored reference.
    pub rest: MeanMax,
    /// Pixels seen through glass (transmissive surfaces), compared apart.
    pub through_glass: usize,
    /// Their error against the exact reference: the screen-space transmission's.
    pub glass: MeanMax,
}

impl FrameComparison {
    /// The errors in summary.
    pub fn summary(&self) -> EndToEndErrors {
        EndToEndErrors {
            compared: self.pixels.len(),
            silhouette: self.silhouette,
            away: self.away.len(),
            strokes: self.strokes,
            total: MeanMax::of(self.pixels.iter().map(|p| p.total)),
            storage: MeanMax::of(self.pixels.iter().map(|p| p.storage)),
            rest: MeanMax::of(self.pixels.iter().map(|p| p.rest)),
            through_glass: self.transmissive.len(),
            glass: MeanMax::of(self.transmissive.iter().map(|p| p.total)),
        }
    }
}

impl<'a> SceneReference<'a> {
    /// The reference of `scene` (its triangles in `bvh`: [`SceneBvh::new`]) seen by its
    /// camera at `width` × `height`, lit by `lights`, stored with `precision` (a frame's
    /// G-buffer storage: [`precision_of`]), on up to `threads` threads.
    pub fn new(
        scene: &'a Scene,
        bvh: &'a SceneBvh,
        lights: &'a [Light],
        (width, height): (u32, u32),
        precision: GBufferPrecision,
        threads: usize,
    ) -> Self {
        let shading = SceneShading::new(scene, bvh, lights, width, height);
        Self::shaded(scene, bvh, shading, precision, 1, threads)
    }

    /// As [`SceneReference::new`] for a scene lit by its environment too: the
    /// environment's integral ([`SceneShading::with_environment`], `sampling.samples`
    /// samples of each strategy) costs thousands of BRDF evaluations a pixel, so one
    /// pixel in `sampling.stride`² (the centre of each block) is shaded and compared; the
    /// others still tell edges apart.
    pub fn with_environment(
        scene: &'a Scene,
        bvh: &'a SceneBvh,
        lights: &'a [Light],
        (width, height): (u32, u32),
        precision: GBufferPrecision,
        sampling: EnvironmentReference,
        threads: usize,
    ) -> Self {
        let shading =
            SceneShading::new(scene, bvh, lights, width, height).with_environment(sampling.samples);
        Self::shaded(scene, bvh, shading, precision, sampling.stride, threads)
    }

    fn shaded(
        scene: &'a Scene,
        bvh: &'a SceneBvh,
        shading: SceneShading<'a>,
        precision: GBufferPrecision,
        stride: u32,
        threads: usize,
    ) -> Self {
        let (width, height) = (shading.width(), shading.height());
        let surfaces = shading.surfaces(threads);
        let stride = stride.max(1);
        let shaded = |i: usize| {
            let (x, y) = (i as u32 % width, i as u32 / width);
            x % stride == stride / 2 && y % stride == stride / 2
        };
        let pixels: Vec<Option<ReferencePixel>> = {
            let shading = &shading;
            let chunk = surfaces.len().div_ceil(threads.max(1)).max(1);
            std::thread::scope(|scope| {
                let handles: Vec<_> = surfaces
                    .chunks(chunk)
                    .enumerate()
                    .map(|(k, part)| {
                        scope.spawn(move || {
                            part.iter()
                                .enumerate()
                                .map(|(j, s)| {
                                    s.map(|surface| {
                                        if shaded(k * chunk + j) {
                                            reference_pixel(
                                                scene, shading, &precision, surface, None,
                                            )
                                        } else {
                                            unshaded_pixel(scene, &precision, surface)
                                        }
                                    })
                                })
                                .collect::<Vec<_>>()
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .flat_map(|h| h.join().expect("a reference thread panicked"))
                    .collect()
            })
        };
        let seen = pixels.iter().map(|p| p.map(|p| p.material)).collect();
        let blended = if scene.materials.iter().any(|m| m.is_see_through()) {
            let shading = &shading;
            per_pixel(width, height, threads, |x, y| {
                let i = (y * width + x) as usize;
                shading
                    .blended_surfaces(x, y)
                    .into_iter()
                    .map(|s| {
                        let radiance = if shaded(i) {
                            shading.radiance(&s)
                        } else {
                            [f64::NAN; 3]
                        };
                        (s, radiance)
                    })
                    .collect()
            })
        } else {
            vec![Vec::new(); (width * height) as usize]
        };
        SceneReference {
            scene,
            bvh,
            shading,
            width,
            height,
            pixels,
            seen,
            blended,
        }
    }

    /// Whether two hits' triangles of one object share a vertex index (so the shading
    /// normal is continuous between them where they meet).
    fn share_a_vertex(&self, a: &SurfacePoint, b: &SurfacePoint) -> bool {
        let indices = |s: &SurfacePoint| -> Option<&[u32]> {
            let mesh = self
                .scene
                .meshes
                .get(self.scene.objects.get(s.hit.object)?.mesh)?;
            mesh.indices.get(3 * s.hit.triangle..3 * s.hit.triangle + 3)
        };
        match (indices(a), indices(b)) {
            (Some(p), Some(q)) => p.iter().any(|i| q.contains(i)),
            _ => false,
        }
    }

    /// Whether pixel (`x`, `y`) lies within one pixel of an edge: a pixel whose ray sees
    /// another object or material (or nothing where it sees something), or across a
    /// crease (a triangle sharing no vertex with its own, its shading normal more than
    /// [`CREASE_ANGLE`] from its own).
    pub fn at_silhouette(&self, x: u32, y: u32) -> bool {
        let (w, h) = (self.width, self.height);
        let own = &self.pixels[(y * w + x) as usize];
        (y.saturating_sub(1)..(y + 2).min(h)).any(|yy| {
            (x.saturating_sub(1)..(x + 2).min(w)).any(|xx| {
                let other = &self.pixels[(yy * w + xx) as usize];
                let objects = |i: usize| self.blended[i].iter().map(|(s, _)| s.hit.object);
                if !objects((y * w + x) as usize).eq(objects((yy * w + xx) as usize)) {
                    return true; // another blended surface in front
                }
                match (own, other) {
                    (None, None) => false,
                    (Some(a), Some(b)) => {
                        a.material != b.material
                            || a.surface.hit.object != b.surface.hit.object
                            || (a.surface.n.angle_between(b.surface.n) > CREASE_ANGLE
                                && !self.share_a_vertex(&a.surface, &b.surface))
                    }
                    _ => true,
                }
            })
        })
    }

    /// Whether a ray within two sub-pixel steps (2/256 of a pixel: a rasteriser snaps
    /// vertices to 2^−subPixelPrecisionBits, 8 on lavapipe) of pixel (`x`, `y`)'s centre
    /// sees `material`: geometry thinner than a pixel has no silhouette pixel beside it.
    fn seen_within_snapping(&self, x: u32, y: u32, material: Option<usize>) -> bool {
        let reach = 2.0 / 256.0;
        let camera = &self.scene.camera;
        (0..8).any(|k| {
            let (sin, cos) = (f64::from(k) * std::f64::consts::FRAC_PI_4).sin_cos();
            let ray = camera_ray(
                camera,
                self.width,
                self.height,
                f64::from(x) + 0.5 + reach * cos,
                f64::from(y) + 0.5 + reach * sin,
            );
            let hit = self
                .bvh
                .closest_hit(&ray, f64::from(camera.near), f64::from(camera.far));
            hit.map(|h| self.scene.objects[h.object].material) == material
        })
    }

    /// Compares `frame` (read back with its HDR image and G-buffer, at this reference's
    /// size) pixel by pixel; an empty comparison if it lacks them or its size differs.
    pub fn compare(&self, frame: &Frame) -> FrameComparison {
        let mut out = FrameComparison::default();
        let Some(g) = frame.gbuffer.as_ref() else {
            return out;
        };
        let strokes_only = materials_of_strokes_only(self.scene);
        let n = (self.width * self.height) as usize;
        if (frame.width, frame.height) != (self.width, self.height)
            || g.texels.len() != n
            || frame.hdr.len() != n
        {
            return out;
        }
        for y in 0..self.height {
            for x in 0..self.width {
                let i = (y * self.width + x) as usize;
                let texel = &g.texels[i];
                let gpu_material =
                    (texel.depth < 1.0).then_some(usize::from(texel.material_direction[0]));
                if gpu_material.is_some_and(|m| strokes_only.get(m) == Some(&true)) {
                    out.strokes += 1;
                    continue;
                }
                if gpu_material != self.seen[i] {
                    if self.at_silhouette(x, y) {
                        out.silhouette += 1;
                    } else if !self.seen_within_snapping(x, y, gpu_material) {
                        out.away.push((x, y));
                    }
                    continue;
                }
                let Some(p) = &self.pixels[i] else {
                    continue; // background both
                };
                if self.at_silhouette(x, y) {
                    out.silhouette += 1;
                    continue;
                }
                if !p.is_shaded() {
                    continue; // not sampled
                }
                let gpu = [0, 1, 2].map(|c| f64::from(frame.hdr[i][c]));
                if gpu.iter().any(|c| !c.is_finite()) {
                    out.non_finite += 1;
                    continue;
                }
                // Blended surfaces in front: the forward pass shades them from their
                // own inputs (nothing stored), over the opaque surface's radiance.
                let exact = SceneShading::blended_over(&self.blended[i], p.exact);
                let as_stored = SceneShading::blended_over(&self.blended[i], p.as_stored);
                let compared = ComparedPixel {
                    x,
                    y,
                    gpu,
                    total: relative(gpu, exact),
                    storage: relative(as_stored, exact),
                    rest: relative(gpu, as_stored),
                };
                let through_glass = self.blended[i].iter().any(|(s, _)| {
                    self.scene
                        .objects
                        .get(s.hit.object)
                        .and_then(|o| self.scene.materials.get(o.material))
                        .is_some_and(|m| m.is_transmissive())
                });
                if through_glass {
                    out.transmissive.push(compared);
                } else {
                    out.pixels.push(compared);
                }
            }
        }
        out
    }

    /// Stores every pixel's surface again with `precision` (another G-buffer storage:
    /// [`precision_of`]), on up to `threads` threads: the rays, hits and exact radiance
    /// are kept.
    pub fn store_as(&mut self, precision: GBufferPrecision, threads: usize) {
        let (scene, shading) = (self.scene, &self.shading);
        let chunk = self.pixels.len().div_ceil(threads.max(1)).max(1);
        std::thread::scope(|scope| {
            for part in self.pixels.chunks_mut(chunk) {
                scope.spawn(move || {
                    for pixel in part.iter_mut().flatten().filter(|p| p.is_shaded()) {
                        *pixel = reference_pixel(
                            scene,
                            shading,
                            &precision,
                            pixel.surface,
                            Some(pixel.exact),
                        );
                    }
                });
            }
        });
    }

    /// The reference pixel at (`x`, `y`): its opaque surface.
    pub fn pixel(&self, x: u32, y: u32) -> Option<&ReferencePixel> {
        self.pixels.get((y * self.width + x) as usize)?.as_ref()
    }

    /// The blended surfaces in front of pixel (`x`, `y`)'s opaque surface, nearest
    /// first, each with its radiance (see [`SceneShading::blended_over`]).
    pub fn blended(&self, x: u32, y: u32) -> &[(SurfacePoint, [f64; 3])] {
        self.blended
            .get((y * self.width + x) as usize)
            .map_or(&[], Vec::as_slice)
    }
}

/// A pixel the reference does not shade: its surface, stored, and NaN radiance.
fn unshaded_pixel(
    scene: &Scene,
    precision: &GBufferPrecision,
    surface: SurfacePoint,
) -> ReferencePixel {
    let material = scene.objects[surface.hit.object].material;
    let from_base_color = scene
        .materials
        .get(material)
        .is_some_and(|m| m.conductor_from_base_color);
    ReferencePixel {
        surface,
        stored: precision.store(&surface, from_base_color),
        material,
        exact: [f64::NAN; 3],
        as_stored: [f64::NAN; 3],
    }
}

/// A shaded pixel: its surface stored with `precision`, each shaded (the exact radiance
/// taken as given when known).
fn reference_pixel(
    scene: &Scene,
    shading: &SceneShading,
    precision: &GBufferPrecision,
    surface: SurfacePoint,
    exact: Option<[f64; 3]>,
) -> ReferencePixel {
    let pixel = unshaded_pixel(scene, precision, surface);
    ReferencePixel {
        exact: exact.unwrap_or_else(|| shading.radiance(&surface)),
        as_stored: shading.radiance(&pixel.stored),
        ..pixel
    }
}
