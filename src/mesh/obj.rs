//! OBJ importer via `tobj`, loading polygons untriangulated (tobj would fan concave n-gons) and
//! triangulating each face with [`super::polygon::triangulate`]. Materials come from the `.mtl`
//! files named by `mtllib`, parsed here (tobj's MTL parser panics on short `Kd` lines): `Kd` is the
//! base colour, `d`/`Tr` its alpha, `Pm`/`Pr` metallic/roughness when present, `map_Kd` and
//! `norm`/`map_Bump`/`bump` the textures. A missing `.mtl` is a warning; faces then get the default
//! material. Points (`p`), polylines (`l`) and faces of fewer than three vertices are skipped with a
//! counted warning.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::off::file_stem;
use super::{ImportError, Material, Mesh, Siblings, polygon};

/// Reads an OBJ file into an unprocessed [`Mesh`] (see [`super::load`] for the processing).
pub(super) fn load(
    path: &Path,
    bytes: &[u8],
    files: Siblings,
    warnings: &mut Vec<String>,
) -> Result<Mesh, ImportError> {
    if let Some(bad) = bad_reference(bytes) {
        return Err(ImportError::parse(path, format!("OBJ parse error: {bad}")));
    }
    let (skipped, filtered) = non_surface_elements(bytes);
    let mut reader = filtered.as_deref().unwrap_or(bytes);
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials in the order tobj will index them (it appends each library's list).
    let parsed: RefCell<Vec<Material>> = RefCell::new(Vec::new());
    let mtl_warnings: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let loaded = tobj::load_obj_buf(&mut reader, &options, |mtl_path| {
        let full = files.resolve(mtl_path);
        match files.read(&full) {
            Ok(bytes) => {
                let mats = parse_mtl(
                    &String::from_utf8_lossy(&bytes),
                    full.parent().unwrap_or(Path::new("")),
                    files,
                    &mtl_warnings,
                    &full,
                );
                let mut map = HashMap::new();
                let mut tobj_mats = Vec::new();
                let mut store = parsed.borrow_mut();
                for m in mats {
                    map.insert(m.name.clone(), tobj_mats.len());
                    tobj_mats.push(tobj::Material {
                        name: m.name.clone(),
                        ..Default::default()
                    });
                    store.push(m);
                }
                Ok((tobj_mats, map.into_iter().collect()))
            }
            Err(e) => {
                mtl_warnings.borrow_mut().push(format!(
                    "{}: material library {} cannot be read ({e}); using the default material",
                    path.display(),
                    full.display()
                ));
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    });
    warnings.extend(mtl_warnings.into_inner());
    let (models, _) = loaded.map_err(|e| {
        let located = locate_error(bytes)
            .map(|l| format!(" ({l})"))
            .unwrap_or_default();
        ImportError::parse(path, format!("OBJ parse error: {e}{located}"))
    })?;
    let mut materials = parsed.into_inner();
    let default_id = materials.len() as u32;
    materials.push(Material::default());

    let mut mesh = Mesh {
        name: file_stem(path),
        has_normals: true,
        has_uvs: true,
        materials,
        ..Default::default()
    };
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut corners: Vec<u32> = Vec::new();
    let mut unknown_material = false;
    let mut fanned = 0;
    for model in &models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        let nv = m.positions.len() / 3;
        let has_n = !m.normals.is_empty() && m.normals.len() == m.positions.len();
        let has_t = !m.texcoords.is_empty() && m.texcoords.len() / 2 == nv;
        mesh.has_normals &= has_n;
        mesh.has_uvs &= has_t;
        for v in 0..nv {
            let p = [
                m.positions[3 * v],
                m.positions[3 * v + 1],
                m.positions[3 * v + 2],
            ];
            if !p.iter().all(|c| c.is_finite()) {
                return Err(ImportError::NonFinite {
                    path: path.to_path_buf(),
                    vertex: v,
                    context: format!(" (of object '{}', in tobj's order)", model.name),
                    position: p,
                });
            }
            mesh.positions.push(p);
            mesh.normals.push(if has_n {
                [m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]]
            } else {
                [0.0; 3]
            });
            // OBJ texture coordinates have their origin bottom-left; ours top-left.
            mesh.uvs.push(if has_t {
                [m.texcoords[2 * v], 1.0 - m.texcoords[2 * v + 1]]
            } else {
                [0.0; 2]
            });
        }
        let material = match m.material_id {
            Some(id) if id < default_id as usize => id as u32,
            Some(_) => {
                unknown_material = true;
                default_id
            }
            None => default_id,
        };
        let mut start = 0usize;
        let arities: Vec<usize> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.iter().map(|&a| a as usize).collect()
        };
        for (f, arity) in arities.into_iter().enumerate() {
            let Some(face) = m.indices.get(start..start + arity) else {
                return Err(ImportError::parse(
                    path,
                    format!("object '{}': face {f} is truncated", model.name),
                ));
            };
            start += arity;
            corners.clear();
            for (k, &i) in face.iter().enumerate() {
                if i as usize >= nv {
                    return Err(ImportError::IndexOutOfRange {
                        path: path.to_path_buf(),
                        context: format!("object '{}', face {f}, corner {k}", model.name),
                        index: i as i64,
                        vertex_count: nv,
                    });
                }
                corners.push(base + i);
            }
            let before = tris.len();
            if !polygon::triangulate(&mesh.positions, &corners, &mut tris) {
                fanned += 1;
            }
            mesh.material_ids
                .extend(std::iter::repeat_n(material, tris.len() - before));
        }
    }
    for (n, what) in [
        (skipped.points, "point elements ('p')"),
        (skipped.lines, "polyline elements ('l')"),
        (skipped.short_faces, "faces with fewer than 3 vertices"),
    ] {
        if n > 0 {
            warnings.push(format!("{}: skipped {n} {what}", path.display()));
        }
    }
    polygon::warn_fanned(fanned, path, warnings);
    if unknown_material {
        warnings.push(format!(
            "{}: faces use a material not found in any .mtl; using the default",
            path.display()
        ));
    }
    if !mesh.has_normals {
        mesh.normals.iter_mut().for_each(|n| *n = [0.0; 3]);
    }
    if !mesh.has_uvs {
        mesh.uvs.iter_mut().for_each(|t| *t = [0.0; 2]);
    }
    mesh.indices = tris.iter().flatten().copied().collect();
    Ok(mesh)
}

