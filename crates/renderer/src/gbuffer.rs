//! The G-buffer: its layout, its targets, and the CPU decoding of its texels (used by
//! the parity tests and the reference). The pass that fills it is `passes/gbuffer.rs`.
//! The layout is documented in docs/gbuffer.md.

use combustion_vk::{vk, Image};

#[cfg(doc)]
use crate::options::SurfaceStorage;
use crate::options::{BaseColorStorage, GBufferStorage};
use crate::variant::ShaderVariant;

pub use crate::color::srgb_to_linear;

/// Material index (16-bit uint) and anisotropy direction angle (16-bit, [0, π)).
pub const MATERIAL_DIRECTION_FORMAT: vk::Format = vk::Format::R16G16_UINT;
/// Depth (32-bit float, 1 = far/background).
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The clear coat's octahedral normal (rg), perceptual roughness (b) and weight (a),
/// 16-bit unorm each, as the default surface storage keeps the base's.
pub const CLEARCOAT_FORMAT: vk::Format = vk::Format::R16G16B16A16_UNORM;
/// The sheen's linear colour (rgb) and perceptual roughness (a), 16-bit unorm each.
pub const SHEEN_FORMAT: vk::Format = vk::Format::R16G16B16A16_UNORM;
/// The thin film's weight (r) and thickness in nanometres (g), 32-bit float each: the
/// film's colours turn with its thickness (a 16-bit step would move them visibly), so the
/// thickness is kept as the material and texture give it.
pub const FILM_FORMAT: vk::Format = vk::Format::R32G32_SFLOAT;
/// KHR_materials_specular's colour (rgb, linear, may exceed 1) and factor (a), the
/// material's factors times its textures, 16-bit float each (1 is exact: a pixel of a
/// material without the extension is the plain dielectric bit for bit).
pub const SPECULAR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// The names the G-buffer's targets are asked for with (`targets::ImageRequest`), each
/// also its debug name.
pub const BASE_COLOR_METALNESS: &str = "gbuffer base colour + metalness";
/// The octahedral normal, roughness and anisotropy target's name.
pub const NORMAL_ROUGHNESS_ANISOTROPY: &str = "gbuffer normal + roughness + anisotropy";
/// The material index and anisotropy direction target's name.
pub const MATERIAL_DIRECTION: &str = "gbuffer material + anisotropy direction";
/// The depth target's name.
pub const DEPTH: &str = "gbuffer depth";
/// The emissive + occlusion target's name.
pub const EMISSIVE: &str = "gbuffer emissive + occlusion";
/// The clear coat's target's name.
pub const CLEARCOAT: &str = "gbuffer clear coat";
/// The sheen's target's name.
pub const SHEEN: &str = "gbuffer sheen";
/// The thin film's target's name.
pub const FILM: &str = "gbuffer thin film";
/// The specular target's name.
pub const SPECULAR: &str = "gbuffer specular";

/// The G-buffer's targets a frame of `variant` draws into, in `storage`'s formats (the
/// emissive target in `emissive_format`, the HDR image's): colour targets with colour
/// attachment, sampled and transfer-source usage; depth with depth attachment, sampled
/// and transfer-source usage. The three colour targets and depth always; the emissive +
/// occlusion target, the clear coat's, the sheen's, the thin film's and the specular
/// one in variants with them.
pub(crate) fn requests(
    variant: ShaderVariant,
    storage: GBufferStorage,
    emissive_format: vk::Format,
) -> Vec<crate::targets::ImageRequest> {
    use crate::targets::ImageRequest;
    let color = vk::ImageUsageFlags::COLOR_ATTACHMENT
        | vk::ImageUsageFlags::SAMPLED
        | vk::ImageUsageFlags::TRANSFER_SRC;
    let depth = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
        | vk::ImageUsageFlags::SAMPLED
        | vk::ImageUsageFlags::TRANSFER_SRC;
    let mut requests = vec![
        ImageRequest::new(BASE_COLOR_METALNESS, storage.base_color.vk(), color),
        ImageRequest::new(NORMAL_ROUGHNESS_ANISOTROPY, storage.surface.vk(), color),
        ImageRequest::new(MATERIAL_DIRECTION, MATERIAL_DIRECTION_FORMAT, color),
        ImageRequest::new(DEPTH, DEPTH_FORMAT, depth),
    ];
    for (wanted, name, format) in [
        (
            variant.has_emissive_occlusion_target(),
            EMISSIVE,
            emissive_format,
        ),
        (variant.clearcoat, CLEARCOAT, CLEARCOAT_FORMAT),
        (variant.sheen, SHEEN, SHEEN_FORMAT),
        (variant.iridescence, FILM, FILM_FORMAT),
        (variant.specular, SPECULAR, SPECULAR_FORMAT),
    ] {
        if wanted {
            requests.push(ImageRequest::new(name, format, color));
        }
    }
    requests
}

