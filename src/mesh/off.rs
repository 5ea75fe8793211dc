//! OFF (Object File Format) importer: `[ST][C][N]OFF` header, optional `#` comments, a counts line
//! `vertices faces edges` (possibly on the header line), one vertex per line (`x y z`, then normals
//! for `N`, colours for `C`, texture coordinates for `ST`, all but position and normal ignored),
//! one face per line (`n i0 .. i(n-1)`, anything after the indices such as a colour is ignored).
//! Faces with more than three corners are triangulated with [`super::polygon::triangulate`].

use std::path::Path;

use super::{ImportError, Material, Mesh, polygon};

/// Reads an OFF file into an unprocessed [`Mesh`] (see [`super::load`] for the processing).
pub(super) fn load(
    path: &Path,
    bytes: &[u8],
    warnings: &mut Vec<String>,
) -> Result<Mesh, ImportError> {
    parse(path, &String::from_utf8_lossy(bytes), warnings)
}

fn parse(path: &Path, text: &str, warnings: &mut Vec<String>) -> Result<Mesh, ImportError> {
    let err = |line: usize, msg: String| ImportError::parse(path, format!("line {line}: {msg}"));
    // Significant lines: comments stripped, blank lines skipped, with 1-based line numbers.
    let mut lines = text.lines().enumerate().filter_map(|(i, l)| {
        let l = l.split('#').next().unwrap_or("").trim();
        (!l.is_empty()).then_some((i + 1, l))
    });
    let Some((hline, header)) = lines.next() else {
        return Err(ImportError::parse(
            path,
            "empty file (expected an 'OFF' header)",
        ));
    };
    let mut htoks = header.split_whitespace();
    let magic = htoks.next().unwrap_or("");
    let Some(prefix) = magic.strip_suffix("OFF") else {
        return Err(err(
            hline,
            format!("expected an 'OFF' header, found '{magic}'"),
        ));
    };
    let mut rest = prefix;
    let has_st = rest.starts_with("ST");
    if has_st {
        rest = &rest[2..];
    }
    let has_color = rest.starts_with('C');
    if has_color {
        rest = &rest[1..];
    }
    let has_normal = rest.starts_with('N');
    if has_normal {
        rest = &rest[1..];
    }
    if !rest.is_empty() {
        return Err(err(
            hline,
            format!("unsupported OFF variant '{magic}' (4D or nD OFF)"),
        ));
    }
    let mut counts: Vec<&str> = htoks.collect();
    if counts.first() == Some(&"BINARY") {
        return Err(err(hline, "binary OFF is not supported".into()));
    }
    let mut cline = hline;
    if counts.is_empty() {
        let Some((l, c)) = lines.next() else {
            return Err(err(
                hline,
                "missing the counts line 'vertices faces edges'".into(),
            ));
        };
        cline = l;
        counts = c.split_whitespace().collect();
    }
    let parse_count = |s: Option<&&str>, what: &str| -> Result<usize, ImportError> {
        let s = s.ok_or_else(|| err(cline, format!("missing {what} count")))?;
        s.parse::<usize>()
            .map_err(|_| err(cline, format!("bad {what} count '{s}'")))
    };
    let nv = parse_count(counts.first(), "vertex")?;
    let nf = parse_count(counts.get(1), "face")?;
    // Never trust counts for allocation: each vertex needs at least a few bytes of text.
    let cap = text.len() / 6 + 1;
    let mut mesh = Mesh {
        name: file_stem(path),
        has_normals: has_normal,
        has_uvs: false,
        materials: vec![Material::default()],
        ..Default::default()
    };
    mesh.positions.reserve(nv.min(cap));
    for v in 0..nv {
        let Some((l, line)) = lines.next() else {
            return Err(ImportError::parse(
                path,
                format!("file ends after {v} of {nv} vertices"),
            ));
        };
        let mut toks = line.split_whitespace();
        let mut num = |what: &str| -> Result<f32, ImportError> {
            let t = toks
                .next()
                .ok_or_else(|| err(l, format!("vertex {v}: missing {what}")))?;
            t.parse::<f32>()
                .map_err(|_| err(l, format!("vertex {v}: bad {what} '{t}'")))
        };
        let p = [num("x")?, num("y")?, num("z")?];
        if !p.iter().all(|c| c.is_finite()) {
            return Err(ImportError::NonFinite {
                path: path.to_path_buf(),
                vertex: v,
                context: format!(" (line {l})"),
                position: p,
            });
        }
        let n = if has_normal {
            [num("nx")?, num("ny")?, num("nz")?]
        } else {
            [0.0; 3]
        };
        mesh.positions.push(p);
        mesh.normals.push(n);
        mesh.uvs.push([0.0; 2]);
    }
    let mut tris = Vec::new();
    let mut corners = Vec::new();
    let mut skipped = 0usize;
    let mut fanned = 0usize;
    for f in 0..nf {
        let Some((l, line)) = lines.next() else {
            return Err(ImportError::parse(
                path,
                format!("file ends after {f} of {nf} faces"),
            ));
        };
        let mut toks = line.split_whitespace();
        let count_tok = toks.next().unwrap_or("");
        let count: usize = count_tok
            .parse()
            .map_err(|_| err(l, format!("face {f}: bad corner count '{count_tok}'")))?;
        corners.clear();
        for k in 0..count {
            let t = toks
                .next()
                .ok_or_else(|| err(l, format!("face {f}: has {k} of {count} vertex indices")))?;
            let i: i64 = t
                .parse()
                .map_err(|_| err(l, format!("face {f}: bad vertex index '{t}'")))?;
            if i < 0 || i as u64 >= nv as u64 {
                return Err(ImportError::IndexOutOfRange {
                    path: path.to_path_buf(),
                    context: format!("line {l}, face {f}, corner {k}"),
                    index: i,
                    vertex_count: nv,
                });
            }
            corners.push(i as u32);
        }
        if count < 3 {
            skipped += 1;
            continue;
        }
        if !polygon::triangulate(&mesh.positions, &corners, &mut tris) {
            fanned += 1;
        }
    }
    polygon::warn_fanned(fanned, path, warnings);
    if let Some((first, _)) = lines.next() {
        warnings.push(format!(
            "{}: {} line(s) after the {nf} declared faces ignored (from line {first})",
            path.display(),
            1 + lines.count()
        ));
    }
    polygon::set_triangles(&mut mesh, tris, skipped, path, warnings);
    Ok(mesh)
}

/// The file name without extension, as a mesh name.
pub(super) fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}
