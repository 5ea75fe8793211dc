//! The scene's materials on the GPU: one table of every mesh's materials (global ids: a mesh's
//! local ids offset by the materials of the meshes before it), the global material of every vertex
//! (vertices are split per material, so a triangle's material is its first vertex's), per-mesh UV
//! ranges, and every base-colour and normal texture (with a mip chain, box-filtered in linear
//! space) in one bindless array (texture 0 is white, used where a material has none or its file cannot be read,
//! with a warning). The passes read these (`crate::passes::materials` drives them); this module
//! imports no pass.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use bytemuck::{Pod, Zeroable};

use crate::builder::BuiltMesh;
use crate::gpu::{Buffer, Context, GpuError, GpuResult, Image, TextureSet, vk};
use crate::mesh::{Material, Mesh};

/// One material as the shaders read it (mirrors `MaterialGpu` in shaders_glsl/common/material.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MaterialGpu {
    /// Linear RGBA factor.
    pub base_color: [f32; 4],
    /// Metallic and roughness factors in [0, 1].
    pub metallic: f32,
    pub roughness: f32,
    /// Index into the texture array (0 = white).
    pub base_color_texture: u32,
    /// Index of the tangent-space normal map ([`NO_TEXTURE`] = none).
    pub normal_texture: u32,
    /// Index of the glTF metallic-roughness texture (linear: blue scales metallic, green
    /// roughness; [`NO_TEXTURE`] = none).
    pub metallic_roughness_texture: u32,
    pub _pad: [u32; 3],
}
const _: () = assert!(size_of::<MaterialGpu>() == 48);

/// Per mesh: UV range of its vertex codes and flags (mirrors `MeshMaterialGpu` in GLSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MeshMaterialGpu {
    /// UV of code 0 and of code 65535 (per axis).
    pub uv_min: [f32; 2],
    pub uv_max: [f32; 2],
    /// `MESH_HAS_UVS` | `MESH_HAS_NORMALS`.
    pub flags: u32,
    /// Global id of the mesh's material 0.
    pub material_offset: u32,
    /// The mesh's materials (local ids past the last count as the last).
    pub material_count: u32,
    pub _pad: u32,
}
const _: () = assert!(size_of::<MeshMaterialGpu>() == 32);

/// [`MeshMaterialGpu::flags`]: the source had texture coordinates.
pub const MESH_HAS_UVS: u32 = 1;
/// [`MeshMaterialGpu::flags`]: the source had normals.
pub const MESH_HAS_NORMALS: u32 = 2;

fn mesh_flags(has_uvs: bool, has_normals: bool) -> u32 {
    (if has_uvs { MESH_HAS_UVS } else { 0 }) | (if has_normals { MESH_HAS_NORMALS } else { 0 })
}

/// [`MaterialGpu::normal_texture`] of a material without a normal map.
pub const NO_TEXTURE: u32 = u32::MAX;

/// Most materials a scene may have (material depth holds `id + 1` in 24 bits).
pub const MAX_MATERIALS: usize = (1 << 24) - 2;

/// A decoded RGBA8 texture: sRGB-encoded colour, or linear data (normal maps).
#[derive(Clone, Debug)]
pub struct TextureData {
    /// Source file (`None` for built-in textures).
    pub path: Option<PathBuf>,
    /// Size in texels.
    pub width: u32,
    pub height: u32,
    /// RGBA8 texels, row-major, top row first.
    pub rgba: Vec<u8>,
    /// Colour (sampled through an sRGB format) rather than linear data.
    pub srgb: bool,
}

/// Exact sRGB decode of an 8-bit value.
pub fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Exact sRGB encode to 8 bits.
pub fn linear_to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

