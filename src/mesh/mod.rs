//! Mesh import: glTF, OBJ, PLY, STL and OFF into one in-memory [`Mesh`].
//!
//! Every importer validates what it reads (NaN/Inf positions and out-of-range indices are errors
//! that name the file and the element), drops degenerate triangles with a counted warning and welds
//! identical vertices.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

mod gltf_loader;
pub mod normals;
mod obj;
mod off;
mod ply;
pub mod polygon;
mod stl;

/// A material as the renderer needs it (glTF metallic-roughness subset; a default for other formats).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The material's name in the source.
    pub name: String,
    /// Base colour, linear RGBA.
    pub base_color: [f32; 4],
    /// Metallic factor, 0 to 1.
    pub metallic: f32,
    /// Roughness factor, 0 to 1.
    pub roughness: f32,
    /// Base-colour texture file, if the source names one and it exists on disk.
    pub base_color_texture: Option<PathBuf>,
    /// Normal-map texture file, if the source names one and it exists on disk.
    pub normal_texture: Option<PathBuf>,
    /// glTF metallic-roughness texture file (linear; blue = metallic, green = roughness, each
    /// multiplying its factor), if the source names one and it exists on disk.
    pub metallic_roughness_texture: Option<PathBuf>,
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
            metallic_roughness_texture: None,
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
    /// The mesh's name (file or glTF node).
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals; computed from faces (area-weighted) when the source has none.
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates; zeros when the source has none.
    pub uvs: Vec<[f32; 2]>,
    /// Triangle list.
    pub indices: Vec<u32>,
    /// One per triangle, indexing `materials`.
    pub material_ids: Vec<u32>,
    /// Materials (triangles index them).
    pub materials: Vec<Material>,
    /// Whether the source had normals / UVs (false: they were generated).
    pub has_normals: bool,
    /// Whether the vertices carry UVs.
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
        if !self.indices.len().is_multiple_of(3) {
            return Err(format!(
                "{} indices is not a multiple of 3",
                self.indices.len()
            ));
        }
        // The first offender of each kind (in parallel: meshes reach billions of indices).
        if let Some(i) = first_where(&self.indices, |&v| v as usize >= n) {
            let v = self.indices[i];
            return Err(format!("index {i} = {v} is out of range ({n} vertices)"));
        }
        if self.material_ids.len() != self.triangle_count() {
            return Err(format!(
                "{} material ids for {} triangles",
                self.material_ids.len(),
                self.triangle_count()
            ));
        }
        if let Some(i) = first_where(&self.material_ids, |&m| m as usize >= self.materials.len()) {
            return Err(format!(
                "material id {} out of range ({} materials)",
                self.material_ids[i],
                self.materials.len()
            ));
        }
        if let Some(i) = first_where(&self.positions, |p| !p.iter().all(|c| c.is_finite())) {
            return Err(format!("position {i} is not finite"));
        }
        Ok(())
    }
}

/// The index of the first element of `v` for which `bad` holds: chunks in parallel, each scanned
/// sequentially (a per-element parallel search cost several times the scan on one thread).
fn first_where<T: Sync>(v: &[T], bad: impl Fn(&T) -> bool + Sync) -> Option<usize> {
    use rayon::prelude::*;
    const CHUNK: usize = 1 << 16;
    let c = v.par_chunks(CHUNK).position_first(|c| c.iter().any(&bad))?;
    let at = c * CHUNK;
    v[at..].iter().position(bad).map(|i| at + i)
}

/// Options for [`load`].
#[derive(Clone, Debug)]
pub struct ImportOptions {
    /// glTF only: return one [`Mesh`] per node that has a mesh (named after the node) instead of
    /// merging the whole scene into one. Other formats always give one mesh.
    pub split_nodes: bool,
    /// Crease angle in degrees for vertices without a source normal (see
    /// [`normals::crease_normals`]): faces meeting at a sharper angle are shaded apart and their
    /// shared vertices split. Default [`normals::DEFAULT_CREASE_DEG`]; 180 shades smoothly
    /// everywhere.
    pub crease_deg: f32,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            split_nodes: false,
            crease_deg: normals::DEFAULT_CREASE_DEG,
        }
    }
}