/// The G-buffer's images of one frame (from the frame's images, by name).
pub struct GBufferTargets<'a> {
    /// Base colour and metalness ([`BaseColorStorage::vk`]), colour attachment 0.
    pub base_color_metalness: &'a Image,
    /// Octahedral normal, perceptual roughness and anisotropy strength
    /// ([`SurfaceStorage::vk`]), colour attachment 1.
    pub normal_roughness_anisotropy: &'a Image,
    /// Material index and anisotropy direction ([`MATERIAL_DIRECTION_FORMAT`]), colour
    /// attachment 2.
    pub material_direction: &'a Image,
    /// Depth ([`DEPTH_FORMAT`], 1 = far plane), the depth attachment.
    pub depth: &'a Image,
    /// Emitted radiance (rgb) and occlusion (a), present in the `EMISSIVE` and
    /// `OCCLUSION` variants only, in the HDR image's format (f16 or f32): emission is
    /// stored at the precision of the frame it is added to, so an f32 frame neither
    /// rounds it to 11 bits nor saturates it at 65504.
    pub emissive: Option<&'a Image>,
    /// The clear coat ([`CLEARCOAT_FORMAT`]), present in the `CLEARCOAT` variant only:
    /// the colour attachment after the emissive target's (or in its place).
    pub clearcoat: Option<&'a Image>,
    /// The sheen ([`SHEEN_FORMAT`]), present in the `SHEEN` variant only: the colour
    /// attachment after the clear coat's (or in its place).
    pub sheen: Option<&'a Image>,
    /// The thin film ([`FILM_FORMAT`]), present in the `IRIDESCENCE` variant only: the
    /// colour attachment after the sheen's (or in its place).
    pub film: Option<&'a Image>,
    /// The dielectric's specular colour and factor ([`SPECULAR_FORMAT`]), present in the
    /// `SPECULAR` variant only: the last colour attachment.
    pub specular: Option<&'a Image>,
}

impl<'a> GBufferTargets<'a> {
    /// The G-buffer among `images` (a frame's, which [`requests`] asked for).
    pub(crate) fn of(images: &crate::targets::FrameImages<'a>) -> Self {
        Self {
            base_color_metalness: images.get(BASE_COLOR_METALNESS),
            normal_roughness_anisotropy: images.get(NORMAL_ROUGHNESS_ANISOTROPY),
            material_direction: images.get(MATERIAL_DIRECTION),
            depth: images.get(DEPTH),
            emissive: images.find(EMISSIVE),
            clearcoat: images.find(CLEARCOAT),
            sheen: images.find(SHEEN),
            film: images.find(FILM),
            specular: images.find(SPECULAR),
        }
    }

    /// The three targets every variant has (what parity tests read back).
    pub fn colors(&self) -> [&'a Image; 3] {
        [
            self.base_color_metalness,
            self.normal_roughness_anisotropy,
            self.material_direction,
        ]
    }

