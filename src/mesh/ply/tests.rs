//! The fast path against the ply-rs path: on every PLY file at hand, on generated binary files
//! of every layout the fast path takes (and some it declines), and on their truncations and
//! mutations. The ply-rs path is the oracle: [`agree`] wants the same mesh and warnings, or
//! the same error.

use std::path::{Path, PathBuf};

use super::*;

/// The import as it was before the fast path: the ply-rs path alone.
fn ply_rs_only(bytes: &[u8], warnings: &mut Vec<String>) -> Result<Mesh, ImportError> {
    let path = Path::new("t.ply");
    check_header_numbers(path, bytes)?;
    load_ply_rs(path, bytes, warnings)
}

/// Checks that [`load`] ends as the ply-rs path does on `bytes`: the same mesh and warnings, or
/// the same error. Returns whether the fast path took the file.
fn agree(bytes: &[u8]) -> bool {
    let path = Path::new("t.ply");
    let (mut w1, mut w2) = (vec!["before".to_string()], vec!["before".to_string()]);
    let a = load(path, bytes, &mut w1);
    let b = ply_rs_only(bytes, &mut w2);
    match (&a, &b) {
        (Ok(a), Ok(b)) => {
            same_mesh(a, b).unwrap();
            assert_eq!(w1, w2);
        }
        (Err(a), Err(b)) => assert_eq!(stable(a), stable(b)),
        _ => panic!(
            "fast path {:?} against ply-rs path {:?}",
            a.as_ref().err(),
            b.as_ref().err()
        ),
    }
    let took = fast_path_check("t.ply", bytes).unwrap();
    assert!(!took || a.is_ok());
    took
}

/// An error's message without the set of tokens ply-rs's grammar expected (a `HashSet`,
/// printed in a different order each time).
fn stable(e: &ImportError) -> String {
    let m = e.to_string();
    match m.find("ExpectedSet") {
        Some(i) => m[..i].to_string(),
        None => m,
    }
}

/// A binary PLY file under construction: header lines and payload written in step.
struct Ply {
    be: bool,
    header: String,
    body: Vec<u8>,
}

impl Ply {
    fn new(be: bool) -> Self {
        let order = if be { "big" } else { "little" };
        Self {
            be,
            header: format!("ply\nformat binary_{order}_endian 1.0\n"),
            body: Vec::new(),
        }
    }

    fn line(&mut self, l: &str) -> &mut Self {
        self.header.push_str(l);
        self.header.push('\n');
        self
    }

    /// Appends `v` as a `ty` (a PLY type name), converted with `as`.
    fn scalar(&mut self, ty: &str, v: f64) -> &mut Self {
        macro_rules! put {
            ($t:ty) => {{
                let x = v as $t;
                let b = if self.be {
                    x.to_be_bytes()
                } else {
                    x.to_le_bytes()
                };
                self.body.extend_from_slice(&b);
            }};
        }
        match ty {
            "char" | "int8" => put!(i8),
            "uchar" | "uint8" => put!(u8),
            "short" | "int16" => put!(i16),
            "ushort" | "uint16" => put!(u16),
            "int" | "int32" => put!(i32),
            "uint" | "uint32" => put!(u32),
            "float" | "float32" => put!(f32),
            "double" | "float64" => put!(f64),
            _ => panic!("type {ty}"),
        }
        self
    }

    fn list(&mut self, count_ty: &str, item_ty: &str, items: &[f64]) -> &mut Self {
        self.scalar(count_ty, items.len() as f64);
        for &v in items {
            self.scalar(item_ty, v);
        }
        self
    }

    fn bytes(&self) -> Vec<u8> {
        let mut b = self.header.clone().into_bytes();
        b.extend_from_slice(b"end_header\n");
        b.extend_from_slice(&self.body);
        b
    }
}

/// splitmix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a>(&mut self, v: &[&'a str]) -> &'a str {
        v[self.below(v.len())]
    }
    fn chance(&mut self, percent: usize) -> bool {
        self.below(100) < percent
    }
}

