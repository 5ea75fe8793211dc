//! glTF 2.0 importer (`.gltf` and `.glb`).
//!
//! The document is parsed and validated with the `gltf` crate's JSON model and validation (a
//! POSITION accessor without `min`/`max` is tolerated), but the GLB
//! container, the buffers (GLB blob, `data:` URIs, external files) and the accessors are read here
//! with bounds-checked code: `gltf::import` fails on a missing image and the crate's accessor
//! iterators can panic on inconsistent files. Missing textures are warnings; missing buffers are
//! errors. The default scene (else the first, else every root node) is walked with each node's
//! world matrix: positions are transformed, normals use the inverse transpose, and the winding is
//! flipped under a mirroring (negative-determinant) transform.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use glam::{DMat3, DMat4, DVec3, Mat4};
use gltf::mesh::Mode;

use super::{ImportError, ImportOptions, Material, Mesh, Siblings};

/// Accessors larger than this many elements without a buffer view are refused: they are zeros
/// (plus sparse substitutions) that cost memory (about 100 bytes per vertex through the import)
/// without taking room in the file, so a few bytes of JSON could ask for gigabytes.
const MAX_VIEWLESS_ELEMENTS: usize = 1 << 20;

/// The scene may expand (nodes instancing meshes, primitives sharing accessors) to at most this
/// many vertices plus triangle corners per byte of input (the file and its buffers), but always to
/// `MIN_EXPANSION_BUDGET`: a few KB of JSON naming one large accessor from many nodes or
/// primitives would otherwise ask for gigabytes (about 100 bytes a vertex through the import).
/// With `split_nodes` every node's mesh copies all materials, each copy charged as a vertex.
const EXPANSION_PER_BYTE: usize = 64;
/// See [`EXPANSION_PER_BYTE`]: 8 M vertices and corners (or material copies), under 1 GB.
const MIN_EXPANSION_BUDGET: usize = 1 << 23;

/// Reads a glTF file into unprocessed meshes: one, or one per node with a mesh.
pub(super) fn load(
    path: &Path,
    bytes: &[u8],
    files: Siblings,
    opts: &ImportOptions,
    warnings: &mut Vec<String>,
) -> Result<Vec<Mesh>, ImportError> {
    let (json_bytes, blob) = if bytes.starts_with(b"glTF") {
        split_glb(path, bytes)?
    } else {
        (bytes, None)
    };
    check_draco(path, json_bytes)?;
    // The JSON is parsed as JSON only: `gltf::Gltf::from_slice*` would take a JSON chunk starting
    // with "glTF" for a nested GLB and subtract with overflow on its length (gltf-1.4.1
    // src/binary.rs:252).
    let root: gltf::json::Root = gltf::json::deserialize::from_slice(json_bytes)
        .map_err(|e| ImportError::parse(path, format!("invalid glTF: {e}")))?;
    let doc = &gltf::Document::from_json_without_validation(root);
    validate(path, doc)?;
    let buffers = load_buffers(path, files, doc, blob)?;
    let materials = load_materials(path, files, doc, warnings);
    let default_material = materials.len() as u32;
    let mut all_materials = materials;
    all_materials.push(Material::default());

    let input_bytes = bytes.len() + buffers.iter().map(Vec::len).sum::<usize>();
    let budget = input_bytes
        .saturating_mul(EXPANSION_PER_BYTE)
        .max(MIN_EXPANSION_BUDGET);
    let mut ctx = Ctx {
        path,
        buffers: &buffers,
        budget,
        budget_left: budget,
        input_bytes,
        cache: HashMap::new(),
        skipped_modes: 0,
        default_material,
        notes: Vec::new(),
    };

    // Roots to walk.
    let roots: Vec<gltf::Node> =
        if let Some(scene) = doc.default_scene().or_else(|| doc.scenes().next()) {
            scene.nodes().collect()
        } else {
            let children: HashSet<usize> = doc
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()))
                .collect();
            doc.nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        };
    let file_name = super::off::file_stem(path);
    let mut merged = Mesh {
        name: file_name,
        materials: all_materials.clone(),
        has_normals: true,
        has_uvs: true,
        ..Default::default()
    };
    let mut split: Vec<Mesh> = Vec::new();
    let mut visited = HashSet::new();
    let mut stack: Vec<(gltf::Node, DMat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, DMat4::IDENTITY))
        .collect();
    let mut any_mesh_node = false;
    while let Some((node, parent)) = stack.pop() {
        if !visited.insert(node.index()) {
            warnings.push(format!(
                "{}: node {} is reachable twice (cycle or shared child); visited once",
                path.display(),
                node.index()
            ));
            continue;
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix()).as_dmat4();
        let world = parent * local;
        if let Some(gmesh) = node.mesh() {
            any_mesh_node = true;
            if opts.split_nodes {
                let name = node
                    .name()
                    .map(str::to_owned)
                    .unwrap_or_else(|| format!("node{}", node.index()));
                // Each node's mesh has a copy of every material: charged like as many vertices.
                ctx.charge(all_materials.len())?;
                let mut m = Mesh {
                    name,
                    materials: all_materials.clone(),
                    has_normals: true,
                    has_uvs: true,
                    ..Default::default()
                };
                ctx.append_mesh(&gmesh, &world, &mut m)?;
                split.push(m);
            } else {
                ctx.append_mesh(&gmesh, &world, &mut merged)?;
            }
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
    }
    warnings.append(&mut ctx.notes);
    if ctx.skipped_modes > 0 {
        warnings.push(format!(
            "{}: skipped {} primitive instance(s) that are points or lines",
            path.display(),
            ctx.skipped_modes
        ));
    }
    let meshes = if opts.split_nodes {
        split
    } else {
        vec![merged]
    };
    let tris: usize = meshes.iter().map(Mesh::triangle_count).sum();
    if tris == 0 {
        let detail = if !any_mesh_node {
            "no node of the scene has a mesh".to_string()
        } else if ctx.skipped_modes > 0 {
            "only points and lines primitives".to_string()
        } else {
            "the meshes are empty".to_string()
        };
        return Err(ImportError::NoTriangles {
            path: path.to_path_buf(),
            detail,
        });
    }
    Ok(meshes)
}