    /// Every colour attachment of the G-buffer pass, in attachment order.
    pub fn attachments(&self) -> Vec<&'a Image> {
        let mut all = self.colors().to_vec();
        all.extend(self.emissive);
        all.extend(self.clearcoat);
        all.extend(self.sheen);
        all.extend(self.film);
        all.extend(self.specular);
        all
    }
}

/// One G-buffer texel as stored: what the lighting pass's `texelFetch` reads, before
/// the shader decodes it (a unorm code c of n bits as c / (2ⁿ − 1), exactly in f64; an
/// f16 as its value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GBufferTexel {
    /// Base colour (sRGB-encoded, or linear with [`BaseColorStorage::LinearHalf`]) and
    /// linear metalness.
    pub base_color_metalness: [f64; 4],
    /// How the base colour is stored (what decodes it).
    pub base_color_storage: BaseColorStorage,
    /// Octahedral normal xy, perceptual roughness, anisotropy strength.
    pub normal_roughness_anisotropy: [f64; 4],
    /// RG16_UINT: material index, anisotropy direction angle.
    pub material_direction: [u16; 2],
    /// D32_SFLOAT depth.
    pub depth: f32,
    /// The clear coat's target: octahedral normal xy, perceptual roughness, weight (all
    /// 0 in frames without the coat's target: no coat).
    pub clearcoat: [f64; 4],
    /// The sheen's target: linear colour, perceptual roughness (all 0 in frames without
    /// it: no sheen).
    pub sheen: [f64; 4],
    /// The thin film's target: weight, thickness in nm (0 in frames without it: no film).
    pub film: [f64; 2],
    /// The specular target: colour (rgb), factor (a) as stored (f16); [1, 1, 1, 1] in
    /// frames without it: the plain dielectric.
    pub specular: [f64; 4],
    /// The emissive + occlusion target: the emitted radiance the lighting pass adds (rgb)
    /// and the glTF occlusion (a), as stored (f16 or f32); [0, 0, 0, 1] in frames without
    /// the target: no emission, no occlusion.
    pub emissive_occlusion: [f64; 4],
}