/// What an import did to the source data, summed over all returned meshes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportReport {
    /// Triangles in the source after triangulating polygons, strips and fans, before any were dropped.
    pub source_triangles: usize,
    /// Triangles removed by [`drop_degenerate`] (repeated index or zero area).
    pub degenerate_dropped: usize,
    /// Vertices removed by [`weld`] because an identical vertex already existed.
    pub vertices_welded: usize,
    /// Vertices removed because no kept triangle referenced them (see [`remove_unreferenced`]).
    pub unreferenced_removed: usize,
    /// Vertices added by splitting at creases when normals were generated
    /// ([`normals::crease_normals`]).
    pub crease_splits: usize,
    /// Human-readable notes on what was tolerated (missing textures, skipped primitives, ...).
    pub warnings: Vec<String>,
}

/// The result of [`load`]: one or more validated meshes and what happened on the way.
#[derive(Clone, Debug)]
pub struct Import {
    /// At least one mesh; every one passes [`Mesh::validate`] and has at least one triangle.
    pub meshes: Vec<Mesh>,
    /// Counts and warnings for the whole file.
    pub report: ImportReport,
}

/// Why a file could not be imported. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// The file (or a file it references) could not be read.
    #[error("{}: cannot read {}: {source}", .path.display(), .file.display())]
    Io {
        /// The file being imported.
        path: PathBuf,
        /// The file that failed to read (the imported file itself or e.g. a glTF buffer).
        file: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The extension is not one of the supported formats.
    #[error(
        "{}: unknown mesh format '{ext}' (supported: .gltf, .glb, .obj, .ply, .stl, .off)",
        .path.display()
    )]
    UnknownFormat {
        /// The file being imported.
        path: PathBuf,
        /// The extension found (empty if none).
        ext: String,
    },
    /// The file is malformed; `message` names the element (line, face, accessor, ...).
    #[error("{}: {message}", .path.display())]
    Parse {
        /// The file being imported.
        path: PathBuf,
        /// What is wrong and where.
        message: String,
    },
    /// A vertex position is NaN or infinite.
    #[error("{}: vertex {vertex}{context} has a non-finite position {position:?}", .path.display())]
    NonFinite {
        /// The file being imported.
        path: PathBuf,
        /// The vertex index in the source (within the element named by `context`).
        vertex: usize,
        /// Where the vertex lives, e.g. " (mesh 'Box', primitive 0, accessor 2)"; may be empty.
        context: String,
        /// The offending value.
        position: [f32; 3],
    },
    /// A face/primitive references a vertex that does not exist.
    #[error(
        "{}: {context}: index {index} is out of range ({vertex_count} vertices)",
        .path.display()
    )]
    IndexOutOfRange {
        /// The file being imported.
        path: PathBuf,
        /// The element holding the index, e.g. "mesh 'Box' primitive 0, index accessor 0, element 7".
        context: String,
        /// The bad index value.
        index: i64,
        /// How many vertices the index may address.
        vertex_count: usize,
    },
    /// The glTF uses KHR_draco_mesh_compression.
    #[error(
        "{}: Draco compression is not supported (KHR_draco_mesh_compression); \
         re-export the file without Draco",
        .path.display()
    )]
    Draco {
        /// The file being imported.
        path: PathBuf,
    },
    /// A glTF buffer file named by the document does not exist.
    #[error("{}: buffer {index} file {} is missing", .path.display(), .buffer.display())]
    MissingBuffer {
        /// The file being imported.
        path: PathBuf,
        /// The buffer index in the glTF document.
        index: usize,
        /// The missing file.
        buffer: PathBuf,
    },
    /// The file has no (non-degenerate) triangles.
    #[error("{}: no triangles to import ({detail})", .path.display())]
    NoTriangles {
        /// The file being imported.
        path: PathBuf,
        /// Why, e.g. "only points and lines" or "all 4 triangles are degenerate".
        detail: String,
    },
    /// The imported mesh broke a [`Mesh`] invariant (an importer bug, reported rather than panicking).
    #[error("{}: imported mesh is invalid: {message}", .path.display())]
    Invalid {
        /// The file being imported.
        path: PathBuf,
        /// The failed invariant.
        message: String,
    },
}

