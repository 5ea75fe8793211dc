//! The fast path of the PLY importer: binary PLY (either byte order) read straight from the bytes.
//!
//! ply-rs reads every element into a value of its own (a `Vec` per face, a `String` per property
//! name and element), which made parsing a third of the import of a 1.6 M-triangle scan. This
//! path reads the same files without allocating per element, and produces exactly the [`Mesh`]
//! and warnings of the ply-rs path (`super::load_ply_rs`) for every file it accepts.
//!
//! It accepts only what it reads exactly as that path does, and declines (returns `None`) all
//! else, which the ply-rs path then reads (and refuses, if it must, with its own error): ASCII;
//! a header line its grammar might read otherwise (only `ply`, `format`, `comment`, `obj_info`,
//! `element`, `property` and `end_header` lines in ply-rs's exact syntax, each ending in `\n` or
//! `\r\n`, are taken); duplicate element or property names (ply-rs's map moves or replaces them);
//! a list with a floating-point count; no `vertex` element, or one without `x`, `y` or `z`, or
//! with a list under a name the importer reads; no `face` element, a `face` before the `vertex`
//! element, a face without exactly one `vertex_indices` / `vertex_index` list of an integer type;
//! and every error of the payload: a truncated element, a negative list count, an index out of
//! range, a non-finite position. Since every error goes to the ply-rs path, the two cannot
//! disagree on one.
//!
//! Allocations are bounded by the bytes present: a vertex or face count is reserved only as far
//! as the remaining payload could hold that many elements.

use std::path::Path;

use super::super::off::file_stem;
use super::super::{Material, Mesh, polygon};

/// Most elements, and most properties of one element, the fast path takes (a hostile header with
/// thousands of names would make its duplicate checks quadratic; ply-rs reads such files).
const MAX_NAMES: usize = 256;

/// A PLY scalar type (ply-rs's `ScalarType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type named `s` in a header (the names and aliases of ply-rs's grammar).
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    fn is_int(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }
}

/// A property's type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

impl Kind {
    /// Bytes of the property in one element: exact for a scalar, the least (an empty list) for a
    /// list.
    fn min_size(self) -> usize {
        match self {
            Kind::Scalar(t) => t.size(),
            Kind::List { count, .. } => count.size(),
        }
    }
}

#[derive(Debug)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

impl Element {
    /// The size of one element if it has no list.
    fn fixed_size(&self) -> Option<usize> {
        self.properties
            .iter()
            .try_fold(0usize, |sum, p| match p.kind {
                Kind::Scalar(t) => sum.checked_add(t.size()),
                Kind::List { .. } => None,
            })
    }

    /// The fewest bytes one element takes.
    fn min_size(&self) -> usize {
        self.properties.iter().map(|p| p.kind.min_size()).sum()
    }

    fn property(&self, name: &str) -> Option<usize> {
        self.properties.iter().position(|p| p.name == name)
    }
}

/// A binary PLY header as the fast path takes it.
#[derive(Debug)]
struct Header {
    big_endian: bool,
    elements: Vec<Element>,
    /// Offset of the payload (just past the `end_header` line).
    body: usize,
}

/// ply-rs's `ident`: `[a-zA-Z_][a-zA-Z0-9_-]*`.
fn is_ident(s: &str) -> bool {
    let mut b = s.bytes();
    matches!(b.next(), Some(c) if c.is_ascii_alphabetic() || c == b'_')
        && b.all(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'-')
}

fn is_digits(s: &str) -> bool {
    !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit())
}

