//! Mesh import: every shared asset with its real counts, hand-built files for each format and
//! feature, and a small fuzz pass (truncations, byte flips) asserting no panic.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use vgeo::mesh::{self, ImportError, ImportOptions, Mesh};

// ---------------------------------------------------------------------------------------------
// Helpers

fn assets_dir() -> PathBuf {
    common::shared_assets()
}

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vgeo-import-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("write test file");
    p
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [
        a[0] as f64 - b[0] as f64,
        a[1] as f64 - b[1] as f64,
        a[2] as f64 - b[2] as f64,
    ]
}

fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

fn dot(u: [f64; 3], v: [f64; 3]) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

/// Geometric normal (unnormalized, length = 2 * area) of triangle `t`.
fn tri_normal(m: &Mesh, t: usize) -> [f64; 3] {
    let p = |k: usize| m.positions[m.indices[3 * t + k] as usize];
    cross(sub(p(1), p(0)), sub(p(2), p(0)))
}

fn total_area(m: &Mesh) -> f64 {
    (0..m.triangle_count())
        .map(|t| dot(tri_normal(m, t), tri_normal(m, t)).sqrt() / 2.0)
        .sum()
}

/// Loads and checks the invariants every import must hold.
fn load_ok(path: &Path, opts: &ImportOptions) -> mesh::Import {
    let import =
        mesh::load(path, opts).unwrap_or_else(|e| panic!("{} should load: {e}", path.display()));
    assert!(!import.meshes.is_empty());
    for m in &import.meshes {
        m.validate()
            .unwrap_or_else(|e| panic!("{}: invalid mesh: {e}", path.display()));
        assert!(m.triangle_count() > 0);
        for n in &m.normals {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!(
                (len - 1.0).abs() < 1e-4,
                "{}: normal {n:?} not unit",
                path.display()
            );
        }
    }
    import
}

fn load_err(path: &Path) -> ImportError {
    match mesh::load(path, &ImportOptions::default()) {
        Ok(i) => panic!(
            "{} should fail, loaded {} meshes",
            path.display(),
            i.meshes.len()
        ),
        Err(e) => e,
    }
}

fn assert_msg(e: &ImportError, needles: &[&str]) {
    let msg = e.to_string();
    for n in needles {
        assert!(
            msg.contains(n),
            "error message {msg:?} should contain {n:?}"
        );
    }
}

/// Standard base64 with padding (test-side encoder for data URIs).
fn base64(data: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(T[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Shared assets

/// What a shared asset must give: counts from assets/README.md and from checking each file.
enum Expect {
    Ok {
        /// README triangle count (after triangulating polygons).
        source: usize,
        /// Zero-area or repeated-index triangles (checked with an independent script).
        degenerate: usize,
        /// Vertices of the final mesh (unique positions for attribute-less formats).
        vertices: Option<usize>,
        unreferenced: usize,
    },
    Err(&'static [&'static str]),
}

fn expectations() -> HashMap<&'static str, Expect> {
    use Expect::*;
    let ok = |source, degenerate, vertices, unreferenced| Ok {
        source,
        degenerate,
        vertices,
        unreferenced,
    };
    HashMap::from([
        // 35,947 vertices in the file, 1,113 of them unreferenced.
        ("scanned/bunny.ply", ok(69_451, 0, Some(34_834), 1_113)),
        ("scanned/lucy.ply", ok(99_970, 0, Some(49_987), 0)),
        ("scanned/turbineblade.ply", ok(199_034, 0, Some(99_519), 0)),
        // 2,930 positions but 3,225 distinct position/uv pairs.
        ("scanned/spot.obj", ok(5_856, 0, Some(3_225), 0)),
        ("gltf/Lantern/Lantern.gltf", ok(5_394, 0, None, 0)),
        (
            "gltf/FlightHelmet/FlightHelmet.gltf",
            ok(94_722, 0, None, 0),
        ),
        // 56 triangles with two coincident corners; 722 distinct positions. The 168 corners of the
        // dropped triangles of this triangle soup become unreferenced.
        ("hard/Spider_binary.stl", ok(1_368, 56, Some(722), 168)),
        ("hard/triangle_with_two_solids.stl", ok(2, 0, Some(6), 0)),
        ("hard/concave_polygon.obj", ok(64, 0, Some(64), 0)),
        ("hard/sphereWithHole.stl", ok(285, 0, Some(146), 0)),
        // 2,798 vertices, 2,733 distinct positions.
        ("hard/elephant-with-holes.off", ok(4_463, 0, Some(2_733), 0)),
        ("hard/degtri_sliding.off", ok(8, 4, Some(8), 0)),
        // 20 vertices, 5 pairs coincide.
        ("hard/quads_to_stitch.off", ok(16, 0, Some(15), 0)),
        (
            "hard/tetra_intersected_by_triangle.off",
            ok(5, 0, Some(7), 0),
        ),
        ("hard/fold.off", ok(12, 0, Some(12), 0)),
        // Vertex 0 of the POSITION accessor (accessor 2) is (-inf, -0.5, 0.5).
        (
            "invalid/BoxWithInfinites.glb",
            Err(&[
                "BoxWithInfinites.glb",
                "vertex 0",
                "non-finite",
                "accessor 2",
            ]),
        ),
        // The first index is 255 (24 vertices).
        (
            "invalid/IndexOutOfRange/IndexOutOfRange.gltf",
            Err(&[
                "IndexOutOfRange.gltf",
                "index 255",
                "out of range",
                "24 vertices",
                "element 0",
            ]),
        ),
        (
            "invalid/IndexOutOfRange/AllIndicesOutOfRange.gltf",
            Err(&[
                "AllIndicesOutOfRange.gltf",
                "index 65535",
                "out of range",
                "24 vertices",
            ]),
        ),
    ])
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("read {}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            walk(&p, out);
        } else {
            out.push(p);
        }
    }
}