/// Runs the `gltf` crate's validation (which the document accessors rely on to not panic), except
/// that a POSITION accessor's missing `min`/`max` is tolerated: exporters often omit them and we
/// compute bounds ourselves.
fn validate(path: &Path, doc: &gltf::Document) -> Result<(), ImportError> {
    use gltf::json::validation::{Error, Validate};
    let root = doc.as_json();
    // gltf-json's own check of POSITION min/max indexes `accessors` without a bounds check.
    for (mi, m) in root.meshes.iter().enumerate() {
        for (pi, p) in m.primitives.iter().enumerate() {
            let pos = p.attributes.get(&gltf::json::validation::Checked::Valid(
                gltf::Semantic::Positions,
            ));
            if let Some(a) = pos.filter(|a| a.value() >= root.accessors.len()) {
                return Err(ImportError::parse(
                    path,
                    format!(
                        "invalid glTF: meshes[{mi}].primitives[{pi}] POSITION accessor {} does not exist ({} accessors)",
                        a.value(),
                        root.accessors.len()
                    ),
                ));
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |p, e| {
        let p = p();
        let benign = matches!(e, Error::Missing)
            && (p.as_str().ends_with(".min") || p.as_str().ends_with(".max"));
        if !benign {
            errors.push(format!("{p}: {e}"));
        }
    });
    if errors.is_empty() {
        return Ok(());
    }
    let shown = errors.len().min(8);
    Err(ImportError::parse(
        path,
        format!(
            "invalid glTF: {}{}",
            errors[..shown].join("; "),
            if errors.len() > shown { "; ..." } else { "" }
        ),
    ))
}

/// Splits a GLB container into its JSON chunk and optional BIN chunk, with every length checked.
fn split_glb<'a>(
    path: &Path,
    bytes: &'a [u8],
) -> Result<(&'a [u8], Option<&'a [u8]>), ImportError> {
    let err = |m: String| ImportError::parse(path, format!("bad GLB container: {m}"));
    let u32_at = |o: usize| -> Option<u32> {
        bytes
            .get(o..o + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let version = u32_at(4).ok_or_else(|| err("truncated header".into()))?;
    if version != 2 {
        return Err(err(format!("version {version} (only 2 is supported)")));
    }
    let length = u32_at(8).ok_or_else(|| err("truncated header".into()))? as usize;
    if length > bytes.len() || length < 12 {
        return Err(err(format!(
            "header says {length} bytes, file has {}",
            bytes.len()
        )));
    }
    let data = &bytes[..length];
    let mut offset = 12usize;
    let mut json = None;
    let mut bin = None;
    while offset < data.len() {
        let (Some(len), Some(kind)) = (u32_at(offset), u32_at(offset + 4)) else {
            return Err(err(format!("truncated chunk header at byte {offset}")));
        };
        let start = offset + 8;
        let end = start
            .checked_add(len as usize)
            .filter(|&e| e <= data.len())
            .ok_or_else(|| {
                err(format!(
                    "chunk at byte {offset} claims {len} bytes, past the end"
                ))
            })?;
        let chunk = &data[start..end];
        match kind {
            0x4E4F_534A if json.is_none() => json = Some(chunk),
            0x004E_4942 if bin.is_none() => bin = Some(chunk),
            _ => {} // Unknown chunks are skipped (spec).
        }
        // Chunks are 4-byte aligned.
        offset = end.checked_add(3).map(|e| e & !3).unwrap_or(usize::MAX);
    }
    let json = json.ok_or_else(|| err("no JSON chunk".into()))?;
    Ok((json, bin))
}

/// Rejects Draco-compressed files up front with a clear message.
fn check_draco(path: &Path, json: &[u8]) -> Result<(), ImportError> {
    const DRACO: &str = "KHR_draco_mesh_compression";
    let Ok(value) = serde_json::from_slice::<serde_json::Value>(json) else {
        return Ok(()); // The validating parse reports the syntax error.
    };
    let required = value
        .get("extensionsRequired")
        .and_then(|v| v.as_array())
        .is_some_and(|a| a.iter().any(|e| e.as_str() == Some(DRACO)));
    let on_primitive = value
        .get("meshes")
        .and_then(|m| m.as_array())
        .is_some_and(|meshes| {
            meshes.iter().any(|m| {
                m.get("primitives")
                    .and_then(|p| p.as_array())
                    .is_some_and(|prims| {
                        prims
                            .iter()
                            .any(|p| p.get("extensions").and_then(|e| e.get(DRACO)).is_some())
                    })
            })
        });
    if required || on_primitive {
        return Err(ImportError::Draco {
            path: path.to_path_buf(),
        });
    }
    Ok(())
}

/// Decodes `%XX` escapes of a relative URI.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            let hex = std::str::from_utf8(&b[i + 1..i + 3])
                .ok()
                .and_then(|h| u8::from_str_radix(h, 16).ok());
            if let Some(v) = hex {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Standard base64 (padding optional, whitespace ignored); `None` on an invalid character.
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

fn load_buffers(
    path: &Path,
    files: Siblings,
    doc: &gltf::Document,
    blob: Option<&[u8]>,
) -> Result<Vec<Vec<u8>>, ImportError> {
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let index = buffer.index();
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .ok_or_else(|| {
                    ImportError::parse(
                        path,
                        format!("buffer {index} refers to the GLB BIN chunk, which is missing"),
                    )
                })?
                .to_vec(),
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let Some((header, payload)) = uri.split_once(',') else {
                    return Err(ImportError::parse(
                        path,
                        format!("buffer {index}: malformed data URI"),
                    ));
                };
                if !header.ends_with(";base64") {
                    return Err(ImportError::parse(
                        path,
                        format!("buffer {index}: data URI is not base64"),
                    ));
                }
                base64_decode(payload).ok_or_else(|| {
                    ImportError::parse(path, format!("buffer {index}: invalid base64 in data URI"))
                })?
            }
            gltf::buffer::Source::Uri(uri) => {
                let file = files.resolve(percent_decode(uri));
                match files.read(&file) {
                    Ok(d) => d,
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                        return Err(ImportError::MissingBuffer {
                            path: path.to_path_buf(),
                            index,
                            buffer: file,
                        });
                    }
                    Err(e) => return Err(ImportError::io(path, &file, e)),
                }
            }
        };
        if data.len() < buffer.length() {
            return Err(ImportError::parse(
                path,
                format!(
                    "buffer {index} has {} bytes but byteLength is {}",
                    data.len(),
                    buffer.length()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// A texture's file, if it is an existing file next to the document; otherwise a warning.
///
/// The image's JSON is read directly: `gltf::Image::source` unwraps a missing `uri` (an image with
/// neither `uri` nor `bufferView`) and a missing `mimeType` of a `bufferView` image, neither of
/// which the crate's validation reports.
fn texture_file(
    path: &Path,
    files: Siblings,
    doc: &gltf::Document,
    texture: gltf::Texture,
    what: &str,
    material: &str,
    warnings: &mut Vec<String>,
) -> Option<PathBuf> {
    let index = texture.source().index();
    let image = doc.as_json().images.get(index);
    match image.map(|i| (i.uri.as_deref(), i.buffer_view.is_some())) {
        Some((Some(uri), false)) if !uri.starts_with("data:") => {
            let file = files.resolve(percent_decode(uri));
            if files.is_file(&file) {
                Some(file)
            } else {
                warnings.push(format!(
                    "{}: material '{material}' {what} texture {} not found; ignored",
                    path.display(),
                    file.display()
                ));
                None
            }
        }
        Some((None, false)) | None => {
            warnings.push(format!(
                "{}: material '{material}' {what} texture: image {index} has neither a uri nor a \
                 bufferView; ignored",
                path.display()
            ));
            None
        }
        Some(_) => {
            warnings.push(format!(
                "{}: material '{material}' {what} texture is embedded (not a file); ignored",
                path.display()
            ));
            None
        }
    }
}

fn load_materials(
    path: &Path,
    files: Siblings,
    doc: &gltf::Document,
    warnings: &mut Vec<String>,
) -> Vec<Material> {
    doc.materials()
        .map(|m| {
            let name = m
                .name()
                .map(str::to_owned)
                .unwrap_or_else(|| format!("material{}", m.index().unwrap_or(0)));
            let pbr = m.pbr_metallic_roughness();
            let base_color_texture = pbr.base_color_texture().and_then(|t| {
                texture_file(
                    path,
                    files,
                    doc,
                    t.texture(),
                    "base-colour",
                    &name,
                    warnings,
                )
            });
            let normal_texture = m.normal_texture().and_then(|t| {
                texture_file(path, files, doc, t.texture(), "normal", &name, warnings)
            });
            let metallic_roughness_texture = pbr.metallic_roughness_texture().and_then(|t| {
                texture_file(
                    path,
                    files,
                    doc,
                    t.texture(),
                    "metallic-roughness",
                    &name,
                    warnings,
                )
            });
            Material {
                name,
                base_color: pbr.base_color_factor(),
                metallic: pbr.metallic_factor(),
                roughness: pbr.roughness_factor(),
                base_color_texture,
                normal_texture,
                metallic_roughness_texture,
            }
        })
        .collect()
}

/// One primitive's data, read once and shared by every node instancing it.
struct Prim {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    uvs: Option<Vec<[f32; 2]>>,
    /// Triangles (after strip/fan conversion), indices into `positions`.
    triangles: Vec<[u32; 3]>,
    material: u32,
}

struct Ctx<'a> {
    path: &'a Path,
    buffers: &'a [Vec<u8>],
    /// Vertices plus triangle corners the scene may expand to (see [`EXPANSION_PER_BYTE`]), and
    /// what is left of them, and the input size it was computed from.
    budget: usize,
    budget_left: usize,
    input_bytes: usize,
    /// Keyed by (mesh index, primitive index); `None` for skipped (points/lines) primitives.
    cache: HashMap<(usize, usize), Option<std::rc::Rc<Prim>>>,
    skipped_modes: usize,
    default_material: u32,
    /// Warnings from reading primitives (once per primitive, however many nodes instance it).
    notes: Vec<String>,
}

impl Ctx<'_> {
    /// Takes `cost` vertices and triangle corners (or materials copied) from the budget.
    fn charge(&mut self, cost: usize) -> Result<(), ImportError> {
        self.budget_left = self.budget_left.checked_sub(cost).ok_or_else(|| {
            ImportError::parse(
                self.path,
                format!(
                    "the scene expands (nodes instancing meshes, primitives sharing accessors) \
                     to more than {} vertices and triangle corners, the limit for {} bytes of \
                     input; refused as a likely hostile file",
                    self.budget, self.input_bytes
                ),
            )
        })?;
        Ok(())
    }

    fn append_mesh(
        &mut self,
        gmesh: &gltf::Mesh,
        world: &DMat4,
        out: &mut Mesh,
    ) -> Result<(), ImportError> {
        let m3 = DMat3::from_mat4(*world);
        let det = m3.determinant();
        let normal_matrix = if det.abs() > 1e-300 {
            m3.inverse().transpose()
        } else {
            DMat3::ZERO
        };
        let flip = det < 0.0;
        for prim in gmesh.primitives() {
            let key = (gmesh.index(), prim.index());
            let data = match self.cache.get(&key) {
                Some(d) => d.clone(),
                None => {
                    let d = self.read_primitive(gmesh, &prim)?.map(std::rc::Rc::new);
                    self.cache.insert(key, d.clone());
                    d
                }
            };
            let Some(data) = data else {
                self.skipped_modes += 1;
                continue;
            };
            self.charge(data.positions.len() + 3 * data.triangles.len())?;
            let base = out.positions.len() as u32;
            for p in &data.positions {
                let w = world.transform_point3(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
                out.positions.push([w.x as f32, w.y as f32, w.z as f32]);
            }
            match &data.normals {
                Some(ns) => {
                    for n in ns {
                        let w = normal_matrix * DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
                        let w = w.normalize_or_zero();
                        out.normals.push([w.x as f32, w.y as f32, w.z as f32]);
                    }
                }
                None => {
                    out.has_normals = false;
                    out.normals
                        .extend(std::iter::repeat_n([0.0; 3], data.positions.len()));
                }
            }
            match &data.uvs {
                Some(ts) => out.uvs.extend_from_slice(ts),
                None => {
                    out.has_uvs = false;
                    out.uvs
                        .extend(std::iter::repeat_n([0.0; 2], data.positions.len()));
                }
            }
            for t in &data.triangles {
                let t = if flip { [t[0], t[2], t[1]] } else { *t };
                out.indices.extend(t.iter().map(|i| i + base));
            }
            out.material_ids
                .extend(std::iter::repeat_n(data.material, data.triangles.len()));
        }
        Ok(())
    }

    fn read_primitive(
        &mut self,
        gmesh: &gltf::Mesh,
        prim: &gltf::Primitive,
    ) -> Result<Option<Prim>, ImportError> {
        let mesh_name = gmesh
            .name()
            .map(str::to_owned)
            .unwrap_or_else(|| format!("#{}", gmesh.index()));
        let what = format!("mesh '{mesh_name}' primitive {}", prim.index());
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return Ok(None);
        }
        let pos_acc = prim.get(&gltf::Semantic::Positions).ok_or_else(|| {
            ImportError::parse(self.path, format!("{what}: no POSITION attribute"))
        })?;
        let pos_ctx = format!("{what}, POSITION accessor {}", pos_acc.index());
        let flat = self.read_accessor(&pos_acc, 3, &pos_ctx)?;
        let positions: Vec<[f32; 3]> = flat
            .chunks_exact(3)
            .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
            .collect();
        if let Some(v) = positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(ImportError::NonFinite {
                path: self.path.to_path_buf(),
                vertex: v,
                context: format!(" ({pos_ctx})"),
                position: positions[v],
            });
        }
        let nv = positions.len();
        let normals = match prim.get(&gltf::Semantic::Normals) {
            Some(acc) => {
                let ctx = format!("{what}, NORMAL accessor {}", acc.index());
                let flat = self.read_accessor(&acc, 3, &ctx)?;
                if flat.len() != 3 * nv {
                    return Err(ImportError::parse(
                        self.path,
                        format!("{ctx}: {} normals for {nv} positions", flat.len() / 3),
                    ));
                }
                // Non-finite normals become zero, i.e. recomputed later.
                Some(
                    flat.chunks_exact(3)
                        .map(|c| {
                            let n = [c[0] as f32, c[1] as f32, c[2] as f32];
                            if n.iter().all(|x| x.is_finite()) {
                                n
                            } else {
                                [0.0; 3]
                            }
                        })
                        .collect(),
                )
            }
            None => None,
        };
        let uvs = match prim.get(&gltf::Semantic::TexCoords(0)) {
            Some(acc) => {
                let ctx = format!("{what}, TEXCOORD_0 accessor {}", acc.index());
                let flat = self.read_accessor(&acc, 2, &ctx)?;
                if flat.len() != 2 * nv {
                    return Err(ImportError::parse(
                        self.path,
                        format!("{ctx}: {} uvs for {nv} positions", flat.len() / 2),
                    ));
                }
                Some(
                    flat.chunks_exact(2)
                        .map(|c| {
                            let t = [c[0] as f32, c[1] as f32];
                            if t.iter().all(|x| x.is_finite()) {
                                t
                            } else {
                                [0.0; 2]
                            }
                        })
                        .collect(),
                )
            }
            None => None,
        };
        let indices: Vec<u32> = match prim.indices() {
            Some(acc) => {
                let ctx = format!("{what}, index accessor {}", acc.index());
                let flat = self.read_accessor(&acc, 1, &ctx)?;
                let mut out = Vec::with_capacity(flat.len());
                for (k, &i) in flat.iter().enumerate() {
                    if !(i >= 0.0 && i < nv as f64) {
                        return Err(ImportError::IndexOutOfRange {
                            path: self.path.to_path_buf(),
                            context: format!("{ctx}, element {k}"),
                            index: i as i64,
                            vertex_count: nv,
                        });
                    }
                    out.push(i as u32);
                }
                out
            }
            None => (0..nv as u32).collect(),
        };
        let n = indices.len();
        // Corners that make no triangle: a TRIANGLES list's remainder past a multiple of 3, a
        // strip or fan too short for one triangle.
        let unused = match mode {
            Mode::Triangles => n % 3,
            _ if n < 3 => n,
            _ => 0,
        };
        if unused > 0 {
            let (what_count, unit) = if prim.indices().is_some() {
                ("index count", "indices")
            } else {
                ("vertex count (non-indexed)", "vertices")
            };
            let kind = match mode {
                Mode::Triangles => "TRIANGLES",
                Mode::TriangleStrip => "TRIANGLE_STRIP",
                _ => "TRIANGLE_FAN",
            };
            let why = if mode == Mode::Triangles {
                "is not a multiple of 3"
            } else {
                "is less than 3"
            };
            self.notes.push(format!(
                "{}: {what} ({kind}): {what_count} {n} {why}; the last {unused} {unit} dropped",
                self.path.display()
            ));
        }
        let mut triangles = Vec::new();
        match mode {
            Mode::Triangles => {
                triangles.extend(indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
            }
            Mode::TriangleStrip => {
                for i in 0..n.saturating_sub(2) {
                    let (a, b, c) = (indices[i], indices[i + 1], indices[i + 2]);
                    triangles.push(if i % 2 == 0 { [a, b, c] } else { [a, c, b] });
                }
            }
            _ => {
                for i in 0..n.saturating_sub(2) {
                    triangles.push([indices[i + 1], indices[i + 2], indices[0]]);
                }
            }
        }
        let material = prim
            .material()
            .index()
            .map(|i| i as u32)
            .unwrap_or(self.default_material);
        Ok(Some(Prim {
            positions,
            normals,
            uvs,
            triangles,
            material,
        }))
    }

    /// Reads an accessor as `count * comps` f64 values (exact for every glTF component type),
    /// applying `normalized`, strides and sparse substitution, with every range checked.
    fn read_accessor(
        &self,
        acc: &gltf::Accessor,
        comps: usize,
        ctx: &str,
    ) -> Result<Vec<f64>, ImportError> {
        use gltf::accessor::{DataType, Dimensions};
        let err = |m: String| ImportError::parse(self.path, format!("{ctx}: {m}"));
        let dims = acc.dimensions();
        let have = match dims {
            Dimensions::Scalar => 1,
            Dimensions::Vec2 => 2,
            Dimensions::Vec3 => 3,
            Dimensions::Vec4 => 4,
            _ => {
                return Err(err(format!(
                    "matrix type {dims:?} where {comps} components were expected"
                )));
            }
        };
        if have != comps {
            return Err(err(format!(
                "{have} components per element, expected {comps}"
            )));
        }
        let dt = acc.data_type();
        let csize = dt.size();
        let elem = csize * comps;
        let count = acc.count();
        let read = |bytes: &[u8], o: usize| -> Option<f64> {
            let b = bytes.get(o..o.checked_add(csize)?)?;
            Some(match dt {
                DataType::I8 => b[0] as i8 as f64,
                DataType::U8 => b[0] as f64,
                DataType::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
                DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
                DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            })
        };
        // Byte slice of a buffer view, bounds-checked.
        let view_bytes = |view: &gltf::buffer::View| -> Result<&[u8], ImportError> {
            let buf = self
                .buffers
                .get(view.buffer().index())
                .ok_or_else(|| err(format!("buffer {} not loaded", view.buffer().index())))?;
            let start = view.offset();
            start
                .checked_add(view.length())
                .and_then(|end| buf.get(start..end))
                .ok_or_else(|| {
                    err(format!(
                        "buffer view {} (bytes {}..+{}) is outside buffer {} ({} bytes)",
                        view.index(),
                        start,
                        view.length(),
                        view.buffer().index(),
                        buf.len()
                    ))
                })
        };
        let total = count
            .checked_mul(comps)
            .ok_or_else(|| err(format!("count {count} too large")))?;
        let mut out = match acc.view() {
            Some(view) => {
                let bytes = view_bytes(&view)?;
                let stride = view.stride().unwrap_or(elem);
                if stride < elem {
                    return Err(err(format!(
                        "byteStride {stride} is smaller than the element size {elem}"
                    )));
                }
                let needed = if count == 0 {
                    Some(0)
                } else {
                    stride
                        .checked_mul(count - 1)
                        .and_then(|x| x.checked_add(elem))
                        .and_then(|x| x.checked_add(acc.offset()))
                };
                match needed {
                    Some(n) if n <= bytes.len() => {}
                    _ => {
                        return Err(err(format!(
                            "{count} elements (stride {stride}, offset {}) do not fit in buffer view {} ({} bytes)",
                            acc.offset(),
                            view.index(),
                            bytes.len()
                        )));
                    }
                }
                let mut out = Vec::with_capacity(total);
                for i in 0..count {
                    let base = acc.offset() + i * stride;
                    for c in 0..comps {
                        out.push(
                            read(bytes, base + c * csize)
                                .ok_or_else(|| err(format!("element {i} out of bounds")))?,
                        );
                    }
                }
                out
            }
            None => {
                if count > MAX_VIEWLESS_ELEMENTS {
                    return Err(err(format!("{count} elements without a buffer view")));
                }
                vec![0.0; total]
            }
        };
        if let Some(sparse) = acc.sparse() {
            let scount = sparse.count();
            let idx = sparse.indices();
            let ibytes = view_bytes(&idx.view())?;
            let isize = match idx.index_type() {
                gltf::accessor::sparse::IndexType::U8 => 1,
                gltf::accessor::sparse::IndexType::U16 => 2,
                gltf::accessor::sparse::IndexType::U32 => 4,
            };
            let vals = sparse.values();
            let vbytes = view_bytes(&vals.view())?;
            for s in 0..scount {
                let io = s
                    .checked_mul(isize)
                    .and_then(|x| x.checked_add(idx.offset()));
                let target = io
                    .and_then(|o| ibytes.get(o..o.checked_add(isize)?))
                    .map(|b| match isize {
                        1 => b[0] as usize,
                        2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
                    });
                let Some(target) = target.filter(|&t| t < count) else {
                    return Err(err(format!(
                        "sparse index {s} is missing or out of range ({count} elements)"
                    )));
                };
                for c in 0..comps {
                    let o = s
                        .checked_mul(elem)
                        .and_then(|x| x.checked_add(vals.offset()))
                        .and_then(|x| x.checked_add(c * csize));
                    let v = o
                        .and_then(|o| read(vbytes, o))
                        .ok_or_else(|| err(format!("sparse value {s} out of bounds")))?;
                    out[target * comps + c] = v;
                }
            }
        }
        if acc.normalized() {
            let scale = |v: f64| match dt {
                DataType::I8 => (v / 127.0).max(-1.0),
                DataType::U8 => v / 255.0,
                DataType::I16 => (v / 32767.0).max(-1.0),
                DataType::U16 => v / 65535.0,
                DataType::U32 => v / 4_294_967_295.0,
                DataType::F32 => v,
            };
            out.iter_mut().for_each(|v| *v = scale(*v));
        }
        Ok(out)
    }
}