const TYPES: &[&str] = &[
    "char", "int8", "uchar", "uint8", "short", "int16", "ushort", "uint16", "int", "int32", "uint",
    "uint32", "float", "float32", "double", "float64",
];
const INT_TYPES: &[&str] = &[
    "char", "int8", "uchar", "uint8", "short", "int16", "ushort", "uint16", "int", "int32", "uint",
    "uint32",
];

/// The largest value (also a list length) a type holds, capped at 1000.
fn max_of(ty: &str) -> usize {
    match ty {
        "char" | "int8" => 127,
        "uchar" | "uint8" => 255,
        _ => 1000,
    }
}

/// A value for a `ty` property: fractional for floats, in range for integers.
fn value(r: &mut Rng, ty: &str) -> f64 {
    let n = r.below(max_of(ty) + 1) as f64;
    match ty {
        "float" | "float32" | "double" | "float64" => n / 7.0 - 50.0,
        "char" | "int8" | "short" | "int16" | "int" | "int32" => n - (max_of(ty) / 2) as f64,
        _ => n,
    }
}

/// An element the importer ignores, with `n` random properties (scalars and lists), header and
/// payload; `count` elements.
fn extra_element(r: &mut Rng, p: &mut Ply, name: &str, count: usize) {
    let props: Vec<(bool, &str, &str)> = (0..1 + r.below(4))
        .map(|_| (r.chance(40), r.pick(INT_TYPES), r.pick(TYPES)))
        .collect();
    p.line(&format!("element {name} {count}"));
    for (k, (list, ct, t)) in props.iter().enumerate() {
        if *list {
            p.line(&format!("property list {ct} {t} p{k}"));
        } else {
            p.line(&format!("property {t} p{k}"));
        }
    }
    for _ in 0..count {
        for (list, ct, t) in &props {
            if *list {
                let items: Vec<f64> = (0..r.below(5)).map(|_| value(r, t)).collect();
                p.list(ct, t, &items);
            } else {
                let v = value(r, t);
                p.scalar(t, v);
            }
        }
    }
}

