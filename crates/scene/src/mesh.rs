use std::f32::consts::PI;

use crate::motion::{MorphTarget, SkinWeights};

/// A vertex as the G-buffer pass consumes it: `#[repr(C)]`, 72 bytes, plain old data
/// (`bytemuck::Pod`). Every component must be finite, the colour's in [0, 1]
/// ([`Mesh::validate`]). `Default` is the origin with no normal or tangent, coordinates
/// (0, 0) and a white colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Position in the mesh's own (object) space, metres; an [`crate::Object`]'s
    /// transform places it in the world.
    pub position: [f32; 3],
    /// Shading normal in object space, unit length expected (the shaders normalise it
    /// after transforming it by the object's normal matrix).
    pub normal: [f32; 3],
    /// Tangent xyz and the bitangent sign w (bitangent = w · normal × tangent), as in glTF.
    pub tangent: [f32; 4],
    /// Texture coordinates (glTF TEXCOORD_0 convention: u right, v down, (0, 0) is the
    /// top-left corner of the image's first row). The renderer uploads position,
    /// normal, tangent and uv as one 48-byte stream and `uv1` as a second one.
    pub uv: [f32; 2],
    /// The second texture-coordinate set (glTF TEXCOORD_1; a copy of `uv` where the
    /// mesh has none), for texture slots that ask for set 1.
    pub uv1: [f32; 2],
    /// Linear RGBA colour (glTF COLOR_0; white where the mesh has none), multiplied into
    /// the material's base colour and alpha. Uploaded as a stream of its own, and only
    /// for meshes that have a colour other than white ([`Mesh::has_colors`]).
    pub color: [f32; 4],
}

impl Default for Vertex {
    fn default() -> Self {
        Self {
            position: [0.0; 3],
            normal: [0.0; 3],
            tangent: [0.0; 4],
            uv: [0.0; 2],
            uv1: [0.0; 2],
            color: [1.0; 4],
        }
    }
}

/// How a mesh's indices join its vertices into primitives.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Topology {
    /// Three indices per triangle (a triangle list): a surface, lit, casting shadows,
    /// seen by every reference.
    #[default]
    Triangles,
    /// Two indices per segment (a line list), each segment rasterised one pixel wide
    /// (Vulkan's line rasterisation, width 1) into the G-buffer. No surface: no shadow
    /// is cast, no reference ray hits it, and glTF's points and lines are given an unlit
    /// material (docs/gltf.md, "Points and lines").
    Lines,
    /// One index per point (a point list), each point one pixel (point size 1) in the
    /// G-buffer; otherwise as [`Topology::Lines`].
    Points,
}

impl Topology {
    /// Indices per primitive: 3, 2 or 1.
    pub fn indices_per_primitive(self) -> usize {
        match self {
            Self::Triangles => 3,
            Self::Lines => 2,
            Self::Points => 1,
        }
    }

    /// The primitive's name, plural (`triangles`, `line segments`, `points`), for
    /// messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Triangles => "triangles",
            Self::Lines => "line segments",
            Self::Points => "points",
        }
    }
}

/// An indexed mesh in its own (object) space: triangles, or points or lines
/// ([`Topology`]).
///
/// Triangles are counter-clockwise seen from their front (outside), the face back-face
/// culling keeps. [`Mesh::validate`] checks the indices and that every attribute is
/// finite.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// A name for messages and tools (not necessarily unique).
    pub name: String,
    /// The vertices the indices refer to.
    pub vertices: Vec<Vertex>,
    /// Indices into `vertices`, [`Topology::indices_per_primitive`] per primitive: three
    /// per triangle in triangle-list order (or two per segment, one per point).
    pub indices: Vec<u32>,
    /// What the indices make: triangles, line segments or points.
    pub topology: Topology,
    /// The joints influencing each vertex, for a mesh a skin places (objects attached to
    /// a node with a [`crate::motion::Skin`]); `None` for a rigid mesh.
    pub skin: Option<SkinWeights>,
    /// Morph targets (glTF's), displacing the vertices by the weights of the node the
    /// object hangs from; empty for a mesh of one shape.
    pub morph_targets: Vec<MorphTarget>,
}