impl ImportError {
    /// Shorthand for a [`ImportError::Parse`].
    pub(crate) fn parse(path: &Path, message: impl Into<String>) -> Self {
        ImportError::Parse {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// Shorthand for reading `file` failing while importing `path`.
    pub(crate) fn io(path: &Path, file: &Path, source: std::io::Error) -> Self {
        ImportError::Io {
            path: path.to_path_buf(),
            file: file.to_path_buf(),
            source,
        }
    }
}

/// The file formats [`load`] understands, chosen by file extension (case-insensitive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// glTF 2.0, JSON (`.gltf`) or binary (`.glb`).
    Gltf,
    /// Wavefront OBJ with optional MTL materials.
    Obj,
    /// Stanford PLY, ASCII or binary.
    Ply,
    /// STL, ASCII (any number of `solid` blocks) or binary.
    Stl,
    /// Object File Format (Geomview / CGAL / Princeton Shape Benchmark).
    Off,
}

impl Format {
    /// The format for `path`'s extension, or `None` if unsupported.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "gltf" | "glb" => Format::Gltf,
            "obj" => Format::Obj,
            "ply" => Format::Ply,
            "stl" => Format::Stl,
            "off" => Format::Off,
            _ => return None,
        })
    }
}

/// Where an importer finds the files a mesh file names (glTF buffers and images, OBJ material
/// libraries and their textures): the folder next to the file on disk, or nowhere for a file held
/// in memory ([`load_bytes`]), where every such file is simply missing.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Siblings<'a> {
    dir: Option<&'a Path>,
}

impl<'a> Siblings<'a> {
    /// Files relative to `dir`.
    pub(crate) fn dir(dir: &'a Path) -> Self {
        Self { dir: Some(dir) }
    }

    /// No external files at all.
    pub(crate) fn none() -> Self {
        Self { dir: None }
    }

    /// The path of `relative` (already percent-decoded) as error messages and [`Material`] name it.
    pub(crate) fn resolve(&self, relative: impl AsRef<Path>) -> PathBuf {
        match self.dir {
            Some(d) => d.join(relative),
            None => relative.as_ref().to_path_buf(),
        }
    }

    /// Reads a file returned by [`Siblings::resolve`]; `NotFound` for an in-memory import.
    pub(crate) fn read(&self, file: &Path) -> std::io::Result<Vec<u8>> {
        match self.dir {
            Some(_) => std::fs::read(file),
            None => Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "an in-memory import has no external files",
            )),
        }
    }

    /// Whether `file` (from [`Siblings::resolve`]) exists as a file.
    pub(crate) fn is_file(&self, file: &Path) -> bool {
        self.dir.is_some() && file.is_file()
    }
}

/// Loads a mesh file (format by extension) into validated meshes.
///
/// Every importer: rejects NaN/Inf positions ([`ImportError::NonFinite`]) and out-of-range indices
/// ([`ImportError::IndexOutOfRange`]); triangulates polygons (ear clipping on the best-fit plane);
/// then [`drop_degenerate`] (counted, with a warning), [`remove_unreferenced`], [`weld`], and
/// crease-angle normals for vertices without a (usable) source normal
/// ([`normals::crease_normals`], [`ImportOptions::crease_deg`]). UVs are zero where the
/// source has none and follow the glTF convention (origin top-left; OBJ/PLY `v` is flipped).
/// A file with no triangle left is an error, never an empty mesh. Files the mesh file names
/// (glTF buffers and textures, OBJ `.mtl` libraries) are read from its folder.
pub fn load(path: &Path, opts: &ImportOptions) -> Result<Import, ImportError> {
    let format = Format::from_path(path).ok_or_else(|| ImportError::UnknownFormat {
        path: path.to_path_buf(),
        ext: path
            .extension()
            .map(|e| e.to_string_lossy().into_owned())
            .unwrap_or_default(),
    })?;
    let bytes = std::fs::read(path).map_err(|e| ImportError::io(path, path, e))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    import(path, &bytes, format, Siblings::dir(dir), opts)
}

/// Imports a mesh file held in memory, exactly as [`load`] imports a file on disk except that
/// every file it names (glTF buffers and images, OBJ `.mtl` libraries) is missing: a glTF needing
/// an external buffer fails with [`ImportError::MissingBuffer`], missing textures and material
/// libraries are warnings. `name` stands for the file's path in errors and warnings and names the
/// mesh (its stem), as a path would.
pub fn load_bytes(
    bytes: &[u8],
    format: Format,
    name: &str,
    opts: &ImportOptions,
) -> Result<Import, ImportError> {
    import(Path::new(name), bytes, format, Siblings::none(), opts)
}