/// A random binary PLY file of a layout the fast path takes.
fn random_ply(r: &mut Rng) -> Vec<u8> {
    let be = r.chance(50);
    let mut p = Ply::new(be);
    if r.chance(50) {
        p.line("comment made by the fast path's test");
    }
    if r.chance(30) {
        p.line("obj_info random");
    }
    if r.chance(30) {
        let n = r.below(4);
        extra_element(r, &mut p, "before", n);
    }
    // Vertex properties: name, type, whether it is a list (never under a read name).
    let mut vprops: Vec<(String, &str, bool)> = ["x", "y", "z"]
        .iter()
        .map(|n| (n.to_string(), r.pick(TYPES), false))
        .collect();
    for n in ["nx", "ny", "nz"] {
        if r.chance(60) {
            vprops.push((n.into(), r.pick(TYPES), false));
        }
    }
    let uv_names = [
        ("u", "v"),
        ("s", "t"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ];
    for _ in 0..r.below(3) {
        let (u, v) = uv_names[r.below(4)];
        for n in [u, v] {
            if r.chance(80) && !vprops.iter().any(|(m, _, _)| m == n) {
                vprops.push((n.into(), r.pick(TYPES), false));
            }
        }
    }
    for (k, n) in ["red", "green", "blue", "alpha", "quality"]
        .iter()
        .enumerate()
    {
        if r.chance(25) {
            vprops.push((n.to_string(), r.pick(TYPES), false));
        }
        if r.chance(5) {
            vprops.push((format!("list{k}"), r.pick(TYPES), true));
        }
    }
    for i in (1..vprops.len()).rev() {
        vprops.swap(i, r.below(i + 1));
    }
    let nv = 3 + r.below(40);
    p.line(&format!("element vertex {nv}"));
    let count_type = r.pick(&["uchar", "ushort"]);
    for (n, t, list) in &vprops {
        if *list {
            p.line(&format!("property list {count_type} {t} {n}"));
        } else {
            p.line(&format!("property {t} {n}"));
        }
    }
    for _ in 0..nv {
        for (_, t, list) in &vprops {
            if *list {
                let items: Vec<f64> = (0..r.below(4)).map(|_| value(r, t)).collect();
                p.list(count_type, t, &items);
            } else {
                let v = value(r, t);
                p.scalar(t, v);
            }
        }
    }
    if r.chance(30) {
        let n = r.below(4);
        extra_element(r, &mut p, "between", n);
    }
    // Face: the index list among other properties.
    let index_types: Vec<&str> = INT_TYPES
        .iter()
        .copied()
        .filter(|t| max_of(t) >= nv)
        .collect();
    let (ct, it) = (r.pick(INT_TYPES), r.pick(&index_types));
    let name = r.pick(&["vertex_indices", "vertex_index"]);
    let mut fprops: Vec<(String, &str, &str, bool)> = vec![(name.into(), ct, it, true)];
    for k in 0..r.below(4) {
        let list = r.chance(30);
        fprops.push((format!("f{k}"), r.pick(INT_TYPES), r.pick(TYPES), list));
    }
    for i in (1..fprops.len()).rev() {
        fprops.swap(i, r.below(i + 1));
    }
    let nf = r.below(30);
    p.line(&format!("element face {nf}"));
    for (n, ct, t, list) in &fprops {
        if *list {
            p.line(&format!("property list {ct} {t} {n}"));
        } else {
            p.line(&format!("property {t} {n}"));
        }
    }
    for _ in 0..nf {
        for (n, ct, t, list) in &fprops {
            if n == name {
                let corners = [0, 1, 2, 3, 3, 3, 3, 4, 4, 5, 6, 8][r.below(12)];
                let items: Vec<f64> = (0..corners).map(|_| r.below(nv) as f64).collect();
                p.list(ct, t, &items);
            } else if *list {
                let items: Vec<f64> = (0..r.below(4)).map(|_| value(r, t)).collect();
                p.list(ct, t, &items);
            } else {
                let v = value(r, t);
                p.scalar(t, v);
            }
        }
    }
    if r.chance(30) {
        let n = r.below(4);
        extra_element(r, &mut p, "after", n);
    }
    let mut bytes = p.bytes();
    if r.chance(15) {
        bytes.extend_from_slice(&[7; 5]);
    }
    bytes
}

#[test]
fn random_layouts_read_the_same_on_both_paths() {
    let mut r = Rng(1);
    for i in 0..3000 {
        let bytes = random_ply(&mut r);
        assert!(
            agree(&bytes),
            "file {i} declined: {}",
            String::from_utf8_lossy(&bytes[..200.min(bytes.len())])
        );
    }
}

#[test]
fn truncations_and_mutations_end_as_on_the_ply_rs_path() {
    let mut r = Rng(2);
    for _ in 0..40 {
        let bytes = random_ply(&mut r);
        for len in 0..bytes.len() {
            agree(&bytes[..len]);
        }
        for _ in 0..200 {
            let mut m = bytes.clone();
            for _ in 0..1 + r.below(3) {
                let k = r.below(m.len());
                m[k] = match r.below(3) {
                    0 => r.next() as u8,
                    1 => m[k] ^ (1 << r.below(8)),
                    _ => [0, 0xff, b'\n', b' ', b'1'][r.below(5)],
                };
            }
            agree(&m);
        }
    }
}

/// The quad and polygon file of the tests: a unit square as a quad, a concave (L-shaped)
/// hexagon, a triangle, a two-corner face and an empty one.
fn polygons(be: bool, count: &str, index: &str) -> Vec<u8> {
    let mut p = Ply::new(be);
    let pts = [
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 1.0],
        [2.0, 0.0],
        [2.0, 2.0],
        [0.5, 2.0],
    ];
    p.line(&format!("element vertex {}", pts.len()))
        .line("property float x")
        .line("property float y")
        .line("property float z")
        .line("element face 5")
        .line("property uchar flags")
        .line(&format!("property list {count} {index} vertex_indices"))
        .line("property list uchar float texcoord");
    for [x, y] in pts {
        p.scalar("float", x).scalar("float", y).scalar("float", 0.0);
    }
    let faces: [&[f64]; 5] = [
        &[0., 1., 2., 3.],
        &[0., 4., 5., 6., 3., 2.],
        &[0., 1., 2.],
        &[1., 2.],
        &[],
    ];
    for f in faces {
        p.scalar("uchar", 1.0)
            .list(count, index, f)
            .list("uchar", "float", &[0.5, 0.25]);
    }
    p.bytes()
}

