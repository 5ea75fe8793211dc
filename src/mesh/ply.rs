//! PLY importer (ASCII and binary, via `ply-rs`). Reads element `vertex` (`x y z`, optional
//! `nx ny nz`, optional `u v` / `s t` / `texture_u texture_v`, any scalar type) and element `face`
//! (`vertex_indices` or `vertex_index`, a list of any integer type). Other elements and properties
//! are read past and ignored. Faces with more than three corners are triangulated with
//! [`super::polygon::triangulate`].
//!
//! Binary files of the usual layouts take a fast path ([`fast`]) that reads the bytes directly and
//! gives exactly the mesh and warnings of the ply-rs path below; it leaves every other file, and
//! every error, to that path.

mod fast;

use std::path::Path;

use ply_rs::parser::Parser;
use ply_rs::ply::{ElementDef, Encoding, Property, PropertyAccess, PropertyType};

use super::off::file_stem;
use super::{ImportError, Material, Mesh, polygon};

/// One `vertex` element: only the properties we use.
#[derive(Default)]
struct Vertex {
    p: [f64; 3],
    n: [f64; 3],
    uv: [f64; 2],
}

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => v as f64,
        Property::UChar(v) => v as f64,
        Property::Short(v) => v as f64,
        Property::UShort(v) => v as f64,
        Property::Int(v) => v as f64,
        Property::UInt(v) => v as f64,
        Property::Float(v) => v as f64,
        Property::Double(v) => v,
        _ => return None,
    })
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: String, property: Property) {
        let Some(v) = scalar(&property) else { return };
        match name.as_str() {
            "x" => self.p[0] = v,
            "y" => self.p[1] = v,
            "z" => self.p[2] = v,
            "nx" => self.n[0] = v,
            "ny" => self.n[1] = v,
            "nz" => self.n[2] = v,
            "u" | "s" | "texture_u" | "texture_s" => self.uv[0] = v,
            "v" | "t" | "texture_v" | "texture_t" => self.uv[1] = v,
            _ => {}
        }
    }
}

/// One `face` element: its vertex index list (negative values kept to report them).
#[derive(Default)]
struct Face {
    corners: Vec<i64>,
    /// The index list had a non-integer type.
    bad_type: bool,
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Self::default()
    }
    fn set_property(&mut self, name: String, property: Property) {
        if name != "vertex_indices" && name != "vertex_index" {
            return;
        }
        self.corners = match property {
            Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
            Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
            Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
            Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
            _ => {
                self.bad_type = true;
                Vec::new()
            }
        };
    }
}

/// Any other element: read and discarded.
struct Ignore;

impl PropertyAccess for Ignore {
    fn new() -> Self {
        Ignore
    }
}

/// Where element payloads come from: ply-rs for binary files; for ASCII our own tokenizer, because
/// ply-rs's grammar rejects valid numbers such as `.5`, `nan` and `inf` (the latter must become a
/// clear non-finite error, not a syntax error) and reports lines relative to the element.
enum Payload<'a, 'b> {
    Binary(&'a mut &'b [u8]),
    Ascii(AsciiTokens),
}

/// Whitespace-separated tokens of an ASCII PLY body, read on demand, with 1-based line numbers.
struct AsciiTokens {
    body: String,
    pos: usize,
    line: usize,
    last_line: usize,
}

impl AsciiTokens {
    fn new(body: String, first_line: usize) -> Self {
        Self {
            body,
            pos: 0,
            line: first_line,
            last_line: first_line,
        }
    }

    /// The next token and its line.
    fn next_token(&mut self) -> Option<(usize, &str)> {
        let bytes = self.body.as_bytes();
        while let Some(&b) = bytes.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        // Token boundaries are ASCII whitespace, hence char boundaries.
        let token = self.body.get(start..self.pos).filter(|t| !t.is_empty())?;
        Some((self.line, token))
    }

    fn number(&mut self, what: &dyn Fn() -> String) -> Result<f64, String> {
        match self.next_token() {
            Some((line, t)) => {
                // The token is shown (cut to 32 characters) only when it is not a number.
                let parsed = t.parse::<f64>().map_err(|_| {
                    let shown: String = t.chars().take(32).collect();
                    format!("line {line}: {}: '{shown}' is not a number", what())
                });
                self.last_line = line;
                parsed
            }
            None => Err(format!(
                "file ends at line {} while reading {}",
                self.last_line,
                what()
            )),
        }
    }