#[test]
fn every_shared_asset_loads_with_its_real_counts_or_fails_clearly() {
    let root = assets_dir();
    let expect = expectations();
    let mut files = Vec::new();
    for folder in ["scanned", "gltf", "hard", "invalid"] {
        let d = root.join(folder);
        assert!(d.is_dir(), "missing assets folder {}", d.display());
        walk(&d, &mut files);
    }
    let mut seen = 0;
    let mut loaded: HashMap<String, mesh::Import> = HashMap::new();
    for file in &files {
        let name = file.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let ext = file
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        if matches!(ext.as_str(), "mtl" | "png" | "bin") || name.starts_with("README") {
            continue;
        }
        let rel = file
            .strip_prefix(&root)
            .expect("under root")
            .to_string_lossy()
            .replace('\\', "/");
        let Some(exp) = expect.get(rel.as_str()) else {
            panic!("asset {rel} has no expected counts in this test; add them");
        };
        seen += 1;
        match exp {
            Expect::Ok {
                source,
                degenerate,
                vertices,
                unreferenced,
            } => {
                let import = load_ok(file, &ImportOptions::default());
                let r = &import.report;
                assert_eq!(import.meshes.len(), 1, "{rel}");
                let m = &import.meshes[0];
                assert_eq!(r.source_triangles, *source, "{rel}: source triangles");
                assert_eq!(
                    r.degenerate_dropped, *degenerate,
                    "{rel}: degenerate triangles"
                );
                assert_eq!(
                    m.triangle_count(),
                    source - degenerate,
                    "{rel}: triangles kept"
                );
                assert_eq!(
                    r.unreferenced_removed, *unreferenced,
                    "{rel}: unreferenced vertices"
                );
                if let Some(v) = vertices {
                    // Welded vertices, before generated normals split some at creases.
                    assert_eq!(m.positions.len() - r.crease_splits, *v, "{rel}: vertices");
                }
                let has_drop_warning = r
                    .warnings
                    .iter()
                    .any(|w| w.contains(&format!("dropped {degenerate} degenerate")));
                assert_eq!(
                    has_drop_warning,
                    *degenerate > 0,
                    "{rel}: warnings {:?}",
                    r.warnings
                );
                loaded.insert(rel, import);
            }
            Expect::Err(needles) => {
                let e = load_err(file);
                assert_msg(&e, needles);
            }
        }
    }
    assert_eq!(
        seen,
        expect.len(),
        "every expected asset must exist under {}",
        root.display()
    );

    // FlightHelmet: 5 materials, with the base-colour textures that exist on disk (1 is absent).
    let fh = &loaded["gltf/FlightHelmet/FlightHelmet.gltf"];
    let mats = &fh.meshes[0].materials;
    assert_eq!(mats.len(), 5);
    assert_eq!(mats[0].name, "GlassPlasticMat");
    let with_tex = mats
        .iter()
        .filter(|m| m.base_color_texture.as_ref().is_some_and(|p| p.is_file()))
        .count();
    assert_eq!(with_tex, 4, "only FlightHelmet_baseColor1.png is missing");
    assert!(
        mats.iter().all(|m| m.normal_texture.is_none()),
        "normal maps are absent here"
    );
    assert!(
        fh.report
            .warnings
            .iter()
            .any(|w| w.contains("FlightHelmet_baseColor1.png"))
    );
    // Every material is used by its own mesh (5 meshes, 5 materials).
    let mut used = vec![0usize; 5];
    fh.meshes[0]
        .material_ids
        .iter()
        .for_each(|&i| used[i as usize] += 1);
    assert!(used.iter().all(|&u| u > 0), "material use {used:?}");

    // Lantern: loads although its base-colour texture is missing, with a warning naming it.
    let lantern = &loaded["gltf/Lantern/Lantern.gltf"];
    assert!(
        lantern
            .report
            .warnings
            .iter()
            .any(|w| w.contains("Lantern_baseColor.png") && w.contains("not found")),
        "{:?}",
        lantern.report.warnings
    );
    let lm = &lantern.meshes[0];
    assert_eq!(lm.materials.len(), 1);
    assert!(lm.materials[0].base_color_texture.is_none());
    assert!(
        lm.materials[0]
            .normal_texture
            .as_ref()
            .is_some_and(|p| p.ends_with("Lantern_normal.png"))
    );
    assert!(lm.has_normals && lm.has_uvs);
    // The root node rotates by 180 degrees about Y: the pole's x (about -3.8 .. -9.6 in the file)
    // comes out positive.
    let (lo, hi) = lm.bounds().expect("bounds");
    assert!(lo[0] > -10.0 && hi[0] > 5.0, "bounds {lo:?} {hi:?}");

    // Bunny: the 1,113 unreferenced vertices are gone.
    let bunny = &loaded["scanned/bunny.ply"].meshes[0];
    let mut referenced = vec![false; bunny.positions.len()];
    bunny
        .indices
        .iter()
        .for_each(|&i| referenced[i as usize] = true);
    assert!(referenced.iter().all(|r| *r));
    assert!(!bunny.has_normals && !bunny.has_uvs);
    assert!(bunny.uvs.iter().all(|t| *t == [0.0, 0.0]));

    // Spot: UVs but no normals in the file.
    let spot = &loaded["scanned/spot.obj"].meshes[0];
    assert!(spot.has_uvs && !spot.has_normals);
}

#[test]
fn concave_polygon_triangulation_covers_its_exact_area() {
    let path = assets_dir().join("hard/concave_polygon.obj");
    let (m, report) = mesh::load_mesh(&path).expect("load");
    assert_eq!(report.source_triangles, 64);
    assert_eq!(m.triangle_count(), 64);
    // Independent polygon area: parse the file's single face, shoelace in its plane (x = -1.146).
    let text = std::fs::read_to_string(&path).expect("read");
    let verts: Vec<[f64; 3]> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let c: Vec<f64> = l
                .split_whitespace()
                .map(|t| t.parse().expect("number"))
                .collect();
            [c[0], c[1], c[2]]
        })
        .collect();
    assert!(
        verts.iter().all(|v| v[0] == -1.146),
        "the polygon lies in the plane x = -1.146"
    );
    let face: Vec<usize> = text
        .lines()
        .find_map(|l| l.strip_prefix("f "))
        .expect("face")
        .split_whitespace()
        .map(|t| {
            t.split('/')
                .next()
                .expect("index")
                .parse::<usize>()
                .expect("int")
                - 1
        })
        .collect();
    assert_eq!(face.len(), 66);
    let shoelace: f64 = (0..face.len())
        .map(|i| {
            let (a, b) = (verts[face[i]], verts[face[(i + 1) % face.len()]]);
            a[1] * b[2] - b[1] * a[2]
        })
        .sum::<f64>()
        / 2.0;
    let area = total_area(&m);
    assert!(shoelace.abs() > 0.1);
    assert!(
        (area - shoelace.abs()).abs() < 1e-5 * shoelace.abs(),
        "triangles {area} vs polygon {}",
        shoelace.abs()
    );
    // Winding kept: every triangle faces the polygon's way (sign of the shoelace along +x).
    for t in 0..m.triangle_count() {
        assert!(
            tri_normal(&m, t)[0] * shoelace > 0.0,
            "triangle {t} flipped"
        );
    }
    // The .mtl's Kd is the base colour.
    assert_eq!(m.materials.len(), 1);
    assert_eq!(m.materials[0].name, "test");
    assert_eq!(
        m.materials[0].base_color,
        [0.141176, 0.184314, 0.411765, 1.0]
    );
}

// ---------------------------------------------------------------------------------------------
// Hand-built files

/// A concave "U" (8 corners, area 5) in 2D, placed on a tilted plane in 3D.
fn u_shape_3d() -> (Vec<[f64; 3]>, f64) {
    let u2 = [
        [0.0, 0.0],
        [3.0, 0.0],
        [3.0, 3.0],
        [2.0, 3.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 3.0],
        [0.0, 3.0],
    ];
    let area = 3.0 * 3.0 - 1.0 * 2.0; // 7
    // Orthonormal tilted basis: e1 = (1, 1, 0)/sqrt2, e2 = (-1, 1, 2)/sqrt6; origin (5, -2, 1).
    let s2 = 2f64.sqrt();
    let s6 = 6f64.sqrt();
    let e1 = [1.0 / s2, 1.0 / s2, 0.0];
    let e2 = [-1.0 / s6, 1.0 / s6, 2.0 / s6];
    let pts = u2
        .iter()
        .map(|p| {
            [
                5.0 + p[0] * e1[0] + p[1] * e2[0],
                -2.0 + p[0] * e1[1] + p[1] * e2[1],
                1.0 + p[0] * e1[2] + p[1] * e2[2],
            ]
        })
        .collect();
    (pts, area)
}