#[test]
fn polygons_with_every_list_count_and_index_type() {
    for be in [false, true] {
        for count in ["uchar", "ushort", "uint", "char", "short", "int"] {
            for index in INT_TYPES {
                let bytes = polygons(be, count, index);
                assert!(agree(&bytes), "{count} {index}");
                let mut w = Vec::new();
                let m = load(Path::new("t.ply"), &bytes, &mut w).unwrap();
                // 2 + 4 + 1 triangles; two faces skipped.
                assert_eq!(m.triangle_count(), 7);
                assert_eq!(w, ["t.ply: skipped 2 faces with fewer than 3 vertices"]);
            }
        }
    }
}

/// A small well-formed file (vertex, face, an edge element) with `header` lines in place of
/// the standard ones, the payload little endian.
fn with_header(header: &str) -> Vec<u8> {
    let mut p = Ply::new(false);
    for [x, y, z] in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        p.scalar("float", x).scalar("float", y).scalar("float", z);
    }
    p.list("uchar", "int", &[0.0, 1.0, 2.0]);
    p.scalar("int", 0.0).scalar("int", 1.0);
    let mut b = header.as_bytes().to_vec();
    b.extend_from_slice(&p.body);
    b
}

const STANDARD: &str = "ply\nformat binary_little_endian 1.0\ncomment c\nelement vertex 3\n\
    property float x\nproperty float y\nproperty float z\nelement face 1\n\
    property list uchar int vertex_indices\nelement edge 1\nproperty int a\nproperty int b\n\
    end_header\n";

#[test]
fn header_variants_the_fast_path_takes() {
    let variants = [
        STANDARD.to_string(),
        STANDARD.replace('\n', "\r\n"),
        STANDARD.replace('\n', " \t\n"),
        STANDARD.replace(' ', " \t "),
        STANDARD.replace("comment c", "comment"),
        STANDARD.replace("comment c", "comment c\r"),
        STANDARD.replace("comment c", "comment \t"),
        STANDARD.replace("comment c", "comment  élément\tvertex 99 ply"),
        STANDARD.replace("comment c", "obj_info vtkPolyData 1.0"),
        STANDARD.replace("comment c\n", "") + "",
        STANDARD
            .replace(
                "format binary_little_endian 1.0\ncomment c\n",
                "comment c\n",
            )
            .replace(
                "end_header",
                "format binary_little_endian 12.034\nend_header",
            ),
        STANDARD.replace("float", "float32"),
        STANDARD.replace("uchar int", "uint8 int32"),
        STANDARD.replace("edge", "my-edge_2"),
    ];
    for h in variants {
        assert!(agree(&with_header(&h)), "{h:?}");
    }
}

