//! STL importer (own parser: `stl_io` stops at the first `endsolid` and requires "solid " with a
//! space). Binary when the size is exactly `84 + 50 * count`; otherwise ASCII if the file starts
//! with `solid`, with any number of `solid ... endsolid` blocks; otherwise binary again (a truncated
//! binary file is an error). Facet normals are ignored: they would keep every facet's corners apart
//! through welding, so normals are recomputed from the welded surface (`has_normals = false`).

use std::path::Path;

use super::off::file_stem;
use super::{ImportError, Material, Mesh, polygon};

/// Reads an STL file into an unprocessed [`Mesh`] (a triangle soup; [`super::load`] welds it).
pub(super) fn load(
    path: &Path,
    bytes: &[u8],
    warnings: &mut Vec<String>,
) -> Result<Mesh, ImportError> {
    let mut mesh = Mesh {
        name: file_stem(path),
        materials: vec![Material::default()],
        ..Default::default()
    };
    let binary_count = (bytes.len() >= 84)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64);
    let exact_binary = binary_count.is_some_and(|n| 84 + 50 * n == bytes.len() as u64);
    let starts_solid = {
        let head = &bytes[..bytes.len().min(512)];
        let text = String::from_utf8_lossy(head);
        // Binary headers may start with "solid" too; text has no NUL bytes.
        !head.contains(&0)
            && text
                .trim_start_matches('\u{feff}')
                .trim_start()
                .starts_with("solid")
    };
    if !exact_binary && starts_solid {
        parse_ascii(path, &String::from_utf8_lossy(bytes), &mut mesh, warnings)?;
    } else {
        parse_binary(path, bytes, &mut mesh, warnings)?;
    }
    let tris = mesh.indices.len() / 3;
    mesh.normals = vec![[0.0; 3]; mesh.positions.len()];
    mesh.uvs = vec![[0.0; 2]; mesh.positions.len()];
    mesh.material_ids = vec![0; tris];
    Ok(mesh)
}

fn check_finite(path: &Path, mesh: &Mesh, p: [f32; 3], context: String) -> Result<(), ImportError> {
    if p.iter().all(|c| c.is_finite()) {
        return Ok(());
    }
    Err(ImportError::NonFinite {
        path: path.to_path_buf(),
        vertex: mesh.positions.len(),
        context,
        position: p,
    })
}

fn parse_binary(
    path: &Path,
    bytes: &[u8],
    mesh: &mut Mesh,
    warnings: &mut Vec<String>,
) -> Result<(), ImportError> {
    if bytes.len() < 84 {
        return Err(ImportError::parse(
            path,
            format!(
                "not an ASCII STL (no 'solid') and too short for binary STL ({} bytes)",
                bytes.len()
            ),
        ));
    }
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    let room = (bytes.len() - 84) / 50;
    if room < n {
        return Err(ImportError::parse(
            path,
            format!(
                "binary STL declares {n} triangles but the file only holds {room} (truncated?)"
            ),
        ));
    }
    if room > n || !(bytes.len() - 84).is_multiple_of(50) {
        warnings.push(format!(
            "{}: {} bytes after the {n} declared triangles ignored",
            path.display(),
            bytes.len() - 84 - 50 * n
        ));
    }
    mesh.positions.reserve(3 * n);
    for t in 0..n {
        let base = 84 + 50 * t + 12;
        for k in 0..3 {
            let mut p = [0.0f32; 3];
            for (c, v) in p.iter_mut().enumerate() {
                let o = base + 12 * k + 4 * c;
                let b = bytes
                    .get(o..o + 4)
                    .ok_or_else(|| ImportError::parse(path, "truncated"))?;
                *v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            }
            check_finite(path, mesh, p, format!(" (triangle {t}, corner {k})"))?;
            mesh.indices.push(mesh.positions.len() as u32);
            mesh.positions.push(p);
        }
    }
    Ok(())
}

fn parse_ascii(
    path: &Path,
    text: &str,
    mesh: &mut Mesh,
    warnings: &mut Vec<String>,
) -> Result<(), ImportError> {
    let err = |line: usize, msg: String| ImportError::parse(path, format!("line {line}: {msg}"));
    let mut in_loop = false;
    let mut loop_start = 0usize;
    let mut solids = 0usize;
    let mut facet = 0usize;
    let mut corners: Vec<u32> = Vec::new();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut skipped = 0usize;
    let mut fanned = 0usize;
    for (i, line) in text.lines().enumerate() {
        let l = i + 1;
        let mut toks = line.split_whitespace();
        let Some(kw) = toks.next() else { continue };
        match kw.trim_start_matches('\u{feff}') {
            "solid" => solids += 1,
            "endsolid" | "facet" | "endfacet" => {}
            "outer" => {
                if in_loop {
                    return Err(err(l, "'outer loop' inside a loop".into()));
                }
                in_loop = true;
                loop_start = l;
                corners.clear();
            }
            "vertex" => {
                if !in_loop {
                    return Err(err(l, "'vertex' outside 'outer loop'".into()));
                }
                let mut p = [0.0f32; 3];
                for (c, v) in p.iter_mut().enumerate() {
                    let t = toks
                        .next()
                        .ok_or_else(|| err(l, format!("vertex has {c} of 3 coordinates")))?;
                    *v = t
                        .parse()
                        .map_err(|_| err(l, format!("bad vertex coordinate '{t}'")))?;
                }
                check_finite(path, mesh, p, format!(" (line {l})"))?;
                corners.push(mesh.positions.len() as u32);
                mesh.positions.push(p);
            }
            "endloop" => {
                if !in_loop {
                    return Err(err(l, "'endloop' without 'outer loop'".into()));
                }
                in_loop = false;
                if corners.len() < 3 {
                    skipped += 1;
                } else if !polygon::triangulate(&mesh.positions, &corners, &mut tris) {
                    fanned += 1;
                }
                facet += 1;
            }
            other => {
                let shown: String = other.chars().take(32).collect();
                return Err(err(l, format!("unexpected '{shown}' in ASCII STL")));
            }
        }
    }
    if in_loop {
        return Err(ImportError::parse(
            path,
            format!("file ends inside the loop opened at line {loop_start}"),
        ));
    }
    if solids > 1 {
        warnings.push(format!(
            "{}: {solids} 'solid' blocks merged",
            path.display()
        ));
    }
    if skipped > 0 {
        warnings.push(format!(
            "{}: skipped {skipped} of {facet} facets with fewer than 3 vertices",
            path.display()
        ));
    }
    polygon::warn_fanned(fanned, path, warnings);
    mesh.indices = tris.iter().flatten().copied().collect();
    Ok(())
}
