//! A small PLY (ascii / binary little- and big-endian) and OBJ reader: positions and triangles
//! (polygons fan-triangulated), enough for vgeo's scanned meshes.

use std::path::Path;

pub struct TriMesh {
    pub positions: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

impl TriMesh {
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &self.positions {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        (lo, hi)
    }

    /// Area-weighted vertex normals.
    pub fn normals(&self) -> Vec<[f32; 3]> {
        let mut n = vec![[0f64; 3]; self.positions.len()];
        for t in self.indices.chunks_exact(3) {
            let p = |i: u32| self.positions[i as usize].map(|c| c as f64);
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let f = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            for &i in t {
                for a in 0..3 {
                    n[i as usize][a] += f[a];
                }
            }
        }
        n.into_iter()
            .map(|v| {
                let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                if l > 0.0 {
                    [(v[0] / l) as f32, (v[1] / l) as f32, (v[2] / l) as f32]
                } else {
                    [0.0, 1.0, 0.0]
                }
            })
            .collect()
    }
}

pub fn load(path: &Path) -> Result<TriMesh, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let mesh = match ext.as_str() {
        "ply" => load_ply(&bytes),
        "obj" => load_obj(&bytes),
        _ => Err(format!("unknown mesh format '{ext}' (ply or obj)")),
    }
    .map_err(|e| format!("{}: {e}", path.display()))?;
    if mesh.indices.is_empty() {
        return Err(format!("{}: no triangles", path.display()));
    }
    let nv = mesh.positions.len() as u32;
    if mesh.indices.iter().any(|&i| i >= nv) {
        return Err(format!("{}: face index out of range", path.display()));
    }
    Ok(mesh)
}

fn load_obj(bytes: &[u8]) -> Result<TriMesh, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "OBJ is not UTF-8".to_string())?;
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let v: Vec<f32> = it.take(3).filter_map(|s| s.parse().ok()).collect();
                if v.len() != 3 {
                    return Err(format!("bad vertex line: {line}"));
                }
                positions.push([v[0], v[1], v[2]]);
            }
            Some("f") => {
                let n = positions.len() as i64;
                let poly: Vec<u32> = it
                    .map(|s| {
                        let i: i64 = s.split('/').next().unwrap_or("").parse().unwrap_or(0);
                        (if i < 0 { n + i } else { i - 1 }) as u32
                    })
                    .collect();
                for k in 1..poly.len().saturating_sub(1) {
                    indices.extend([poly[0], poly[k], poly[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(TriMesh { positions, indices })
}

#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Le,
    Be,
}

#[derive(Clone, Copy)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn parse(s: &str) -> Result<Ty, String> {
        Ok(match s {
            "char" | "int8" => Ty::I8,
            "uchar" | "uint8" => Ty::U8,
            "short" | "int16" => Ty::I16,
            "ushort" | "uint16" => Ty::U16,
            "int" | "int32" => Ty::I32,
            "uint" | "uint32" => Ty::U32,
            "float" | "float32" => Ty::F32,
            "double" | "float64" => Ty::F64,
            _ => return Err(format!("unknown PLY type {s}")),
        })
    }
    fn size(self) -> usize {
        match self {
            Ty::I8 | Ty::U8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
}

struct Prop {
    name: String,
    ty: Ty,
    list_count: Option<Ty>,
}

struct Element {
    name: String,
    count: usize,
    props: Vec<Prop>,
}

struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    format: Format,
    tokens: Vec<&'a str>,
    tok: usize,
}

impl<'a> Reader<'a> {
    fn value(&mut self, ty: Ty) -> Result<f64, String> {
        if self.format == Format::Ascii {
            let t = self.tokens.get(self.tok).ok_or("PLY body ends early")?;
            self.tok += 1;
            return t.parse::<f64>().map_err(|_| format!("bad PLY number {t}"));
        }
        let n = ty.size();
        let b = self
            .data
            .get(self.pos..self.pos + n)
            .ok_or("PLY body ends early")?;
        self.pos += n;
        let mut a = [0u8; 8];
        a[..n].copy_from_slice(b);
        if self.format == Format::Be {
            a[..n].reverse();
        }
        Ok(match ty {
            Ty::I8 => a[0] as i8 as f64,
            Ty::U8 => a[0] as f64,
            Ty::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
            Ty::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
            Ty::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Ty::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Ty::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Ty::F64 => f64::from_le_bytes(a),
        })
    }
}

fn load_ply(bytes: &[u8]) -> Result<TriMesh, String> {
    const END: &[u8] = b"end_header";
    let end = bytes
        .windows(END.len())
        .position(|w| w == END)
        .ok_or("no PLY end_header")?;
    let mut body = end + END.len();
    while body < bytes.len() && bytes[body] != b'\n' {
        body += 1;
    }
    body += 1;
    let header = std::str::from_utf8(&bytes[..end]).map_err(|_| "PLY header is not text")?;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for line in header.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["format", "ascii", ..] => format = Some(Format::Ascii),
            ["format", "binary_little_endian", ..] => format = Some(Format::Le),
            ["format", "binary_big_endian", ..] => format = Some(Format::Be),
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count.parse().map_err(|_| "bad PLY element count")?,
                props: Vec::new(),
            }),
            ["property", "list", c, t, name] => elements
                .last_mut()
                .ok_or("PLY property before element")?
                .props
                .push(Prop {
                    name: name.to_string(),
                    ty: Ty::parse(t)?,
                    list_count: Some(Ty::parse(c)?),
                }),
            ["property", t, name] => elements
                .last_mut()
                .ok_or("PLY property before element")?
                .props
                .push(Prop {
                    name: name.to_string(),
                    ty: Ty::parse(t)?,
                    list_count: None,
                }),
            _ => {}
        }
    }
    let format = format.ok_or("PLY without format")?;
    let data = bytes.get(body.min(bytes.len())..).unwrap_or(&[]);
    let tokens = if format == Format::Ascii {
        std::str::from_utf8(data)
            .map_err(|_| "PLY body is not text")?
            .split_whitespace()
            .collect()
    } else {
        Vec::new()
    };
    let mut r = Reader {
        data,
        pos: 0,
        format,
        tokens,
        tok: 0,
    };
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    let mut poly = Vec::new();
    for el in &elements {
        let xyz: Vec<Option<usize>> = el
            .props
            .iter()
            .map(|p| ["x", "y", "z"].iter().position(|n| *n == p.name))
            .collect();
        for _ in 0..el.count {
            let mut v = [0f32; 3];
            for (pi, p) in el.props.iter().enumerate() {
                if let Some(ct) = p.list_count {
                    let n = r.value(ct)? as usize;
                    poly.clear();
                    for _ in 0..n {
                        poly.push(r.value(p.ty)? as u32);
                    }
                    if el.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index")
                    {
                        for k in 1..poly.len().saturating_sub(1) {
                            indices.extend([poly[0], poly[k], poly[k + 1]]);
                        }
                    }
                } else {
                    let x = r.value(p.ty)?;
                    if let Some(a) = xyz[pi] {
                        v[a] = x as f32;
                    }
                }
            }
            if el.name == "vertex" {
                positions.push(v);
            }
        }
    }
    Ok(TriMesh { positions, indices })
}