/// The PLY importer's fast path checked against its ply-rs path on `bytes` (named `name` in
/// warnings): `Ok(true)` if the fast path read the file and the ply-rs path read exactly the same
/// mesh and warnings, `Ok(false)` if the fast path left the file to the ply-rs path, `Err` with the
/// first difference otherwise. For the fuzz target `import_ply` and the tests.
#[doc(hidden)]
pub fn ply_fast_path_check(name: &str, bytes: &[u8]) -> Result<bool, String> {
    ply::fast_path_check(name, bytes)
}

/// The one import path of [`load`] and [`load_bytes`].
fn import(
    path: &Path,
    bytes: &[u8],
    format: Format,
    files: Siblings,
    opts: &ImportOptions,
) -> Result<Import, ImportError> {
    let mut report = ImportReport::default();
    let w = &mut report.warnings;
    let raws = match format {
        Format::Gltf => gltf_loader::load(path, bytes, files, opts, w)?,
        Format::Obj => vec![obj::load(path, bytes, files, w)?],
        Format::Ply => vec![ply::load(path, bytes, w)?],
        Format::Stl => vec![stl::load(path, bytes, w)?],
        Format::Off => vec![off::load(path, bytes, w)?],
    };
    let mut meshes = Vec::with_capacity(raws.len());
    let mut empty = Vec::new();
    for raw in raws {
        let name = raw.name.clone();
        let tris = raw.triangle_count();
        match finish(path, raw, opts, &mut report)? {
            Some(mesh) => meshes.push(mesh),
            None => empty.push(format!("'{name}' ({tris} triangles)")),
        }
    }
    if meshes.is_empty() {
        return Err(ImportError::NoTriangles {
            path: path.to_path_buf(),
            detail: if report.source_triangles == 0 {
                "the file has no triangles".to_string()
            } else {
                format!("all {} triangles are degenerate", report.source_triangles)
            },
        });
    }
    if !empty.is_empty() {
        report.warnings.push(format!(
            "{}: skipped {} mesh(es) with only degenerate triangles: {}",
            path.display(),
            empty.len(),
            empty.join(", ")
        ));
    }
    Ok(Import { meshes, report })
}

/// Loads a mesh file with default options and merges everything into one [`Mesh`].
pub fn load_mesh(path: &Path) -> Result<(Mesh, ImportReport), ImportError> {
    let import = load(path, &ImportOptions::default())?;
    let mesh = merge(import.meshes);
    mesh.validate().map_err(|message| ImportError::Invalid {
        path: path.to_path_buf(),
        message,
    })?;
    Ok((mesh, import.report))
}

/// Concatenates meshes (materials appended, ids offset) into one; the name is the first mesh's.
/// `has_normals`/`has_uvs` are true only if they are true for every input.
pub fn merge(meshes: Vec<Mesh>) -> Mesh {
    let mut iter = meshes.into_iter();
    let Some(mut out) = iter.next() else {
        return Mesh::default();
    };
    for m in iter {
        let vbase = out.positions.len() as u32;
        let mbase = out.materials.len() as u32;
        out.positions.extend_from_slice(&m.positions);
        out.normals.extend_from_slice(&m.normals);
        out.uvs.extend_from_slice(&m.uvs);
        out.indices.extend(m.indices.iter().map(|i| i + vbase));
        out.material_ids
            .extend(m.material_ids.iter().map(|i| i + mbase));
        out.materials.extend(m.materials);
        out.has_normals &= m.has_normals;
        out.has_uvs &= m.has_uvs;
    }
    out
}