#[test]
fn obj_concave_ngon_with_materials() {
    let dir = scratch("obj");
    let (pts, area) = u_shape_3d();
    let mut obj = String::from("mtllib mats.mtl\n");
    for p in &pts {
        obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    obj += "v 0 0 10\nv 1 0 10\nv 0 1 10\nvt 0.25 0.75\n";
    obj += "usemtl red\nf 1 2 3 4 5 6 7 8\nusemtl grey\nf 9/1 10/1 11/1\n";
    write(
        &dir,
        "mats.mtl",
        "newmtl red\nKd 1 0 0\nPm 0.5\nPr 0.25\nnewmtl grey\nKd 0.5\nnewmtl unused\nKd 0 1 0\n",
    );
    let path = write(&dir, "u.obj", &obj);
    let import = load_ok(&path, &ImportOptions::default());
    let m = &import.meshes[0];
    assert_eq!(import.report.source_triangles, 6 + 1);
    assert_eq!(m.triangle_count(), 7);
    // Split the triangles by material: the n-gon's cover exactly the U.
    let mut ngon = m.clone();
    let keep: Vec<usize> = (0..m.triangle_count())
        .filter(|&t| m.materials[m.material_ids[t] as usize].name == "red")
        .collect();
    assert_eq!(keep.len(), 6);
    ngon.indices = keep
        .iter()
        .flat_map(|&t| m.indices[3 * t..3 * t + 3].to_vec())
        .collect();
    assert!(
        (total_area(&ngon) - area).abs() < 1e-4,
        "area {} vs {area}",
        total_area(&ngon)
    );
    // A fan from corner 0 would cover 9 (the whole square) or overlap; check against it.
    assert!((total_area(&ngon) - 9.0).abs() > 1.0);
    // Materials: unused dropped, short "Kd 0.5" read as grey (tobj's own parser panics on it).
    assert_eq!(m.materials.len(), 2);
    let red = m.materials.iter().find(|x| x.name == "red").expect("red");
    assert_eq!(red.base_color, [1.0, 0.0, 0.0, 1.0]);
    assert_eq!((red.metallic, red.roughness), (0.5, 0.25));
    let grey = m.materials.iter().find(|x| x.name == "grey").expect("grey");
    assert_eq!(grey.base_color, [0.5, 0.5, 0.5, 1.0]);
    // Only the triangle had UVs, so the mesh does not claim any; OBJ v is flipped to top-left.
    assert!(!m.has_uvs && !m.has_normals);

    // Missing .mtl: a warning naming it, and the default material.
    let path = write(
        &dir,
        "nomtl.obj",
        "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nusemtl red\nf 1/1 2/1 3/1\n",
    );
    let import = load_ok(&path, &ImportOptions::default());
    assert!(
        import
            .report
            .warnings
            .iter()
            .any(|w| w.contains("missing.mtl")),
        "{:?}",
        import.report.warnings
    );
    let m = &import.meshes[0];
    assert_eq!(m.materials.len(), 1);
    assert_eq!(m.materials[0].name, "default");
    assert!(m.has_uvs);
    assert_eq!(m.uvs[0], [0.25, 0.25]);

    // Bad index: the error names the file and the line.
    let path = write(&dir, "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    assert_msg(&load_err(&path), &["bad.obj", "line 4", "'7'"]);
    // NaN position.
    let path = write(&dir, "nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
    assert_msg(&load_err(&path), &["nan.obj", "vertex 1", "non-finite"]);
    std::fs::remove_dir_all(&dir).ok();
}

fn binary_ply() -> Vec<u8> {
    let mut b = b"ply\nformat binary_little_endian 1.0\ncomment test\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty float s\nproperty float t\nelement face 2\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n".to_vec();
    // Square 0..3 (z = 0), apex 4, vertex 5 unreferenced.
    let v: [[f32; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.5, 0.0],
        [9.0, 9.0, 9.0],
    ];
    for (i, p) in v.iter().enumerate() {
        for c in p {
            b.extend_from_slice(&c.to_le_bytes());
        }
        b.push(200);
        b.extend_from_slice(&(i as f32 * 0.1).to_le_bytes());
        b.extend_from_slice(&0.25f32.to_le_bytes());
    }
    b.push(4);
    for i in [0i32, 1, 2, 3] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b.push(3);
    for i in [1i32, 4, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b.extend_from_slice(&0i32.to_le_bytes());
    b.extend_from_slice(&1i32.to_le_bytes());
    b
}

fn ascii_ply() -> String {
    // A concave quad, an unused vertex and a triangle; "vertex_index" as a uint8/uint32 list.
    "ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n\
     property float nx\nproperty float ny\nproperty float nz\nelement face 2\n\
     property list uint8 uint32 vertex_index\nend_header\n\
     0 0 0 0 0 1\n2 1 0 0 0 1\n0 2 0 0 0 1\n1 1 0 0 0 1\n-1 1 0 0 0 1\n0 0 5 0 0 1\n1 0 5 0 0 1\n0 1 5 0 0 1\n\
     4 0 1 2 3\n3 5 6 7\n"
        .to_string()
}

#[test]
fn ply_binary_and_ascii() {
    let dir = scratch("ply");
    let path = write(&dir, "bin.ply", binary_ply());
    let import = load_ok(&path, &ImportOptions::default());
    let m = &import.meshes[0];
    assert_eq!(import.report.source_triangles, 3);
    assert_eq!(import.report.unreferenced_removed, 1);
    assert_eq!(m.positions.len(), 5);
    assert!(m.has_uvs && !m.has_normals);
    // s/t read, t flipped to a top-left origin.
    assert!(
        m.uvs
            .iter()
            .any(|t| (t[0] - 0.4).abs() < 1e-6 && (t[1] - 0.75).abs() < 1e-6),
        "{:?}",
        m.uvs
    );
    assert!((total_area(m) - 1.5).abs() < 1e-6);
    // Computed normals point along +z for this counter-clockwise face.
    assert!(m.normals.iter().all(|n| (n[2] - 1.0).abs() < 1e-6));
    assert!(import.report.warnings.iter().any(|w| w.contains("'edge'")));

    let path = write(&dir, "ascii.ply", ascii_ply());
    let import = load_ok(&path, &ImportOptions::default());
    let m = &import.meshes[0];
    assert_eq!(import.report.source_triangles, 3);
    assert_eq!(import.report.unreferenced_removed, 1);
    // The dart (0,0) (2,1) (0,2) (1,1) is a concave quad of area 1 (notch at (1,1)); a fan from
    // corner 0 would cover 3. Plus the triangle of area 0.5.
    assert!((total_area(m) - 1.5).abs() < 1e-6, "area {}", total_area(m));
    assert!(m.has_normals);
    for t in 0..m.triangle_count() {
        assert!(tri_normal(m, t)[2] > 0.0, "triangle {t} flipped");
    }
    // Truncated and out-of-range files: errors naming the file and the element.
    let mut text = ascii_ply();
    text = text.replace("3 5 6 7\n", "3 5 6 8\n");
    let path = write(&dir, "badindex.ply", &text);
    assert_msg(
        &load_err(&path),
        &["badindex.ply", "face 1", "index 8", "8 vertices"],
    );
    let path = write(
        &dir,
        "inf.ply",
        ascii_ply().replace("2 1 0 0 0 1\n", "2 inf 0 0 0 1\n"),
    );
    assert_msg(&load_err(&path), &["inf.ply", "vertex 1", "non-finite"]);
    let path = write(
        &dir,
        "syntax.ply",
        ascii_ply().replace("0 2 0 0 0 1\n", "0 2 zero 0 0 1\n"),
    );
    assert_msg(
        &load_err(&path),
        &[
            "syntax.ply",
            "line 15",
            "element 'vertex' 2",
            "property 'z'",
            "'zero'",
        ],
    );
    let mut b = binary_ply();
    let body = b.len() - (6 * 21 + 1 + 16 + 1 + 12 + 8);
    b[body + 21 + 4..body + 21 + 8].copy_from_slice(&f32::NAN.to_le_bytes()); // vertex 1, y
    let path = write(&dir, "nan.ply", &b);
    assert_msg(&load_err(&path), &["nan.ply", "vertex 1", "non-finite"]);
    // ply-rs's header grammar would panic on a number that overflows u64.
    let path = write(
        &dir,
        "huge.ply",
        ascii_ply().replace("element vertex 8", "element vertex 184467440737095516150"),
    );
    assert_msg(
        &load_err(&path),
        &["huge.ply", "header line 3", "too large"],
    );
    let b = binary_ply();
    let path = write(&dir, "short.ply", &b[..b.len() - 20]);
    assert_msg(&load_err(&path), &["short.ply", "face"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// The glTF test scene's binary buffer and JSON (without the buffer's `uri`).
///
/// Mesh 0 (unit square at z = 0, normals +z): a TRIANGLE_STRIP [0 1 2 3], a POINTS primitive and a
/// TRIANGLE_FAN [0 1 3 2]. Mesh 1: a non-indexed TRIANGLES triangle at z = 5 without normals.
/// Nodes: "Root" (scale 2) -> "Child" (translation x + 10, mesh 0), "Mirror" (scale x -1,
/// mesh 0), "Tri" (mesh 1).
fn gltf_scene(extra_root: &str) -> (Vec<u8>, String) {
    let mut bin = Vec::new();
    let f = |b: &mut Vec<u8>, vals: &[f32]| {
        vals.iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()))
    };
    f(
        &mut bin,
        &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0],
    ); // 0..48
    f(
        &mut bin,
        &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
    ); // 48..96
    for i in [0u16, 1, 2, 3, 0, 1, 3, 2] {
        bin.extend_from_slice(&i.to_le_bytes()); // 96..104 strip, 104..112 fan
    }
    f(&mut bin, &[0.0, 0.0, 5.0, 1.0, 0.0, 5.0, 0.0, 1.0, 5.0]); // 112..148
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}}, {extra_root}
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": [
    {{"name": "Root", "scale": [2, 2, 2], "children": [1, 2, 3]}},
    {{"name": "Child", "translation": [10, 0, 0], "mesh": 0}},
    {{"name": "Mirror", "scale": [-1, 1, 1], "mesh": 0}},
    {{"name": "Tri", "mesh": 1}}
  ],
  "meshes": [
    {{"name": "square", "primitives": [
      {{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2, "mode": 5}},
      {{"attributes": {{"POSITION": 0}}, "mode": 0}},
      {{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 3, "mode": 6}}
    ]}},
    {{"name": "tri", "primitives": [{{"attributes": {{"POSITION": 4}}}}]}}
  ],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 2, "componentType": 5123, "count": 4, "type": "SCALAR"}},
    {{"bufferView": 3, "componentType": 5123, "count": 4, "type": "SCALAR"}},
    {{"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 5], "max": [1, 1, 5]}}
  ],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 48, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 96, "byteLength": 8}},
    {{"buffer": 0, "byteOffset": 104, "byteLength": 8}},
    {{"buffer": 0, "byteOffset": 112, "byteLength": 36}}
  ],
  "buffers": [{{"byteLength": 148 BUFFER_URI}}]
}}"#
    );
    (bin, json)
}

