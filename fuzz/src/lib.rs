//! The entry points of the fuzz targets (`fuzz/fuzz_targets/`), shared with the stable test that
//! replays the corpora and the regressions (`tests/fuzz_replay.rs` includes this file), so that a
//! file replays exactly as it was fuzzed.
//!
//! Each entry point feeds the bytes to the code under test and checks what came back: a panic, an
//! abort or a broken invariant is a finding; a clear error is a correct answer to a bad file.

use vgeo::format;
use vgeo::mesh::{self, Format, ImportOptions};

/// What an import or a load made of the bytes.
#[derive(Debug)]
pub enum Outcome {
    /// Loaded, with the importer's warnings (none for a `.vgeo` file).
    Loaded { warnings: Vec<String> },
    /// Refused with this error message.
    Refused(String),
}

/// The import options for `data`, derived from its length so that the fuzzer covers them without
/// a header of its own (the corpus files stay plain mesh files): glTF node splitting on odd
/// lengths; crease angle 60 (the default), 0 (every edge a crease) or 180 (smooth everywhere).
pub fn options(data: &[u8]) -> ImportOptions {
    ImportOptions {
        split_nodes: data.len() % 2 == 1,
        crease_deg: [60.0, 0.0, 180.0][data.len() / 2 % 3],
    }
}

/// Imports `data` as a `format` file named `name` (in memory: every file it names is missing) and
/// checks the result: at least one mesh, each valid with a triangle; or an error that names the
/// file. A PLY file the importer's fast path reads must read the same through ply-rs
/// (`mesh::ply_fast_path_check`).
pub fn import(format: Format, name: &str, data: &[u8]) -> Outcome {
    if format == Format::Ply
        && let Err(e) = mesh::ply_fast_path_check(name, data)
    {
        panic!("{name}: the PLY fast path and the ply-rs path differ: {e}");
    }
    match mesh::load_bytes(data, format, name, &options(data)) {
        Ok(import) => {
            assert!(!import.meshes.is_empty(), "{name}: loaded without a mesh");
            for m in &import.meshes {
                if let Err(e) = m.validate() {
                    panic!("{name}: mesh '{}' is invalid: {e}", m.name);
                }
                assert!(m.triangle_count() > 0, "{name}: mesh '{}' is empty", m.name);
            }
            Outcome::Loaded {
                warnings: import.report.warnings,
            }
        }
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.contains(name),
                "the error does not name the file: {message}"
            );
            Outcome::Refused(message)
        }
    }
}

/// Loads `data` as a `.vgeo` file twice: as it is, and with the header's length and the head's and
/// pages' checksums made right (`format::fix_checksums`) (a mutation almost always breaks the checksum, which would hide every later check from
/// the fuzzer). The outcome is the second load's. A loaded mesh must survive what its users do
/// without checks (decode every cluster's triangles, every level as a mesh) and save to a file
/// that loads again and saves to the same bytes.
pub fn load_vgeo(data: &[u8]) -> Outcome {
    let _ = format::load(data);
    let mut fixed = data.to_vec();
    format::fix_checksums(&mut fixed);
    let m = match format::load(&fixed) {
        Ok(m) => m,
        Err(e) => return Outcome::Refused(e.to_string()),
    };
    let _ = m.positions();
    for ci in 0..m.clusters.len() {
        let _ = m.cluster_triangles(ci);
    }
    for level in &m.stats.levels {
        let _ = m.level_mesh(level.level);
    }
    let saved = format::save(&m);
    let again = format::load(&saved)
        .unwrap_or_else(|e| panic!("a loaded .vgeo file saved again does not load: {e}"));
    assert!(
        format::save(&again) == saved,
        "a loaded .vgeo file saved, loaded and saved again changed"
    );
    Outcome::Loaded {
        warnings: Vec::new(),
    }
}