/// Merges vertices whose position, normal and UV are bit-identical, keeping the first occurrence
/// (vertex order is otherwise preserved). Returns how many vertices were removed.
pub fn weld(mesh: &mut Mesh) -> usize {
    let n = mesh.positions.len();
    if mesh.normals.len() != n || mesh.uvs.len() != n {
        return 0;
    }
    let mut first: HashMap<[u32; 8], u32, crate::hash::FxBuild> =
        HashMap::with_capacity_and_hasher(n, Default::default());
    let mut remap = Vec::with_capacity(n);
    let mut kept = 0u32;
    let mut keep = Vec::with_capacity(n);
    for v in 0..n {
        let (p, nn, t) = (mesh.positions[v], mesh.normals[v], mesh.uvs[v]);
        let key = [
            p[0].to_bits(),
            p[1].to_bits(),
            p[2].to_bits(),
            nn[0].to_bits(),
            nn[1].to_bits(),
            nn[2].to_bits(),
            t[0].to_bits(),
            t[1].to_bits(),
        ];
        match first.get(&key) {
            Some(&k) => remap.push(k),
            None => {
                first.insert(key, kept);
                remap.push(kept);
                keep.push(v);
                kept += 1;
            }
        }
    }
    let removed = n - keep.len();
    if removed > 0 {
        apply_vertex_remap(mesh, &keep, &remap);
    }
    removed
}

/// Removes vertices that no triangle references and renumbers the indices. Returns the count.
pub fn remove_unreferenced(mesh: &mut Mesh) -> usize {
    let n = mesh.positions.len();
    let mut used = vec![false; n];
    for &i in &mesh.indices {
        if let Some(u) = used.get_mut(i as usize) {
            *u = true;
        }
    }
    let mut remap = vec![0u32; n];
    let mut keep = Vec::with_capacity(n);
    for (v, &u) in used.iter().enumerate() {
        if u {
            remap[v] = keep.len() as u32;
            keep.push(v);
        }
    }
    let removed = n - keep.len();
    if removed > 0 {
        apply_vertex_remap(mesh, &keep, &remap);
    }
    removed
}

/// Keeps the vertices `keep` (old indices, ascending) and maps every index through `remap`.
fn apply_vertex_remap(mesh: &mut Mesh, keep: &[usize], remap: &[u32]) {
    let pick3 = |src: &[[f32; 3]]| keep.iter().filter_map(|&v| src.get(v).copied()).collect();
    mesh.positions = pick3(&mesh.positions);
    mesh.normals = pick3(&mesh.normals);
    mesh.uvs = keep
        .iter()
        .filter_map(|&v| mesh.uvs.get(v).copied())
        .collect();
    for i in &mut mesh.indices {
        if let Some(&r) = remap.get(*i as usize) {
            *i = r;
        }
    }
}

/// Twice the area of triangle `abc` computed in f64, and its longest squared edge.
fn area2_and_edge2(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> (f64, f64) {
    let d = |p: [f32; 3], q: [f32; 3]| {
        [
            q[0] as f64 - p[0] as f64,
            q[1] as f64 - p[1] as f64,
            q[2] as f64 - p[2] as f64,
        ]
    };
    let (u, v, w) = (d(a, b), d(a, c), d(b, c));
    let cr = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len2 = |x: [f64; 3]| x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    (len2(cr).sqrt(), len2(u).max(len2(v)).max(len2(w)))
}

/// Relative area below which a triangle counts as zero-area: twice its area divided by its longest
/// squared edge (a shape measure independent of scale). 1e-10 is far below anything f32 positions
/// can resolve for a real triangle.
pub const DEGENERATE_RELATIVE_AREA: f64 = 1e-10;

/// Removes triangles with a repeated index or zero area (see [`DEGENERATE_RELATIVE_AREA`]),
/// together with their material ids. Returns how many were removed.
pub fn drop_degenerate(mesh: &mut Mesh) -> usize {
    let tri_count = mesh.triangle_count();
    let mut kept_idx = Vec::with_capacity(mesh.indices.len());
    let mut kept_mat = Vec::with_capacity(tri_count);
    for t in 0..tri_count {
        let tri = [
            mesh.indices[3 * t],
            mesh.indices[3 * t + 1],
            mesh.indices[3 * t + 2],
        ];
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            continue;
        }
        let p = |i: u32| mesh.positions.get(i as usize).copied();
        let (Some(a), Some(b), Some(c)) = (p(tri[0]), p(tri[1]), p(tri[2])) else {
            continue;
        };
        let (area2, edge2) = area2_and_edge2(a, b, c);
        // Written so that a NaN area also counts as degenerate.
        let proper = area2 > 0.0 && area2 > DEGENERATE_RELATIVE_AREA * edge2;
        if !proper {
            continue;
        }
        kept_idx.extend_from_slice(&tri);
        kept_mat.push(mesh.material_ids.get(t).copied().unwrap_or(0));
    }
    let removed = tri_count - kept_mat.len();
    mesh.indices = kept_idx;
    mesh.material_ids = kept_mat;
    removed
}