fn gltf_with_data_uri() -> String {
    let (bin, json) = gltf_scene("");
    json.replace(
        "BUFFER_URI",
        &format!(
            r#", "uri": "data:application/octet-stream;base64,{}""#,
            base64(&bin)
        ),
    )
}

fn glb() -> Vec<u8> {
    let (bin, json) = gltf_scene("");
    glb_container(json.replace("BUFFER_URI", "").as_bytes(), Some(&bin))
}

/// A GLB file: header, the JSON chunk (space-padded to 4 bytes), the BIN chunk if any.
fn glb_container(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let mut json = json.to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + bin.map_or(0, |b| 8 + b.len());
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if let Some(bin) = bin {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
    }
    out
}

#[test]
fn gltf_hierarchy_strip_fan_mirror_and_split() {
    let dir = scratch("gltf");
    let path = write(&dir, "scene.gltf", gltf_with_data_uri());
    let import = load_ok(&path, &ImportOptions::default());
    let r = &import.report;
    // Per instance of mesh 0: strip 2 + fan 2; two instances; plus the non-indexed triangle.
    assert_eq!(r.source_triangles, 9);
    assert_eq!(r.degenerate_dropped, 0);
    assert!(
        r.warnings.iter().any(|w| w.contains("points or lines")),
        "{:?}",
        r.warnings
    );
    let m = &import.meshes[0];
    assert_eq!(m.triangle_count(), 9);
    assert!(!m.has_normals, "mesh 1 has no normals");
    assert!(!m.has_uvs);
    assert_eq!(m.materials.len(), 1);
    // World transforms: Child spans x 20..22, Mirror x -2..0, Tri z = 10; everything scaled by 2.
    let (lo, hi) = m.bounds().expect("bounds");
    assert_eq!((lo, hi), ([-2.0, 0.0, 0.0], [22.0, 2.0, 10.0]));
    assert!(
        (total_area(m) - (8.0 * 2.0 + 2.0)).abs() < 1e-9,
        "area {}",
        total_area(m)
    );
    // Winding fixed under the mirror: every triangle's geometric normal agrees with its
    // (transformed, inverse-transpose) vertex normals, which all point to +z.
    for t in 0..m.triangle_count() {
        let g = tri_normal(m, t);
        assert!(g[2] > 0.0, "triangle {t} wound the wrong way: {g:?}");
        for k in 0..3 {
            let n = m.normals[m.indices[3 * t + k] as usize];
            assert!((n[2] - 1.0).abs() < 1e-6, "normal {n:?}");
        }
    }
    // The strip and fan cover the same square: welding leaves 4 vertices per instance + 3.
    assert_eq!(m.positions.len(), 4 + 4 + 3);
    assert_eq!(r.vertices_welded, 8);

    // One mesh per node, named after the node.
    let import = load_ok(
        &path,
        &ImportOptions {
            split_nodes: true,
            ..Default::default()
        },
    );
    let names: Vec<&str> = import.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["Child", "Mirror", "Tri"]);
    let counts: Vec<usize> = import.meshes.iter().map(Mesh::triangle_count).collect();
    assert_eq!(counts, [4, 4, 1]);
    assert_eq!(import.report.source_triangles, 9);
    let (lo, hi) = import.meshes[1].bounds().expect("bounds");
    assert_eq!((lo, hi), ([-2.0, 0.0, 0.0], [0.0, 2.0, 0.0]));
    assert!(import.meshes[0].has_normals && !import.meshes[2].has_normals);

    // The same scene as .GLB (upper-case extension) loads identically.
    let path = write(&dir, "scene.GLB", glb());
    let (merged, report) = mesh::load_mesh(&path).expect("glb");
    assert_eq!(report.source_triangles, 9);
    assert_eq!(merged.triangle_count(), 9);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn gltf_accessor_features_stride_sparse_normalized_u8_indices() {
    // Interleaved position+normal (stride 24), u8 indices, a sparse override of vertex 2's position,
    // normalized u16 texture coordinates, a TRIANGLE_FAN, and a node matrix translating x by 5.
    let mut b = Vec::new();
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        for c in p.iter().chain(&[0.0, 0.0, 1.0]) {
            b.extend_from_slice(&c.to_le_bytes()); // 0..96
        }
    }
    b.extend_from_slice(&[0, 1, 2, 3, 0, 0, 0, 0]); // 96..100 indices, padding
    b.extend_from_slice(&[2, 0, 0, 0]); // 104..106 sparse index 2 (u16), padding
    for c in [2.0f32, 2.0, 0.0] {
        b.extend_from_slice(&c.to_le_bytes()); // 108..120 sparse value
    }
    for t in [0u16, 0, 65535, 0, 65535, 65535, 0, 65535] {
        b.extend_from_slice(&t.to_le_bytes()); // 120..136
    }
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 5,0,0,1]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 3}}, "indices": 2, "mode": 6}}]}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [2,2,0],
      "sparse": {{"count": 1, "indices": {{"bufferView": 2, "componentType": 5123}}, "values": {{"bufferView": 3}}}}}},
    {{"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 1, "componentType": 5121, "count": 4, "type": "SCALAR"}},
    {{"bufferView": 4, "componentType": 5123, "normalized": true, "count": 4, "type": "VEC2"}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 96, "byteStride": 24}},
    {{"buffer": 0, "byteOffset": 96, "byteLength": 4}},
    {{"buffer": 0, "byteOffset": 104, "byteLength": 2}},
    {{"buffer": 0, "byteOffset": 108, "byteLength": 12}},
    {{"buffer": 0, "byteOffset": 120, "byteLength": 16}}],
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}]}}"#,
        b.len(),
        base64(&b)
    );
    let dir = scratch("gltf-accessors");
    let import = load_ok(&write(&dir, "sparse.gltf", json), &ImportOptions::default());
    let m = &import.meshes[0];
    assert_eq!(m.triangle_count(), 2);
    assert!(m.has_normals && m.has_uvs);
    assert_eq!(
        m.positions,
        [
            [5.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [7.0, 2.0, 0.0],
            [5.0, 1.0, 0.0]
        ]
    );
    assert_eq!(m.uvs, [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    // Fan (1 2 0) (2 3 0) over the kite (0,0) (1,0) (2,2) (0,1): area 2.
    assert_eq!(m.indices, [1, 2, 0, 2, 3, 0]);
    assert!((total_area(m) - 2.0).abs() < 1e-9);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn gltf_errors_name_the_file_and_the_problem() {
    let dir = scratch("gltf-errors");
    // Draco required.
    let (_, json) = gltf_scene(
        r#""extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"],"#,
    );
    let path = write(
        &dir,
        "draco.gltf",
        json.replace("BUFFER_URI", r#", "uri": "draco.bin""#),
    );
    assert_msg(
        &load_err(&path),
        &["draco.gltf", "Draco compression is not supported"],
    );
    // Draco only on a primitive.
    let json = gltf_with_data_uri().replace(
        r#""indices": 2, "mode": 5}"#,
        r#""indices": 2, "mode": 5, "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}"#,
    );
    let path = write(&dir, "draco_prim.gltf", json);
    assert_msg(
        &load_err(&path),
        &["draco_prim.gltf", "Draco compression is not supported"],
    );
    // Missing buffer file.
    let (_, json) = gltf_scene("");
    let path = write(
        &dir,
        "nobin.gltf",
        json.replace("BUFFER_URI", r#", "uri": "not%20here.bin""#),
    );
    assert_msg(&load_err(&path), &["nobin.gltf", "not here.bin", "missing"]);
    // Buffer shorter than its byteLength.
    let (bin, json) = gltf_scene("");
    write(&dir, "short.bin", &bin[..100]);
    let path = write(
        &dir,
        "short.gltf",
        json.replace("BUFFER_URI", r#", "uri": "short.bin""#),
    );
    assert_msg(&load_err(&path), &["short.gltf", "buffer 0", "byteLength"]);
    // Index out of range in the strip's index accessor.
    let (mut bin, json) = gltf_scene("");
    bin[98..100].copy_from_slice(&9u16.to_le_bytes());
    write(&dir, "oob.bin", &bin);
    let path = write(
        &dir,
        "oob.gltf",
        json.replace("BUFFER_URI", r#", "uri": "oob.bin""#),
    );
    assert_msg(
        &load_err(&path),
        &[
            "oob.gltf",
            "mesh 'square' primitive 0",
            "index accessor 2",
            "element 1",
            "index 9",
            "4 vertices",
        ],
    );
    // Only points.
    let json = gltf_with_data_uri()
        .replace(r#""mode": 5}"#, r#""mode": 0}"#)
        .replace(r#""mode": 6}"#, r#""mode": 1}"#)
        .replace(
            r#"{"attributes": {"POSITION": 4}}"#,
            r#"{"attributes": {"POSITION": 4}, "mode": 3}"#,
        );
    let path = write(&dir, "points.gltf", json);
    assert_msg(
        &load_err(&path),
        &["points.gltf", "no triangles", "points and lines"],
    );
    // Unknown extension, garbage.
    assert_msg(
        &load_err(&write(&dir, "mesh.fbx", "x")),
        &["mesh.fbx", "unknown mesh format", "fbx"],
    );
    assert_msg(
        &load_err(&write(&dir, "junk.gltf", "{ not json")),
        &["junk.gltf", "invalid glTF"],
    );
    assert_msg(
        &load_err(&dir.join("absent.obj")),
        &["absent.obj", "cannot read"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

fn binary_stl() -> Vec<u8> {
    // Two triangles sharing an edge (a unit square).
    let mut b = vec![0u8; 80];
    b[..5].copy_from_slice(b"solid"); // a binary file whose header starts with "solid"
    b.extend_from_slice(&2u32.to_le_bytes());
    for tri in [
        [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ] {
        for _ in 0..3 {
            b.extend_from_slice(&0f32.to_le_bytes());
        }
        for p in tri {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        b.extend_from_slice(&0u16.to_le_bytes());
    }
    b
}

#[test]
fn stl_binary_with_solid_header_and_off_ngons() {
    let dir = scratch("stl-off");
    let path = write(&dir, "square.stl", binary_stl());
    let import = load_ok(&path, &ImportOptions::default());
    assert_eq!(import.report.source_triangles, 2);
    assert_eq!(import.report.vertices_welded, 2);
    assert_eq!(import.meshes[0].positions.len(), 4);
    let b = binary_stl();
    assert_msg(
        &load_err(&write(&dir, "cut.stl", &b[..b.len() - 10])),
        &["cut.stl", "declares 2 triangles"],
    );

    // OFF with a comment, counts on the header line, a concave pentagon with a colour after it.
    let off = "OFF 5 1 0\n# arrow\n0 0 0\n2 1 0\n0 2 0\n1 1 0\n-1 1 0\n5 0 1 2 3 4 255 0 0\n";
    let import = load_ok(&write(&dir, "arrow.off", off), &ImportOptions::default());
    let m = &import.meshes[0];
    assert_eq!(import.report.source_triangles, 3);
    // (0,0) (2,1) (0,2) (1,1) (-1,1): area 2 - 1 + 1 = 2 by the shoelace formula.
    assert!((total_area(m) - 2.0).abs() < 1e-9, "area {}", total_area(m));
    assert_msg(
        &load_err(&write(
            &dir,
            "oob.off",
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
        )),
        &["oob.off", "line 6", "face 0", "index 3", "3 vertices"],
    );
    assert_msg(
        &load_err(&write(
            &dir,
            "nan.off",
            "OFF\n3 1 0\n0 0 0\nNaN 0 0\n0 1 0\n3 0 1 2\n",
        )),
        &["nan.off", "vertex 1", "line 4", "non-finite"],
    );
    assert_msg(
        &load_err(&write(
            &dir,
            "line.off",
            "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n",
        )),
        &["line.off", "degenerate"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn in_memory_import_equals_file_import_and_has_no_external_files() {
    let dir = scratch("in-memory");
    let cases: Vec<(&str, mesh::Format, Vec<u8>)> = vec![
        ("scene.glb", mesh::Format::Gltf, glb()),
        (
            "scene.gltf",
            mesh::Format::Gltf,
            gltf_with_data_uri().into_bytes(),
        ),
        ("bin.ply", mesh::Format::Ply, binary_ply()),
        ("ascii.ply", mesh::Format::Ply, ascii_ply().into_bytes()),
        ("square.stl", mesh::Format::Stl, binary_stl()),
        (
            "arrow.off",
            mesh::Format::Off,
            b"OFF 5 1 0\n0 0 0\n2 1 0\n0 2 0\n1 1 0\n-1 1 0\n5 0 1 2 3 4\n".to_vec(),
        ),
        (
            "quad.obj",
            mesh::Format::Obj,
            b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n".to_vec(),
        ),
    ];
    for (name, format, bytes) in &cases {
        let path = write(&dir, name, bytes);
        let from_file = load_ok(&path, &ImportOptions::default());
        let from_memory = mesh::load_bytes(bytes, *format, name, &ImportOptions::default())
            .unwrap_or_else(|e| panic!("{name} from memory: {e}"));
        assert_eq!(from_memory.report, {
            let mut r = from_file.report.clone();
            let prefix = format!("{}: ", path.display());
            for w in &mut r.warnings {
                *w = w.replace(&prefix, &format!("{name}: "));
            }
            r
        });
        assert_eq!(from_memory.meshes.len(), from_file.meshes.len());
        for (a, b) in from_memory.meshes.iter().zip(&from_file.meshes) {
            assert_eq!(a.name, b.name);
            assert_eq!(
                (&a.positions, &a.normals, &a.uvs, &a.indices),
                (&b.positions, &b.normals, &b.uvs, &b.indices)
            );
        }
    }
    // Nothing is read from disk: an external buffer is missing (the file import of the same JSON
    // finds it), a material library is a warning.
    let (bin, json) = gltf_scene("");
    write(&dir, "ext.bin", &bin);
    let json = json.replace("BUFFER_URI", r#", "uri": "ext.bin""#);
    load_ok(&write(&dir, "ext.gltf", &json), &ImportOptions::default());
    match mesh::load_bytes(
        json.as_bytes(),
        mesh::Format::Gltf,
        "ext.gltf",
        &ImportOptions::default(),
    ) {
        Err(e @ ImportError::MissingBuffer { .. }) => {
            assert_msg(&e, &["ext.gltf", "ext.bin", "missing"])
        }
        other => panic!("expected a missing buffer, got {other:?}"),
    }
    let obj = b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let import = mesh::load_bytes(obj, mesh::Format::Obj, "m.obj", &ImportOptions::default())
        .expect("obj without its mtl");
    assert!(
        import
            .report
            .warnings
            .iter()
            .any(|w| w.contains("m.obj") && w.contains("m.mtl")),
        "{:?}",
        import.report.warnings
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn weld_and_drop_degenerate_semantics() {
    let mut m = Mesh {
        name: "t".into(),
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [-0.0, 0.0, 0.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 6],
        uvs: vec![
            [0.0, 0.0],
            [0.0, 0.0],
            [0.0, 0.0],
            [0.0, 0.0],
            [0.0, 0.0],
            [0.0, 0.0],
        ],
        // ok, repeated index, collinear (0, 3, 4) on y = 0, ok using the duplicate of vertex 1.
        indices: vec![0, 1, 2, 1, 1, 2, 0, 3, 4, 5, 3, 2],
        material_ids: vec![0, 1, 2, 3],
        materials: vec![Default::default(); 4],
        has_normals: true,
        has_uvs: false,
    };
    assert_eq!(mesh::drop_degenerate(&mut m), 2);
    assert_eq!(m.material_ids, [0, 3]);
    // Vertex 3 equals vertex 1 bit for bit; -0.0 differs from 0.0 in its bits and is kept.
    assert_eq!(mesh::weld(&mut m), 1);
    assert_eq!(m.indices, [0, 1, 2, 4, 1, 2]);
    assert_eq!(mesh::remove_unreferenced(&mut m), 1); // the former vertex 4 at (2, 0, 0)
    assert_eq!(m.positions.len(), 4);
    m.validate().expect("valid");
}

// ---------------------------------------------------------------------------------------------
// Nothing dropped without a word: counts that make no triangle, skipped elements, trailing data.

/// The warnings of `import` that contain every needle.
fn warnings_with<'a>(import: &'a mesh::Import, needles: &[&str]) -> Vec<&'a String> {
    import
        .report
        .warnings
        .iter()
        .filter(|w| needles.iter().all(|n| w.contains(n)))
        .collect()
}

/// A glTF whose primitives have counts that are not a multiple of 3 (or too short for a strip):
/// mesh "leftovers": 0 = non-indexed TRIANGLES over 4 vertices, 1 = TRIANGLES with 5 indices,
/// 2 = TRIANGLE_STRIP with 2 indices, 3 = TRIANGLE_FAN with 4 indices (complete); mesh "whole": a
/// non-indexed triangle over the first 3 vertices. Node 0 instances "leftovers" twice (nodes 0 and
/// 1), so that a warning per primitive, not per instance, is checked.
fn gltf_leftovers() -> String {
    let mut b = Vec::new();
    for c in [
        0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0,
    ] {
        b.extend_from_slice(&c.to_le_bytes()); // 0..48: 4 positions
    }
    for i in [0u16, 1, 2, 1, 3, 0, 1, 0, 1, 2, 3, 0] {
        b.extend_from_slice(&i.to_le_bytes()); // 48..58 list, 58..60 pad, 60..64 strip, 64..72 fan
    }
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0, 1, 2]}}],
  "nodes": [{{"mesh": 0}}, {{"mesh": 0, "translation": [5, 0, 0]}}, {{"mesh": 1}}],
  "meshes": [
    {{"name": "leftovers", "primitives": [
      {{"attributes": {{"POSITION": 0}}}},
      {{"attributes": {{"POSITION": 0}}, "indices": 1}},
      {{"attributes": {{"POSITION": 0}}, "indices": 2, "mode": 5}},
      {{"attributes": {{"POSITION": 0}}, "indices": 3, "mode": 6}}]}},
    {{"name": "whole", "primitives": [{{"attributes": {{"POSITION": 4}}}}]}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 1, "componentType": 5123, "count": 5, "type": "SCALAR"}},
    {{"bufferView": 2, "componentType": 5123, "count": 2, "type": "SCALAR"}},
    {{"bufferView": 3, "componentType": 5123, "count": 4, "type": "SCALAR"}},
    {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 48, "byteLength": 10}},
    {{"buffer": 0, "byteOffset": 60, "byteLength": 4}},
    {{"buffer": 0, "byteOffset": 64, "byteLength": 8}}],
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}]}}"#,
        b.len(),
        base64(&b)
    )
}

#[test]
fn gltf_counts_not_a_multiple_of_3_are_warned_with_what_was_dropped() {
    let dir = scratch("gltf-leftovers");
    let path = write(&dir, "leftovers.gltf", gltf_leftovers());
    let import = load_ok(&path, &ImportOptions::default());
    // Per instance of "leftovers": 1 (4 vertices) + 1 (5 indices) + 0 (strip of 2) + 2 (fan of 4);
    // two instances, plus "whole".
    assert_eq!(import.report.source_triangles, 2 * (1 + 1 + 2) + 1);
    let w = |needles: &[&str]| warnings_with(&import, needles).len();
    let all = ["leftovers.gltf", "mesh 'leftovers'"];
    assert_eq!(
        w(&[
            &all[..],
            &[
                "primitive 0",
                "TRIANGLES",
                "vertex count (non-indexed) 4 is not a multiple of 3",
                "the last 1 vertices dropped"
            ]
        ]
        .concat()),
        1,
        "{:?}",
        import.report.warnings
    );
    assert_eq!(
        w(&[
            &all[..],
            &[
                "primitive 1",
                "index count 5 is not a multiple of 3",
                "the last 2 indices dropped"
            ]
        ]
        .concat()),
        1,
        "{:?}",
        import.report.warnings
    );
    assert_eq!(
        w(&[
            &all[..],
            &[
                "primitive 2",
                "TRIANGLE_STRIP",
                "index count 2 is less than 3",
                "the last 2 indices dropped"
            ]
        ]
        .concat()),
        1,
        "{:?}",
        import.report.warnings
    );
    // The complete fan and the complete triangle are not mentioned; nothing else dropped.
    assert_eq!(w(&["dropped"]), 3, "{:?}", import.report.warnings);
    assert_eq!(w(&["primitive 3"]), 0);
    assert_eq!(w(&["mesh 'whole'"]), 0);

    // The same from memory names the given file name.
    let import = mesh::load_bytes(
        gltf_leftovers().as_bytes(),
        mesh::Format::Gltf,
        "in-memory.gltf",
        &ImportOptions::default(),
    )
    .expect("loads from memory");
    assert_eq!(
        warnings_with(&import, &["in-memory.gltf", "mesh 'leftovers'", "dropped"]).len(),
        3
    );
    // A file with complete primitives warns about no dropped corners.
    let clean = load_ok(
        &write(&dir, "clean.gltf", gltf_with_data_uri()),
        &ImportOptions::default(),
    );
    assert!(warnings_with(&clean, &["dropped"]).is_empty());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn obj_ply_off_stl_warn_about_what_they_skip() {
    let dir = scratch("skips");
    // OBJ: a point, a polyline of 3 points (tobj would make it a triangle), a 2-vertex face, and
    // one real triangle.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\np 4\nl 1 2 3\nf 1 4\nf 1 2 3\n";
    let import = load_ok(&write(&dir, "skips.obj", obj), &ImportOptions::default());
    assert_eq!(import.report.source_triangles, 1, "the polyline is no face");
    for needles in [
        &["skips.obj", "skipped 1 point elements ('p')"][..],
        &["skips.obj", "skipped 1 polyline elements ('l')"],
        &["skips.obj", "skipped 1 faces with fewer than 3 vertices"],
    ] {
        assert_eq!(
            warnings_with(&import, needles).len(),
            1,
            "{needles:?} in {:?}",
            import.report.warnings
        );
    }
    let plain = load_ok(
        &write(&dir, "plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        &ImportOptions::default(),
    );
    assert!(
        plain.report.warnings.is_empty(),
        "{:?}",
        plain.report.warnings
    );

    // PLY: faces beyond the declared count (ASCII) and bytes after the last element (binary).
    let ascii = ascii_ply() + "3 0 1 2\n";
    let import = load_ok(&write(&dir, "extra.ply", ascii), &ImportOptions::default());
    assert_eq!(import.report.source_triangles, 3);
    assert_eq!(
        warnings_with(
            &import,
            &[
                "extra.ply",
                "data (from line 23) after the declared elements ignored"
            ]
        )
        .len(),
        1,
        "{:?}",
        import.report.warnings
    );
    let mut bin = binary_ply();
    bin.extend_from_slice(&[0u8; 7]);
    let import = load_ok(
        &write(&dir, "extra_bin.ply", bin),
        &ImportOptions::default(),
    );
    assert_eq!(
        warnings_with(
            &import,
            &[
                "extra_bin.ply",
                "7 bytes after the declared elements ignored"
            ]
        )
        .len(),
        1,
        "{:?}",
        import.report.warnings
    );
    let clean = load_ok(
        &write(&dir, "clean.ply", ascii_ply()),
        &ImportOptions::default(),
    );
    assert!(
        clean.report.warnings.is_empty(),
        "{:?}",
        clean.report.warnings
    );

    // OFF: two lines past the declared faces (a face count that undercounts), and a 2-corner face.
    let off = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n2 0 1\n3 1 3 2\n3 0 2 3\n";
    let import = load_ok(&write(&dir, "extra.off", off), &ImportOptions::default());
    assert_eq!(import.report.source_triangles, 1);
    for needles in [
        &[
            "extra.off",
            "2 line(s) after the 2 declared faces ignored (from line 9)",
        ][..],
        &["extra.off", "skipped 1 faces with fewer than 3 vertices"],
    ] {
        assert_eq!(
            warnings_with(&import, needles).len(),
            1,
            "{needles:?} in {:?}",
            import.report.warnings
        );
    }

    // STL: a facet with 2 vertices (ASCII), bytes past the declared triangles (binary).
    let stl = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n\
               facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid s\n";
    let import = load_ok(&write(&dir, "short.stl", stl), &ImportOptions::default());
    assert_eq!(import.report.source_triangles, 1);
    assert_eq!(
        warnings_with(
            &import,
            &[
                "short.stl",
                "skipped 1 of 2 facets with fewer than 3 vertices"
            ]
        )
        .len(),
        1,
        "{:?}",
        import.report.warnings
    );
    let mut bin = binary_stl();
    bin.extend_from_slice(&[0u8; 30]);
    let import = load_ok(&write(&dir, "long.stl", bin), &ImportOptions::default());
    assert_eq!(
        warnings_with(
            &import,
            &[
                "long.stl",
                "30 bytes after the 2 declared triangles ignored"
            ]
        )
        .len(),
        1,
        "{:?}",
        import.report.warnings
    );
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------------------------
// Hostile glTF: documents the gltf crate's validation passes but its accessors unwrap on.

/// The GLB test scene with a material whose base-colour texture shows image `image` (JSON).
fn glb_with_image(image: &str) -> Vec<u8> {
    let (bin, json) = gltf_scene(&format!(
        r#""materials": [{{"name": "m", "pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}],
  "textures": [{{"source": 0}}], "images": [{image}],"#
    ));
    glb_container(json.replace("BUFFER_URI", "").as_bytes(), Some(&bin))
}

/// Regression (found by a mutation fuzzer): an image with neither `uri` nor `bufferView` made
/// `gltf::Image::source` panic (gltf-1.4.1 src/image.rs:128, `uri.unwrap()`).
#[test]
fn gltf_image_without_uri_or_buffer_view_is_a_warning_not_a_panic() {
    let bytes = glb_with_image("{}");
    let import = mesh::load_bytes(
        &bytes,
        mesh::Format::Gltf,
        "noimage.glb",
        &ImportOptions::default(),
    )
    .expect("the mesh loads without its texture");
    assert_eq!(import.report.source_triangles, 9);
    assert_eq!(
        warnings_with(
            &import,
            &[
                "noimage.glb",
                "material 'm'",
                "base-colour",
                "image 0",
                "neither"
            ]
        )
        .len(),
        1,
        "{:?}",
        import.report.warnings
    );
    assert_eq!(import.meshes[0].materials[0].base_color_texture, None);
}

/// Regression: an image with a `bufferView` but no `mimeType` made `gltf::Image::source` panic
/// (gltf-1.4.1 src/image.rs:125, `mime_type.unwrap()`).
#[test]
fn gltf_image_in_a_buffer_view_without_mime_type_is_a_warning_not_a_panic() {
    let bytes = glb_with_image(r#"{"bufferView": 0}"#);
    let import = mesh::load_bytes(
        &bytes,
        mesh::Format::Gltf,
        "nomime.glb",
        &ImportOptions::default(),
    )
    .expect("the mesh loads without its texture");
    assert_eq!(
        warnings_with(&import, &["nomime.glb", "material 'm'", "embedded"]).len(),
        1,
        "{:?}",
        import.report.warnings
    );
}

/// Regression: a GLB whose JSON chunk is itself a GLB header with a length under 12 made the gltf
/// crate's GLB parser subtract with overflow (gltf-1.4.1 src/binary.rs:252), a panic in debug
/// builds. The JSON chunk is now parsed as JSON only.
#[test]
fn gltf_nested_glb_header_in_the_json_chunk_is_an_error_not_a_panic() {
    let mut inner = b"glTF".to_vec();
    inner.extend_from_slice(&2u32.to_le_bytes());
    inner.extend_from_slice(&4u32.to_le_bytes());
    let bytes = glb_container(&inner, None);
    match mesh::load_bytes(
        &bytes,
        mesh::Format::Gltf,
        "nested.glb",
        &ImportOptions::default(),
    ) {
        Err(e) => assert_msg(&e, &["nested.glb", "invalid glTF"]),
        Ok(_) => panic!("a GLB header is no JSON document"),
    }
}

/// A few bytes of JSON must not ask for gigabytes: an accessor without a buffer view (zeros plus
/// sparse substitutions) of more than 2^20 elements is refused.
#[test]
fn gltf_huge_accessor_without_buffer_view_is_refused() {
    let gltf = |count: usize| {
        let mut b = Vec::new();
        b.extend_from_slice(&1u32.to_le_bytes());
        for c in [1.0f32, 0.0, 0.0] {
            b.extend_from_slice(&c.to_le_bytes());
        }
        format!(
            r#"{{"asset": {{"version": "2.0"}}, "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "accessors": [{{"componentType": 5126, "count": {count}, "type": "VEC3",
    "sparse": {{"count": 1, "indices": {{"bufferView": 0, "componentType": 5125}}, "values": {{"bufferView": 1}}}}}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 4}}, {{"buffer": 0, "byteOffset": 4, "byteLength": 12}}],
  "buffers": [{{"byteLength": 16, "uri": "data:application/octet-stream;base64,{}"}}]}}"#,
            base64(&b)
        )
    };
    let load = |count| {
        mesh::load_bytes(
            gltf(count).as_bytes(),
            mesh::Format::Gltf,
            "zeros.gltf",
            &ImportOptions::default(),
        )
    };
    match load((1 << 20) + 1) {
        Err(e) => assert_msg(
            &e,
            &[
                "zeros.gltf",
                "POSITION accessor 0",
                "1048577 elements without a buffer view",
            ],
        ),
        Ok(_) => panic!("2^20 + 1 zero vertices should be refused"),
    }
    // Within the limit the accessor is read: zeros with vertex 1 moved, so the only triangle
    // (0, 1, 2) is degenerate.
    match load(6) {
        Err(e) => assert_msg(&e, &["zeros.gltf", "all 2 triangles are degenerate"]),
        Ok(_) => panic!("only degenerate triangles"),
    }
}

/// Regression (cargo fuzz, import_obj): tobj turned a relative reference past the start into an
/// index near `usize::MAX` and multiplied it (overflow panic, tobj-4.0.5 src/lib.rs:860), and took a
/// `0` texture-coordinate or normal reference for none. Every reference is now checked first; a
/// forward reference within the file stays allowed, as tobj allows it.
#[test]
fn obj_references_past_either_end_or_zero_are_errors_not_panics() {
    let load = |obj: &str| {
        mesh::load_bytes(
            obj.as_bytes(),
            mesh::Format::Obj,
            "refs.obj",
            &ImportOptions::default(),
        )
    };
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
    for (face, line, needle) in [
        (
            "f 1/1/-2 2/1/1 3/1/1",
            6,
            "bad normal reference '-2' (1 defined so far)",
        ),
        (
            "f 1/-9223372036854775807 2 3",
            6,
            "bad texture coordinate reference",
        ),
        (
            "f -4 -3 -2",
            6,
            "bad vertex reference '-4' (3 defined so far)",
        ),
        (
            "f 1/0 2/1 3/1",
            6,
            "bad texture coordinate reference '0' (1 defined)",
        ),
        ("f 1//0 2//1 3//1", 6, "bad normal reference '0'"),
        ("f 1 2 4", 6, "bad vertex reference '4' (3 defined)"),
    ] {
        match load(&format!("{tri}{face}\n")) {
            Err(e) => assert_msg(&e, &["refs.obj", &format!("line {line}"), needle]),
            Ok(_) => panic!("{face} should be refused"),
        }
    }
    // A face may refer forward to a vertex defined later in the file.
    let import = load("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n").expect("forward reference");
    assert_eq!(import.report.source_triangles, 1);
}

/// Regression: ear clipping a self-intersecting n-gon cost O(n^3) (a 2,000-corner star polygon
/// took 9 s to import, a 20,000-corner one hours); its work is bounded now, the rest fanned with a
/// warning.
#[test]
fn self_intersecting_polygon_imports_in_bounded_time_with_a_warning() {
    let n = 3001usize;
    let k = n / 2 - 1;
    let mut off = format!("OFF\n{n} 1 0\n");
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        let r = 1.0 + 0.3 * (i % 3) as f64;
        off += &format!("{:.5} {:.5} 0\n", r * a.cos(), r * a.sin());
    }
    off += &n.to_string();
    for i in 0..n {
        off += &format!(" {}", (i * k) % n);
    }
    off += "\n";
    let start = std::time::Instant::now();
    let import = mesh::load_bytes(
        off.as_bytes(),
        mesh::Format::Off,
        "star.off",
        &ImportOptions::default(),
    )
    .expect("the star loads");
    assert!(
        start.elapsed().as_secs_f64() < 10.0,
        "{:?}",
        start.elapsed()
    );
    assert_eq!(import.report.source_triangles, n - 2);
    assert_eq!(
        warnings_with(
            &import,
            &["star.off", "1 polygon(s) too costly to ear-clip"]
        )
        .len(),
        1,
        "{:?}",
        import.report.warnings
    );
}

// ---------------------------------------------------------------------------------------------
// Fuzz: truncations and byte flips never panic; whatever loads is valid.

#[test]
fn fuzzed_files_never_panic() {
    let dir = scratch("fuzz");
    let assets = assets_dir();
    let read = |rel: &str| std::fs::read(assets.join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"));
    let (pts, _) = u_shape_3d();
    let mut obj = String::new();
    for p in &pts {
        obj += &format!("v {} {} {}\nvt 0.5 0.5\nvn 0 0 1\n", p[0], p[1], p[2]);
    }
    obj += "mtllib m.mtl\nusemtl a\nf 1/1/1 2/2/2 3/3/3 4/4/4 5/5/5 6/6/6 7/7/7 8/8/8\n";
    write(&dir, "m.mtl", "newmtl a\nKd 1 0.5 0\nmap_Kd tex.png\n");
    let seeds: Vec<(&str, Vec<u8>)> = vec![
        ("obj", obj.into_bytes()),
        ("ply", binary_ply()),
        ("ply", ascii_ply().into_bytes()),
        ("gltf", gltf_with_data_uri().into_bytes()),
        ("glb", glb()),
        ("stl", binary_stl()),
        ("stl", read("hard/triangle_with_two_solids.stl")),
        ("off", read("hard/fold.off")),
        ("off", read("hard/quads_to_stitch.off")),
    ];
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let (mut ok, mut err) = (0, 0);
    for (s, (ext, bytes)) in seeds.iter().enumerate() {
        let mut variants: Vec<Vec<u8>> = Vec::new();
        let step = (bytes.len() / 48).max(1);
        for cut in (0..bytes.len()).step_by(step) {
            variants.push(bytes[..cut].to_vec());
        }
        // Runs of digits (counts, offsets, indices) replaced by extreme values.
        let runs: Vec<usize> = (0..bytes.len())
            .filter(|&i| bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_digit()))
            .collect();
        for _ in 0..if runs.is_empty() { 0 } else { 32 } {
            let start = runs[(next() % runs.len() as u64) as usize];
            let end = (start..bytes.len())
                .find(|&i| !bytes[i].is_ascii_digit())
                .unwrap_or(bytes.len());
            let value: &[u8] = [
                &b"0"[..],
                b"3",
                b"65535",
                b"4294967296",
                b"18446744073709551616",
            ][(next() % 5) as usize];
            let mut v = bytes.clone();
            v.splice(start..end, value.iter().copied());
            variants.push(v);
        }
        for _ in 0..48 {
            let mut v = bytes.clone();
            for _ in 0..1 + next() % 3 {
                let i = (next() % bytes.len() as u64) as usize;
                v[i] ^= 1 << (next() % 8);
                if next() % 4 == 0 {
                    v[i] = [b'-', b'9', b'e', 0xff, b'\n', b' '][(next() % 6) as usize];
                }
            }
            variants.push(v);
        }
        for (k, v) in variants.iter().enumerate() {
            let path = write(&dir, &format!("f{s}_{k}.{ext}"), v);
            match mesh::load(&path, &ImportOptions::default()) {
                Ok(import) => {
                    ok += 1;
                    for m in &import.meshes {
                        m.validate()
                            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                        assert!(m.triangle_count() > 0);
                    }
                }
                Err(e) => {
                    err += 1;
                    assert!(
                        e.to_string().contains(&format!("f{s}_{k}.{ext}")),
                        "error must name the file: {e}"
                    );
                }
            }
            std::fs::remove_file(&path).ok();
        }
    }
    // Both outcomes must occur, or the fuzzing tested nothing.
    assert!(ok > 20 && err > 20, "ok {ok}, err {err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn patch_materials_cut_a_mesh_into_equal_coherent_patches() {
    let (mut mesh, _) =
        vgeo::mesh::load_mesh(&common::assets().join("spot.obj")).expect("spot loads");
    let tris = mesh.triangle_count();
    vgeo::mesh::assign_patch_materials(&mut mesh, 64);
    mesh.validate().expect("still valid");
    assert_eq!(mesh.materials.len(), 64);
    let mut counts = vec![0usize; 64];
    for &m in &mesh.material_ids {
        counts[m as usize] += 1;
    }
    let per = tris.div_ceil(64);
    assert!(counts[..63].iter().all(|&c| c == per), "{counts:?}");
    assert!(counts[63] >= 1 && counts[63] <= per);
    // Coherent: a patch's bounding box is far smaller than the mesh's (Morton runs).
    let (lo, hi) = mesh.bounds().expect("bounds");
    let diag = |a: [f32; 3], b: [f32; 3]| (0..3).map(|k| (b[k] - a[k]).powi(2)).sum::<f32>().sqrt();
    let mut boxes = vec![([f32::MAX; 3], [f32::MIN; 3]); 64];
    for (t, &m) in mesh.material_ids.iter().enumerate() {
        for v in 0..3 {
            let p = mesh.positions[mesh.indices[3 * t + v] as usize];
            let b = &mut boxes[m as usize];
            for (k, c) in p.iter().enumerate() {
                b.0[k] = b.0[k].min(*c);
                b.1[k] = b.1[k].max(*c);
            }
        }
    }
    let mean: f32 = boxes.iter().map(|b| diag(b.0, b.1)).sum::<f32>() / 64.0;
    assert!(mean < 0.5 * diag(lo, hi), "mean patch diagonal {mean}");
    // Distinct colours, deterministic.
    let mut again = mesh.clone();
    vgeo::mesh::assign_patch_materials(&mut again, 64);
    assert_eq!(again.material_ids, mesh.material_ids);
    assert_ne!(mesh.materials[0].base_color, mesh.materials[32].base_color);
    // More materials than triangles: one per triangle.
    let mut tiny = mesh.clone();
    tiny.indices.truncate(9);
    tiny.material_ids.truncate(3);
    vgeo::mesh::assign_patch_materials(&mut tiny, 64);
    assert_eq!(tiny.materials.len(), 3);
}

/// Meshes without normals get crease-angle normals: a cube's 90-degree edges split its 8 corners
/// into 24 flat-shaded vertices at the default 60 degrees; 180 degrees shades it smoothly.
#[test]
fn generated_normals_split_at_creases() {
    let dir = scratch("crease");
    let off = "OFF\n8 6 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n\
               4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
    let path = write(&dir, "cube.off", off);
    let flat = load_ok(&path, &ImportOptions::default());
    assert_eq!(flat.report.crease_splits, 16);
    let m = &flat.meshes[0];
    assert_eq!(m.positions.len(), 24);
    for tri in m.indices.chunks_exact(3) {
        let p: [glam::Vec3; 3] =
            std::array::from_fn(|k| glam::Vec3::from(m.positions[tri[k] as usize]));
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        for &i in tri {
            let n = glam::Vec3::from(m.normals[i as usize]);
            assert!(n.dot(face) > 0.9999, "corner normal {n} on face {face}");
        }
    }
    let smooth = load_ok(
        &path,
        &ImportOptions {
            crease_deg: 180.0,
            ..Default::default()
        },
    );
    assert_eq!(smooth.report.crease_splits, 0);
    assert_eq!(smooth.meshes[0].positions.len(), 8);
    // A source with normals keeps them.
    let helmet = load_ok(
        &assets_dir().join("gltf/FlightHelmet/FlightHelmet.gltf"),
        &ImportOptions::default(),
    );
    assert_eq!(helmet.report.crease_splits, 0);
}