/// A G-buffer read back to the CPU.
#[derive(Clone, Debug)]
pub struct GBufferReadback {
    /// The storage the texels were read from.
    pub storage: GBufferStorage,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width · height` texels, row-major from the top-left.
    pub texels: Vec<GBufferTexel>,
}

impl GBufferTexel {
    /// The linear base colour the lighting pass decodes (`base_color_decode`,
    /// gbuffer_encoding.glsl), in f64.
    pub fn base_color(&self) -> [f64; 3] {
        let [r, g, b, _] = self.base_color_metalness;
        match self.base_color_storage {
            BaseColorStorage::Srgb8 | BaseColorStorage::Srgb16 => [r, g, b].map(srgb_to_linear),
            BaseColorStorage::LinearHalf => [r, g, b],
        }
    }

    /// The base colour's 8-bit sRGB codes (`base_color_srgb8_code`): the conductor
    /// tables' index.
    pub fn base_color_srgb8_code(&self) -> [u8; 3] {
        let [r, g, b, _] = self.base_color_metalness;
        let code = |e: f64| (e * 255.0).round().clamp(0.0, 255.0) as u8;
        match self.base_color_storage {
            BaseColorStorage::Srgb8 | BaseColorStorage::Srgb16 => [r, g, b].map(code),
            BaseColorStorage::LinearHalf => [r, g, b].map(|c| code(crate::linear_to_srgb(c))),
        }
    }
}

/// CPU mirror of `octahedral_decode` (gbuffer_encoding.glsl), in f64.
pub fn octahedral_decode(encoded: [f64; 2]) -> [f64; 3] {
    let sign = |x: f64| if x >= 0.0 { 1.0 } else { -1.0 };
    let (ex, ey) = (encoded[0] * 2.0 - 1.0, encoded[1] * 2.0 - 1.0);
    let mut n = [ex, ey, 1.0 - ex.abs() - ey.abs()];
    if n[2] < 0.0 {
        n[0] = (1.0 - ey.abs()) * sign(ex);
        n[1] = (1.0 - ex.abs()) * sign(ey);
    }
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    n.map(|c| c / len)
}

/// CPU mirror of `orthonormal_basis` (gbuffer_encoding.glsl), in f64.
pub fn orthonormal_basis(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let s = if n[2] >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n[2]);
    let c = n[0] * n[1] * a;
    (
        [1.0 + s * n[0] * n[0] * a, s * c, -s * n[0]],
        [c, s + n[1] * n[1] * a, -n[1]],
    )
}

/// CPU mirror of `anisotropy_direction_decode` (gbuffer_encoding.glsl), in f64.
pub fn anisotropy_direction_decode(n: [f64; 3], encoded: u16) -> [f64; 3] {
    let (t0, b0) = orthonormal_basis(n);
    let phi = f64::from(encoded) * (std::f64::consts::PI / 65536.0);
    let (s, c) = phi.sin_cos();
    [0, 1, 2].map(|i| c * t0[i] + s * b0[i])
}

/// CPU mirror of `octahedral_encode` (gbuffer_encoding.glsl), in f64, before quantisation.
pub fn octahedral_encode(n: [f64; 3]) -> [f64; 2] {
    let sign = |x: f64| if x >= 0.0 { 1.0 } else { -1.0 };
    let l1 = n[0].abs() + n[1].abs() + n[2].abs();
    let (x, y, z) = (n[0] / l1, n[1] / l1, n[2] / l1);
    let (ex, ey) = if z >= 0.0 {
        (x, y)
    } else {
        ((1.0 - y.abs()) * sign(x), (1.0 - x.abs()) * sign(y))
    };
    [ex * 0.5 + 0.5, ey * 0.5 + 0.5]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unorm16(x: f64) -> f64 {
        (x * 65535.0).round() / 65535.0
    }

    fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
        let dot: f64 = (0..3).map(|i| a[i] * b[i]).sum();
        let cross = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        (cross.iter().map(|c| c * c).sum::<f64>()).sqrt().atan2(dot)
    }

    /// Spherical Fibonacci points: an even cover of the sphere.
    fn sphere_points(count: usize) -> impl Iterator<Item = [f64; 3]> {
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        (0..count).map(move |i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * i as f64;
            [r * phi.cos(), r * phi.sin(), z]
        })
    }

    #[test]
    fn octahedral_normals_survive_16_bit_storage() {
        let mut worst = 0.0f64;
        for n in sphere_points(200_000).chain([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])
        {
            let e = octahedral_encode(n).map(unorm16);
            worst = worst.max(angle(n, octahedral_decode(e)));
        }
        // Measured 6.30e-5 rad (0.0036°) over these 200 003 directions, the error
        // Cigolle et al. 2014 report for 2×16-bit octahedral encoding; the bound leaves
        // 3 % for directions this sampling misses.
        assert!(worst < 6.5e-5, "worst angular error {worst:e} rad");
    }

    #[test]
    fn anisotropy_direction_round_trips_up_to_sign() {
        let mut worst = 0.0f64;
        for n in sphere_points(20_000) {
            let (t0, b0) = orthonormal_basis(n);
            for k in 0..8 {
                let phi = -3.0 + k as f64 * 0.8;
                let dir = [0, 1, 2].map(|i| phi.cos() * t0[i] + phi.sin() * b0[i]);
                // Encode as the shader does: angle folded to [0, π), 16 bits.
                let mut a = phi;
                if a < 0.0 {
                    a += std::f64::consts::PI;
                }
                let code = ((a * 65536.0 / std::f64::consts::PI).round() as u32 & 0xffff) as u16;
                let back = anisotropy_direction_decode(n, code);
                // t and −t are the same direction for GGX.
                let e = angle(dir, back).min(angle(dir, back.map(|c| -c)));
                worst = worst.max(e);
            }
        }
        // Half a 16-bit step of π/65536 rad = 2.4e-5 rad.
        assert!(worst <= 2.4e-5 + 1e-12, "worst {worst:e} rad");
    }
}