/// Reads the header of a binary PLY file: `None` for ASCII files and for anything that ply-rs's
/// grammar (`ply_rs::parser::ply_grammar`) might read otherwise or refuse. Lines are what ply-rs
/// reads with `read_line` (up to `\n`); a line is its words separated by spaces and tabs, with
/// no leading blank, trailing blanks allowed, and an optional `\r` before the `\n`.
fn header(bytes: &[u8]) -> Option<Header> {
    let mut pos = 0;
    let mut big_endian = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut first = true;
    loop {
        let rest = bytes.get(pos..)?;
        let len = rest.iter().position(|&b| b == b'\n')?;
        let raw = rest.get(..len)?;
        pos += len + 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        // ply-rs reads lines as UTF-8; its grammar takes a `\r` only as (part of) the line break.
        if raw.contains(&b'\r') {
            return None;
        }
        let line = std::str::from_utf8(raw).ok()?;
        if line.starts_with([' ', '\t']) {
            return None;
        }
        let mut words = [""; 6];
        let mut n = 0;
        for w in line.split([' ', '\t']).filter(|w| !w.is_empty()) {
            if n == words.len() {
                // Only a comment has this many words.
                break;
            }
            words[n] = w;
            n += 1;
        }
        let words = &words[..n];
        if first {
            if words != ["ply"] {
                return None;
            }
            first = false;
            continue;
        }
        match words {
            ["comment" | "obj_info", ..] => {}
            ["format", encoding, version] => {
                let (major, minor) = version.split_once('.')?;
                if big_endian.is_some() || !is_digits(major) || !is_digits(minor) {
                    return None;
                }
                big_endian = Some(match *encoding {
                    "binary_little_endian" => false,
                    "binary_big_endian" => true,
                    _ => return None,
                });
            }
            ["element", name, count] => {
                if !is_ident(name)
                    || !is_digits(count)
                    || elements.len() == MAX_NAMES
                    || elements.iter().any(|e| e.name == *name)
                {
                    return None;
                }
                elements.push(Element {
                    name: name.to_string(),
                    count: count.parse().ok()?,
                    properties: Vec::new(),
                });
            }
            ["property", ty, name] | ["property", "list", _, ty, name] => {
                let kind = match words {
                    [_, "list", count, ..] => Kind::List {
                        count: Scalar::parse(count).filter(|c| c.is_int())?,
                        item: Scalar::parse(ty)?,
                    },
                    _ => Kind::Scalar(Scalar::parse(ty)?),
                };
                let e = elements.last_mut()?;
                if !is_ident(name)
                    || e.properties.len() == MAX_NAMES
                    || e.properties.iter().any(|p| p.name == *name)
                {
                    return None;
                }
                e.properties.push(Property {
                    name: name.to_string(),
                    kind,
                });
            }
            ["end_header"] => break,
            _ => return None,
        }
    }
    Some(Header {
        big_endian: big_endian?,
        elements,
        body: pos,
    })
}

/// The payload, read front to back.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let end = self.pos.checked_add(n)?;
        let s = self.bytes.get(self.pos..end)?;
        self.pos = end;
        Some(s)
    }

    fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }
}

/// The first `N` bytes of `b`.
fn array<const N: usize>(b: &[u8]) -> Option<[u8; N]> {
    b.get(..N)?.try_into().ok()
}

macro_rules! number {
    ($ty:ty, $be:expr, $b:expr) => {{
        let a = array::<{ std::mem::size_of::<$ty>() }>($b)?;
        if $be {
            <$ty>::from_be_bytes(a)
        } else {
            <$ty>::from_le_bytes(a)
        }
    }};
}

/// A scalar of type `t` at the start of `b`, as the ply-rs path converts it (`ply::scalar`).
#[inline(always)]
fn float<const BE: bool>(t: Scalar, b: &[u8]) -> Option<f64> {
    Some(match t {
        Scalar::I8 => number!(i8, BE, b) as f64,
        Scalar::U8 => number!(u8, BE, b) as f64,
        Scalar::I16 => number!(i16, BE, b) as f64,
        Scalar::U16 => number!(u16, BE, b) as f64,
        Scalar::I32 => number!(i32, BE, b) as f64,
        Scalar::U32 => number!(u32, BE, b) as f64,
        Scalar::F32 => number!(f32, BE, b) as f64,
        Scalar::F64 => number!(f64, BE, b),
    })
}

/// An integer of type `t` at the start of `b` (`None` for a float type).
#[inline(always)]
fn int<const BE: bool>(t: Scalar, b: &[u8]) -> Option<i64> {
    Some(match t {
        Scalar::I8 => number!(i8, BE, b) as i64,
        Scalar::U8 => number!(u8, BE, b) as i64,
        Scalar::I16 => number!(i16, BE, b) as i64,
        Scalar::U16 => number!(u16, BE, b) as i64,
        Scalar::I32 => number!(i32, BE, b) as i64,
        Scalar::U32 => number!(u32, BE, b) as i64,
        Scalar::F32 | Scalar::F64 => return None,
    })
}

