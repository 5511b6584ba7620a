//! What the integration tests share: a seeded generator and scene builders.

#![allow(dead_code)]

use combustion_scene::{builtin_scene, Mesh, Object, Scene, Vertex};
use glam::{DVec3, Mat4};

/// xorshift64*: deterministic test data, no `rand`.
pub struct Random(u64);

impl Random {
    pub fn new(seed: u64) -> Random {
        Random(seed.max(1))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [low, high).
    pub fn range(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.unit()
    }

    /// Uniform below `n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// A uniformly distributed unit vector.
    pub fn direction(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let length2 = v.length_squared();
            if length2 > 1e-6 && length2 <= 1.0 {
                return v / length2.sqrt();
            }
        }
    }
}

/// A scene with these meshes placed by these (mesh, transform) pairs, no lights (the
/// rest from a built-in scene).
pub fn scene_of(meshes: Vec<Mesh>, objects: &[(usize, Mat4)]) -> Scene {
    let base = builtin_scene("spheres").expect("built-in scene");
    Scene {
        name: "test".into(),
        meshes,
        objects: objects
            .iter()
            .map(|&(mesh, transform)| Object {
                mesh,
                material: 0,
                transform,
                casts_shadows: true,
                node: None,
            })
            .collect(),
        lights: Vec::new(),
        ..base
    }
}

fn vertex(position: [f32; 3]) -> Vertex {
    Vertex {
        position,
        normal: [0.0, 1.0, 0.0],
        tangent: [1.0, 0.0, 0.0, 1.0],
        ..Vertex::default()
    }
}

/// A mesh of the given quads (corners counter-clockwise seen from the front), each two
/// triangles sharing the diagonal from its first corner to its third.
pub fn quads_mesh(name: &str, quads: &[[[f32; 3]; 4]]) -> Mesh {
    let mut mesh = Mesh {
        name: name.into(),
        ..Mesh::default()
    };
    for quad in quads {
        let base = mesh.vertices.len() as u32;
        mesh.vertices.extend(quad.iter().map(|&p| vertex(p)));
        mesh.indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    mesh
}

/// The closed box [-h, h]³ from six quads facing outwards (24 vertices: the faces share
/// corner positions, not vertices).
pub fn box_mesh(h: f32) -> Mesh {
    let faces: [[[f32; 3]; 4]; 6] = [
        [[h, -h, -h], [h, h, -h], [h, h, h], [h, -h, h]],
        [[-h, -h, -h], [-h, -h, h], [-h, h, h], [-h, h, -h]],
        [[-h, h, -h], [-h, h, h], [h, h, h], [h, h, -h]],
        [[-h, -h, -h], [h, -h, -h], [h, -h, h], [-h, -h, h]],
        [[-h, -h, h], [h, -h, h], [h, h, h], [-h, h, h]],
        [[-h, -h, -h], [-h, h, -h], [h, h, -h], [h, -h, -h]],
    ];
    quads_mesh("box", &faces)
}

/// A square grid of `cells`² quads of side `size` in the xz plane facing +y, centred at
/// the origin, with shared vertices.
pub fn grid_mesh(size: f32, cells: u32) -> Mesh {
    let mut mesh = Mesh {
        name: "grid".into(),
        ..Mesh::default()
    };
    let row = cells + 1;
    for i in 0..=cells {
        for j in 0..=cells {
            let x = size * (i as f32 / cells as f32 - 0.5);
            let z = size * (j as f32 / cells as f32 - 0.5);
            mesh.vertices.push(vertex([x, 0.0, z]));
        }
    }
    for i in 0..cells {
        for j in 0..cells {
            let a = i * row + j;
            // (x, z) → (x, z + 1) → (x + 1, z + 1) is counter-clockwise seen from +y.
            mesh.indices
                .extend_from_slice(&[a, a + 1, a + row + 1, a, a + row + 1, a + row]);
        }
    }
    mesh
}

/// `Mesh::uv_sphere` with its seam and pole vertices welded to one position each (the
/// f32 angles 2π and π do not give exactly the positions of 0), so the mesh is closed
/// by shared vertex positions.
pub fn welded_uv_sphere(radius: f32, segments: u32, rings: u32) -> Mesh {
    let mut mesh = Mesh::uv_sphere("welded sphere", radius, segments, rings);
    let row = (segments + 1) as usize;
    for ring in 0..=rings as usize {
        let first = mesh.vertices[ring * row].position;
        mesh.vertices[ring * row + segments as usize].position = first;
        if ring == 0 || ring == rings as usize {
            for seg in 0..row {
                mesh.vertices[ring * row + seg].position = first;
            }
        }
    }
    mesh
}

/// A world-space point of a mesh vertex under `transform`, in f64 as the hierarchy
/// places it.
pub fn place(transform: Mat4, p: [f32; 3]) -> DVec3 {
    transform
        .as_dmat4()
        .transform_point3(DVec3::from(p.map(f64::from)))
}