#[test]
fn header_variants_left_to_ply_rs() {
    let variants = [
        STANDARD.replace("binary_little_endian", "ascii"),
        STANDARD.replace("\nelement", "\n element"),
        STANDARD.replace("comment c", "comment c\rd"),
        STANDARD.replace("comment c", "comment c\r \n"),
        STANDARD.replace("comment c", ""),
        STANDARD.replace("comment c", "commentary"),
        STANDARD.replace("comment c", "format binary_little_endian 1.0"),
        STANDARD.replace("comment c", "format binary_big_endian 1.0"),
        STANDARD.replace("1.0", "1"),
        STANDARD.replace("1.0", "1.0.0"),
        STANDARD.replace("ply\n", "ply2\n"),
        STANDARD.replace("ply\n", "ply\nply\n"),
        STANDARD.replace("end_header\n", "end_header"),
        STANDARD.replace("end_header\n", "end_header x\n"),
        STANDARD.replace("property float z", "property float z\nproperty float z"),
        STANDARD.replace("element edge 1", "element vertex 1"),
        STANDARD.replace("property float z", "property int64 z"),
        STANDARD.replace("property float z", "property list uchar float z"),
        STANDARD.replace("property float z", "property float w"),
        STANDARD.replace("vertex 3", "vertex +3"),
        STANDARD.replace("vertex 3", "vertex 3 3"),
        STANDARD.replace("list uchar int", "list float int"),
        STANDARD.replace("list uchar int", "list uchar float"),
        STANDARD.replace("list uchar int vertex_indices", "int vertex_indices"),
        STANDARD.replace(
            "vertex_indices",
            "vertex_indices\nproperty list uchar int vertex_index",
        ),
        STANDARD.replace("vertex_indices", "indices"),
        STANDARD.replace("ply\nformat binary_little_endian 1.0\n", "ply\n"),
        STANDARD.replace("property int a", "property int 2a"),
    ];
    for h in variants {
        assert!(!agree(&with_header(&h)), "{h:?}");
    }
    // Faces before vertices; no face element.
    let mut p = Ply::new(true);
    p.line("element face 1")
        .line("property list uchar uint vertex_indices")
        .line("element vertex 3")
        .line("property double x")
        .line("property double y")
        .line("property double z");
    p.list("uchar", "uint", &[0.0, 1.0, 2.0]);
    for k in 0..9 {
        p.scalar("double", (k % 4) as f64);
    }
    assert!(!agree(&p.bytes()));
    let mut p = Ply::new(false);
    p.line("element vertex 1")
        .line("property float x")
        .line("property float y")
        .line("property float z");
    p.scalar("float", 1.0)
        .scalar("float", 1.0)
        .scalar("float", 1.0);
    assert!(!agree(&p.bytes()));
}

#[test]
fn bad_payloads_give_the_ply_rs_errors() {
    let good = with_header(STANDARD);
    assert!(agree(&good));
    let body = STANDARD.len();
    // Non-finite positions, an index out of range, a negative one, a negative list count.
    let mut cases = Vec::new();
    let mut b = good.clone();
    b[body + 4..body + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    cases.push(b);
    let mut b = good.clone();
    b[body + 12..body + 16].copy_from_slice(&f32::INFINITY.to_le_bytes());
    cases.push(b);
    let mut b = good.clone();
    b[body + 37..body + 41].copy_from_slice(&3i32.to_le_bytes());
    cases.push(b);
    let mut b = good.clone();
    b[body + 37..body + 41].copy_from_slice(&(-1i32).to_le_bytes());
    cases.push(b);
    let h = STANDARD.replace("list uchar int", "list char int");
    let mut b = with_header(&h);
    b[h.len() + 36] = 0xff;
    cases.push(b);
    for b in cases {
        assert!(!agree(&b));
    }
    // Hostile counts: no allocation beyond the bytes present, the ply-rs error.
    for (from, to) in [
        ("vertex 3", "vertex 4000000000"),
        ("face 1", "face 4000000000"),
        ("edge 1", "edge 18446744073709551615"),
        ("list uchar int", "list uint int"),
    ] {
        let h = STANDARD.replace(from, to);
        let mut b = with_header(&h);
        if from.starts_with("list") {
            b[h.len() + 36..h.len() + 40].copy_from_slice(&u32::MAX.to_le_bytes());
        }
        assert!(!agree(&b), "{to}");
    }
    // An element without properties costs nothing whatever its count (ply-rs would count to
    // it); the rest reads as usual.
    let h = STANDARD.replace(
        "element edge",
        "element nothing 18446744073709551615\nelement edge",
    );
    let (m, w) = fast::load(Path::new("t.ply"), &with_header(&h)).unwrap();
    assert_eq!(m.triangle_count(), 1);
    assert_eq!(w.len(), 2, "{w:?}");
    // Trailing bytes: a warning, as on the ply-rs path.
    let mut b = good.clone();
    b.extend_from_slice(b"tail");
    assert!(agree(&b));
}

#[test]
fn attributes_from_every_alias_and_type() {
    for be in [false, true] {
        let mut p = Ply::new(be);
        p.line("element vertex 3")
            .line("property uchar red")
            .line("property double x")
            .line("property short y")
            .line("property char z")
            .line("property float nz")
            .line("property float ny")
            .line("property int nx")
            .line("property float u")
            .line("property double s")
            .line("property ushort texture_t")
            .line("property list uchar uchar extra")
            .line("element face 1")
            .line("property list uchar ushort vertex_index");
        for k in 0..3 {
            let f = k as f64;
            p.scalar("uchar", 200.0)
                .scalar("double", f * 1.25)
                .scalar("short", -f)
                .scalar("char", if k == 1 { 3.0 } else { 0.0 })
                .scalar("float", 0.5)
                .scalar("float", 0.25)
                .scalar("int", -2.0)
                .scalar("float", 9.0)
                .scalar("double", f / 3.0)
                .scalar("ushort", 2.0)
                .list("uchar", "uchar", &[1.0, 2.0][..k.min(2)]);
        }
        p.list("uchar", "ushort", &[0.0, 1.0, 2.0]);
        let bytes = p.bytes();
        assert!(agree(&bytes));
        let mut w = Vec::new();
        let m = load(Path::new("t.ply"), &bytes, &mut w).unwrap();
        assert!(m.has_normals && m.has_uvs);
        assert_eq!(m.positions[1], [1.25, -1.0, 3.0]);
        assert_eq!(m.normals[2], [-2.0, 0.25, 0.5]);
        // `s` comes after `u`: it wins.
        assert_eq!(m.uvs[2], [(2.0f64 / 3.0) as f32, -1.0]);
        assert!(w.is_empty());
    }
}

/// Every `.ply` file under `dir`, recursively.
fn plys(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            plys(&p, out);
        } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("ply"))
            || p.parent().is_some_and(|d| d.ends_with("import_ply"))
        {
            out.push(p);
        }
    }
}