impl Mesh {
    /// A UV sphere of `radius` centred at the origin, with `segments` around the axis
    /// (y) and `rings` from pole to pole. Tangents point along increasing longitude,
    /// so anisotropy stretches highlights around the y axis.
    pub fn uv_sphere(name: &str, radius: f32, segments: u32, rings: u32) -> Mesh {
        let segments = segments.max(3);
        let rings = rings.max(2);
        let mut vertices = Vec::with_capacity(((segments + 1) * (rings + 1)) as usize);
        for ring in 0..=rings {
            let theta = PI * ring as f32 / rings as f32;
            let (sin_t, cos_t) = theta.sin_cos();
            for seg in 0..=segments {
                let phi = 2.0 * PI * seg as f32 / segments as f32;
                let (sin_p, cos_p) = phi.sin_cos();
                let normal = [sin_t * cos_p, cos_t, -sin_t * sin_p];
                // d(position)/d(phi), normalised; at the poles use the limit direction.
                let tangent = [-sin_p, 0.0, -cos_p];
                vertices.push(Vertex {
                    position: normal.map(|c| c * radius),
                    normal,
                    tangent: [tangent[0], tangent[1], tangent[2], 1.0],
                    uv: [seg as f32 / segments as f32, ring as f32 / rings as f32],
                    uv1: [seg as f32 / segments as f32, ring as f32 / rings as f32],
                    color: [1.0; 4],
                });
            }
        }
        let mut indices = Vec::with_capacity((segments * rings * 6) as usize);
        let row = segments + 1;
        for ring in 0..rings {
            for seg in 0..segments {
                let a = ring * row + seg;
                let b = a + row;
                // Counter-clockwise seen from outside.
                if ring != 0 {
                    indices.extend_from_slice(&[a, b, a + 1]);
                }
                if ring != rings - 1 {
                    indices.extend_from_slice(&[a + 1, b, b + 1]);
                }
            }
        }
        Mesh {
            name: name.to_owned(),
            vertices,
            indices,
            ..Default::default()
        }
    }

    /// A square of side `size` in the xz plane facing +y, centred at the origin.
    pub fn plane(name: &str, size: f32) -> Mesh {
        let h = size / 2.0;
        let v = |x: f32, z: f32| Vertex {
            position: [x, 0.0, z],
            normal: [0.0, 1.0, 0.0],
            tangent: [1.0, 0.0, 0.0, 1.0],
            uv: [x / size + 0.5, z / size + 0.5],
            uv1: [x / size + 0.5, z / size + 0.5],
            color: [1.0; 4],
        };
        Mesh {
            name: name.to_owned(),
            vertices: vec![v(-h, -h), v(-h, h), v(h, h), v(h, -h)],
            indices: vec![0, 1, 2, 0, 2, 3],
            ..Default::default()
        }
    }