impl TextureData {
    /// The mip chain below this texture (level 1 onwards; level 0 is `self`): each level halves
    /// the previous one (rounded down, at least 1) with a 2x2 box filter (of the colour in linear
    /// space for sRGB textures; alpha and linear data averaged as they are), down to 1x1.
    pub fn mip_chain(&self) -> Vec<(u32, u32, Vec<u8>)> {
        let lut: Vec<f32> = (0..=255u8)
            .map(|c| {
                if self.srgb {
                    srgb_to_linear(c)
                } else {
                    c as f32 / 255.0
                }
            })
            .collect();
        let mut out: Vec<(u32, u32, Vec<u8>)> = Vec::new();
        let (mut w, mut h) = (self.width, self.height);
        while w > 1 || h > 1 {
            let prev: &[u8] = out.last().map(|l| l.2.as_slice()).unwrap_or(&self.rgba);
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let mut next = vec![0u8; 4 * nw as usize * nh as usize];
            for y in 0..nh {
                for x in 0..nw {
                    let mut acc = [0.0f32; 4];
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let sx = (2 * x + dx).min(w - 1) as usize;
                        let sy = (2 * y + dy).min(h - 1) as usize;
                        let p = &prev[4 * (sy * w as usize + sx)..][..4];
                        for k in 0..3 {
                            acc[k] += lut[p[k] as usize];
                        }
                        acc[3] += p[3] as f32;
                    }
                    let o = &mut next[4 * (y as usize * nw as usize + x as usize)..][..4];
                    for k in 0..3 {
                        o[k] = if self.srgb {
                            linear_to_srgb(acc[k] * 0.25)
                        } else {
                            (acc[k] * 0.25 * 255.0).round() as u8
                        };
                    }
                    o[3] = (acc[3] * 0.25).round() as u8;
                }
            }
            out.push((nw, nh, next));
            (w, h) = (nw, nh);
        }
        out
    }

    /// The 1x1 white texture (index 0).
    pub fn white() -> Self {
        Self {
            path: None,
            width: 1,
            height: 1,
            rgba: vec![255; 4],
            srgb: true,
        }
    }

    /// A 1x1 flat normal map (what an unreadable normal map becomes).
    pub fn flat_normal() -> Self {
        Self {
            path: None,
            width: 1,
            height: 1,
            rgba: vec![128, 128, 255, 255],
            srgb: false,
        }
    }
}

/// What a texture of the material table holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum TextureKind {
    /// Base colour, sampled through an sRGB format; white when unreadable.
    BaseColor,
    /// Tangent-space normal map (linear); flat when unreadable.
    Normal,
    /// glTF metallic-roughness (linear, blue metallic, green roughness); white (the factors
    /// alone) when unreadable.
    MetallicRoughness,
}

impl TextureKind {
    fn srgb(self) -> bool {
        self == TextureKind::BaseColor
    }

    fn describe(self) -> &'static str {
        match self {
            TextureKind::BaseColor => "base-colour texture unreadable, using white",
            TextureKind::Normal => "normal texture unreadable, using a flat one",
            TextureKind::MetallicRoughness => {
                "metallic-roughness texture unreadable, using the factors alone"
            }
        }
    }

    fn fallback(self) -> TextureData {
        match self {
            TextureKind::Normal => TextureData::flat_normal(),
            TextureKind::BaseColor => TextureData::white(),
            TextureKind::MetallicRoughness => TextureData {
                srgb: false,
                ..TextureData::white()
            },
        }
    }
}

/// What a mesh brings to the scene's material table (kept by a scene that changes, so that the
/// table can be rebuilt when meshes come and go).
#[derive(Clone, Debug)]
pub struct MeshMaterialSource {
    pub name: String,
    pub materials: Vec<Material>,
    pub uv_min: [f32; 2],
    pub uv_max: [f32; 2],
    pub has_uvs: bool,
    pub has_normals: bool,
}

impl MeshMaterialSource {
    /// The material part of a built mesh.
    pub fn of(m: &BuiltMesh) -> Self {
        Self {
            name: m.name.clone(),
            materials: m.materials.clone(),
            uv_min: m.quantization.uv_min,
            uv_max: m.quantization.uv_max,
            has_uvs: m.has_uvs,
            has_normals: m.has_normals,
        }
    }
}

/// The scene's materials on the CPU (what [`GpuMaterials`] uploads; also what CPU references read).
/// Textures are named here and decoded by [`SceneMaterials::load_textures`].
#[derive(Clone, Debug, Default)]
pub struct SceneMaterials {
    /// Global material table.
    pub materials: Vec<MaterialGpu>,
    /// Names, parallel to `materials`.
    pub names: Vec<String>,
    /// Per mesh: UV range, flags, first global material.
    pub meshes: Vec<MeshMaterialGpu>,
    /// Global material id of every vertex, in the scene's vertex order (meshes concatenated):
    /// [`SceneMaterials::new`] only, for CPU references (the GPU reads the local ids from the
    /// meshes' pages and adds `MeshMaterialGpu::material_offset`).
    pub vertex_materials: Vec<u32>,
    /// Texture files by index (index 0, the white texture, has none); each file once per use
    /// (colour or normal map).
    pub texture_paths: Vec<Option<PathBuf>>,
    /// Per texture: what it holds (decides its format and what replaces it when unreadable).
    pub texture_kinds: Vec<TextureKind>,
    /// `mesh: material` that named each texture first (for warnings).
    pub texture_users: Vec<String>,
}