/// Normalizes every normal; vertices whose normal is zero or not finite get the area-weighted
/// average of their triangles' normals (or +Z if those cancel out). Returns how many were computed.
pub fn fill_missing_normals(mesh: &mut Mesh) -> usize {
    let n = mesh.positions.len();
    mesh.normals.resize(n, [0.0; 3]);
    let mut need = vec![false; n];
    let mut any = false;
    for (v, nn) in mesh.normals.iter_mut().enumerate() {
        let len = (nn[0] as f64).hypot(nn[1] as f64).hypot(nn[2] as f64);
        if len.is_finite() && len > 1e-20 {
            *nn = [
                (nn[0] as f64 / len) as f32,
                (nn[1] as f64 / len) as f32,
                (nn[2] as f64 / len) as f32,
            ];
        } else {
            need[v] = true;
            any = true;
        }
    }
    if !any {
        return 0;
    }
    let mut acc = vec![[0.0f64; 3]; n];
    for tri in mesh.indices.chunks_exact(3) {
        let (ia, ib, ic) = (tri[0] as usize, tri[1] as usize, tri[2] as usize);
        if !(need.get(ia).copied().unwrap_or(false)
            || need.get(ib).copied().unwrap_or(false)
            || need.get(ic).copied().unwrap_or(false))
        {
            continue;
        }
        let (Some(a), Some(b), Some(c)) = (
            mesh.positions.get(ia),
            mesh.positions.get(ib),
            mesh.positions.get(ic),
        ) else {
            continue;
        };
        let u = [
            b[0] as f64 - a[0] as f64,
            b[1] as f64 - a[1] as f64,
            b[2] as f64 - a[2] as f64,
        ];
        let w = [
            c[0] as f64 - a[0] as f64,
            c[1] as f64 - a[1] as f64,
            c[2] as f64 - a[2] as f64,
        ];
        // Unnormalized cross product: its length is twice the area, i.e. area weighting.
        let cr = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        for i in [ia, ib, ic] {
            if need[i] {
                for k in 0..3 {
                    acc[i][k] += cr[k];
                }
            }
        }
    }
    let mut computed = 0;
    for v in 0..n {
        if !need[v] {
            continue;
        }
        computed += 1;
        let a = acc[v];
        let len = a[0].hypot(a[1]).hypot(a[2]);
        mesh.normals[v] = if len.is_finite() && len > 0.0 {
            [
                (a[0] / len) as f32,
                (a[1] / len) as f32,
                (a[2] / len) as f32,
            ]
        } else {
            [0.0, 0.0, 1.0]
        };
    }
    computed
}

/// Replaces `mesh`'s materials by `n` generated ones (`n` >= 1), each a spatially coherent patch:
/// triangles sorted by the Morton code of their centroid (10 bits per axis over the bounds) and cut
/// into `n` runs of equal size (the last may be shorter; with fewer triangles than `n`, only as many
/// materials as triangles are used). Base colours are spread over hue, every fourth material is
/// metal, roughness varies; no textures. Deterministic. For benchmarks of material cost (the
/// `drawcalls` scene's 64 materials per mesh).
pub fn assign_patch_materials(mesh: &mut Mesh, n: u32) {
    let n = n.max(1);
    let tris = mesh.indices.len() / 3;
    let (lo, hi) = mesh.bounds().unwrap_or(([0.0; 3], [1.0; 3]));
    let morton = |t: usize| {
        let mut code = 0u32;
        for (k, (l, h)) in lo.iter().zip(hi).enumerate() {
            let c: f32 = (0..3)
                .map(|v| mesh.positions[mesh.indices[3 * t + v] as usize][k])
                .sum::<f32>()
                / 3.0;
            let spread = (h - l).max(f32::MIN_POSITIVE);
            let q = (((c - l) / spread).clamp(0.0, 1.0) * 1023.0) as u32;
            for bit in 0..10 {
                code |= ((q >> bit) & 1) << (3 * bit + k as u32);
            }
        }
        code
    };
    let mut order: Vec<(u32, u32)> = (0..tris).map(|t| (morton(t), t as u32)).collect();
    order.sort_unstable();
    let per = tris.div_ceil(n as usize).max(1);
    mesh.material_ids = vec![0; tris];
    for (rank, &(_, t)) in order.iter().enumerate() {
        mesh.material_ids[t as usize] = (rank / per) as u32;
    }
    let used = if tris == 0 {
        1
    } else {
        tris.div_ceil(per) as u32
    };
    mesh.materials = (0..used)
        .map(|i| {
            let h = i as f32 / used as f32 * 6.0;
            let f = |o: f32| (((h + o) % 6.0 - 3.0).abs() - 1.0).clamp(0.0, 1.0);
            Material {
                name: format!("patch{i}"),
                base_color: [
                    0.15 + 0.8 * f(0.0),
                    0.15 + 0.8 * f(4.0),
                    0.15 + 0.8 * f(2.0),
                    1.0,
                ],
                metallic: if i % 4 == 3 { 1.0 } else { 0.0 },
                roughness: 0.25 + 0.5 * ((i * 7 % 11) as f32 / 10.0),
                ..Material::default()
            }
        })
        .collect();
}

