#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! One glTF primitive's attributes → a [`Mesh`]: checks, degenerate triangles, normals
//! (flat when missing, glTF's rule), tangents (given, MikkTSpace, or a frame from the
//! normal), welding.
//!
//! Every index is checked below the vertex count as the primitive is read
//! ([`check_attributes`]); lookups by index still go through `get` (clippy's
//! `indexing_slicing` is denied here), a lookup that could only miss on a broken
//! invariant giving a harmless default (a degenerate triangle, a zero normal).

use std::collections::HashMap;

use glam::Vec3;

use crate::{Mesh, Vertex};

/// The attributes of one primitive, as read.
pub(crate) struct PrimitiveData {
    pub positions: Vec<[f32; 3]>,
    pub normals: Option<Vec<[f32; 3]>>,
    pub tangents: Option<Vec<[f32; 4]>>,
    pub uvs: Option<Vec<[f32; 2]>>,
    /// TEXCOORD_1.
    pub uvs1: Option<Vec<[f32; 2]>>,
    /// COLOR_0 as RGBA (alpha 1 for a VEC3 accessor), in [0, 1].
    pub colors: Option<Vec<[f32; 4]>>,
    /// A triangle list.
    pub indices: Vec<u32>,
    /// The vertices carry data the [`Vertex`] does not (joint influences, morph-target
    /// displacements, looked up by [`BuildStats::sources`]): welding keeps vertices made
    /// from different ones apart.
    pub keep_sources_apart: bool,
}

/// What building the mesh did, for the report.
#[derive(Debug, Default)]
pub(crate) struct BuildStats {
    pub degenerate: usize,
    pub generated_normals: bool,
    pub repaired_normals: usize,
    pub generated_tangents: bool,
    pub repaired_tangents: usize,
    pub warnings: Vec<String>,
    /// Each built vertex's index among the primitive's vertices (what it was made from).
    pub sources: Vec<u32>,
}

/// Tolerance on |v| − 1 under which a given normal or tangent is kept bit for bit.
const UNIT_TOLERANCE: f32 = 1e-5;

fn finite_check<const N: usize>(name: &str, values: &[[f32; N]]) -> Result<(), String> {
    match values
        .iter()
        .enumerate()
        .find(|(_, v)| !v.iter().all(|x| x.is_finite()))
    {
        Some((i, value)) => Err(format!(
            "{name} of vertex {i} is not finite {}",
            crate::message_numbers(value)
        )),
        None => Ok(()),
    }
}

/// Whether triangle (a, b, c) has no area: repeated indices, or edges collinear to f32
/// precision (|e₁ × e₂| ≤ 2⁻²³·|e₁|·|e₂|, computed in f64).
fn degenerate(p: &[[f32; 3]], a: u32, b: u32, c: u32) -> bool {
    if a == b || b == c || a == c {
        return true;
    }
    let (Some(p0), Some(p1), Some(p2)) = (position(p, a), position(p, b), position(p, c)) else {
        return true;
    };
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let cross = e1.cross(e2).length();
    let limit = f64::from(f32::EPSILON) * e1.length() * e2.length();
    !cross.is_finite() || cross <= limit
}

/// A unit vector orthogonal to `n` (Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited"): the tangent of the normal's reference basis, as the G-buffer uses it.
pub(crate) fn reference_tangent(n: Vec3) -> Vec3 {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x)
}

/// Position `i` of `p` in f64 (none past the end).
fn position(p: &[[f32; 3]], i: u32) -> Option<glam::DVec3> {
    p.get(i as usize)
        .map(|v| glam::DVec3::from(v.map(f64::from)))
}

/// The area-weighted normal of triangle `t` (its edges' cross product, not normalised;
/// zero for a triangle that is not one).
fn face_cross(p: &[[f32; 3]], t: &[u32]) -> glam::DVec3 {
    let &[a, b, c] = t else {
        return glam::DVec3::ZERO;
    };
    match (position(p, a), position(p, b), position(p, c)) {
        (Some(p0), Some(p1), Some(p2)) => (p1 - p0).cross(p2 - p0),
        _ => glam::DVec3::ZERO,
    }
}

fn face_normal(p: &[[f32; 3]], t: &[u32]) -> Vec3 {
    face_cross(p, t).normalize_or_zero().as_vec3()
}

/// Element `i` of an optional attribute, or `default` where the primitive has none.
fn attribute<T: Copy>(values: Option<&Vec<T>>, i: usize, default: T) -> T {
    values.and_then(|v| v.get(i)).copied().unwrap_or(default)
}

