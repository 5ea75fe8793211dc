//! Mesh import: glTF, OBJ, PLY, STL and OFF into one in-memory [`Mesh`].
//!
//! Every importer validates what it reads (NaN/Inf positions and out-of-range indices are errors
//! that name the file and the element), drops degenerate triangles with a counted warning and welds
//! identical vertices.

use std::path::PathBuf;

/// A material as the renderer needs it (glTF metallic-roughness subset; a default for other formats).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub base_color: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
    /// Base-colour texture file, if the source names one and it exists on disk.
    pub base_color_texture: Option<PathBuf>,
    /// Normal-map texture file, if the source names one and it exists on disk.
    pub normal_texture: Option<PathBuf>,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".into(),
            base_color: [0.8, 0.8, 0.8, 1.0],
            metallic: 0.0,
            roughness: 0.6,
            base_color_texture: None,
            normal_texture: None,
        }
    }
}

/// An indexed triangle mesh with per-vertex attributes and a material per triangle.
///
/// Invariants (held by every importer and checked by [`Mesh::validate`]):
/// `normals.len() == uvs.len() == positions.len()`, `indices.len() % 3 == 0`, every index is in range,
/// `material_ids.len() == indices.len() / 3`, every material id indexes `materials`, all positions finite.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<[f32; 3]>,
    /// Unit normals; computed from faces (area-weighted) when the source has none.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates; zeros when the source has none.
    pub uvs: Vec<[f32; 2]>,
    /// Triangle list.
    pub indices: Vec<u32>,
    /// One per triangle, indexing `materials`.
    pub material_ids: Vec<u32>,
    pub materials: Vec<Material>,
    /// Whether the source had normals / UVs (false: they were generated).
    pub has_normals: bool,
    pub has_uvs: bool,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Axis-aligned bounds `(min, max)`; `None` for an empty mesh.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        let mut lo = first;
        let mut hi = first;
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Some((lo, hi))
    }

    /// Checks the invariants documented on [`Mesh`].
    pub fn validate(&self) -> Result<(), String> {
        let n = self.positions.len();
        if self.normals.len() != n || self.uvs.len() != n {
            return Err(format!(
                "attribute counts differ: {} positions, {} normals, {} uvs",
                n,
                self.normals.len(),
                self.uvs.len()
            ));
        }
        if self.indices.len() % 3 != 0 {
            return Err(format!(
                "{} indices is not a multiple of 3",
                self.indices.len()
            ));
        }
        if let Some((i, &v)) = self
            .indices
            .iter()
            .enumerate()
            .find(|(_, v)| **v as usize >= n)
        {
            return Err(format!("index {i} = {v} is out of range ({n} vertices)"));
        }
        if self.material_ids.len() != self.triangle_count() {
            return Err(format!(
                "{} material ids for {} triangles",
                self.material_ids.len(),
                self.triangle_count()
            ));
        }
        if let Some(m) = self
            .material_ids
            .iter()
            .find(|m| **m as usize >= self.materials.len())
        {
            return Err(format!(
                "material id {m} out of range ({} materials)",
                self.materials.len()
            ));
        }
        if let Some(i) = self
            .positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(format!("position {i} is not finite"));
        }
        Ok(())
    }
}