    /// A box of sides `size` (x, y, z) centred at the origin: six flat faces, each its
    /// own four vertices (normals along the axes, outward; counter-clockwise seen from
    /// outside), uv spanning each face.
    pub fn cuboid(name: &str, size: [f32; 3]) -> Mesh {
        let half = size.map(|s| s / 2.0);
        let axis = |i: usize, s: f32| {
            let mut a = [0.0f32; 3];
            a[i] = s;
            a
        };
        // (normal axis, sign, u axis, v axis) with u × v = the outward normal.
        let faces = [
            (0, 1.0, 1, 2),
            (0, -1.0, 2, 1),
            (1, 1.0, 2, 0),
            (1, -1.0, 0, 2),
            (2, 1.0, 0, 1),
            (2, -1.0, 1, 0),
        ];
        let mut vertices = Vec::with_capacity(24);
        let mut indices = Vec::with_capacity(36);
        for (n, sign, u, v) in faces {
            let first = vertices.len() as u32;
            for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut position = [0.0f32; 3];
                position[n] = sign * half[n];
                position[u] = du * half[u];
                position[v] = dv * half[v];
                let tangent = axis(u, 1.0);
                vertices.push(Vertex {
                    position,
                    normal: axis(n, sign),
                    tangent: [tangent[0], tangent[1], tangent[2], 1.0],
                    uv: [(du + 1.0) / 2.0, (1.0 - dv) / 2.0],
                    uv1: [(du + 1.0) / 2.0, (1.0 - dv) / 2.0],
                    color: [1.0; 4],
                });
            }
            indices.extend([first, first + 1, first + 2, first, first + 2, first + 3]);
        }
        Mesh {
            name: name.to_owned(),
            vertices,
            indices,
            ..Default::default()
        }
    }

    /// Whether some vertex has a colour other than white (the renderer then uploads
    /// and reads the colour stream).
    pub fn has_colors(&self) -> bool {
        self.vertices.iter().any(|v| v.color != [1.0; 4])
    }

    /// The box (min, max corners) around its vertices, in its own space; `None` without
    /// vertices.
    pub fn bounds(&self) -> Option<(glam::Vec3, glam::Vec3)> {
        let mut lo = glam::Vec3::splat(f32::INFINITY);
        let mut hi = glam::Vec3::splat(f32::NEG_INFINITY);
        for v in &self.vertices {
            lo = lo.min(glam::Vec3::from(v.position));
            hi = hi.max(glam::Vec3::from(v.position));
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }

    /// The number of primitives (triangles, segments or points).
    pub fn primitive_count(&self) -> usize {
        self.indices.len() / self.topology.indices_per_primitive()
    }

    /// The number of triangles: 0 for points and lines.
    pub fn triangle_count(&self) -> usize {
        match self.topology {
            Topology::Triangles => self.indices.len() / 3,
            Topology::Lines | Topology::Points => 0,
        }
    }

    /// Checks indices and attribute values: a whole number of primitives, every index
    /// below the vertex count, every component of every vertex attribute (`position`,
    /// `normal`, `tangent`, `uv`, `uv1`, `color`) finite and the colour's in [0, 1]. The error message names the first
    /// problem (the vertex and attribute, or the index).
    pub fn validate(&self) -> Result<(), String> {
        if self.indices.len() % self.topology.indices_per_primitive() != 0 {
            return Err(format!(
                "{} indices is not a whole number of {}",
                self.indices.len(),
                self.topology.name()
            ));
        }
        if let Some(&bad) = self
            .indices
            .iter()
            .find(|&&i| i as usize >= self.vertices.len())
        {
            return Err(format!(
                "index {bad} is out of range ({} vertices)",
                self.vertices.len()
            ));
        }
        let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
        for (i, v) in self.vertices.iter().enumerate() {
            let attributes: [(&str, &[f32]); 6] = [
                ("position", &v.position),
                ("normal", &v.normal),
                ("tangent", &v.tangent),
                ("uv", &v.uv),
                ("uv1", &v.uv1),
                ("color", &v.color),
            ];
            if let Some((name, values)) = attributes.iter().find(|(_, values)| !finite(values)) {
                return Err(format!(
                    "vertex {i} has a NaN or infinite {name} {}",
                    crate::message_numbers(values)
                ));
            }
            if !v.color.iter().all(|c| (0.0..=1.0).contains(c)) {
                return Err(format!(
                    "vertex {i} has a colour {} outside [0, 1]",
                    crate::message_numbers(&v.color)
                ));
            }
        }
        if let Some(skin) = &self.skin {
            skin.validate(self.vertices.len())?;
        }
        for (t, target) in self.morph_targets.iter().enumerate() {
            let lists: [(&str, &[[f32; 3]]); 3] = [
                ("position", &target.positions),
                ("normal", &target.normals),
                ("tangent", &target.tangents),
            ];
            for (name, list) in lists {
                if !list.is_empty() && list.len() != self.vertices.len() {
                    return Err(format!(
                        "morph target {t} has {} {name} displacements for {} vertices",
                        list.len(),
                        self.vertices.len()
                    ));
                }
                if let Some(v) = list.iter().position(|d| !d.iter().all(|x| x.is_finite())) {
                    return Err(format!(
                        "morph target {t}'s {name} displacement of vertex {v} is not finite"
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_is_closed_and_outward_facing() {
        let mesh = Mesh::uv_sphere("s", 2.0, 16, 8);
        mesh.validate().unwrap();
        // Every triangle's geometric normal points away from the centre (counter-clockwise
        // winding seen from outside), which the G-buffer pass's back-face culling relies on.
        for tri in mesh.indices.chunks(3) {
            let p: [glam::Vec3; 3] =
                std::array::from_fn(|k| glam::Vec3::from(mesh.vertices[tri[k] as usize].position));
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            let centre = (p[0] + p[1] + p[2]) / 3.0;
            assert!(n.dot(centre) > 0.0, "triangle {tri:?} faces inwards");
        }
        // Tangents are unit and orthogonal to normals (away from the poles' limit).
        for v in &mesh.vertices {
            let n = glam::Vec3::from(v.normal);
            let t = glam::Vec3::from_slice(&v.tangent[..3]);
            assert!((t.length() - 1.0).abs() < 1e-5);
            assert!(n.dot(t).abs() < 1e-5);
        }
    }

    /// The box is closed and faces outwards: every triangle's geometric normal is its
    /// vertices' normal (so flat shading agrees with the winding), pointing away from
    /// the centre, and its faces enclose the stated volume (divergence theorem).
    #[test]
    fn cuboid_is_closed_and_outward_facing() {
        let mesh = Mesh::cuboid("b", [2.0, 0.5, 1.0]);
        mesh.validate().unwrap();
        let mut volume = 0.0f64;
        for tri in mesh.indices.chunks(3) {
            let p: [glam::DVec3; 3] = std::array::from_fn(|k| {
                glam::Vec3::from(mesh.vertices[tri[k] as usize].position).as_dvec3()
            });
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            let shading = glam::Vec3::from(mesh.vertices[tri[0] as usize].normal).as_dvec3();
            assert!(n.normalize().abs_diff_eq(shading, 1e-12), "{tri:?}");
            assert!(
                n.dot(p[0] + p[1] + p[2]) > 0.0,
                "triangle {tri:?} faces inwards"
            );
            volume += p[0].dot(p[1].cross(p[2])) / 6.0;
        }
        assert!((volume - 1.0).abs() < 1e-12, "volume {volume}");
        for v in &mesh.vertices {
            let n = glam::Vec3::from(v.normal);
            let t = glam::Vec3::from_slice(&v.tangent[..3]);
            assert_eq!(n.dot(t), 0.0);
        }
    }

    #[test]
    fn every_attribute_is_checked_for_finite_values() {
        type Set = fn(&mut Vertex, f32);
        let attributes: [(&str, Set); 5] = [
            ("position", |v, x| v.position[1] = x),
            ("normal", |v, x| v.normal[2] = x),
            ("tangent", |v, x| v.tangent[3] = x),
            ("uv", |v, x| v.uv[0] = x),
            ("uv1", |v, x| v.uv1[1] = x),
        ];
        for (name, set) in attributes {
            for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                let mut mesh = Mesh::plane("p", 1.0);
                set(&mut mesh.vertices[2], bad);
                let message = mesh
                    .validate()
                    .expect_err(&format!("{name} = {bad} accepted"));
                assert!(
                    message.contains("vertex 2") && message.contains(&format!("infinite {name} (")),
                    "{name} = {bad}: {message}"
                );
            }
        }
    }
}