/// Checks that every attribute has one element per position, every component is
/// finite, and every index is below the vertex count.
fn check_attributes(data: &PrimitiveData) -> Result<(), String> {
    let count = data.positions.len();
    let check_len = |what: &str, n: usize| {
        if n == count {
            Ok(())
        } else {
            Err(format!("{what} has {n} elements but POSITION has {count}"))
        }
    };
    finite_check("POSITION", &data.positions)?;
    if let Some(normals) = &data.normals {
        check_len("NORMAL", normals.len())?;
        finite_check("NORMAL", normals)?;
    }
    if let Some(tangents) = &data.tangents {
        check_len("TANGENT", tangents.len())?;
        finite_check("TANGENT", tangents)?;
    }
    for (name, uvs) in [("TEXCOORD_0", &data.uvs), ("TEXCOORD_1", &data.uvs1)] {
        if let Some(uvs) = uvs {
            check_len(name, uvs.len())?;
            finite_check(name, uvs)?;
        }
    }
    if let Some(colors) = &data.colors {
        check_len("COLOR_0", colors.len())?;
        finite_check("COLOR_0", colors)?;
    }
    if let Some(&bad) = data.indices.iter().find(|&&i| i as usize >= count) {
        return Err(format!("index {bad} is out of range ({count} vertices)"));
    }
    Ok(())
}

/// Builds a mesh of points or lines (`topology`) from their data as given: no normals
/// are generated, nothing is welded or dropped. A vertex keeps its normal where the
/// primitive has unit ones, else +z (points and lines are drawn unlit: nothing shades
/// with it), and its tangent where it has a unit one with a kept normal, else the
/// normal's reference tangent.
pub(crate) fn build_strokes(
    name: String,
    data: PrimitiveData,
    topology: crate::Topology,
) -> Result<Mesh, String> {
    check_attributes(&data)?;
    if data.indices.is_empty() {
        return Err(format!("has no {}", topology.name()));
    }
    let vertices = data
        .positions
        .iter()
        .enumerate()
        .map(|(i, &position)| {
            let given = data
                .normals
                .as_ref()
                .and_then(|n| n.get(i))
                .map(|&n| Vec3::from(n))
                .filter(|n| (n.length() - 1.0).abs() <= UNIT_TOLERANCE);
            let normal = given.unwrap_or(Vec3::Z);
            let tangent = data
                .tangents
                .as_ref()
                .and_then(|t| t.get(i))
                .copied()
                .filter(|t| {
                    given.is_some() && (Vec3::from_slice(t).length() - 1.0).abs() <= UNIT_TOLERANCE
                })
                .unwrap_or_else(|| reference_tangent(normal).extend(1.0).to_array());
            let uv = attribute(data.uvs.as_ref(), i, [0.0; 2]);
            Vertex {
                position,
                normal: normal.to_array(),
                tangent,
                uv,
                uv1: attribute(data.uvs1.as_ref(), i, uv),
                color: attribute(data.colors.as_ref(), i, [1.0; 4]),
            }
        })
        .collect();
    Ok(Mesh {
        name,
        vertices,
        indices: data.indices,
        topology,
        ..Mesh::default()
    })
}