#[test]
fn every_ply_file_at_hand_reads_the_same_on_both_paths() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    plys(&root.join("../shared/assets"), &mut files);
    plys(&root.join("assets"), &mut files);
    plys(&root.join("fuzz/corpus/import_ply"), &mut files);
    plys(&root.join("fuzz/regressions/import_ply"), &mut files);
    let mut taken = Vec::new();
    for f in &files {
        let bytes = std::fs::read(f).unwrap();
        if agree(&bytes) {
            taken.push(f.file_name().unwrap().to_string_lossy().into_owned());
        }
        // Cuts of the small files at every byte, of the large ones at 16 places.
        let step = if bytes.len() <= 1 << 16 {
            1
        } else {
            bytes.len() / 16
        };
        for len in (0..bytes.len()).step_by(step) {
            agree(&bytes[..len]);
        }
    }
    taken.sort();
    for want in ["binary_be.ply", "binary_le.ply"] {
        assert!(
            taken.iter().any(|t| t == want),
            "{want} not taken: {taken:?}"
        );
    }
    if root.join("../shared/assets/scanned").is_dir() {
        for want in ["lucy.ply", "turbineblade.ply"] {
            assert!(
                taken.iter().any(|t| t == want),
                "{want} not taken: {taken:?}"
            );
        }
    }
    eprintln!("{} files, the fast path took {taken:?}", files.len());
}

/// Parse time of both paths on the file `VGEO_PLY_TIMING` names (best of 5 each):
/// `VGEO_PLY_TIMING=/tmp/lucy16.ply cargo test --release --lib parse_time -- --ignored --nocapture`.
#[test]
#[ignore]
fn parse_time_of_both_paths() {
    let Some(file) = std::env::var_os("VGEO_PLY_TIMING") else {
        eprintln!("VGEO_PLY_TIMING names no file");
        return;
    };
    let bytes = std::fs::read(&file).unwrap();
    let path = Path::new("t.ply");
    let best = |f: &dyn Fn() -> Mesh| {
        (0..5)
            .map(|_| {
                let t = std::time::Instant::now();
                let m = f();
                let s = t.elapsed().as_secs_f64();
                drop(m);
                s
            })
            .fold(f64::MAX, f64::min)
    };
    let fast = best(&|| {
        fast::load(path, &bytes)
            .expect("the fast path takes the file")
            .0
    });
    let slow = best(&|| load_ply_rs(path, &bytes, &mut Vec::new()).unwrap());
    eprintln!(
        "{}: fast path {:.1} ms, ply-rs path {:.1} ms",
        std::path::Path::new(&file).display(),
        fast * 1e3,
        slow * 1e3
    );
}