/// Elements of an OBJ file that are not surfaces, counted.
#[derive(Default)]
struct NonSurface {
    points: usize,
    lines: usize,
    short_faces: usize,
}

/// Counts what tobj would skip without a word (`p` points, `f` with one or two vertices) or read
/// wrongly (an `l` polyline of three or more points becomes a polygon), and returns a copy of the
/// file with the `l` statements commented out when there are any (line numbers unchanged).
fn non_surface_elements(bytes: &[u8]) -> (NonSurface, Option<Vec<u8>>) {
    let mut found = NonSurface::default();
    let mut polylines = Vec::new();
    let mut start = 0usize;
    for line in bytes.split(|&b| b == b'\n') {
        let mut toks = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty());
        match toks.next() {
            Some(b"p") => found.points += 1,
            Some(b"l") => {
                found.lines += 1;
                let at = line.iter().position(|b| !b.is_ascii_whitespace());
                polylines.extend(at.map(|a| start + a));
            }
            Some(b"f") if toks.count() < 3 => found.short_faces += 1,
            _ => {}
        }
        start += line.len() + 1;
    }
    let filtered = (!polylines.is_empty()).then(|| {
        let mut copy = bytes.to_vec();
        for at in polylines {
            if let Some(b) = copy.get_mut(at) {
                *b = b'#';
            }
        }
        copy
    });
    (found, filtered)
}