/// Builds the mesh. `needs_uv_tangents`: the material has a normal map or anisotropy, so
/// missing tangents are generated with MikkTSpace. `flip`: reverse the winding (the
/// mesh is placed by a transform with negative determinant).
pub(crate) fn build_mesh(
    name: String,
    data: PrimitiveData,
    needs_uv_tangents: bool,
    flip: bool,
) -> Result<(Mesh, BuildStats), String> {
    let mut stats = BuildStats::default();
    check_attributes(&data)?;
    let count = data.positions.len();
    let total = data.indices.len() / 3;
    let mut triangles: Vec<u32> = Vec::with_capacity(total.saturating_mul(3));
    for t in data.indices.chunks_exact(3) {
        let &[a, b, c] = t else { continue };
        if degenerate(&data.positions, a, b, c) {
            stats.degenerate = stats.degenerate.saturating_add(1);
        } else {
            triangles.extend_from_slice(t);
        }
    }
    if triangles.is_empty() {
        return Err(if total == 0 {
            "has no triangles".to_owned()
        } else {
            format!("all {total} triangles are degenerate (zero area)")
        });
    }
    if stats.degenerate > 0 {
        stats.warnings.push(format!(
            "dropped {} degenerate (zero-area) triangle(s) of {total}",
            stats.degenerate
        ));
    }

    let uv_of = |i: u32| attribute(data.uvs.as_ref(), i as usize, [0.0; 2]);
    // Set 1 falls back to set 0 where the primitive has none.
    let uv1_of = |i: u32| attribute(data.uvs1.as_ref(), i as usize, uv_of(i));
    let color_of = |i: u32| attribute(data.colors.as_ref(), i as usize, [1.0; 4]);
    let (mut vertices, mut indices, tangents_missing) = match &data.normals {
        None => {
            // glTF: flat normals, and given tangents are ignored.
            stats.generated_normals = true;
            let mut vertices = Vec::with_capacity(triangles.len());
            for t in triangles.chunks_exact(3) {
                let n = face_normal(&data.positions, t);
                for &i in t {
                    vertices.push(Vertex {
                        position: attribute(Some(&data.positions), i as usize, [0.0; 3]),
                        normal: n.to_array(),
                        tangent: [0.0; 4],
                        uv: uv_of(i),
                        uv1: uv1_of(i),
                        color: color_of(i),
                    });
                }
            }
            stats.sources = triangles.clone();
            let indices = (0..vertices.len() as u32).collect();
            (vertices, indices, true)
        }
        Some(normals) => {
            let mut vertices: Vec<Vertex> = data
                .positions
                .iter()
                .zip(normals)
                .enumerate()
                .map(|(i, (&position, &normal))| Vertex {
                    position,
                    normal,
                    tangent: attribute(data.tangents.as_ref(), i, [0.0; 4]),
                    uv: uv_of(i as u32),
                    uv1: uv1_of(i as u32),
                    color: color_of(i as u32),
                })
                .collect();
            // Normals must be unit: normalise those that are not; replace zero ones by
            // the area-weighted mean of the adjacent faces.
            let mut zero = Vec::new();
            for (i, v) in vertices.iter_mut().enumerate() {
                let n = Vec3::from(v.normal);
                let length = n.length();
                if (length - 1.0).abs() > UNIT_TOLERANCE {
                    if length > 1e-12 {
                        v.normal = (n / length).to_array();
                    } else {
                        zero.push(i);
                    }
                }
            }
            if !zero.is_empty() {
                let mut sums = vec![glam::DVec3::ZERO; count];
                for t in triangles.chunks_exact(3) {
                    let n = face_cross(&data.positions, t);
                    for &i in t {
                        if let Some(sum) = sums.get_mut(i as usize) {
                            *sum += n;
                        }
                    }
                }
                for &i in &zero {
                    let n = sums
                        .get(i)
                        .map_or(Vec3::ZERO, |s| s.normalize_or_zero().as_vec3());
                    if let Some(v) = vertices.get_mut(i) {
                        v.normal = if n == Vec3::ZERO { Vec3::Z } else { n }.to_array();
                    }
                }
                stats.repaired_normals = zero.len();
                stats.warnings.push(format!(
                    "{} zero-length normal(s) replaced by the mean of the adjacent faces",
                    zero.len()
                ));
            }
            stats.sources = (0..count as u32).collect();
            (vertices, triangles, data.tangents.is_none())
        }
    };

    // Tangents from the texture coordinates (MikkTSpace), unless an edge is crowded.
    let from_uvs = tangents_missing && needs_uv_tangents && data.uvs.is_some();
    let crowded = if from_uvs {
        most_triangles_on_one_edge(&vertices, &indices)
            .filter(|&n| n > MAX_TRIANGLES_PER_EDGE_FOR_MIKKTSPACE)
    } else {
        None
    };
    if tangents_missing {
        if from_uvs && crowded.is_none() {
            let (v, i) = mikktspace(&vertices, &indices);
            stats.sources = indices
                .iter()
                .map(|&i| attribute(Some(&stats.sources), i as usize, 0))
                .collect();
            vertices = v;
            indices = i;
            stats.generated_tangents = true;
        } else {
            if let Some(n) = crowded {
                stats.warnings.push(format!(
                    "{n} triangles share one edge (MikkTSpace's neighbour search grows with the square of that): tangents from the normals instead, not from the texture coordinates"
                ));
            } else if needs_uv_tangents {
                stats.warnings.push(
                    "the material needs tangents (normal map or anisotropy) but the primitive has neither TANGENT nor TEXCOORD_0; using an arbitrary tangent frame".into(),
                );
            }
            for v in &mut vertices {
                let t = reference_tangent(Vec3::from(v.normal));
                v.tangent = [t.x, t.y, t.z, 1.0];
            }
        }
    } else {
        // Given tangents: unit xyz, w = ±1; replace unusable ones.
        let mut repaired: usize = 0;
        for v in &mut vertices {
            let n = Vec3::from(v.normal);
            let t = Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]);
            let w = if v.tangent[3] < 0.0 { -1.0 } else { 1.0 };
            let length = t.length();
            let along_normal = t.normalize_or_zero().dot(n).abs();
            if length <= 1e-12 || along_normal > 0.9999 {
                let r = reference_tangent(n);
                v.tangent = [r.x, r.y, r.z, w];
                repaired = repaired.saturating_add(1);
            } else if (length - 1.0).abs() > UNIT_TOLERANCE {
                let t = t / length;
                v.tangent = [t.x, t.y, t.z, w];
            } else {
                v.tangent[3] = w;
            }
        }
        if repaired > 0 {
            stats.repaired_tangents = repaired;
            stats.warnings.push(format!(
                "{repaired} zero or normal-parallel tangent(s) replaced by the normal's reference tangent"
            ));
        }
    }

    if stats.generated_normals || stats.generated_tangents {
        let sources = data.keep_sources_apart.then_some(stats.sources.as_slice());
        let (welded, welded_indices, kept) = weld(&vertices, &indices, sources);
        stats.sources = kept
            .iter()
            .map(|&k| attribute(Some(&stats.sources), k as usize, 0))
            .collect();
        (vertices, indices) = (welded, welded_indices);
    }
    if flip {
        for t in indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
    Ok((
        Mesh {
            name,
            vertices,
            indices,
            ..Mesh::default()
        },
        stats,
    ))
}