/// Reads one element of `props` from `c`, calling `scalar(i, bytes)` for scalar property `i` and
/// `list(i, count, items)` for list property `i`. `None` if the payload ends or a list's count is
/// negative (ply-rs then reads to the end of the payload and fails).
#[inline(always)]
fn element<'a, const BE: bool>(
    c: &mut Cursor<'a>,
    props: &[Property],
    mut scalar: impl FnMut(usize, &'a [u8]) -> Option<()>,
    mut list: impl FnMut(usize, usize, &'a [u8]) -> Option<()>,
) -> Option<()> {
    for (i, p) in props.iter().enumerate() {
        match p.kind {
            Kind::Scalar(t) => scalar(i, c.take(t.size())?)?,
            Kind::List { count, item } => {
                let n = usize::try_from(int::<BE>(count, c.take(count.size())?)?).ok()?;
                let items = c.take(n.checked_mul(item.size())?)?;
                list(i, n, items)?;
            }
        }
    }
    Some(())
}

/// Skips `e`'s elements.
fn skip<const BE: bool>(c: &mut Cursor, e: &Element) -> Option<()> {
    if e.properties.is_empty() {
        return Some(());
    }
    if let Some(size) = e.fixed_size() {
        c.take(usize::try_from(e.count).ok()?.checked_mul(size)?)?;
        return Some(());
    }
    // Each element takes at least a byte (a list's count), so this loop ends with the payload.
    for _ in 0..e.count {
        element::<BE>(c, &e.properties, |_, _| Some(()), |_, _, _| Some(()))?;
    }
    Some(())
}

/// Which value of the importer's a vertex property gives: position 0-2, normal 3-5, uv 6-7
/// (`ply::Vertex::set_property`).
fn vertex_slot(name: &str) -> Option<usize> {
    Some(match name {
        "x" => 0,
        "y" => 1,
        "z" => 2,
        "nx" => 3,
        "ny" => 4,
        "nz" => 5,
        "u" | "s" | "texture_u" | "texture_s" => 6,
        "v" | "t" | "texture_v" | "texture_t" => 7,
        _ => return None,
    })
}

/// Reads a binary PLY file into an unprocessed [`Mesh`] and the warnings the ply-rs path would
/// give, or `None` to leave the file to the ply-rs path (see the module's documentation).
pub(super) fn load(path: &Path, bytes: &[u8]) -> Option<(Mesh, Vec<String>)> {
    let h = header(bytes)?;
    if h.big_endian {
        read::<true>(path, bytes, &h)
    } else {
        read::<false>(path, bytes, &h)
    }
}

fn read<const BE: bool>(path: &Path, bytes: &[u8], h: &Header) -> Option<(Mesh, Vec<String>)> {
    let vi = h.elements.iter().position(|e| e.name == "vertex")?;
    let fi = h.elements.iter().position(|e| e.name == "face")?;
    if fi < vi {
        return None;
    }
    let (vertex, face) = (&h.elements[vi], &h.elements[fi]);
    // The vertex properties the importer reads: the last one of each slot, as ply-rs sets them in
    // order (only the uv names can share a slot; names are unique).
    let mut slots: [Option<(usize, Scalar)>; 8] = [None; 8];
    for (i, p) in vertex.properties.iter().enumerate() {
        if let Some(s) = vertex_slot(&p.name) {
            let Kind::Scalar(t) = p.kind else {
                return None;
            };
            slots[s] = Some((i, t));
        }
    }
    if slots[..3].iter().any(Option::is_none) {
        return None;
    }
    let index_prop = match (
        face.property("vertex_indices"),
        face.property("vertex_index"),
    ) {
        (Some(i), None) | (None, Some(i)) => i,
        _ => return None,
    };
    let Kind::List {
        item: index_type, ..
    } = face.properties[index_prop].kind
    else {
        return None;
    };
    if !index_type.is_int() {
        return None;
    }

    let mut mesh = Mesh {
        name: file_stem(path),
        materials: vec![Material::default()],
        has_normals: slots[3..6].iter().all(Option::is_some),
        has_uvs: slots[6].is_some() && slots[7].is_some(),
        ..Default::default()
    };
    let mut warnings = Vec::new();
    let mut c = Cursor { bytes, pos: h.body };
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let (mut skipped, mut fanned) = (0usize, 0usize);
    for (ei, e) in h.elements.iter().enumerate() {
        if ei == vi {
            read_vertices::<BE>(&mut c, e, &slots, &mut mesh)?;
        } else if ei == fi {
            let count = usize::try_from(e.count).ok()?;
            // At most as many faces as the payload holds; three corners each, most often.
            let least = e.min_size() + 3 * index_type.size();
            tris.reserve(count.min(c.remaining() / least));
            let nv = mesh.positions.len();
            if u32::try_from(nv).is_err() {
                return None;
            }
            let mut corners: Vec<u32> = Vec::new();
            for _ in 0..count {
                element::<BE>(
                    &mut c,
                    &e.properties,
                    |_, _| Some(()),
                    |i, n, items| {
                        if i != index_prop {
                            return Some(());
                        }
                        let size = index_type.size();
                        corners.clear();
                        for k in 0..n {
                            let v = int::<BE>(index_type, items.get(k * size..)?)?;
                            if v < 0 || v as u64 >= nv as u64 {
                                return None;
                            }
                            corners.push(v as u32);
                        }
                        Some(())
                    },
                )?;
                match corners.len() {
                    0..=2 => skipped += 1,
                    3 => tris.push([corners[0], corners[1], corners[2]]),
                    _ => {
                        if !polygon::triangulate(&mesh.positions, &corners, &mut tris) {
                            fanned += 1;
                        }
                    }
                }
            }
        } else {
            skip::<BE>(&mut c, e)?;
            warnings.push(format!(
                "{}: PLY element '{}' ignored",
                path.display(),
                e.name
            ));
        }
    }
    if c.remaining() > 0 {
        warnings.push(format!(
            "{}: {} bytes after the declared elements ignored",
            path.display(),
            c.remaining()
        ));
    }
    polygon::warn_fanned(fanned, path, &mut warnings);
    polygon::set_triangles(&mut mesh, tris, skipped, path, &mut warnings);
    Some((mesh, warnings))
}

/// Reads the `vertex` element `e` into `mesh` (positions, normals, uvs as the ply-rs path
/// stores them); `None` on a truncated payload or a non-finite position.
fn read_vertices<const BE: bool>(
    c: &mut Cursor,
    e: &Element,
    slots: &[Option<(usize, Scalar)>; 8],
    mesh: &mut Mesh,
) -> Option<()> {
    let count = usize::try_from(e.count).ok()?;
    let n = count.min(c.remaining() / e.min_size().max(1));
    mesh.positions.reserve(n);
    mesh.normals.reserve(n);
    mesh.uvs.reserve(n);
    let (has_normals, has_uvs) = (mesh.has_normals, mesh.has_uvs);
    let mut push = |v: &[f64; 8]| -> Option<()> {
        let p = [v[0] as f32, v[1] as f32, v[2] as f32];
        if !p.iter().all(|x| x.is_finite()) {
            return None;
        }
        mesh.positions.push(p);
        mesh.normals.push(if has_normals {
            [v[3] as f32, v[4] as f32, v[5] as f32]
        } else {
            [0.0; 3]
        });
        // PLY texture coordinates have their origin bottom-left; ours top-left.
        mesh.uvs.push(if has_uvs {
            [v[6] as f32, 1.0 - v[7] as f32]
        } else {
            [0.0; 2]
        });
        Some(())
    };
    if let Some(size) = e.fixed_size() {
        // No list: each slot's value at a fixed offset in a fixed-size record.
        let data = c.take(count.checked_mul(size)?)?;
        let mut offsets = [None; 8];
        for (s, slot) in slots.iter().enumerate() {
            if let Some((i, t)) = *slot {
                let off: usize = e.properties[..i].iter().map(|p| p.kind.min_size()).sum();
                offsets[s] = Some((off, t));
            }
        }
        for record in data.chunks_exact(size.max(1)) {
            let mut v = [0.0f64; 8];
            for (s, o) in offsets.iter().enumerate() {
                if let Some((off, t)) = *o {
                    v[s] = float::<BE>(t, record.get(off..)?)?;
                }
            }
            push(&v)?;
        }
        return Some(());
    }
    let mut slot_of = vec![None; e.properties.len()];
    for (s, slot) in slots.iter().enumerate() {
        if let Some((i, t)) = *slot {
            slot_of[i] = Some((s, t));
        }
    }
    for _ in 0..count {
        let mut v = [0.0f64; 8];
        element::<BE>(
            c,
            &e.properties,
            |i, b| {
                if let Some((s, t)) = slot_of[i] {
                    v[s] = float::<BE>(t, b)?;
                }
                Some(())
            },
            |_, _, _| Some(()),
        )?;
        push(&v)?;
    }
    Some(())
}