    /// Reads `count` elements of `def`, giving each property to `set` as a scalar or list.
    fn element(
        &mut self,
        def: &ElementDef,
        mut set: impl FnMut(usize, &str, Value) -> Result<(), String>,
    ) -> Result<(), String> {
        for i in 0..def.count {
            for (name, prop) in &def.properties {
                let what = || format!("element '{}' {i}, property '{name}'", def.name);
                match prop.data_type {
                    PropertyType::Scalar(_) => set(i, name, Value::Scalar(self.number(&what)?))?,
                    PropertyType::List(..) => {
                        let n = self.number(&what)?;
                        if !(n >= 0.0 && n.fract() == 0.0 && n < 1e9) {
                            return Err(format!(
                                "line {}: {}: bad list length {n}",
                                self.last_line,
                                what()
                            ));
                        }
                        let mut list = Vec::with_capacity((n as usize).min(64));
                        for _ in 0..n as usize {
                            list.push(self.number(&what)?);
                        }
                        set(i, name, Value::List(list))?;
                    }
                }
            }
        }
        Ok(())
    }
}

/// A property value read from an ASCII body.
enum Value {
    Scalar(f64),
    List(Vec<f64>),
}

/// ply-rs's header grammar panics (`unwrap`) on a number that does not fit in u64; refuse such
/// headers first. Comment and obj_info lines are free text and not checked.
fn check_header_numbers(path: &Path, bytes: &[u8]) -> Result<(), ImportError> {
    let head = &bytes[..bytes.len().min(1 << 20)];
    for (i, line) in head.split(|&b| b == b'\n').enumerate() {
        let line = String::from_utf8_lossy(line);
        let first = line.split_whitespace().next().unwrap_or("");
        if first == "end_header" {
            break;
        }
        if first == "comment" || first == "obj_info" {
            continue;
        }
        for run in line
            .split(|c: char| !c.is_ascii_digit())
            .filter(|r| !r.is_empty())
        {
            if run.parse::<u64>().is_err() {
                return Err(ImportError::parse(
                    path,
                    format!("header line {}: number {run} is too large", i + 1),
                ));
            }
        }
    }
    Ok(())
}

/// Reads a PLY file into an unprocessed [`Mesh`] (see [`super::load`] for the processing).
pub(super) fn load(
    path: &Path,
    bytes: &[u8],
    warnings: &mut Vec<String>,
) -> Result<Mesh, ImportError> {
    check_header_numbers(path, bytes)?;
    if let Some((mesh, w)) = fast::load(path, bytes) {
        warnings.extend(w);
        return Ok(mesh);
    }
    load_ply_rs(path, bytes, warnings)
}

/// Checks the fast path against the ply-rs path on `bytes` (a file named `name`): `Ok(true)` if the
/// fast path took the file and the ply-rs path read the same mesh and warnings, `Ok(false)` if the
/// fast path declined it, `Err` naming the first difference otherwise. (The differential fuzz
/// check, see [`super::ply_fast_path_check`].)
pub(super) fn fast_path_check(name: &str, bytes: &[u8]) -> Result<bool, String> {
    let path = Path::new(name);
    if check_header_numbers(path, bytes).is_err() {
        return Ok(false);
    }
    let Some((fast, fast_warnings)) = fast::load(path, bytes) else {
        return Ok(false);
    };
    let mut warnings = Vec::new();
    let slow = load_ply_rs(path, bytes, &mut warnings)
        .map_err(|e| format!("the fast path read a file that the ply-rs path refuses: {e}"))?;
    if fast_warnings != warnings {
        return Err(format!(
            "warnings differ: fast path {fast_warnings:?}, ply-rs path {warnings:?}"
        ));
    }
    same_mesh(&fast, &slow).map(|()| true)
}