/// Merges bit-identical vertices (made from the same source vertex, when `sources`
/// are given), keeping first-use order. Also returns, per kept vertex, the index of the
/// vertex it was first made from.
fn weld(
    vertices: &[Vertex],
    indices: &[u32],
    sources: Option<&[u32]>,
) -> (Vec<Vertex>, Vec<u32>, Vec<u32>) {
    const WORDS: usize = std::mem::size_of::<Vertex>() / 4;
    let mut map: HashMap<([u32; WORDS], u32), u32> = HashMap::with_capacity(indices.len());
    let mut out = Vec::new();
    let mut kept = Vec::new();
    let new_indices = indices
        .iter()
        .map(|&i| {
            let v = vertices.get(i as usize).copied().unwrap_or_default();
            let words: &[u32] = bytemuck::cast_slice(std::slice::from_ref(&v));
            let mut key = [0u32; WORDS];
            key.copy_from_slice(words);
            let source = sources
                .and_then(|s| s.get(i as usize))
                .copied()
                .unwrap_or(0);
            *map.entry((key, source)).or_insert_with(|| {
                out.push(v);
                kept.push(i);
                // The vertex just pushed: `out` is not empty.
                out.len().saturating_sub(1) as u32
            })
        })
        .collect();
    (out, new_indices, kept)
}

struct MikkGeometry<'a> {
    vertices: &'a [Vertex],
    indices: &'a [u32],
    tangents: Vec<Option<[f32; 4]>>,
}

/// The corner `vert` of triangle `face` in a triangle list (MikkTSpace asks for faces
/// below `indices.len() / 3`, corners below 3: no overflow).
fn corner(face: usize, vert: usize) -> usize {
    face.saturating_mul(3).saturating_add(vert)
}

impl MikkGeometry<'_> {
    /// The vertex at corner `vert` of triangle `face` (indices checked below the vertex
    /// count when the primitive was read).
    fn vertex(&self, face: usize, vert: usize) -> Vertex {
        self.indices
            .get(corner(face, vert))
            .and_then(|&i| self.vertices.get(i as usize))
            .copied()
            .unwrap_or_default()
    }
}

impl bevy_mikktspace::Geometry for MikkGeometry<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertex(face, vert).position
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertex(face, vert).normal
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.vertex(face, vert).uv
    }
    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(slot) = self.tangents.get_mut(corner(face, vert)) {
            *slot = tangent_space.map(|t| t.tangent_encoded());
        }
    }
}

/// Triangles one edge may join before MikkTSpace is not run on a mesh: a manifold mesh
/// has two per edge, real non-manifold art a few; MikkTSpace matches the triangles of an
/// edge pairwise, so a file whose thousands of triangles share one edge would take
/// minutes (333,000 triangles on 4 vertices: 500 s).
const MAX_TRIANGLES_PER_EDGE_FOR_MIKKTSPACE: usize = 64;