/// Drops materials no triangle uses and renumbers `material_ids` (original order kept); a mesh
/// without materials gets the default one.
fn compact_materials(mesh: &mut Mesh) {
    if mesh.materials.is_empty() {
        mesh.materials.push(Material::default());
    }
    let count = mesh.materials.len();
    let mut used = vec![false; count];
    for id in &mut mesh.material_ids {
        if *id as usize >= count {
            *id = 0;
        }
        used[*id as usize] = true;
    }
    if used.iter().all(|u| *u) {
        return;
    }
    let mut remap = vec![0u32; count];
    let mut materials = Vec::new();
    for (i, m) in std::mem::take(&mut mesh.materials).into_iter().enumerate() {
        if used[i] {
            remap[i] = materials.len() as u32;
            materials.push(m);
        }
    }
    for id in &mut mesh.material_ids {
        *id = remap[*id as usize];
    }
    mesh.materials = materials;
}

/// The shared tail of every importer: validation, degenerate removal, compaction, welding,
/// normals, materials. Returns `None` when no triangle survives.
fn finish(
    path: &Path,
    mut mesh: Mesh,
    opts: &ImportOptions,
    report: &mut ImportReport,
) -> Result<Option<Mesh>, ImportError> {
    report.source_triangles += mesh.triangle_count();
    let n = mesh.positions.len();
    // Importers fill these; keep the invariant even if one did not.
    mesh.normals.resize(n, [0.0; 3]);
    mesh.uvs.resize(n, [0.0; 2]);
    if !mesh.indices.len().is_multiple_of(3) {
        return Err(ImportError::Invalid {
            path: path.to_path_buf(),
            message: format!("{} indices is not a multiple of 3", mesh.indices.len()),
        });
    }
    mesh.material_ids.resize(mesh.triangle_count(), 0);
    if let Some(v) = mesh
        .positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(ImportError::NonFinite {
            path: path.to_path_buf(),
            vertex: v,
            context: format!(" (of mesh '{}')", mesh.name),
            position: mesh.positions[v],
        });
    }
    if let Some((k, &i)) = mesh
        .indices
        .iter()
        .enumerate()
        .find(|(_, i)| **i as usize >= n)
    {
        return Err(ImportError::IndexOutOfRange {
            path: path.to_path_buf(),
            context: format!("mesh '{}', triangle {}", mesh.name, k / 3),
            index: i as i64,
            vertex_count: n,
        });
    }
    let dropped = drop_degenerate(&mut mesh);
    if dropped > 0 {
        report.degenerate_dropped += dropped;
        report.warnings.push(format!(
            "{}: dropped {dropped} degenerate triangles (repeated index or zero area) of mesh '{}'",
            path.display(),
            mesh.name
        ));
    }
    report.unreferenced_removed += remove_unreferenced(&mut mesh);
    if mesh.indices.is_empty() {
        return Ok(None);
    }
    report.vertices_welded += weld(&mut mesh);
    report.crease_splits += normals::crease_normals(&mut mesh, opts.crease_deg);
    compact_materials(&mut mesh);
    mesh.validate().map_err(|message| ImportError::Invalid {
        path: path.to_path_buf(),
        message,
    })?;
    Ok(Some(mesh))
}