/// `Err` naming the first difference between meshes `a` (fast path) and `b` (ply-rs path); floats
/// compare bit for bit.
fn same_mesh(a: &Mesh, b: &Mesh) -> Result<(), String> {
    fn bits<const N: usize>(v: &[[f32; N]]) -> Vec<[u32; N]> {
        v.iter().map(|x| x.map(f32::to_bits)).collect()
    }
    fn first_diff<T: PartialEq + std::fmt::Debug>(
        what: &str,
        a: &[T],
        b: &[T],
    ) -> Result<(), String> {
        if a.len() != b.len() {
            return Err(format!("{what}: {} against {}", a.len(), b.len()));
        }
        match a.iter().zip(b).position(|(x, y)| x != y) {
            Some(i) => Err(format!("{what} {i}: {:?} against {:?}", a[i], b[i])),
            None => Ok(()),
        }
    }
    if (&a.name, a.has_normals, a.has_uvs) != (&b.name, b.has_normals, b.has_uvs) {
        return Err(format!(
            "name, has_normals, has_uvs: {:?} against {:?}",
            (&a.name, a.has_normals, a.has_uvs),
            (&b.name, b.has_normals, b.has_uvs)
        ));
    }
    first_diff("position", &bits(&a.positions), &bits(&b.positions))?;
    first_diff("normal", &bits(&a.normals), &bits(&b.normals))?;
    first_diff("uv", &bits(&a.uvs), &bits(&b.uvs))?;
    first_diff("index", &a.indices, &b.indices)?;
    first_diff("material id", &a.material_ids, &b.material_ids)?;
    first_diff("material", &a.materials, &b.materials)
}