/// The largest number of triangles that share one edge, vertices counted as MikkTSpace
/// welds them (equal position, normal and texture coordinates are one vertex).
fn most_triangles_on_one_edge(vertices: &[Vertex], indices: &[u32]) -> Option<usize> {
    // Position, normal and texture coordinates, bit for bit.
    type Attributes = ([u32; 3], [u32; 3], [u32; 2]);
    let mut welded: HashMap<Attributes, u32> = HashMap::new();
    let ids: Vec<u32> = vertices
        .iter()
        .map(|v| {
            let key = (
                v.position.map(f32::to_bits),
                v.normal.map(f32::to_bits),
                v.uv.map(f32::to_bits),
            );
            let next = welded.len() as u32;
            *welded.entry(key).or_insert(next)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    let id = |i: u32| ids.get(i as usize).copied().unwrap_or(u32::MAX);
    for t in indices.chunks_exact(3) {
        let &[i0, i1, i2] = t else { continue };
        for (a, b) in [(i0, i1), (i1, i2), (i2, i0)] {
            let (a, b) = (id(a), id(b));
            let shared = edges.entry((a.min(b), a.max(b))).or_insert(0);
            *shared = shared.saturating_add(1);
        }
    }
    edges.into_values().max()
}

/// MikkTSpace tangents per triangle corner, then unindexed corners (welded later).
fn mikktspace(vertices: &[Vertex], indices: &[u32]) -> (Vec<Vertex>, Vec<u32>) {
    let mut geometry = MikkGeometry {
        vertices,
        indices,
        tangents: vec![None; indices.len()],
    };
    // The error type has no variants: generation cannot fail.
    let _ = bevy_mikktspace::generate_tangents(&mut geometry);
    let corners: Vec<Vertex> = indices
        .iter()
        .zip(&geometry.tangents)
        .map(|(&i, tangent)| {
            let mut v = vertices.get(i as usize).copied().unwrap_or_default();
            let n = Vec3::from(v.normal);
            v.tangent = match tangent {
                Some(t)
                    if Vec3::from_slice(t).is_finite() && Vec3::from_slice(t).length() > 0.5 =>
                {
                    *t
                }
                _ => {
                    let r = reference_tangent(n);
                    [r.x, r.y, r.z, 1.0]
                }
            };
            v
        })
        .collect();
    let indices = (0..corners.len() as u32).collect();
    (corners, indices)
}

#[cfg(test)]
#[allow(clippy::indexing_slicing)] // a test fails by a panic
mod tests {
    use super::*;

    #[test]
    fn reference_tangent_is_orthonormal() {
        for n in [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let t = reference_tangent(n);
            assert!(
                (t.length() - 1.0).abs() < 1e-6 && t.dot(n).abs() < 1e-6,
                "{n} {t}"
            );
        }
    }

    fn quad(normals: bool, uvs: bool) -> PrimitiveData {
        PrimitiveData {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            normals: normals.then(|| vec![[0.0, 0.0, 1.0]; 4]),
            tangents: None,
            uvs: uvs.then(|| vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]),
            uvs1: None,
            colors: None,
            indices: vec![0, 1, 2, 0, 2, 3],
            keep_sources_apart: false,
        }
    }

    #[test]
    fn flat_normals_follow_the_winding() {
        let (mesh, stats) = build_mesh("q".into(), quad(false, false), false, false).unwrap();
        assert!(stats.generated_normals);
        // The two triangles are coplanar: welding merges the shared corners again.
        assert_eq!(mesh.vertices.len(), 4);
        for v in &mesh.vertices {
            assert_eq!(v.normal, [0.0, 0.0, 1.0]);
        }
    }

    #[test]
    fn mikktspace_tangents_follow_u() {
        let (mesh, stats) = build_mesh("q".into(), quad(true, true), true, false).unwrap();
        assert!(stats.generated_tangents);
        for v in &mesh.vertices {
            let t = Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]);
            assert!((t - Vec3::X).length() < 1e-5, "{:?}", v.tangent);
        }
    }

    #[test]
    fn degenerate_triangles_are_dropped_or_refused() {
        let mut data = quad(true, false);
        data.indices.extend_from_slice(&[0, 0, 1, 0, 1, 1]);
        let (mesh, stats) = build_mesh("q".into(), data, false, false).unwrap();
        assert_eq!((stats.degenerate, mesh.indices.len()), (2, 6));
        let mut data = quad(true, false);
        data.positions = vec![[0.0; 3]; 4];
        let err = build_mesh("q".into(), data, false, false).unwrap_err();
        assert!(err.contains("degenerate"), "{err}");
    }
}