fn load_texture(path: &Path, srgb: bool) -> Result<TextureData, String> {
    let img = image::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rgba = img.to_rgba8();
    let (width, height) = rgba.dimensions();
    if width == 0 || height == 0 {
        return Err(format!("{}: empty image", path.display()));
    }
    Ok(TextureData {
        path: Some(path.to_path_buf()),
        width,
        height,
        rgba: rgba.into_raw(),
        srgb,
    })
}

impl SceneMaterials {
    /// Gathers the materials of `built` (meshes without materials get [`Material::default`]) and
    /// names their textures (each file once).
    pub fn new<B: std::borrow::Borrow<BuiltMesh>>(built: &[B]) -> Result<Self, String> {
        let mut s = Self::empty();
        let mut by_path = BTreeMap::new();
        for m in built {
            let m = m.borrow();
            let (offset, count) = s.push_table(&mut by_path, &m.name, &m.materials);
            let q = &m.quantization;
            s.meshes.push(MeshMaterialGpu {
                uv_min: q.uv_min,
                uv_max: q.uv_max,
                flags: mesh_flags(m.has_uvs, m.has_normals),
                material_offset: offset,
                material_count: count,
                _pad: 0,
            });
            let last = count - 1;
            s.vertex_materials.extend((0..m.vertices.len()).map(|v| {
                offset + (m.vertex_materials.get(v).copied().unwrap_or(0) as u32).min(last)
            }));
        }
        s.check_count()?;
        Ok(s)
    }

    /// The table for a scene whose meshes come and go (`crate::scene_gpu`): one entry per mesh
    /// slot (`None`: a free slot, whose [`MeshMaterialGpu`] is all zeros). With every slot used,
    /// in order, this equals [`SceneMaterials::new`] of the same meshes but for
    /// `vertex_materials`, which stays empty.
    pub fn with_layout<'a>(
        meshes: impl IntoIterator<Item = Option<&'a MeshMaterialSource>>,
    ) -> Result<Self, String> {
        let mut s = Self::empty();
        let mut by_path = BTreeMap::new();
        for m in meshes {
            let Some(m) = m else {
                s.meshes.push(MeshMaterialGpu::default());
                continue;
            };
            let (offset, count) = s.push_table(&mut by_path, &m.name, &m.materials);
            s.meshes.push(MeshMaterialGpu {
                uv_min: m.uv_min,
                uv_max: m.uv_max,
                flags: mesh_flags(m.has_uvs, m.has_normals),
                material_offset: offset,
                material_count: count,
                _pad: 0,
            });
        }
        s.check_count()?;
        Ok(s)
    }

    /// The same material table for source meshes (what the classic `brute` and `lod` paths draw):
    /// global ids, textures and per-mesh flags equal [`SceneMaterials::new`]'s for the DAGs built
    /// from `meshes`. UV ranges are `[0, 1]` (the classic paths keep float UVs) and
    /// `vertex_materials` stays empty (they carry the material in their vertices).
    pub fn from_meshes<'a>(meshes: impl IntoIterator<Item = &'a Mesh>) -> Result<Self, String> {
        let mut s = Self::empty();
        let mut by_path = BTreeMap::new();
        for m in meshes {
            let (offset, count) = s.push_table(&mut by_path, &m.name, &m.materials);
            s.meshes.push(MeshMaterialGpu {
                uv_min: [0.0; 2],
                uv_max: [1.0; 2],
                flags: mesh_flags(m.has_uvs, m.has_normals),
                material_offset: offset,
                material_count: count,
                _pad: 0,
            });
        }
        s.check_count()?;
        Ok(s)
    }

    fn empty() -> Self {
        Self {
            texture_paths: vec![None],
            texture_kinds: vec![TextureKind::BaseColor],
            texture_users: vec![String::new()],
            ..Default::default()
        }
    }

    fn check_count(&self) -> Result<(), String> {
        if self.materials.len() > MAX_MATERIALS {
            return Err(format!(
                "{} materials in the scene (at most {MAX_MATERIALS})",
                self.materials.len()
            ));
        }
        Ok(())
    }

    /// Appends one mesh's materials ([`Material::default`] when it has none) to the table, naming
    /// each texture file once per use (`by_path`); returns (first global id, count).
    fn push_table(
        &mut self,
        by_path: &mut BTreeMap<(PathBuf, TextureKind), u32>,
        mesh_name: &str,
        materials: &[Material],
    ) -> (u32, u32) {
        let default = [Material::default()];
        let mats: &[Material] = if materials.is_empty() {
            &default
        } else {
            materials
        };
        let offset = self.materials.len() as u32;
        for mat in mats {
            let mut texture = |p: &Option<PathBuf>, kind: TextureKind, none: u32| {
                let Some(p) = p else { return none };
                *by_path.entry((p.clone(), kind)).or_insert_with(|| {
                    self.texture_paths.push(Some(p.clone()));
                    self.texture_kinds.push(kind);
                    self.texture_users
                        .push(format!("{mesh_name}: material `{}`", mat.name));
                    self.texture_paths.len() as u32 - 1
                })
            };
            let base_color_texture = texture(&mat.base_color_texture, TextureKind::BaseColor, 0);
            let normal_texture = texture(&mat.normal_texture, TextureKind::Normal, NO_TEXTURE);
            let metallic_roughness_texture = texture(
                &mat.metallic_roughness_texture,
                TextureKind::MetallicRoughness,
                NO_TEXTURE,
            );
            self.materials.push(MaterialGpu {
                base_color: mat.base_color,
                metallic: mat.metallic.clamp(0.0, 1.0),
                roughness: mat.roughness.clamp(0.0, 1.0),
                base_color_texture,
                normal_texture,
                metallic_roughness_texture,
                _pad: [0; 3],
            });
            self.names.push(mat.name.clone());
        }
        (offset, mats.len() as u32)
    }

    /// Number of materials.
    pub fn count(&self) -> u32 {
        self.materials.len() as u32
    }

    /// Decodes every texture (in parallel), index for index with `texture_paths`; a file that
    /// cannot be read becomes white, with a warning naming it and the material that uses it.
    pub fn load_textures(&self) -> (Vec<TextureData>, Vec<String>) {
        use rayon::prelude::*;
        let loaded: Vec<Result<TextureData, String>> = self
            .texture_paths
            .par_iter()
            .zip(&self.texture_kinds)
            .map(|(p, &kind)| match p {
                None => Ok(TextureData::white()),
                Some(p) => load_texture(p, kind.srgb()),
            })
            .collect();
        let mut warnings = Vec::new();
        let textures = loaded
            .into_iter()
            .enumerate()
            .map(|(i, r)| {
                r.unwrap_or_else(|e| {
                    let kind = self.texture_kinds[i];
                    warnings.push(format!(
                        "{}: {}: {e}",
                        self.texture_users[i],
                        kind.describe()
                    ));
                    kind.fallback()
                })
            })
            .collect();
        (textures, warnings)
    }
}