/// Finds the first face corner referring to no vertex, texture coordinate or normal, checked
/// before tobj reads the file: tobj turns a relative (negative) reference past the start into an
/// index near `usize::MAX` and `0` into its "missing" marker, then multiplies (an overflow panic
/// with overflow checks, a wrong element without; tobj-4.0.5 src/lib.rs:860) or silently drops
/// the texture coordinate or normal. A positive reference may point forward (tobj allows it) but
/// not past the last element of the file; a relative one counts back from the line it is on.
fn bad_reference(bytes: &[u8]) -> Option<String> {
    let text = String::from_utf8_lossy(bytes);
    let keyword = |line: &str| line.split_whitespace().next().map(str::to_owned);
    let mut totals = [0i64; 3];
    for line in text.lines() {
        match keyword(line).as_deref() {
            Some("v") => totals[0] += 1,
            Some("vt") => totals[1] += 1,
            Some("vn") => totals[2] += 1,
            _ => {}
        }
    }
    let mut so_far = [0i64; 3];
    for (i, line) in text.lines().enumerate() {
        let mut toks = line.split_whitespace();
        match toks.next() {
            Some("v") => so_far[0] += 1,
            Some("vt") => so_far[1] += 1,
            Some("vn") => so_far[2] += 1,
            Some("f") => {
                for tok in toks {
                    // tobj refuses a corner of more than three parts itself.
                    for (k, part) in tok.split('/').enumerate().take(3) {
                        if part.is_empty() {
                            continue;
                        }
                        let (ok, defined) = match part.parse::<i64>() {
                            Ok(x) if x > 0 => (x <= totals[k], totals[k]),
                            Ok(x) if x < 0 => (x >= -so_far[k], so_far[k]),
                            _ => (false, totals[k]),
                        };
                        if !ok {
                            let kind = ["vertex", "texture coordinate", "normal"][k];
                            let when = if part.starts_with('-') { " so far" } else { "" };
                            return Some(format!(
                                "line {}: bad {kind} reference '{part}' ({defined} defined{when})",
                                i + 1
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// Finds the first face line with a bad vertex reference, to point at it after tobj fails.
fn locate_error(bytes: &[u8]) -> Option<String> {
    let text = String::from_utf8_lossy(bytes);
    let (mut v, mut vt, mut vn) = (0i64, 0i64, 0i64);
    for (i, line) in text.lines().enumerate() {
        let mut toks = line.split_whitespace();
        let key = toks.next();
        if let Some(k @ ("v" | "vt" | "vn")) = key {
            let need = if k == "vt" { 1 } else { 3 };
            let nums: Vec<&str> = toks.clone().take(need).collect();
            if nums.len() < need || nums.iter().any(|t| t.parse::<f32>().is_err()) {
                return Some(format!("line {}: malformed '{k}' line", i + 1));
            }
        }
        match key {
            Some("v") => v += 1,
            Some("vt") => vt += 1,
            Some("vn") => vn += 1,
            Some("f") => {
                for tok in toks {
                    for (k, part) in tok.split('/').enumerate() {
                        if part.is_empty() {
                            continue;
                        }
                        let count = [v, vt, vn][k.min(2)];
                        let ok = match part.parse::<i64>() {
                            Ok(x) if x > 0 => x <= count,
                            Ok(x) if x < 0 => -x <= count,
                            _ => false,
                        };
                        if !ok {
                            let kind = ["vertex", "texture coordinate", "normal"][k.min(2)];
                            return Some(format!(
                                "line {}: bad {kind} reference '{part}' ({count} defined so far)",
                                i + 1
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// Parses an MTL library. Unknown statements are ignored; malformed numbers give warnings.
fn parse_mtl(
    text: &str,
    dir: &Path,
    files: Siblings,
    warnings: &RefCell<Vec<String>>,
    file: &Path,
) -> Vec<Material> {
    let mut out: Vec<Material> = Vec::new();
    let texture = |rest: &[&str], what: &str, material: &str| -> Option<PathBuf> {
        // Options such as "-bm 1.0" precede the file name; the name is the last token.
        let name = rest.last()?;
        let p = dir.join(name.replace('\\', "/"));
        if files.is_file(&p) {
            Some(p)
        } else {
            warnings.borrow_mut().push(format!(
                "{}: material '{material}' {what} texture {} not found",
                file.display(),
                p.display()
            ));
            None
        }
    };
    for (i, line) in text.lines().enumerate() {
        let toks: Vec<&str> = line
            .split('#')
            .next()
            .unwrap_or("")
            .split_whitespace()
            .collect();
        let Some((&key, rest)) = toks.split_first() else {
            continue;
        };
        if key == "newmtl" {
            out.push(Material {
                name: rest.join(" "),
                ..Material::default()
            });
            continue;
        }
        let Some(m) = out.last_mut() else { continue };
        let nums: Option<Vec<f32>> = rest.iter().map(|t| t.parse::<f32>().ok()).collect();
        let nums = nums.filter(|n| n.iter().all(|x| x.is_finite()));
        let mut bad = false;
        match key {
            "Kd" => match nums.as_deref() {
                // One value means grey.
                Some([g]) => m.base_color[..3].copy_from_slice(&[*g; 3]),
                Some([r, g, b, ..]) => m.base_color[..3].copy_from_slice(&[*r, *g, *b]),
                _ => bad = true,
            },
            "d" => match nums.as_deref() {
                Some([a, ..]) => m.base_color[3] = *a,
                _ => bad = true,
            },
            "Tr" => match nums.as_deref() {
                Some([t, ..]) => m.base_color[3] = 1.0 - *t,
                _ => bad = true,
            },
            "Pm" => match nums.as_deref() {
                Some([x, ..]) => m.metallic = *x,
                _ => bad = true,
            },
            "Pr" => match nums.as_deref() {
                Some([x, ..]) => m.roughness = *x,
                _ => bad = true,
            },
            "map_Kd" => {
                let name = m.name.clone();
                m.base_color_texture = texture(rest, "base-colour", &name);
            }
            "norm" | "map_Bump" | "map_bump" | "bump" => {
                let name = m.name.clone();
                m.normal_texture = texture(rest, "normal", &name);
            }
            _ => {}
        }
        if bad {
            warnings.borrow_mut().push(format!(
                "{}: line {}: bad '{key}' values ignored",
                file.display(),
                i + 1
            ));
        }
    }
    out
}