/// The ply-rs path: every PLY file the fast path does not take ([`check_header_numbers`] first).
fn load_ply_rs(path: &Path, bytes: &[u8], warnings: &mut Vec<String>) -> Result<Mesh, ImportError> {
    let mut reader = bytes;
    let perr = |what: &str, e: std::io::Error| ImportError::parse(path, format!("{what}: {e}"));
    let header = Parser::<Ignore>::new()
        .read_header(&mut reader)
        .map_err(|e| perr("bad PLY header", e))?;
    let has =
        |def: &ElementDef, names: &[&str]| names.iter().any(|n| def.properties.contains_key(*n));
    let mut payload = if header.encoding == Encoding::Ascii {
        let rest = reader;
        let header_lines = 3
            + header.comments.len()
            + header.obj_infos.len()
            + header
                .elements
                .values()
                .map(|e| 1 + e.properties.len())
                .sum::<usize>();
        Payload::Ascii(AsciiTokens::new(
            String::from_utf8_lossy(rest).into_owned(),
            header_lines + 1,
        ))
    } else {
        Payload::Binary(&mut reader)
    };
    let mut mesh = Mesh {
        name: file_stem(path),
        materials: vec![Material::default()],
        ..Default::default()
    };
    let mut faces: Option<Vec<Face>> = None;
    let mut vertex_seen = false;
    for (name, def) in &header.elements {
        match name.as_str() {
            "vertex" => {
                for axis in ["x", "y", "z"] {
                    if !def.properties.contains_key(axis) {
                        return Err(ImportError::parse(
                            path,
                            format!("element 'vertex' has no property '{axis}'"),
                        ));
                    }
                }
                let verts = match &mut payload {
                    Payload::Binary(r) => Parser::<Vertex>::new()
                        .read_payload_for_element(r, def, &header)
                        .map_err(|e| perr("reading element 'vertex'", e))?,
                    Payload::Ascii(t) => {
                        let mut verts: Vec<Vertex> = Vec::new();
                        t.element(def, |i, name, value| {
                            if verts.len() <= i {
                                verts.push(Vertex::default());
                            }
                            if let (Value::Scalar(v), Some(vert)) = (value, verts.last_mut()) {
                                vert.set_property(name.to_string(), Property::Double(v));
                            }
                            Ok(())
                        })
                        .map_err(|m| ImportError::parse(path, m))?;
                        verts
                    }
                };
                mesh.has_normals = has(def, &["nx"]) && has(def, &["ny"]) && has(def, &["nz"]);
                mesh.has_uvs = has(def, &["u", "s", "texture_u", "texture_s"])
                    && has(def, &["v", "t", "texture_v", "texture_t"]);
                for (i, v) in verts.iter().enumerate() {
                    let p = [v.p[0] as f32, v.p[1] as f32, v.p[2] as f32];
                    if !p.iter().all(|c| c.is_finite()) {
                        return Err(ImportError::NonFinite {
                            path: path.to_path_buf(),
                            vertex: i,
                            context: String::new(),
                            position: p,
                        });
                    }
                    mesh.positions.push(p);
                    mesh.normals
                        .push([v.n[0] as f32, v.n[1] as f32, v.n[2] as f32]);
                    // PLY texture coordinates have their origin bottom-left; ours top-left.
                    mesh.uvs.push([v.uv[0] as f32, 1.0 - v.uv[1] as f32]);
                }
                if !mesh.has_uvs {
                    mesh.uvs.iter_mut().for_each(|t| *t = [0.0; 2]);
                }
                vertex_seen = true;
            }
            "face" => {
                if !has(def, &["vertex_indices", "vertex_index"]) {
                    return Err(ImportError::parse(
                        path,
                        "element 'face' has no 'vertex_indices' or 'vertex_index' list",
                    ));
                }
                let f = match &mut payload {
                    Payload::Binary(r) => Parser::<Face>::new()
                        .read_payload_for_element(r, def, &header)
                        .map_err(|e| perr("reading element 'face'", e))?,
                    Payload::Ascii(t) => {
                        let mut faces: Vec<Face> = Vec::new();
                        t.element(def, |i, name, value| {
                            if faces.len() <= i {
                                faces.push(Face::default());
                            }
                            if name != "vertex_indices" && name != "vertex_index" {
                                return Ok(());
                            }
                            let (Value::List(list), Some(face)) = (value, faces.last_mut()) else {
                                return Err(format!("face {i}: '{name}' is not a list"));
                            };
                            if list.iter().any(|x| x.fract() != 0.0) {
                                return Err(format!("face {i}: vertex indices must be integers"));
                            }
                            face.corners = list.into_iter().map(|x| x as i64).collect();
                            Ok(())
                        })
                        .map_err(|m| ImportError::parse(path, m))?;
                        faces
                    }
                };
                faces = Some(f);
            }
            other => {
                match &mut payload {
                    Payload::Binary(r) => {
                        Parser::<Ignore>::new()
                            .read_payload_for_element(r, def, &header)
                            .map_err(|e| perr(&format!("reading element '{other}'"), e))?;
                    }
                    Payload::Ascii(t) => t
                        .element(def, |_, _, _| Ok(()))
                        .map_err(|m| ImportError::parse(path, m))?,
                }
                warnings.push(format!("{}: PLY element '{other}' ignored", path.display()));
            }
        }
    }
    if !vertex_seen {
        return Err(ImportError::parse(path, "no 'vertex' element"));
    }
    // Data past the declared elements (a header that undercounts them, say) is not read.
    let trailing = match &mut payload {
        Payload::Binary(r) => (!r.is_empty()).then(|| format!("{} bytes", r.len())),
        Payload::Ascii(t) => t
            .next_token()
            .map(|(line, _)| format!("data (from line {line})")),
    };
    if let Some(what) = trailing {
        warnings.push(format!(
            "{}: {what} after the declared elements ignored",
            path.display()
        ));
    }
    let Some(faces) = faces else {
        return Err(ImportError::NoTriangles {
            path: path.to_path_buf(),
            detail: "no 'face' element (point cloud?)".into(),
        });
    };
    let nv = mesh.positions.len();
    let mut tris = Vec::with_capacity(faces.len());
    let mut corners = Vec::new();
    let mut skipped = 0usize;
    let mut fanned = 0usize;
    for (fi, face) in faces.iter().enumerate() {
        if face.bad_type {
            return Err(ImportError::parse(
                path,
                format!("face {fi}: vertex index list is not of an integer type"),
            ));
        }
        corners.clear();
        for (k, &i) in face.corners.iter().enumerate() {
            if i < 0 || i as u64 >= nv as u64 {
                return Err(ImportError::IndexOutOfRange {
                    path: path.to_path_buf(),
                    context: format!("face {fi}, corner {k}"),
                    index: i,
                    vertex_count: nv,
                });
            }
            corners.push(i as u32);
        }
        if corners.len() < 3 {
            skipped += 1;
            continue;
        }
        if !polygon::triangulate(&mesh.positions, &corners, &mut tris) {
            fanned += 1;
        }
    }
    polygon::warn_fanned(fanned, path, warnings);
    polygon::set_triangles(&mut mesh, tris, skipped, path, warnings);
    if !mesh.has_normals {
        mesh.normals.iter_mut().for_each(|n| *n = [0.0; 3]);
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests;