/// The materials on the GPU.
pub struct GpuMaterials {
    /// [`MaterialGpu`] per global material.
    pub table: Buffer,
    /// [`MeshMaterialGpu`] per mesh.
    pub meshes: Buffer,
    /// Base-colour (sRGB) and normal (linear) textures with their mip chains.
    pub textures: TextureSet,
    /// Number of materials.
    pub count: u32,
    /// Warnings of [`SceneMaterials::new`].
    pub warnings: Vec<String>,
}

impl GpuMaterials {
    /// Decodes `s`'s textures and uploads everything.
    pub fn new(ctx: &Context, s: &SceneMaterials) -> GpuResult<Self> {
        let (textures, warnings) = s.load_textures();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let up = |name: &str, bytes: &[u8]| Buffer::with_data(ctx, name, bytes, usage);
        let chains: Vec<Vec<(u32, u32, Vec<u8>)>> = {
            use rayon::prelude::*;
            textures.par_iter().map(TextureData::mip_chain).collect()
        };
        let mut images = Vec::with_capacity(textures.len());
        for (i, (t, chain)) in textures.iter().zip(&chains).enumerate() {
            let name = match &t.path {
                Some(p) => format!("texture {i} ({})", p.display()),
                None => "texture 0 (white)".into(),
            };
            let mut levels = vec![(t.width, t.height, t.rgba.as_slice())];
            levels.extend(chain.iter().map(|(w, h, d)| (*w, *h, d.as_slice())));
            images.push(Image::with_rgba8_mips(
                ctx,
                &name,
                &levels,
                if t.srgb {
                    vk::Format::R8G8B8A8_SRGB
                } else {
                    vk::Format::R8G8B8A8_UNORM
                },
            )?);
        }
        if s.materials.is_empty() {
            return Err(GpuError::Other("the scene has no materials".into()));
        }
        Ok(Self {
            table: up("materials", bytemuck::cast_slice(&s.materials))?,
            meshes: up("mesh materials", bytemuck::cast_slice(&s.meshes))?,
            textures: TextureSet::new(ctx, "material textures", images)?,
            count: s.count(),
            warnings,
        })
    }
}

/// What `shade` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadeMode {
    /// Directional light plus ambient.
    Lit = 0,
    /// The GBuffer's albedo.
    Albedo = 1,
    /// The GBuffer's normal (`n * 0.5 + 0.5`).
    Normals = 2,
    /// A hashed colour per material id.
    Materials = 3,
}
